// The wheel odometry of the sliding window (doc/wheels.md "Fusion"): the readings back to the
// oldest frame, the odometry's two scale factors (parameter blocks of the solve and of the
// marginalisation prior, kept across resets: they are a calibration) and what became of the
// intervals that left the window.
#pragma once

#include <ceres/cost_function.h>

#include <Eigen/Geometry>
#include <deque>
#include <memory>
#include <optional>
#include <vector>

#include "estimator/window_slot.h"
#include "rgbdi/common/wheel_odometry.h"
#include "rgbdi/estimator/ground_plane_gate.h"
#include "rgbdi/estimator/wheel_options.h"
#include "rgbdi/estimator/wheel_preintegration.h"

namespace rgbdi::estimator {

/// A wheel factor and the parameter blocks it reads, in its order.
struct WheelTerm {
  std::unique_ptr<ceres::CostFunction> cost;
  std::vector<double*> blocks;
};

/// What the window made of an interval's wheel odometry.
enum class WheelVerdict { Consistent, Slip, Stuck, Lifted };

struct WindowWheels {
  std::deque<WheelOdometrySample> readings;  ///< time order, robot clock
  double scale_v[1] = {1.0};                 ///< forward-speed scale (true = scale * reported)
  double scale_w[1] = {1.0};                 ///< yaw-rate scale
  /// The scales' prior (mean, ScalarPrior) is in the problem until the marginalisation prior
  /// carries it; pending again whenever that prior is dropped (reset, failed marginalisation).
  bool scale_prior_pending = true;
  double prior_mean_v = 1.0, prior_mean_w = 1.0;
  /// Online calibration ([wheel] estimate_extrinsic_yaw, estimate_time_offset): parameter blocks
  /// of the solve and the marginalisation prior like the scales; constants when not estimated.
  double extrinsic_yaw[1] = {0.0};  ///< [rad] correction about the wheel frame's z
  double time_offset[1] = {0.0};    ///< [s] t_imu = t_wheel + this (init(): the configured one)
  bool calib_prior_pending = true;  ///< as scale_prior_pending, for the two above
  double prior_mean_yaw = 0.0, prior_mean_td = 0.0;
  int intervals_used = 0;  ///< intervals marginalised with their wheel factor
  int intervals_gap = 0;   ///< intervals marginalised without readings covering them
  /// Intervals marginalised without their factor because it disagreed with the window's states.
  int intervals_slip = 0, intervals_stuck = 0, intervals_lifted = 0;
  int factors_gated = 0;  ///< factors left out of solves (summed over updates)
  /// Runs of consecutive left-out intervals of one kind, [t_start, t_end] on the IMU clock.
  struct Episode {
    double t_start = 0.0, t_end = 0.0;
    WheelVerdict verdict = WheelVerdict::Slip;
  };
  std::vector<Episode> episodes;
  /// The floor's planes met (heights of the wheel frame) and the present one (ground plane).
  GroundPlanes ground;
  int ground_plane_used = 0, ground_plane_gated = 0;  ///< frame constraints (summed over updates)

  /// Starts from the configuration (the time offset and its prior mean).
  void init(const WheelOptions& opt);
  /// The wheel frame in the body frame: the configured one, turned by the learnt yaw when it is
  /// estimated (exactly the configured one otherwise).
  Eigen::Isometry3d T_body_wheel(const WheelOptions& opt) const;
  /// The odometry's calibration in effect (the scales, T_body_wheel(opt), the time offset).
  WheelCalibration calibration(const WheelOptions& opt) const;
  /// The factor of the interval `pre` between the poses `pose_a` and `pose_b`, for the solve and
  /// the marginalisation alike: with the extrinsic yaw and time offset blocks when [wheel]
  /// calibrates online (WheelCalibrationFactor), else on the scales alone (WheelFactor).
  WheelTerm factor(const WheelPreintegration& pre, double* pose_a, double* pose_b,
                   const WheelOptions& opt);
  /// Clamps the calibration to its bounds (after a solve).
  void clampCalibration(const WheelOptions& opt);
  /// Appends a reading (older than the newest one or not finite: ignored).
  void add(const WheelOdometrySample& w);
  /// The readings between window frames a and b pre-integrated (in 3-D with b's gyroscope
  /// samples when [wheel] direction_from_gyro asks for it); nullopt: not covered.
  std::optional<WheelPreintegration> interval(const WindowSlot& a, const WindowSlot& b,
                                              const WheelOptions& opt) const;
  /// The interval [t_a, t_b]'s factor at the window's states of its two frames (poses [p, q])
  /// and the present scales: consistent (squared normalised error <= gate_chi2, or no gate), or
  /// why not: stuck (the wheels report less than fault_motion_ratio of the window's motion, or
  /// one wheel's ticks stood while the other's turned), lifted (the window moved less than that
  /// fraction of the wheels' motion), slip (otherwise).
  WheelVerdict check(const WheelPreintegration& pre, const double* pose_a, const double* pose_b,
                     double t_a, double t_b, const WheelOptions& opt) const;
  /// The encoder ticks of each wheel over [t_a, t_b] (readings around it); false without ticks.
  bool tickIncrements(double t_a, double t_b, std::int64_t* left, std::int64_t* right) const;
  /// Counts the verdict of the interval [t_a, t_b] that leaves the window (a left-out one joins
  /// or starts an episode).
  void count(WheelVerdict v, double t_a, double t_b);
  /// Drops the readings that no interval starting at IMU-clock time t or later needs.
  void trimBefore(double t, const WheelOptions& opt);
  /// The marginalisation prior was dropped: the priors of the scales and of the calibration
  /// become pending again, around their present values (nothing changes for a pending one).
  void priorDropped();
};

}  // namespace rgbdi::estimator
