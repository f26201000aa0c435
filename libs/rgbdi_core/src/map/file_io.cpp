#include "map/file_io.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "rgbdi/common/whole_file.h"
#include "rgbdi/map/map_directory.h"

namespace rgbdi::map::detail {
namespace {

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw MapError(path + ": " + what + ": " + std::strerror(errno));
}

}  // namespace

void Fnv1a64::update(const void* data, std::size_t n) {
  const auto* p = static_cast<const unsigned char*>(data);
  std::uint64_t h = h_;
  for (std::size_t i = 0; i < n; ++i) {
    h ^= p[i];
    h *= 1099511628211ull;
  }
  h_ = h;
}

std::string hex64(std::uint64_t v) {
  static const char* digits = "0123456789abcdef";
  std::string s(16, '0');
  for (int i = 15; i >= 0; --i, v >>= 4) s[static_cast<std::size_t>(i)] = digits[v & 0xF];
  return s;
}

FileDigest digestFile(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) fail(path, "cannot open");
  FileDigest d;
  Fnv1a64 h;
  std::vector<char> buffer(1 << 20);
  for (;;) {
    const ssize_t n = ::read(fd, buffer.data(), buffer.size());
    if (n < 0) {
      if (errno == EINTR) continue;
      const int err = errno;
      ::close(fd);
      errno = err;
      fail(path, "read error");
    }
    if (n == 0) break;
    h.update(buffer.data(), static_cast<std::size_t>(n));
    d.bytes += static_cast<std::uint64_t>(n);
  }
  ::close(fd);
  d.fnv1a64 = h.value();
  return d;
}

DurableFile::DurableFile(std::string path) : path_(std::move(path)) {
  fd_ = ::open(path_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd_ < 0) fail(path_, "cannot create file");
}

DurableFile::~DurableFile() {
  if (fd_ >= 0) ::close(fd_);
}

void DurableFile::write(const std::string& bytes) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd_, bytes.data() + done, bytes.size() - done);
    if (n < 0) {
      if (errno == EINTR) continue;
      fail(path_, "write failed");
    }
    done += static_cast<std::size_t>(n);
  }
}

void DurableFile::close() {
  if (::fsync(fd_) != 0) fail(path_, "fsync failed");
  const int fd = fd_;
  fd_ = -1;
  if (::close(fd) != 0) fail(path_, "close failed");
}

void writeDurably(const std::string& path, const std::string& bytes) {
  DurableFile f(path);
  f.write(bytes);
  f.close();
}

void fsyncPath(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) fail(path, "cannot open for fsync");
  if (::fsync(fd) != 0) {
    const int err = errno;
    ::close(fd);
    errno = err;
    fail(path, "fsync failed");
  }
  ::close(fd);
}

std::vector<char> readWholeFile(const std::string& path) {
  std::vector<char> data;
  switch (rgbdi::readWholeFile(path, data)) {
    case FileReadError::kOpen:
      fail(path, "cannot open");
    case FileReadError::kRead:
      fail(path, "read error");
    case FileReadError::kNone:
      break;
  }
  return data;
}

}  // namespace rgbdi::map::detail
