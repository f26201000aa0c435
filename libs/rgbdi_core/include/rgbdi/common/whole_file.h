// Reading a whole file into memory: the per-frame image files of a rawlog, the map files.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace rgbdi {

/// Which step of readWholeFile failed (errno holds that step's reason).
enum class FileReadError { kNone, kOpen, kRead };

/// Reads the file at `path` into `out`, reusing its capacity: one read per file of the size
/// fstat reports (plus the one that sees its end), straight into `out`, without a stdio buffer.
/// On failure `out` is unspecified and errno says why.
FileReadError readWholeFile(const std::string& path, std::vector<std::uint8_t>& out);
FileReadError readWholeFile(const std::string& path, std::vector<char>& out);

}  // namespace rgbdi
