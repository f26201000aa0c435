// The wheel odometry between two window frames, pre-integrated into a planar relative motion of
// the wheel frame, with its noise and its dependence on the two odometry scale factors.
//
// The readings' cumulative poses (x, y, yaw in the odometry frame) are cut at the frames' times
// (IMU clock: reading stamp + [wheel] time_offset_s; the pose there interpolated linearly between
// the two readings around it) and split into increments: increment k moves by d_k (in the wheel
// frame at its start) and turns by a_k. With a forward-speed scale s_v and a yaw-rate scale s_w
// (true = scale * reported), the motion from frame a to frame b in the wheel frame at a is
//   dp(s) = s_v sum_k R(s_w phi_k) d_k,  dyaw(s) = s_w phi_n,  phi_k = a_0 + ... + a_(k-1),
// evaluated exactly for any s (a few dozen increments per interval), with d dp / d s_w.
// Noise (diagonal, in the wheel frame at a): per metre travelled along (sigma_forward), across
// (sigma_lateral) and off the ground plane (sigma_vertical), per radian turned and per metre for
// the yaw, per metre for roll and pitch, each with a floor for a standing robot.
//
// 3-D (direction from the gyroscope): on a ramp, or across a long blind interval, the wheel
// frame does not stay in the plane it had at a. Given the gyroscope's rates, each increment is
// turned by R_k, the wheel frame at its start in the wheel frame at a (integrated from the
// rates, wheel yaw unused): dp(s) = s_v sum_k R_k [d_k; 0], dyaw = s_w phi_n. The rotation is
// then the IMU factor's business: the rotation rows get no weight (the wheels' yaw adds nothing
// to the gyroscope over seconds, and is what slips on skid-steered tracks); the translation keeps
// the planar noise model (the vertical its loose sigma: the gyroscope's tilt drifts with its
// bias error).
#pragma once

#include <Eigen/Core>
#include <deque>
#include <optional>
#include <vector>

#include "rgbdi/common/types.h"
#include "rgbdi/common/wheel_odometry.h"

namespace rgbdi::estimator {

/// The noise model of the wheel odometry ([wheel] keys, see share/config.ini).
struct WheelNoise {
  double forward_sigma_per_sqrt_m = 0.02;   ///< [m / sqrt(m)]
  double lateral_sigma_per_sqrt_m = 0.02;   ///< [m / sqrt(m)]
  double vertical_sigma_per_sqrt_m = 0.05;  ///< [m / sqrt(m)]
  double yaw_sigma_per_sqrt_rad = 0.05;     ///< [rad / sqrt(rad)]
  double yaw_sigma_per_sqrt_m = 0.01;       ///< [rad / sqrt(m)]
  double tilt_sigma_per_sqrt_m = 0.05;      ///< [rad / sqrt(m)] roll and pitch
  double min_sigma_m = 0.002;               ///< [m] floor of every translation sigma
  double min_sigma_rad = 0.002;             ///< [rad] floor of every rotation sigma
};

/// The wheel frame's velocity where an interval is cut (the slope of the interpolation there):
/// forward/lateral [m/s] in the wheel frame at that time, and yaw rate [rad/s].
struct WheelCutRates {
  Eigen::Vector2d v_start = Eigen::Vector2d::Zero(), v_end = Eigen::Vector2d::Zero();
  double w_start = 0.0, w_end = 0.0;
};

/// The motion with the online calibration (WheelCalibrationFactor): translation and yaw of the
/// wheel frame at b in the one at a, and their derivatives.
struct CalibratedWheelMotion {
  Eigen::Vector3d dp, ddp_dsv, ddp_dsw, ddp_dyaw, ddp_dtd;
  double dyaw = 0.0, ddyaw_dsw = 0.0, ddyaw_dtd = 0.0;
};

/// The gyroscope for 3-D pre-integration: its samples over the interval (time order; the rate of
/// a sample is held until the next one, the first one's before it), its bias and the wheel frame's
/// rotation in the body frame.
struct WheelGyro {
  const std::vector<ImuSample>* samples = nullptr;
  Eigen::Vector3d bias = Eigen::Vector3d::Zero();  ///< [rad/s]
  Eigen::Matrix3d R_body_wheel = Eigen::Matrix3d::Identity();
};

class WheelPreintegration {
 public:
  /// The interval [t_a, t_b] (IMU clock) from `readings` (time order; stamps + time_offset_s on
  /// the IMU clock). nullopt when the readings do not cover it (no reading at or before t_a, or
  /// none at or after t_b - max_extrapolation_s): a stream gap. Beyond the newest reading the
  /// rate of its increment goes on (readings come at their own rate: a frame's newest one is
  /// up to a period old).
  static std::optional<WheelPreintegration> between(const std::deque<WheelOdometrySample>& readings,
                                                    double t_a, double t_b, double time_offset_s,
                                                    const WheelNoise& noise,
                                                    double max_extrapolation_s = 0.0,
                                                    const WheelGyro* gyro = nullptr);
  /// From increments directly (tests): d_k [m] and a_k [rad]; with `R` (one per increment:
  /// the wheel frame at its start in the wheel frame at a) the 3-D pre-integration.
  WheelPreintegration(std::vector<Eigen::Vector2d> d, std::vector<double> a,
                      const WheelNoise& noise, std::vector<Eigen::Matrix3d> R = {});

