// Low-level file work of the map directory: files written with fsync, whole-file reads, the
// FNV-1a 64 checksum the manifest records for every file, and fsync of directories. Every
// failure throws MapError naming the path.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace rgbdi::map::detail {

/// FNV-1a, 64 bit (offset basis 14695981039346656037, prime 1099511628211), incremental.
class Fnv1a64 {
 public:
  void update(const void* data, std::size_t n);
  std::uint64_t value() const { return h_; }

 private:
  std::uint64_t h_ = 14695981039346656037ull;
};

/// "0123456789abcdef" form (16 lower-case hex digits) used in manifest.json.
std::string hex64(std::uint64_t v);

struct FileDigest {
  std::uint64_t bytes = 0;
  std::uint64_t fnv1a64 = 0;
};

/// Size and checksum of a file's content (read in chunks).
FileDigest digestFile(const std::string& path);

/// A new file (must not exist) written in order and made durable by close().
class DurableFile {
 public:
  explicit DurableFile(std::string path);
  ~DurableFile();  // closes without fsync when close() was not reached (error path)
  DurableFile(const DurableFile&) = delete;
  DurableFile& operator=(const DurableFile&) = delete;

  void write(const std::string& bytes);
  /// fsync + close; throws MapError on failure.
  void close();

 private:
  std::string path_;
  int fd_ = -1;
};

/// Writes `bytes` to a new file with fsync.
void writeDurably(const std::string& path, const std::string& bytes);
/// fsync of an existing file or directory (opened read-only).
void fsyncPath(const std::string& path);
/// Whole content of a file; "cannot open" names the path and the reason.
std::vector<char> readWholeFile(const std::string& path);

}  // namespace rgbdi::map::detail
