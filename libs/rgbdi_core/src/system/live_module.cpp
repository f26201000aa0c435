#include "rgbdi/system/live_module.h"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <mutex>

#include "rgbdi/system/run_common.h"

namespace rgbdi::system {

std::string liveModulePath() {
  if (const char* env = std::getenv(kLiveModuleEnv); env && *env) return env;
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) return kLiveModuleFile;  // left to the loader's search path
  return (exe.parent_path().parent_path() / "lib" / kLiveModuleFile).string();
}

LiveMain loadLiveModule() {
  static std::mutex mutex;
  static LiveMain entry = nullptr;
  std::lock_guard<std::mutex> lock(mutex);
  if (entry) return entry;
  const std::string path = liveModulePath();
  // RTLD_LOCAL: the module's own copies of rgbdi's code never bind to the executable's.
  // Never closed: its sensor threads and MRPT registrations live until the process ends.
  void* handle = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) {
    const char* why = ::dlerror();
    throw UserError("--live needs the live module " + path +
                    ", which cannot be loaded: " + (why ? why : "unknown reason") + " (set " +
                    kLiveModuleEnv + " to its path if it was moved)");
  }
  void* symbol = ::dlsym(handle, kLiveModuleEntry);
  if (!symbol)
    throw UserError("the live module " + path + " has no entry point " + kLiveModuleEntry +
                    " (a library of another rgbdi build?)");
  entry = reinterpret_cast<LiveMain>(symbol);
  return entry;
}

}  // namespace rgbdi::system
