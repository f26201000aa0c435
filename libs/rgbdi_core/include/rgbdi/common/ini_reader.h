// Validated reading of rgbdi INI files (MRPT INI format, one section per module).
//
// Every option struct loads itself through an IniReader: each get*() names the section, key,
// default and accepted range. A missing key takes its default; a value out of range or not
// parseable throws ConfigError naming file, section, key and the accepted range. After all
// modules have loaded, checkNoUnknownKeys() rejects keys nobody asked for (typos).
#pragma once

#include <Eigen/Core>
#include <map>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace mrpt::config {
class CConfigFileBase;
}

namespace rgbdi {

class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The sections of the rgbdi configuration (share/config.ini), in its order. A section that
/// is added to the file is added here, so that every tool reading part of the file accepts it.
inline const std::vector<std::string> kConfigSections = {
    "camera",  "imu",    "extrinsic", "stream", "frontend", "estimator", "loop", "relocalise",
    "mapping", "navmap", "pipeline",  "output", "convert",  "sim",       "wheel"};

class IniReader {
 public:
  /// Reads the file; throws ConfigError when it cannot be opened or has a line that is not
  /// blank, a comment, a [section] header, an MRPT @directive or "key = value" (the message names
  /// the file and the line number).
  static IniReader fromFile(const std::string& path);
  /// Parses INI text held in memory (label is used in messages instead of a file name); the
  /// same line check as fromFile().
  static IniReader fromText(const std::string& text, const std::string& label = "<memory>");
  /// An empty configuration: every key takes its default.
  static IniReader empty();

  ~IniReader();
  IniReader(IniReader&&) noexcept;
  IniReader& operator=(IniReader&&) noexcept;

  const std::string& label() const { return label_; }
  bool hasKey(const std::string& section, const std::string& key) const;

  double getDouble(const std::string& section, const std::string& key, double def, double min,
                   double max);
  int getInt(const std::string& section, const std::string& key, int def, int min, int max);
  bool getBool(const std::string& section, const std::string& key, bool def);
  std::string getString(const std::string& section, const std::string& key, const std::string& def);
  /// A string that must be one of `allowed`.
  std::string getEnum(const std::string& section, const std::string& key, const std::string& def,
                      const std::vector<std::string>& allowed);
  /// A whitespace/comma separated list of exactly N numbers.
  Eigen::VectorXd getVector(const std::string& section, const std::string& key,
                            const Eigen::VectorXd& def);

  /// Marks a whole section as known (for sections read by other tools).
  void acceptSection(const std::string& section);
  /// Marks every section of the rgbdi configuration (kConfigSections) as known except those
  /// listed: a tool that reads some sections of a full share/config.ini accepts the others.
  void acceptConfigSectionsExcept(const std::vector<std::string>& read_here);
  /// Throws ConfigError listing every key present in the file that no get*() asked for.
  void checkNoUnknownKeys() const;

  /// Builds the error message format used everywhere: "FILE [section] key: what".
  std::string where(const std::string& section, const std::string& key) const;
  [[noreturn]] void fail(const std::string& section, const std::string& key,
                         const std::string& what) const;

 private:
  IniReader(std::unique_ptr<mrpt::config::CConfigFileBase> cfg, std::string label);
  std::string raw(const std::string& section, const std::string& key) const;

  std::unique_ptr<mrpt::config::CConfigFileBase> cfg_;
  std::string label_;
  std::map<std::string, std::set<std::string>> used_;
  std::set<std::string> accepted_sections_;
};

}  // namespace rgbdi
