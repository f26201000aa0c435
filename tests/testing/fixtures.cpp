#include "testing/fixtures.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <iterator>
#include <sstream>
#include <stdexcept>

namespace rgbdi::test {
namespace {
std::string envOr(const char* name, const std::string& fallback) {
  const char* v = std::getenv(name);
  return (v && *v) ? std::string(v) : fallback;
}
}  // namespace

std::string sharedDataDir() { return envOr("RGBDI_SHARED_DATA", RGBDI_DEFAULT_SHARED_DATA); }

std::string fixturePath(const std::string& relative) { return sharedDataDir() + "/" + relative; }

bool inCi() {
  const char* v = std::getenv("CI");
  if (!v) return false;
  const std::string s(v);
  return !(s.empty() || s == "0" || s == "false");
}

std::string binDir() { return envOr("RGBDI_BIN_DIR", RGBDI_DEFAULT_BIN_DIR); }

std::string sourceDir() { return RGBDI_SOURCE_DIR; }

std::string makeTempDir(const std::string& prefix) {
  static std::atomic<int> counter{0};
  namespace fs = std::filesystem;
  for (int attempt = 0; attempt < 1000; ++attempt) {
    const fs::path p = fs::temp_directory_path() / (prefix + "_" + std::to_string(::getpid()) +
                                                    "_" + std::to_string(counter++));
    if (fs::create_directory(p)) return p.string();
  }
  throw std::runtime_error("cannot create temp dir for " + prefix);
}

int runCommand(const std::string& cmd, std::string* output) {
  FILE* pipe = ::popen((cmd + " 2>&1").c_str(), "r");
  if (!pipe) return -1;
  std::array<char, 4096> buf{};
  std::string out;
  size_t n;
  while ((n = std::fread(buf.data(), 1, buf.size(), pipe)) > 0) out.append(buf.data(), n);
  const int status = ::pclose(pipe);
  if (output) *output = out;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

namespace {
/// The content of the file named by `--config FILE` (or `--config=FILE`) in `args`, "" if none.
std::string configFileContent(const std::string& args) {
  std::istringstream words(args);
  std::string word, path;
  while (words >> word) {
    if (word == "--config") {
      words >> path;
    } else if (word.rfind("--config=", 0) == 0) {
      path = word.substr(9);
    }
  }
  if (path.empty()) return "";
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cachedSimSequence: cannot read --config " + path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

/// `args` without the path of its --config file (tests write their configs into fresh temporary
/// directories: the content names the sequence, the path must not).
std::string argsWithoutConfigPath(const std::string& args) {
  std::istringstream words(args);
  std::string word, out;
  while (words >> word) {
    if (word == "--config") {
      words >> word;
      word = "--config <file>";
    } else if (word.rfind("--config=", 0) == 0) {
      word = "--config=<file>";
    }
    out += word + " ";
  }
  return out;
}
}  // namespace

std::string cachedSimSequence(const std::string& args) {
  namespace fs = std::filesystem;
  const std::string sim = binDir() + "/rgbdi-sim";
  struct stat st {};
  if (::stat(sim.c_str(), &st) != 0) throw std::runtime_error("rgbdi-sim not built: " + sim);
  // The key names the arguments (with the content of their --config file, not its path) and the
  // simulator build, so neither an edited config nor a rebuilt simulator ever serves an old
  // sequence.
  const std::string key = std::to_string(std::hash<std::string>{}(argsWithoutConfigPath(args) +
                                                                  "\n" + configFileContent(args))) +
                          "_" + std::to_string(static_cast<long long>(st.st_mtime)) + "_" +
                          std::to_string(static_cast<long long>(st.st_size));
  const fs::path root = fs::path(binDir()).parent_path() / "test-cache";
  fs::create_directories(root);
  const fs::path dir = root / key;
  const std::string lock_path = (root / (key + ".lock")).string();
  const int fd = ::open(lock_path.c_str(), O_CREAT | O_RDWR, 0644);
  if (fd < 0) throw std::runtime_error("cannot open lock file " + lock_path);
  ::flock(fd, LOCK_EX);  // released by close, also when this process dies
  std::string error;
  if (!fs::exists(dir)) {
    const fs::path tmp = root / (key + ".tmp");
    std::error_code ec;
    fs::remove_all(tmp, ec);
    std::string out;
    const int rc = runCommand(sim + " " + args + " --out " + tmp.string(), &out);
    if (rc == 0)
      fs::rename(tmp, dir);
    else
      error = "rgbdi-sim " + args + " failed (status " + std::to_string(rc) + "): " + out;
  }
  ::close(fd);
  if (!error.empty()) throw std::runtime_error(error);
  return dir.string();
}

}  // namespace rgbdi::test
