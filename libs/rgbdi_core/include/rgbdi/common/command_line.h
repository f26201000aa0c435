// The one option parser of rgbdi's command-line tools (MRPT 2.5 on Debian does not install TCLAP,
// so this small one is shared instead of one hand-written loop per app).
//
// Accepted forms: "--name value", "--name=value", "-n value", flags "--name" / "-n", "--" (the
// rest is positional). Every tool gets --help/-h and --version. Errors (unknown option, missing
// or unexpected value, a value the option's setter rejects) throw UsageError with a message for
// the user; tools print it with their usage text and exit with kExitUsage.
#pragma once

#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace rgbdi {

/// Exit statuses shared by the tools (documented in every --help).
constexpr int kExitOk = 0;       ///< success (warnings included)
constexpr int kExitError = 1;    ///< unreadable input, failed run, output not written
constexpr int kExitUsage = 2;    ///< bad command line or configuration
constexpr int kExitDamaged = 3;  ///< damaged input, processed up to the damage, outputs written
constexpr int kExitInterrupted = 130;  ///< Ctrl-C; what was processed is written

/// The "Exit status:" paragraph every --help ends with.
std::string exitStatusHelp();

/// rgbdi's version (CMake project version).
const char* rgbdiVersion();
/// "TOOL (rgbdi) VERSION" for --version.
std::string versionLine(const std::string& tool);

class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class CommandLine {
 public:
  enum class Outcome { Run, Help, Version };

  /// `names`: comma-separated spellings, e.g. "-o,--out". A flag sets *out to true.
  void flag(const std::string& names, bool* out);
  /// An option with a value; `set` may throw UsageError (or std::invalid_argument) to reject it.
  void value(const std::string& names, std::function<void(const std::string&)> set);
  /// Shorthand: stores the value into *out.
  void value(const std::string& names, std::string* out);

  /// Parses argv[1..]; positional arguments are collected in positional(). --help and --version
  /// win over everything else. Throws UsageError.
  Outcome parse(int argc, const char* const* argv);
  const std::vector<std::string>& positional() const { return positional_; }

 private:
  struct Option {
    std::vector<std::string> names;
    bool takes_value = false;
    bool* flag = nullptr;
    std::function<void(const std::string&)> set;
  };
  const Option* find(const std::string& name) const;

  std::vector<Option> options_;
  std::vector<std::string> positional_;
};

/// A non-negative (or, with `positive`, > 0) finite number for `option`; throws UsageError.
double parseNumber(const std::string& option, const std::string& text, bool positive = false);

}  // namespace rgbdi
