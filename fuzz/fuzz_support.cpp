#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "fuzz_target.h"

namespace rgbdi::fuzz {

namespace {
std::string base(const std::string& tag) {
  return (std::filesystem::temp_directory_path() /
          ("rgbdi_fuzz_" + std::to_string(::getpid()) + "_" + tag))
      .string();
}
}  // namespace

std::string writeScratchFile(const std::string& tag, const std::uint8_t* data, std::size_t size) {
  const std::string path = base(tag);
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  f.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  if (!f) throw std::runtime_error(path + ": cannot write the fuzz input");
  return path;
}

std::string readFileBytes(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw std::runtime_error(path + ": cannot read");
  std::ostringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

std::string scratchDir(const std::string& tag) {
  const std::string d = base(tag + "_dir");
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

}  // namespace rgbdi::fuzz
