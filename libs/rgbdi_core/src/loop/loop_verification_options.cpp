// LoopVerificationOptions: the verify_* keys of [loop], one table of keys and ranges for load()
// and validate() (the mapping_options.cpp pattern).
#include <string>
#include <vector>

#include "rgbdi/common/option_keys.h"
#include "rgbdi/loop/loop_verifier.h"

namespace rgbdi::loop {
namespace {

const char* const kSection = "loop";

using IntKey = rgbdi::IntKey<LoopVerificationOptions>;
using DoubleKey = rgbdi::DoubleKey<LoopVerificationOptions>;
using O = LoopVerificationOptions;

const std::vector<IntKey>& intKeys() {
  static const std::vector<IntKey> keys = {
      {"verify_max_hamming_bits", [](O& o) -> int& { return o.max_hamming_bits; }, 0, 2048},
      {"verify_min_matches", [](O& o) -> int& { return o.min_matches; }, 4, 100000},
      {"verify_pnp_iterations", [](O& o) -> int& { return o.pnp_iterations; }, 1, 1000000},
      {"verify_min_pnp_inliers", [](O& o) -> int& { return o.min_pnp_inliers; }, 4, 100000},
      {"verify_min_depth_inliers", [](O& o) -> int& { return o.min_depth_inliers; }, 3, 100000},
      {"verify_refine_rounds", [](O& o) -> int& { return o.refine_rounds; }, 0, 100},
      {"verify_freespace_min_samples", [](O& o) -> int& { return o.freespace_min_samples; }, 1,
       100000},
  };
  return keys;
}

const std::vector<DoubleKey>& doubleKeys() {
  static const std::vector<DoubleKey> keys = {
      {"verify_match_ratio", [](O& o) -> double& { return o.match_ratio; }, 0.01, 1.0},
      {"verify_pnp_threshold_px", [](O& o) -> double& { return o.pnp_threshold_px; }, 0.01, 100.0},
      {"verify_pnp_confidence", [](O& o) -> double& { return o.pnp_confidence; }, 0.5, 0.999999},
      {"verify_depth_tolerance_m", [](O& o) -> double& { return o.depth_tolerance_m; }, 0.0, 10.0},
      {"verify_depth_noise_coeff", [](O& o) -> double& { return o.depth_noise_coeff; }, 0.0, 1.0},
      {"verify_keypoint_sigma_px", [](O& o) -> double& { return o.keypoint_sigma_px; }, 0.01,
       100.0},
      {"verify_depth_tolerance_sigmas", [](O& o) -> double& { return o.depth_tolerance_sigmas; },
       0.0, 100.0},
      {"verify_min_depth_inlier_fraction",
       [](O& o) -> double& { return o.min_depth_inlier_fraction; }, 0.0, 1.0},
      {"verify_max_gravity_deg", [](O& o) -> double& { return o.max_gravity_deg; }, 0.0, 180.0},
      {"verify_max_yaw_deg", [](O& o) -> double& { return o.max_yaw_deg; }, 0.0, 180.0},
      {"verify_max_translation_m", [](O& o) -> double& { return o.max_translation_m; }, 0.0,
       1000.0},
      {"verify_drift_base_m", [](O& o) -> double& { return o.drift_base_m; }, 0.0, 1000.0},
      {"verify_drift_fraction", [](O& o) -> double& { return o.drift_fraction; }, 0.0, 10.0},
      {"verify_drift_base_deg", [](O& o) -> double& { return o.drift_base_deg; }, 0.0, 180.0},
      {"verify_drift_deg_per_m", [](O& o) -> double& { return o.drift_deg_per_m; }, 0.0, 180.0},
      {"verify_freespace_margin_m", [](O& o) -> double& { return o.freespace_margin_m; }, 0.0,
       10.0},
      {"verify_freespace_margin_sigmas", [](O& o) -> double& { return o.freespace_margin_sigmas; },
       0.0, 100.0},
      {"verify_freespace_max_conflict_fraction",
       [](O& o) -> double& { return o.freespace_max_conflict_fraction; }, 0.0, 1.0},
  };
  return keys;
}

[[noreturn]] void failKey(const std::string& key, const std::string& what) {
  throw ConfigError("LoopVerificationOptions [" + std::string(kSection) + "] " + key + ": " + what);
}

// PnP inliers are a subset of the matches and agreeing pairs a subset of the inliers: a gate
// above the one before it could never pass.
template <typename Fail>
void checkConsistency(const O& o, Fail&& fail) {
  if (o.min_pnp_inliers > o.min_matches)
    fail("verify_min_pnp_inliers", "must not exceed verify_min_matches");
  if (o.min_depth_inliers > o.min_pnp_inliers)
    fail("verify_min_depth_inliers", "must not exceed verify_min_pnp_inliers");
}

}  // namespace

void LoopVerificationOptions::validate() const {
  checkKeyRanges(*this, intKeys(), doubleKeys(), failKey);
  checkConsistency(*this,
                   [](const std::string& key, const std::string& what) { failKey(key, what); });
}

LoopVerificationOptions LoopVerificationOptions::load(IniReader& ini) {
  O o;
  loadKeys(ini, kSection, o, intKeys(), doubleKeys());
  o.cross_check = ini.getBool(kSection, "verify_cross_check", o.cross_check);
  o.freespace_for_loops =
      ini.getBool(kSection, "verify_freespace_for_loops", o.freespace_for_loops);
  checkConsistency(o, [&ini](const std::string& key, const std::string& what) {
    ini.fail(kSection, key, what);
  });
  return o;
}

}  // namespace rgbdi::loop
