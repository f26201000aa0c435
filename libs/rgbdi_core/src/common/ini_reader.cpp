#include "rgbdi/common/ini_reader.h"

#include <mrpt/config/CConfigFile.h>
#include <mrpt/config/CConfigFileMemory.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace rgbdi {
namespace {

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return {};
  const auto e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

/// Strips a trailing "; comment" or "# comment" from a value (INI values never contain those).
std::string stripInlineComment(const std::string& v) {
  const auto pos = v.find_first_of(";#");
  return trim(pos == std::string::npos ? v : v.substr(0, pos));
}

std::string fmtRange(double lo, double hi) {
  std::ostringstream os;
  os << "[" << lo << ", " << hi << "]";
  return os.str();
}

/// Throws ConfigError naming `label` and the line of the first line that is neither blank, a
/// comment (';', '#', "//"), a "[section]" header, an MRPT directive ("@define", "@include") nor
/// "key = value" with a non-empty key. MRPT's parser ignores such lines, which would let a typo
/// such as a missing '=' drop a setting without a word.
void checkLines(const std::string& text, const std::string& label) {
  std::istringstream is(text);
  std::string line;
  for (std::size_t n = 1; std::getline(is, line); ++n) {
    const std::string t = trim(line);
    if (t.empty() || t[0] == ';' || t[0] == '#' || t.rfind("//", 0) == 0 || t[0] == '@') continue;
    if (t[0] == '[') {
      const auto close = t.find(']');
      const std::string rest = close == std::string::npos ? "x" : trim(t.substr(close + 1));
      if (close != std::string::npos && close > 1 &&
          (rest.empty() || rest[0] == ';' || rest[0] == '#'))
        continue;
      throw ConfigError(label + " line " + std::to_string(n) + ": '" + t +
                        "' is not a valid [section] header");
    }
    const auto eq = t.find('=');
    if (eq != std::string::npos && !trim(t.substr(0, eq)).empty()) continue;
    throw ConfigError(label + " line " + std::to_string(n) + ": '" + t +
                      "' is not 'key = value', a [section] header, a comment or blank");
  }
}

}  // namespace

IniReader::IniReader(std::unique_ptr<mrpt::config::CConfigFileBase> cfg, std::string label)
    : cfg_(std::move(cfg)), label_(std::move(label)) {}
IniReader::~IniReader() = default;
IniReader::IniReader(IniReader&&) noexcept = default;
IniReader& IniReader::operator=(IniReader&&) noexcept = default;

IniReader IniReader::fromFile(const std::string& path) {
  std::ifstream f(path);
  if (!f) throw ConfigError(path + ": cannot open configuration file");
  std::stringstream ss;
  ss << f.rdbuf();
  return fromText(ss.str(), path);
}

IniReader IniReader::fromText(const std::string& text, const std::string& label) {
  checkLines(text, label);
  try {
    return IniReader(std::make_unique<mrpt::config::CConfigFileMemory>(text), label);
  } catch (const std::exception& e) {
    throw ConfigError(label + ": cannot parse INI: " + e.what());
  }
}

IniReader IniReader::empty() { return fromText("", "<defaults>"); }

std::string IniReader::where(const std::string& section, const std::string& key) const {
  return label_ + " [" + section + "] " + key;
}

void IniReader::fail(const std::string& section, const std::string& key,
                     const std::string& what) const {
  throw ConfigError(where(section, key) + ": " + what);
}

bool IniReader::hasKey(const std::string& section, const std::string& key) const {
  std::vector<std::string> keys;
  cfg_->getAllKeys(section, keys);
  const std::string lk = lower(key);
  return std::any_of(keys.begin(), keys.end(),
                     [&](const std::string& k) { return lower(trim(k)) == lk; });
}

std::string IniReader::raw(const std::string& section, const std::string& key) const {
  return stripInlineComment(cfg_->read_string(section, key, "", false));
}

double IniReader::getDouble(const std::string& section, const std::string& key, double def,
                            double min, double max) {
  used_[lower(section)].insert(lower(key));
  double v = def;
  if (hasKey(section, key)) {
    const std::string s = raw(section, key);
    char* end = nullptr;
    errno = 0;
    v = std::strtod(s.c_str(), &end);
    if (s.empty() || end == s.c_str() || *end != '\0' || errno == ERANGE || !std::isfinite(v))
      fail(section, key, "'" + s + "' is not a number; accepted range " + fmtRange(min, max));
  }
  if (!(v >= min && v <= max)) {
    std::ostringstream os;
    os << "value " << v << " is out of the accepted range " << fmtRange(min, max);
    fail(section, key, os.str());
  }
  return v;
}

