// Atomic file output: write to "<path>.tmp.<pid>" and rename() over the target when complete,
// so an interrupted run never leaves a truncated result file.
#pragma once

#include <functional>
#include <ostream>
#include <stdexcept>
#include <string>

namespace rgbdi {

class IoError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Calls `write(os)` on a temporary file next to `path`, then renames it to `path`.
/// Throws IoError (naming the path) if the file cannot be created, written or renamed;
/// the temporary is removed on any failure and the previous content of `path` is untouched.
void writeFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& write);

/// Same for producers that can only write to a file name (e.g. library save functions):
/// `write(tmp_path)` must create tmp_path; it is renamed to `path` afterwards.
void writeFileAtomicallyVia(const std::string& path,
                            const std::function<void(const std::string& tmp_path)>& write);

}  // namespace rgbdi
