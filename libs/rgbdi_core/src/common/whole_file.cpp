#include "rgbdi/common/whole_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>

namespace rgbdi {
namespace {

template <class Byte>
FileReadError readInto(const std::string& path, std::vector<Byte>& out) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return FileReadError::kOpen;
  const auto failed = [fd] {
    const int err = errno;
    ::close(fd);
    errno = err;
    return FileReadError::kRead;
  };
  struct stat st {};
  if (::fstat(fd, &st) != 0) return failed();
  // The size is a hint (a file may change while it is read, /proc files report 0): the loop
  // reads until read() reports the end, growing `out` when the file holds more.
  out.resize(st.st_size > 0 ? static_cast<std::size_t>(st.st_size) : 0);
  std::size_t got = 0;
  for (;;) {
    if (got == out.size()) {
      // Probe for more in a small buffer first: the usual answer is the end, and growing
      // `out` would allocate and clear a larger block for nothing.
      Byte probe[4096];
      const ssize_t n = ::read(fd, probe, sizeof probe);
      if (n < 0) {
        if (errno == EINTR) continue;
        return failed();
      }
      if (n == 0) break;
      out.insert(out.end(), probe, probe + n);
      got = out.size();
      continue;
    }
    const ssize_t n = ::read(fd, out.data() + got, out.size() - got);
    if (n < 0) {
      if (errno == EINTR) continue;
      return failed();
    }
    if (n == 0) break;
    got += static_cast<std::size_t>(n);
  }
  out.resize(got);
  ::close(fd);
  return FileReadError::kNone;
}

}  // namespace

FileReadError readWholeFile(const std::string& path, std::vector<std::uint8_t>& out) {
  return readInto(path, out);
}

FileReadError readWholeFile(const std::string& path, std::vector<char>& out) {
  return readInto(path, out);
}

}  // namespace rgbdi
