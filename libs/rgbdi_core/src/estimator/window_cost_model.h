// The constants the window's factors are made of. The solve (window_optimisation.h) and the
// marginalisation (window_marginalisation.h) build their factors from the same model: the prior
// must linearise the cost that was minimised.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "rgbdi/common/sensor_options.h"
#include "rgbdi/estimator/estimator_options.h"
#include "rgbdi/estimator/feature_manager.h"

namespace rgbdi::estimator {

struct WindowCostModel {
  WindowCostModel(const EstimatorOptions& opt, const ImuOptions& imu, const ExtrinsicOptions& ext)
      : T_body_cam(ext.T_body_cam),
        reprojection_sqrt_info(EstimatorOptions::kVirtualFocalPx / opt.reprojection_sigma_px),
        cauchy_loss_sigma(opt.cauchy_loss_sigma),
        g_world(0, 0, -imu.gravity_m_s2),
        estimate_time_offset(opt.estimate_time_offset),
        time_offset_prior_mean_s(ext.time_offset_s),
        time_offset_prior_sigma_s(opt.time_offset_prior_sigma_s),
        estimate_readout(opt.estimate_rolling_shutter_readout),
        readout_prior_sigma_s(opt.rolling_shutter_readout_prior_sigma_s),
        readout_max_s(opt.rolling_shutter_readout_max_s),
        hold_verified_depth_constant(opt.verified_depth == "constant"),
        depth_noise_coeff(opt.depth_noise_coeff),
        wheel(opt.wheel) {}

  /// Sigma of the prior of a verified inverse depth [1/m]: depth sigma = c z^2 means
  /// inverse-depth sigma = c, averaged over the independent observations that agreed.
  double depthPriorSigma(const FeatureTrack& f) const {
    return depth_noise_coeff / std::sqrt(std::max(1, f.verified_observations));
  }

  Eigen::Isometry3d T_body_cam;
  double reprojection_sqrt_info;     ///< [1/normalised-plane unit] (virtual focal / pixel sigma)
  double cauchy_loss_sigma;          ///< [unitless] Cauchy scale of the reprojections, in sigmas
  Eigen::Vector3d g_world;           ///< [m/s^2] gravity in the world frame (along -z)
  bool estimate_time_offset;         ///< false: the time offset is a constant
  double time_offset_prior_mean_s;   ///< [s] the configured offset
  double time_offset_prior_sigma_s;  ///< [s]
  /// false: the rolling-shutter readout is the configured constant, applied to each observation
  /// once at window entry (ReprojectionFactor); true: a parameter of the reprojections
  /// (RollingShutterReprojectionFactor), with a prior around the configured value
  /// (WindowState::readout_prior_mean_s)
  bool estimate_readout;
  double readout_prior_sigma_s;  ///< [s]
  double readout_max_s;          ///< [s] the estimate is kept within [0, this]
  /// verified_depth = constant: a verified inverse depth is no variable of the solve nor of the
  /// marginalisation (else it is free, with a prior from the verified mean).
  bool hold_verified_depth_constant;
  double depth_noise_coeff;  ///< [1/m] inverse-depth sigma of one verified observation
  WheelOptions wheel;        ///< the wheel factors' extrinsic, noise, time offset, scales
};

}  // namespace rgbdi::estimator
