#include "rgbdi/frontend/frontend_options.h"

#include <opencv2/core/utility.hpp>
#include <sstream>
#include <string>

namespace rgbdi::frontend {
namespace {

const char* const kSection = "frontend";

// One table of keys and accepted ranges serves both load() and validate(), so options built in
// code are held to the same limits as options read from a file.
struct IntKey {
  const char* key;
  int FrontendOptions::*field;
  int min, max;
};
struct DoubleKey {
  const char* key;
  double FrontendOptions::*field;
  double min, max;
};

const IntKey kIntKeys[] = {
    {"max_features", &FrontendOptions::max_features, 1, 5000},
    {"detect_min_missing", &FrontendOptions::detect_min_missing, 1, 5000},
    {"shi_tomasi_block_size", &FrontendOptions::shi_tomasi_block_size, 3, 31},
    {"border_px", &FrontendOptions::border_px, 0, 100},
    {"klt_window_px", &FrontendOptions::klt_window_px, 5, 101},
    {"klt_pyramid_levels", &FrontendOptions::klt_pyramid_levels, 0, 8},
    {"klt_max_iterations", &FrontendOptions::klt_max_iterations, 1, 1000},
    {"depth_neighbourhood_px", &FrontendOptions::depth_neighbourhood_px, 0, 20},
    {"opencv_threads", &FrontendOptions::opencv_threads, 0, 256},
    {"occlusion_window_px", &FrontendOptions::occlusion_window_px, 0, 50},
    {"occlusion_sample_step_px", &FrontendOptions::occlusion_sample_step_px, 1, 20},
};

const DoubleKey kDoubleKeys[] = {
    {"min_distance_px", &FrontendOptions::min_distance_px, 1.0, 500.0},
    {"shi_tomasi_quality", &FrontendOptions::shi_tomasi_quality, 1e-5, 1.0},
    {"min_gradient_grey_per_px", &FrontendOptions::min_gradient_grey_per_px, 0.0, 255.0},
    {"clahe_clip_limit", &FrontendOptions::clahe_clip_limit, 0.0, 100.0},
    {"klt_epsilon_px", &FrontendOptions::klt_epsilon_px, 1e-6, 1.0},
    {"klt_max_forward_backward_px", &FrontendOptions::klt_max_forward_backward_px, 0.01, 20.0},
    {"ransac_threshold_px", &FrontendOptions::ransac_threshold_px, 0.05, 20.0},
    {"ransac_confidence", &FrontendOptions::ransac_confidence, 0.5, 0.99999},
    {"depth_min_m", &FrontendOptions::depth_min_m, 0.0, 100.0},
    {"depth_max_m", &FrontendOptions::depth_max_m, 0.01, 1000.0},
    {"depth_max_relative_spread", &FrontendOptions::depth_max_relative_spread, 0.0, 1.0},
    {"depth_noise_coeff", &FrontendOptions::depth_noise_coeff, 0.0, 1.0},
    {"depth_max_noise_sigmas", &FrontendOptions::depth_max_noise_sigmas, 0.0, 100.0},
    {"registration_fill_max_relative_diff", &FrontendOptions::registration_fill_max_relative_diff,
     0.0, 1.0},
    {"occlusion_max_residual_sigmas", &FrontendOptions::occlusion_max_residual_sigmas, 0.1, 1000.0},
    {"occlusion_min_valid_fraction", &FrontendOptions::occlusion_min_valid_fraction, 0.0, 1.0},
};

/// Rules between keys, shared by validate() and load(): `fail(key, what)` does not return.
template <typename Fail>
void checkConsistency(const FrontendOptions& o, Fail&& fail) {
  if (o.depth_min_m >= o.depth_max_m) fail("depth_min_m", "must be smaller than depth_max_m");
  if (o.detect_min_missing > o.max_features)
    fail("detect_min_missing", "must not exceed max_features (no image would ever detect)");
  if (o.occlusion_window_px > 0 && !(o.depth_noise_coeff > 0.0))
    fail("depth_noise_coeff",
         "must be positive while occlusion_window_px is on (it scales the occlusion test)");
}

[[noreturn]] void failKey(const std::string& key, const std::string& what) {
  throw ConfigError("FrontendOptions [" + std::string(kSection) + "] " + key + ": " + what);
}

}  // namespace

void FrontendOptions::validate() const {
  for (const IntKey& k : kIntKeys) {
    const int v = this->*k.field;
    if (v < k.min || v > k.max) {
      std::ostringstream os;
      os << "value " << v << " outside [" << k.min << ", " << k.max << "]";
      failKey(k.key, os.str());
    }
  }
  for (const DoubleKey& k : kDoubleKeys) {
    const double v = this->*k.field;
    if (!(v >= k.min && v <= k.max)) {  // also rejects NaN
      std::ostringstream os;
      os << "value " << v << " outside [" << k.min << ", " << k.max << "]";
      failKey(k.key, os.str());
    }
  }
  checkConsistency(*this, failKey);
}

FrontendOptions FrontendOptions::load(IniReader& ini) {
  FrontendOptions o;
  for (const IntKey& k : kIntKeys)
    o.*k.field = ini.getInt(kSection, k.key, o.*k.field, k.min, k.max);
  for (const DoubleKey& k : kDoubleKeys)
    o.*k.field = ini.getDouble(kSection, k.key, o.*k.field, k.min, k.max);
  o.klt_predict_rotation = ini.getBool(kSection, "klt_predict_rotation", o.klt_predict_rotation);
  o.klt_predict_translation =
      ini.getBool(kSection, "klt_predict_translation", o.klt_predict_translation);
  o.klt_predict_every_feature =
      ini.getBool(kSection, "klt_predict_every_feature", o.klt_predict_every_feature);
  checkConsistency(o, [&ini](const std::string& key, const std::string& what) {
    ini.fail(kSection, key, what);
  });
  return o;
}

void applyOpenCvThreads(const FrontendOptions& options) {
  if (options.opencv_threads > 0 && cv::getNumThreads() != options.opencv_threads)
    cv::setNumThreads(options.opencv_threads);
}

}  // namespace rgbdi::frontend
