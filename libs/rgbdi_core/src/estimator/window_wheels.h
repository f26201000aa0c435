// The wheel odometry of the sliding window (doc/wheels.md "Fusion"): the readings back to the
// oldest frame, the odometry's two scale factors (parameter blocks of the solve and of the
// marginalisation prior, kept across resets: they are a calibration) and what became of the
// intervals that left the window.
#pragma once

#include <deque>
#include <optional>

#include "rgbdi/common/wheel_odometry.h"
#include "rgbdi/estimator/wheel_options.h"
#include "rgbdi/estimator/wheel_preintegration.h"

namespace rgbdi::estimator {

struct WindowWheels {
  std::deque<WheelOdometrySample> readings;  ///< time order, robot clock
  double scale_v[1] = {1.0};                 ///< forward-speed scale (true = scale * reported)
  double scale_w[1] = {1.0};                 ///< yaw-rate scale
  /// The scales' prior (mean, ScalarPrior) is in the problem until the marginalisation prior
  /// carries it; pending again whenever that prior is dropped (reset, failed marginalisation).
  bool scale_prior_pending = true;
  double prior_mean_v = 1.0, prior_mean_w = 1.0;
  int intervals_used = 0;  ///< intervals marginalised with their wheel factor
  int intervals_gap = 0;   ///< intervals marginalised without readings covering them

  /// Appends a reading (older than the newest one or not finite: ignored).
  void add(const WheelOdometrySample& w);
  /// The readings between IMU-clock times t_a and t_b pre-integrated; nullopt: not covered.
  std::optional<WheelPreintegration> interval(double t_a, double t_b,
                                              const WheelOptions& opt) const;
  /// Drops the readings that no interval starting at IMU-clock time t or later needs.
  void trimBefore(double t, const WheelOptions& opt);
  /// The marginalisation prior was dropped: the scales' prior becomes pending again, around
  /// their present values (nothing changes when it is pending already).
  void priorDropped();
};

}  // namespace rgbdi::estimator