int IniReader::getInt(const std::string& section, const std::string& key, int def, int min,
                      int max) {
  used_[lower(section)].insert(lower(key));
  long v = def;
  if (hasKey(section, key)) {
    const std::string s = raw(section, key);
    char* end = nullptr;
    errno = 0;
    v = std::strtol(s.c_str(), &end, 10);
    if (s.empty() || end == s.c_str() || *end != '\0' || errno == ERANGE)
      fail(section, key, "'" + s + "' is not an integer; accepted range " + fmtRange(min, max));
  }
  if (v < min || v > max) {
    std::ostringstream os;
    os << "value " << v << " is out of the accepted range " << fmtRange(min, max);
    fail(section, key, os.str());
  }
  return static_cast<int>(v);
}

bool IniReader::getBool(const std::string& section, const std::string& key, bool def) {
  used_[lower(section)].insert(lower(key));
  if (!hasKey(section, key)) return def;
  const std::string s = lower(raw(section, key));
  if (s == "true" || s == "1" || s == "yes" || s == "on") return true;
  if (s == "false" || s == "0" || s == "no" || s == "off") return false;
  fail(section, key, "'" + s + "' is not a boolean; accepted: true/false/1/0/yes/no/on/off");
}

std::string IniReader::getString(const std::string& section, const std::string& key,
                                 const std::string& def) {
  used_[lower(section)].insert(lower(key));
  return hasKey(section, key) ? raw(section, key) : def;
}

std::string IniReader::getEnum(const std::string& section, const std::string& key,
                               const std::string& def, const std::vector<std::string>& allowed) {
  const std::string v = getString(section, key, def);
  if (std::find(allowed.begin(), allowed.end(), v) == allowed.end()) {
    std::string list;
    for (const auto& a : allowed) list += (list.empty() ? "" : "|") + a;
    fail(section, key, "'" + v + "' is not one of " + list);
  }
  return v;
}

Eigen::VectorXd IniReader::getVector(const std::string& section, const std::string& key,
                                     const Eigen::VectorXd& def) {
  used_[lower(section)].insert(lower(key));
  if (!hasKey(section, key)) return def;
  std::string s = raw(section, key);
  std::replace(s.begin(), s.end(), ',', ' ');
  std::istringstream is(s);
  std::vector<double> vals;
  std::string tok;
  while (is >> tok) {
    char* end = nullptr;
    const double d = std::strtod(tok.c_str(), &end);
    if (end == tok.c_str() || *end != '\0' || !std::isfinite(d))
      fail(section, key, "'" + tok + "' is not a number");
    vals.push_back(d);
  }
  if (static_cast<Eigen::Index>(vals.size()) != def.size()) {
    fail(section, key,
         "expected " + std::to_string(def.size()) + " numbers, got " + std::to_string(vals.size()));
  }
  return Eigen::Map<Eigen::VectorXd>(vals.data(), static_cast<Eigen::Index>(vals.size()));
}

void IniReader::acceptSection(const std::string& section) {
  accepted_sections_.insert(lower(section));
}

void IniReader::acceptConfigSectionsExcept(const std::vector<std::string>& read_here) {
  for (const std::string& s : kConfigSections)
    if (std::find(read_here.begin(), read_here.end(), s) == read_here.end()) acceptSection(s);
}

void IniReader::checkNoUnknownKeys() const {
  std::vector<std::string> sections;
  cfg_->getAllSections(sections);
  std::string problems;
  for (const auto& sec : sections) {
    const std::string ls = lower(trim(sec));
    if (ls.empty() || accepted_sections_.count(ls)) continue;
    const auto it = used_.find(ls);
    std::vector<std::string> keys;
    cfg_->getAllKeys(sec, keys);
    if (it == used_.end()) {
      if (!keys.empty()) problems += "\n  " + label_ + " [" + sec + "]: unknown section";
      continue;
    }
    for (const auto& k : keys) {
      if (!it->second.count(lower(trim(k))))
        problems += "\n  " + where(sec, trim(k)) + ": unknown key";
    }
  }
  if (!problems.empty()) throw ConfigError("configuration has unknown entries:" + problems);
}

}  // namespace rgbdi
