// Helpers shared by the test executables: locating real fixtures and the built apps, temp dirs.
#pragma once

#include <gtest/gtest.h>

#include <fstream>
#include <string>

namespace rgbdi::test {

/// Root of ../shared/data (env RGBDI_SHARED_DATA, else the path configured at build time).
std::string sharedDataDir();
/// Absolute path of a fixture below shared/data, e.g. "real/openni2_single_rgbd.rawlog".
std::string fixturePath(const std::string& relative);
/// True when running under CI (env CI set and not "false"/"0").
bool inCi();
/// Directory of the built apps (env RGBDI_BIN_DIR, else the build tree's bin/).
std::string binDir();
/// Project source root (for share/config.ini).
std::string sourceDir();
/// A fresh, empty directory under the system temp dir, unique per call.
std::string makeTempDir(const std::string& prefix);
/// Runs a shell command, returns its exit status; stdout+stderr captured into `output`.
int runCommand(const std::string& cmd, std::string* output = nullptr);
/// The directory of a sequence written by `rgbdi-sim ARGS --out DIR`, generated once per build of
/// rgbdi-sim (and content of the file ARGS name with --config) and shared by every test process
/// that asks for the same arguments (ctest runs each test in its own process; rendering dominates
/// the cost of the app tests). The directory is read-only by convention: tests write their outputs
/// elsewhere. Generation is guarded by a file lock and published by a rename, so concurrent tests
/// never see a partial sequence. Throws with the simulator's output when it fails.
std::string cachedSimSequence(const std::string& args);

}  // namespace rgbdi::test

/// Use at the top of a test that needs a fixture: fails under CI when it is missing, skips
/// (with a message) on a developer machine without ../shared/data.
#define RGBDI_REQUIRE_FIXTURE(path)                                                 \
  do {                                                                              \
    if (!std::ifstream(path).good()) {                                              \
      if (::rgbdi::test::inCi()) FAIL() << "fixture missing (CI is set): " << path; \
      GTEST_SKIP() << "fixture missing: " << path;                                  \
    }                                                                               \
  } while (0)