  /// The motion at scales (s_v, s_w): translation (x, y, z; z = 0 when planar) and yaw;
  /// d dp / d s_w if asked (zero in 3-D: the directions come from the gyroscope).
  void motion(double s_v, double s_w, Eigen::Vector3d* dp, double* dyaw,
              Eigen::Vector3d* ddp_dsw = nullptr) const;
  /// The motion at scales (s_v, s_w), with a correction `yaw` [rad] about the wheel frame's z to
  /// the extrinsic the gyroscope's directions were computed with (3-D only: the planar motion
  /// does not depend on it) and the wheel time offset changed by `dtd` [s] since the cut
  /// (planar only, to first order: the interval's wheel times move by -dtd, so the start gains
  /// the motion at the start's rate and the end loses the motion at the end's rate, as VINS
  /// corrects the camera's features by their velocity times the change of its td). 3-D intervals
  /// do not depend on dtd: they follow the estimate only when they are cut again.
  CalibratedWheelMotion calibratedMotion(double s_v, double s_w, double yaw, double dtd) const;
  /// The rates at the cut times (zero when made from increments; set by between()).
  const WheelCutRates& cutRates() const { return rates_; }
  void setCutRates(const WheelCutRates& r) { rates_ = r; }
  /// [s] the wheel time offset the readings were cut with.
  double cutTimeOffset() const { return cut_time_offset_s_; }
  /// The planar part of motion(): translation (x, y) and yaw.
  void delta(double s_v, double s_w, Eigen::Vector2d* dp, double* dyaw,
             Eigen::Vector2d* ddp_dsw = nullptr) const;
  /// True when the increments' directions come from the gyroscope.
  bool threeD() const { return !R_.empty(); }
  /// [rad] the reported yaw change phi_n (= d dyaw / d s_w).
  double reportedYaw() const { return phi_end_; }
  /// [m] distance travelled as reported (sum of |d_k|).
  double distance() const { return distance_; }
  /// Square root of the information (diagonal) of [dp (3), rotation (3)].
  const Eigen::Matrix<double, 6, 1>& sqrtInformation() const { return sqrt_info_; }
  std::size_t increments() const { return d_.size(); }

 private:
  std::vector<Eigen::Vector2d> d_;
  std::vector<Eigen::Matrix3d> R_;  ///< 3-D: wheel frame at increment k in the one at a
  std::vector<double> phi_;         ///< reported yaw at the start of each increment
  double phi_end_ = 0.0;
  double distance_ = 0.0;
  Eigen::Matrix<double, 6, 1> sqrt_info_;
  WheelCutRates rates_;
  double cut_time_offset_s_ = 0.0;
};

}  // namespace rgbdi::estimator
