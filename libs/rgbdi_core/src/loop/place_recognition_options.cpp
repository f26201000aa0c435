// PlaceRecognitionOptions: the place_ keys of [loop] and their ranges.
#include <string>
#include <vector>

#include "rgbdi/common/option_keys.h"
#include "rgbdi/loop/place_recognizer.h"

namespace rgbdi::loop {
namespace {

const char* const kSection = "loop";

// One table of keys and ranges serves load() and validate().
using IntKey = rgbdi::IntKey<PlaceRecognitionOptions>;
using DoubleKey = rgbdi::DoubleKey<PlaceRecognitionOptions>;

const std::vector<IntKey>& intKeys() {
  static const std::vector<IntKey> keys = {
      {"place_index_tables", [](PlaceRecognitionOptions& o) -> int& { return o.index.tables; }, 1,
       16},
      {"place_index_key_bits", [](PlaceRecognitionOptions& o) -> int& { return o.index.key_bits; },
       8, 20},
      {"place_index_max_key_keyframes",
       [](PlaceRecognitionOptions& o) -> int& { return o.index.max_key_keyframes; }, 1, 100000000},
      {"place_top_k", [](PlaceRecognitionOptions& o) -> int& { return o.top_k; }, 1, 1000},
      {"place_exclude_recent_count",
       [](PlaceRecognitionOptions& o) -> int& { return o.exclude_recent_count; }, 0, 100000},
      {"place_consistency_keyframes",
       [](PlaceRecognitionOptions& o) -> int& { return o.consistency_keyframes; }, 1, 10},
      {"place_proximity_max_candidates",
       [](PlaceRecognitionOptions& o) -> int& { return o.proximity_max_candidates; }, 0, 100},
  };
  return keys;
}

const std::vector<DoubleKey>& doubleKeys() {
  static const std::vector<DoubleKey> keys = {
      {"place_exclude_recent_s",
       [](PlaceRecognitionOptions& o) -> double& { return o.exclude_recent_s; }, 0.0, 1e6},
      {"place_exclude_recent_m",
       [](PlaceRecognitionOptions& o) -> double& { return o.exclude_recent_m; }, 0.0, 1e6},
      {"place_min_normalised_score",
       [](PlaceRecognitionOptions& o) -> double& { return o.min_normalised_score; }, 0.0, 10.0},
      {"place_min_reference_ratio",
       [](PlaceRecognitionOptions& o) -> double& { return o.min_reference_ratio; }, 0.0, 1.0},
      {"place_consistency_window_s",
       [](PlaceRecognitionOptions& o) -> double& { return o.consistency_window_s; }, 0.0, 1e6},
      {"place_proximity_radius_m",
       [](PlaceRecognitionOptions& o) -> double& { return o.proximity_radius_m; }, 0.0, 1000.0},
  };
  return keys;
}

/// The seed is a 64-bit value; the file holds the range an int reads.
constexpr int kMaxSeed = 2147483647;

[[noreturn]] void failKey(const std::string& key, const std::string& what) {
  throw ConfigError("PlaceRecognitionOptions [" + std::string(kSection) + "] " + key + ": " + what);
}

}  // namespace

void PlaceRecognitionOptions::validate() const {
  checkKeyRanges(*this, intKeys(), doubleKeys(), failKey);
  index.validate();
}

PlaceRecognitionOptions PlaceRecognitionOptions::load(IniReader& ini) {
  PlaceRecognitionOptions o;
  loadKeys(ini, kSection, o, intKeys(), doubleKeys());
  o.index.seed = static_cast<std::uint64_t>(
      ini.getInt(kSection, "place_index_seed", static_cast<int>(o.index.seed), 0, kMaxSeed));
  return o;
}

}  // namespace rgbdi::loop
