// The estimated state of the sliding window as its solve and its marginalisation see it: the
// frames and feature tracks, the marginalisation prior, the camera-IMU time offset, the prior
// on the first state that a start leaves, and the wheel odometry.
#pragma once

#include <Eigen/Core>
#include <memory>

#include "estimator/frame_window.h"
#include "estimator/window_wheels.h"
#include "rgbdi/estimator/marginalization.h"

namespace rgbdi::estimator {

/// What a start knows about the first state's speed and biases ([v, ba, bg]), held as a prior
/// until that state is marginalised (from then on it lives inside the marginalisation prior,
/// together with the prior on the time offset around its configured value).
struct StartPrior {
  bool active = false;
  Eigen::Matrix<double, 9, 1> mean = Eigen::Matrix<double, 9, 1>::Zero();
  Eigen::Matrix<double, 9, 1> sigma = Eigen::Matrix<double, 9, 1>::Ones();
};

struct WindowState {
  WindowState(const EstimatorOptions& opt, const ImuOptions& imu, double time_offset_s)
      : frames(opt, imu), time_offset{time_offset_s}, readout{0.0} {
    wheels.init(opt.wheel);
  }

  FrameWindow frames;
  std::shared_ptr<MarginalizationInfo> prior;  ///< null until the first marginalisation
  /// [s] t_imu = t_image + time offset: a parameter block of the solve and the prior (its
  /// address is kept in the prior, so the state is not copied or moved).
  double time_offset[1];
  /// [s] rolling-shutter readout time: a parameter block when it is estimated (address kept in
  /// the prior like the time offset's); else the configured constant.
  double readout[1];
  double readout_prior_mean_s = 0.0;  ///< [s] [camera] rolling_shutter_readout_s
  StartPrior start_prior;
  WindowWheels wheels;  ///< used when [wheel] enable (the scale blocks' addresses are kept too)

  WindowState(const WindowState&) = delete;
  WindowState& operator=(const WindowState&) = delete;
};

}  // namespace rgbdi::estimator
