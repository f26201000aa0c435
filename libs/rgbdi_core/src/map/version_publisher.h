// Atomic publishing of a map directory. `map_dir` (= <parent>/<name>) is a relative symbolic link
// to the sibling version directory <name>.<n>. A save stages its files in <name>.tmp-<n+1>,
// which publish() fsyncs, renames to <name>.<n+1> and links from `map_dir` by renaming a new
// link <name>.link-<n+1> over it (rename(2) replaces atomically). removeOldVersions() then
// deletes the other <name>.<k>, <name>.tmp-<k> and <name>.link-<k> entries (leftovers of
// interrupted saves included). Only entries of exactly these forms are ever removed.
#pragma once

#include <functional>
#include <string>

namespace rgbdi::map::detail {

class VersionPublisher {
 public:
  /// Checks `map_dir` (its parent must exist; it must be absent or a symbolic link: a plain
  /// directory is refused), removes leftover staging directories of interrupted saves and
  /// creates the staging directory. Throws MapError.
  explicit VersionPublisher(const std::string& map_dir);
  /// Removes the staging directory when publish() was not reached (a failed save).
  ~VersionPublisher();
  VersionPublisher(const VersionPublisher&) = delete;
  VersionPublisher& operator=(const VersionPublisher&) = delete;

  /// Where the files of the new version are written.
  const std::string& stagingDir() const { return staging_; }

  /// Makes the staged version durable and the one `map_dir` names; `after_step` is called
  /// after "fsync", "renamed" and "published". Throws MapError (the old version then stays).
  void publish(const std::function<void(const std::string&)>& after_step);
  /// Deletes the versions other than the published one. Throws MapError.
  void removeOldVersions();

 private:
  std::string map_dir_, parent_, name_, staging_, version_dir_name_;
  unsigned long long n_ = 0;
  bool published_ = false;
};

}  // namespace rgbdi::map::detail
