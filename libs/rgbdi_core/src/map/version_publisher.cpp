#include "map/version_publisher.h"

#include <dirent.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <vector>

#include "map/file_io.h"
#include "rgbdi/map/map_directory.h"

namespace rgbdi::map::detail {
namespace {

enum class EntryKind { Version, Staging, Link, Other };

/// Classifies a directory entry of the parent: <name>.<n>, <name>.tmp-<n>, <name>.link-<n>.
EntryKind classify(const std::string& entry, const std::string& name, unsigned long long& n) {
  if (entry.size() <= name.size() + 1 || entry.compare(0, name.size(), name) != 0 ||
      entry[name.size()] != '.')
    return EntryKind::Other;
  std::string rest = entry.substr(name.size() + 1);
  EntryKind kind = EntryKind::Version;
  if (rest.rfind("tmp-", 0) == 0) {
    kind = EntryKind::Staging;
    rest = rest.substr(4);
  } else if (rest.rfind("link-", 0) == 0) {
    kind = EntryKind::Link;
    rest = rest.substr(5);
  }
  if (rest.empty() || rest.size() > 18 || rest.find_first_not_of("0123456789") != std::string::npos)
    return EntryKind::Other;
  n = std::stoull(rest);
  return kind;
}

std::vector<std::string> listDirectory(const std::string& dir) {
  DIR* d = ::opendir(dir.c_str());
  if (!d) throw MapError(dir + ": cannot list directory: " + std::strerror(errno));
  std::vector<std::string> names;
  while (const dirent* e = ::readdir(d)) names.emplace_back(e->d_name);
  ::closedir(d);
  return names;
}

void removeTree(const std::string& path) {
  std::error_code ec;
  std::filesystem::remove_all(path, ec);
  if (ec) throw MapError(path + ": cannot remove: " + ec.message());
}

}  // namespace

VersionPublisher::VersionPublisher(const std::string& map_dir) {
  map_dir_ = map_dir;
  while (map_dir_.size() > 1 && map_dir_.back() == '/') map_dir_.pop_back();
  const std::size_t slash = map_dir_.rfind('/');
  parent_ = slash == std::string::npos ? "." : (slash == 0 ? "/" : map_dir_.substr(0, slash));
  name_ = slash == std::string::npos ? map_dir_ : map_dir_.substr(slash + 1);
  if (name_.empty() || name_ == "." || name_ == ".." || name_ == "/")
    throw MapError(map_dir + ": not a usable map directory name");

  struct stat st {};
  if (::stat(parent_.c_str(), &st) != 0 || !S_ISDIR(st.st_mode))
    throw MapError(map_dir + ": the parent directory " + parent_ + " does not exist");
  if (::lstat(map_dir_.c_str(), &st) == 0 && !S_ISLNK(st.st_mode))
    throw MapError(map_dir + ": exists and is not a map published by rgbdi (a plain " +
                   (S_ISDIR(st.st_mode) ? std::string("directory") : std::string("file")) +
                   ", e.g. a copy): it cannot be replaced atomically; remove or rename it, or "
                   "save to another path");

  unsigned long long max_n = 0;
  for (const std::string& e : listDirectory(parent_)) {
    unsigned long long n = 0;
    const EntryKind kind = classify(e, name_, n);
    if (kind == EntryKind::Other) continue;
    max_n = std::max(max_n, n);
    // A staging directory or link left by an interrupted save is never referenced.
    if (kind == EntryKind::Staging) removeTree(parent_ + "/" + e);
    if (kind == EntryKind::Link) std::remove((parent_ + "/" + e).c_str());
  }
  n_ = max_n + 1;
  version_dir_name_ = name_ + "." + std::to_string(n_);
  staging_ = parent_ + "/" + name_ + ".tmp-" + std::to_string(n_);
  if (::mkdir(staging_.c_str(), 0755) != 0)
    throw MapError(staging_ + ": cannot create the staging directory: " + std::strerror(errno));
}

VersionPublisher::~VersionPublisher() {
  if (published_) return;
  std::error_code ec;
  std::filesystem::remove_all(staging_, ec);  // best effort on the error path
}

void VersionPublisher::publish(const std::function<void(const std::string&)>& after_step) {
  const auto step = [&](const char* s) {
    if (after_step) after_step(s);
  };
  fsyncPath(staging_);
  step("fsync");
  const std::string version_dir = parent_ + "/" + version_dir_name_;
  if (std::rename(staging_.c_str(), version_dir.c_str()) != 0)
    throw MapError(version_dir +
                   ": cannot rename the staged map into place: " + std::strerror(errno));
  staging_ = version_dir;  // a failure below removes the unpublished version
  fsyncPath(parent_);
  step("renamed");
  const std::string link = parent_ + "/" + name_ + ".link-" + std::to_string(n_);
  if (::symlink(version_dir_name_.c_str(), link.c_str()) != 0)
    throw MapError(link + ": cannot create the link: " + std::strerror(errno));
  if (std::rename(link.c_str(), map_dir_.c_str()) != 0) {
    const std::string err = std::strerror(errno);
    std::remove(link.c_str());
    throw MapError(map_dir_ + ": cannot publish the new map: " + err);
  }
  published_ = true;
  fsyncPath(parent_);
  step("published");
}

void VersionPublisher::removeOldVersions() {
  for (const std::string& e : listDirectory(parent_)) {
    unsigned long long n = 0;
    const EntryKind kind = classify(e, name_, n);
    if (kind == EntryKind::Other || (kind == EntryKind::Version && n == n_)) continue;
    if (kind == EntryKind::Link)
      std::remove((parent_ + "/" + e).c_str());
    else
      removeTree(parent_ + "/" + e);
  }
  fsyncPath(parent_);
}

}  // namespace rgbdi::map::detail
