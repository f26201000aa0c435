// The one option parser of rgbdi's command-line tools: TCLAP as MRPT ships it (Debian package
// libmrpt-tclap-dev, CMake target mrpt::tclap) reads the line; this class declares the options
// on it and adds what TCLAP 1.2 lacks for our tools. TCLAP is not seen outside command_line.cpp.
//
// Accepted forms: "--name value", "--name=value", "-n value", flags "--name" / "-n", "--" (the
// rest is positional). Every tool gets --help/-h and --version. Errors (unknown option, missing
// or unexpected value, an option given twice, a value the option's setter rejects) throw UsageError
// with a message for the user; tools print it with usageErrorLine() and exit with kExitUsage.
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
constexpr int kExitNoPose = 4;   ///< rgbdi-slam: the run estimated no pose (summary.json says why)
constexpr int kExitInterrupted = 130;  ///< Ctrl-C; what was processed is written

/// The "Exit status:" paragraph every --help ends with.
std::string exitStatusHelp();

/// rgbdi's version (CMake project version).
const char* rgbdiVersion();
/// "TOOL (rgbdi) VERSION" for --version.
std::string versionLine(const std::string& tool);
/// What every tool prints for a UsageError: one line, "TOOL: MESSAGE (see TOOL --help)\n".
std::string usageErrorLine(const std::string& tool, const std::string& message);

class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class CommandLine {
 public:
  enum class Outcome { Run, Help, Version };

  /// `names`: comma-separated spellings, e.g. "-o,--out" (at least one long name; short names
  /// are one letter). A flag sets *out to true.
  void flag(const std::string& names, bool* out);
  /// An option with a value; `set` may throw UsageError (or std::invalid_argument) to reject it.
  void value(const std::string& names, std::function<void(const std::string&)> set);
  /// Shorthand: stores the value into *out.
  void value(const std::string& names, std::string* out);

  /// Parses argv[1..]; positional arguments are collected in positional(). --help and --version
  /// win over everything else. Setters run after the whole line was read, in declaration order.
  /// Throws UsageError.
  Outcome parse(int argc, const char* const* argv);
  const std::vector<std::string>& positional() const { return positional_; }

 private:
  enum class Kind { Flag, Value };
  struct Option {
    std::vector<std::string> names;  // as spelled on the line: "-o", "--out"
    Kind kind = Kind::Flag;
    bool* flag = nullptr;
    std::function<void(const std::string&)> set;
  };
  void declare(const std::string& names, Kind kind, bool* flag,
               std::function<void(const std::string&)> set);
  const Option* find(const std::string& name) const;

  std::vector<Option> options_;
  std::vector<std::string> positional_;
};

/// A non-negative (or, with `positive`, > 0) finite number for `option`; throws UsageError.
double parseNumber(const std::string& option, const std::string& text, bool positive = false);

}  // namespace rgbdi
