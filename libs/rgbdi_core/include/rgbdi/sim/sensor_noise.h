// Sensor noise applied to ideal renderings (kept separate so tests can use ideal images).
//
// Randomness comes from the caller's std::mt19937_64, so a sequence is reproducible from one
// seed. Per-pixel Gaussian fields are drawn with cv::RNG seeded from that generator, which is
// fast and gives the same numbers on every platform (std::normal_distribution does not).
#pragma once

#include <opencv2/core.hpp>
#include <random>

#include "rgbdi/common/ini_reader.h"

namespace rgbdi::sim {

/// D435-like depth: sigma growing with z^2, millimetre quantisation, range gate, hole blobs.
struct DepthNoiseOptions {
  double sigma_coeff = 0.004;       ///< [1/m] sigma = coeff * z^2
  double min_m = 0.2;               ///< [m] measured depths below this read 0
  double max_m = 10.0;              ///< [m] measured depths above this read 0
  double hole_fraction = 0.015;     ///< [unitless] fraction of pixels inside hole blobs
  double hole_radius_min_px = 1.0;  ///< [px] blob semi-axes are uniform in [min, max]
  double hole_radius_max_px = 4.0;  ///< [px]

  /// Reads [sim] depth_sigma_coeff, depth_min_m, depth_max_m, depth_hole_fraction.
  static DepthNoiseOptions load(IniReader& ini);
};

/// Photometric noise of the colour image.
struct ColorNoiseOptions {
  double sigma = 2.0;  ///< [grey levels] per-pixel, per-channel Gaussian noise

  /// Reads [sim] photometric_noise_sigma.
  static ColorNoiseOptions load(IniReader& ini);
};

/// Ideal depth (CV_32FC1, metres, 0 = no hit) -> measured depth CV_16UC1 in millimetres
/// (0 = invalid). Throws std::invalid_argument on a wrong image type or inconsistent options.
cv::Mat applyDepthNoise(const cv::Mat& ideal_depth_m, const DepthNoiseOptions& options,
                        std::mt19937_64& rng);

/// The hole mask alone (CV_8UC1, 255 = hole): blobs drawn until exactly
/// round(hole_fraction * pixels) pixels are covered.
cv::Mat makeDepthHoleMask(cv::Size size, const DepthNoiseOptions& options, std::mt19937_64& rng);

/// Adds photometric noise to a CV_8UC3 image in place (saturating at 0 and 255).
void applyColorNoise(cv::Mat& rgb, const ColorNoiseOptions& options, std::mt19937_64& rng);

}  // namespace rgbdi::sim
