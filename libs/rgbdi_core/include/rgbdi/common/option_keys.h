// Range-checked numeric option keys. An options struct lists its int and double keys once, with
// their ranges, in two tables; the same tables serve load() (from an INI file: ConfigError naming
// the file, section and key) and validate() (options built in code), so both hold a value to the
// same limits.
#pragma once

#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "rgbdi/common/ini_reader.h"

namespace rgbdi {

template <class Options>
struct IntKey {
  const char* key;
  std::function<int&(Options&)> field;
  int min, max;
};

template <class Options>
struct DoubleKey {
  const char* key;
  std::function<double&(Options&)> field;
  double min, max;
};

/// "value V outside [LO, HI]"
template <typename T>
std::string outsideRange(T v, T lo, T hi) {
  std::ostringstream os;
  os << "value " << v << " outside [" << lo << ", " << hi << "]";
  return os.str();
}

/// Calls fail(key, what) (which must not return) for the first int key, then double key, whose
/// value lies outside its range; NaN counts as outside.
template <class Options, class Fail>
void checkKeyRanges(const Options& options, const std::vector<IntKey<Options>>& ints,
                    const std::vector<DoubleKey<Options>>& doubles, Fail&& fail) {
  Options copy = options;  // the accessors return non-const references
  for (const IntKey<Options>& k : ints) {
    const int v = k.field(copy);
    if (v < k.min || v > k.max) fail(k.key, outsideRange(v, k.min, k.max));
  }
  for (const DoubleKey<Options>& k : doubles) {
    const double v = k.field(copy);
    if (!(v >= k.min && v <= k.max)) fail(k.key, outsideRange(v, k.min, k.max));
  }
}

/// Reads every key of the tables from [section] into `options` (absent keys keep its value).
template <class Options>
void loadKeys(IniReader& ini, const char* section, Options& options,
              const std::vector<IntKey<Options>>& ints,
              const std::vector<DoubleKey<Options>>& doubles) {
  for (const IntKey<Options>& k : ints)
    k.field(options) = ini.getInt(section, k.key, k.field(options), k.min, k.max);
  for (const DoubleKey<Options>& k : doubles)
    k.field(options) = ini.getDouble(section, k.key, k.field(options), k.min, k.max);
}

}  // namespace rgbdi
