#include "rgbdi/common/atomic_file.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>

namespace rgbdi {
namespace {

std::string tmpNameFor(const std::string& path) {
  return path + ".tmp." + std::to_string(::getpid());
}

void commit(const std::string& tmp, const std::string& path) {
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const std::string err = std::strerror(errno);
    std::remove(tmp.c_str());
    throw IoError(path + ": cannot move finished file into place: " + err);
  }
}

}  // namespace

void writeFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& write) {
  const std::string tmp = tmpNameFor(path);
  {
    std::ofstream os(tmp, std::ios::binary | std::ios::trunc);
    if (!os) throw IoError(path + ": cannot create file: " + std::strerror(errno));
    try {
      write(os);
    } catch (...) {
      os.close();
      std::remove(tmp.c_str());
      throw;
    }
    os.flush();
    if (!os) {
      os.close();
      std::remove(tmp.c_str());
      throw IoError(path + ": write failed (disk full?)");
    }
  }
  commit(tmp, path);
}

void writeFileAtomicallyVia(const std::string& path,
                            const std::function<void(const std::string&)>& write) {
  const std::string tmp = tmpNameFor(path);
  try {
    write(tmp);
  } catch (...) {
    std::remove(tmp.c_str());
    throw;
  }
  if (::access(tmp.c_str(), F_OK) != 0) throw IoError(path + ": the writer did not produce a file");
  commit(tmp, path);
}

}  // namespace rgbdi
