// LoopFeatureOptions: the feature_ keys of [loop], their ranges and cross-key rules.
#include <string>
#include <vector>

#include "rgbdi/common/option_keys.h"
#include "rgbdi/loop/loop_features.h"

namespace rgbdi::loop {
namespace {

const char* const kSection = "loop";

// One table of keys and ranges serves load() and validate(), so options built in code are held
// to the same limits as options read from a file.
using IntKey = rgbdi::IntKey<LoopFeatureOptions>;
using DoubleKey = rgbdi::DoubleKey<LoopFeatureOptions>;

const std::vector<IntKey>& intKeys() {
  static const std::vector<IntKey> keys = {
      {"feature_max_keypoints", [](LoopFeatureOptions& o) -> int& { return o.max_keypoints; }, 1,
       100000},
      {"feature_detect_candidates",
       [](LoopFeatureOptions& o) -> int& { return o.detect_candidates; }, 1, 1000000},
      {"feature_fast_threshold", [](LoopFeatureOptions& o) -> int& { return o.fast_threshold; }, 1,
       254},
      {"feature_pyramid_levels", [](LoopFeatureOptions& o) -> int& { return o.pyramid_levels; }, 1,
       16},
      {"feature_border_px", [](LoopFeatureOptions& o) -> int& { return o.border_px; }, 0, 1000},
      {"feature_grid_cols", [](LoopFeatureOptions& o) -> int& { return o.grid_cols; }, 1, 100},
      {"feature_grid_rows", [](LoopFeatureOptions& o) -> int& { return o.grid_rows; }, 1, 100},
      {"feature_depth_window_px", [](LoopFeatureOptions& o) -> int& { return o.depth_window_px; },
       0, 20},
      {"feature_depth_grid_cols", [](LoopFeatureOptions& o) -> int& { return o.depth_grid_cols; },
       0, 160},
      {"feature_depth_grid_rows", [](LoopFeatureOptions& o) -> int& { return o.depth_grid_rows; },
       0, 120},
  };
  return keys;
}

const std::vector<DoubleKey>& doubleKeys() {
  static const std::vector<DoubleKey> keys = {
      {"feature_pyramid_scale", [](LoopFeatureOptions& o) -> double& { return o.pyramid_scale; },
       1.01, 4.0},
      {"feature_depth_min_m", [](LoopFeatureOptions& o) -> double& { return o.depth_min_m; }, 0.0,
       100.0},
      {"feature_depth_max_m", [](LoopFeatureOptions& o) -> double& { return o.depth_max_m; }, 0.01,
       1000.0},
      {"feature_depth_max_relative_spread",
       [](LoopFeatureOptions& o) -> double& { return o.depth_max_relative_spread; }, 0.0, 1.0},
      {"feature_depth_noise_coeff",
       [](LoopFeatureOptions& o) -> double& { return o.depth_noise_coeff; }, 0.0, 1.0},
      {"feature_depth_max_noise_sigmas",
       [](LoopFeatureOptions& o) -> double& { return o.depth_max_noise_sigmas; }, 0.0, 100.0},
  };
  return keys;
}

[[noreturn]] void failKey(const std::string& key, const std::string& what) {
  throw ConfigError("LoopFeatureOptions [" + std::string(kSection) + "] " + key + ": " + what);
}

template <typename Fail>
void checkConsistency(const LoopFeatureOptions& o, Fail&& fail) {
  if (o.depth_min_m >= o.depth_max_m)
    fail("feature_depth_min_m", "must be smaller than feature_depth_max_m");
  // Fewer proposals than kept keypoints would make max_keypoints unreachable by construction.
  if (o.detect_candidates < o.max_keypoints)
    fail("feature_detect_candidates", "must not be smaller than feature_max_keypoints");
  if ((o.depth_grid_cols == 0) != (o.depth_grid_rows == 0))
    fail("feature_depth_grid_rows", "must be 0 exactly when feature_depth_grid_cols is 0");
}

}  // namespace

void LoopFeatureOptions::validate() const {
  checkKeyRanges(*this, intKeys(), doubleKeys(), failKey);
  checkConsistency(*this,
                   [](const std::string& key, const std::string& what) { failKey(key, what); });
}

LoopFeatureOptions LoopFeatureOptions::load(IniReader& ini) {
  LoopFeatureOptions o;
  loadKeys(ini, kSection, o, intKeys(), doubleKeys());
  checkConsistency(o, [&ini](const std::string& key, const std::string& what) {
    ini.fail(kSection, key, what);
  });
  return o;
}

frontend::FrontendOptions LoopFeatureOptions::depthSampling(
    const frontend::FrontendOptions& base) const {
  frontend::FrontendOptions f = base;
  f.depth_min_m = depth_min_m;
  f.depth_max_m = depth_max_m;
  f.depth_neighbourhood_px = depth_window_px;
  f.depth_max_relative_spread = depth_max_relative_spread;
  f.depth_noise_coeff = depth_noise_coeff;
  f.depth_max_noise_sigmas = depth_max_noise_sigmas;
  return f;
}

}  // namespace rgbdi::loop
