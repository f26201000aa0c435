// The start from the wheels (rgbdi/estimator/wheel_start.h, doc/wheels.md "Start from the
// wheels"): known answers for a robot standing, cruising straight and turning at constant speed
// (gravity, velocity and gyroscope bias of the body at the frame), a learnt forward scale, and
// the checks that refuse a start from slipping wheels.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "rgbdi/estimator/ground_plane_gate.h"
#include "rgbdi/estimator/wheel_start.h"
#include "rgbdi/imu/imu_buffer.h"

namespace rgbdi::estimator {
namespace {

constexpr double kG = 9.81;

/// A robot on a flat floor: wheel frame at yaw psi(t) = w t, its origin on a circle of speed v
/// (straight when w = 0); the body (IMU) frame is T_body_wheel away.
struct Drive {
  double v = 0.5;  ///< [m/s] forward speed of the wheel frame
  double w = 0.4;  ///< [rad/s] yaw rate
  Eigen::Isometry3d T_body_wheel = Eigen::Isometry3d::Identity();
  Eigen::Vector3d bg = Eigen::Vector3d(0.004, -0.003, 0.006);  ///< true gyroscope bias
  /// [m/s^2] minus gravity in the drive's frame: (0, 0, g) on a level floor, tilted on a ramp.
  Eigen::Vector3d up = Eigen::Vector3d(0.0, 0.0, kG);

  Eigen::Matrix3d Rz(double t) const {
    return Eigen::AngleAxisd(w * t, Eigen::Vector3d::UnitZ()).matrix();
  }
  Eigen::Vector3d wheelPosition(double t) const {
    if (std::abs(w) < 1e-12) return Eigen::Vector3d(v * t, 0.0, 0.0);
    return Eigen::Vector3d(v / w * std::sin(w * t), v / w * (1.0 - std::cos(w * t)), 0.0);
  }
  Eigen::Matrix3d R_world_body(double t) const {
    return Rz(t) * T_body_wheel.rotation().transpose();
  }
  /// The body origin's offset from the wheel origin, in the wheel frame.
  Eigen::Vector3d q() const {
    return -(T_body_wheel.rotation().transpose() * T_body_wheel.translation());
  }
  Eigen::Vector3d bodyVelocityWorld(double t) const {
    const Eigen::Vector3d v_wheel = Rz(t) * Eigen::Vector3d(v, 0.0, 0.0);
    return v_wheel + w * (Rz(t) * Eigen::Vector3d(-q().y(), q().x(), 0.0));
  }
  Eigen::Vector3d bodyAccelerationWorld(double t) const {
    const Eigen::Vector3d a_wheel = Rz(t) * Eigen::Vector3d(0.0, v * w, 0.0);
    return a_wheel - w * w * (Rz(t) * Eigen::Vector3d(q().x(), q().y(), 0.0));
  }
  ImuSample imu(double t) const {
    ImuSample s;
    s.t = t;
    s.gyr = T_body_wheel.rotation() * Eigen::Vector3d(0.0, 0.0, w) + bg;
    s.acc = R_world_body(t).transpose() * (bodyAccelerationWorld(t) + up);
    return s;
  }
  /// The reading at t: the true wheel pose, distances divided by `distance_scale` (the
  /// odometry's radius error: true = scale x reported).
  WheelOdometrySample reading(double t, double distance_scale = 1.0) const {
    WheelOdometrySample r;
    r.t = t;
    const Eigen::Vector3d p = wheelPosition(t) / distance_scale;
    r.x_m = p.x();
    r.y_m = p.y();
    r.yaw_rad = std::remainder(w * t, 2.0 * M_PI);
    return r;
  }
};

struct Streams {
  imu::ImuBuffer imu;
  std::deque<WheelOdometrySample> readings;
};

/// 200 Hz IMU and 50 Hz readings over [0, t_end]; `edit` may change each reading.
Streams record(const Drive& d, double t_end, double distance_scale = 1.0,
               const std::function<void(WheelOdometrySample&)>& edit = {}) {
  Streams s;
  for (int k = 0; k * 0.005 <= t_end + 1e-9; ++k) s.imu.push(d.imu(k * 0.005));
  for (int k = 0; k * 0.02 <= t_end + 1e-9; ++k) {
    WheelOdometrySample r = d.reading(k * 0.02, distance_scale);
    if (edit) edit(r);
    s.readings.push_back(r);
  }
  return s;
}

Eigen::Isometry3d mountedWheels() {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = (Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(-0.2, Eigen::Vector3d::UnitX()))
                   .matrix();
  T.translation() = Eigen::Vector3d(0.1, -0.05, -0.2);
  return T;
}

/// The calibration in effect when nothing was learnt: the configured one with these scales.
WheelCalibration calib(const WheelOptions& opt, double scale_v = 1.0, double scale_w = 1.0) {
  WheelCalibration c = WheelCalibration::configured(opt);
  c.scale_v = scale_v;
  c.scale_w = scale_w;
  return c;
}

void expectTruth(const WheelStart& s, const Drive& d, double t, double tol_up, double tol_v) {
  ASSERT_EQ(s.failure, nullptr) << s.failure;
  const Eigen::Matrix3d R = d.R_world_body(t);
  EXPECT_LT((s.up_body - R.transpose() * Eigen::Vector3d(0, 0, kG)).norm(), tol_up);
  EXPECT_LT((s.v_body - R.transpose() * d.bodyVelocityWorld(t)).norm(), tol_v);
  EXPECT_LT((s.bg - d.bg).norm(), 1e-9);
}

TEST(WheelStart, TurningAtConstantSpeedGivesGravityVelocityAndBias) {
  Drive d;
  d.T_body_wheel = mountedWheels();
  const Streams s = record(d, 2.0);
  WheelOptions opt;
  opt.T_body_wheel = d.T_body_wheel;
  // The frame between two readings (the newest 10 ms old): the IMU carries the state to it.
  const double t = 1.99;
  const WheelStart start = solveWheelStart(s.readings, calib(opt), s.imu, t, kG, opt);
  // The span's mean velocity is the chord's (1 - (w h)^2 / 24 of the speed): 2e-5 m/s here.
  expectTruth(start, d, t, 1e-3, 1e-4);
  // Forward along the wheel frame's x: 0.5 m/s in the body frame through the extrinsic.
  EXPECT_NEAR(start.v_body.norm(), d.bodyVelocityWorld(t).norm(), 1e-4);
}

TEST(WheelStart, StraightAndStandingAreExact) {
  Drive straight;
  straight.w = 0.0;
  straight.T_body_wheel = mountedWheels();
  WheelOptions opt;
  opt.T_body_wheel = straight.T_body_wheel;
  const Streams s = record(straight, 1.0);
  expectTruth(solveWheelStart(s.readings, calib(opt), s.imu, 1.0, kG, opt), straight, 1.0, 1e-9,
              1e-9);
  Drive standing = straight;
  standing.v = 0.0;
  const Streams r = record(standing, 1.0);
  const WheelStart rest = solveWheelStart(r.readings, calib(opt), r.imu, 1.0, kG, opt);
  expectTruth(rest, standing, 1.0, 1e-9, 1e-9);
  EXPECT_LT(rest.v_body.norm(), 1e-12);
}

TEST(WheelStart, TheLearntForwardScaleGivesTheTrueSpeed) {
  Drive d;
  const Streams s = record(d, 1.0, 1.03);  // wheels 3 % large: they report 1/1.03 of the way
  const WheelOptions opt;
  expectTruth(solveWheelStart(s.readings, calib(opt, 1.03, 1.0), s.imu, 1.0, kG, opt), d, 1.0, 1e-3,
              1e-4);
  // With scale 1 the speed is 3 % short, and gravity tilts by the missing centripetal part.
  const WheelStart wrong = solveWheelStart(s.readings, calib(opt), s.imu, 1.0, kG, opt);
  ASSERT_EQ(wrong.failure, nullptr);
  EXPECT_NEAR(wrong.v_body.norm(), 0.5 / 1.03, 1e-4);
}

TEST(WheelStart, UsesTheCalibrationInEffectNotTheConfiguredOne) {
  // Wheels mounted as mountedWheels() and stamped 30 ms early on the robot clock; the
  // configuration says identity and 0 (what a run learnt online is in the calibration).
  Drive d;
  d.T_body_wheel = mountedWheels();
  const Streams s = record(d, 2.0, 1.0, [](WheelOdometrySample& r) { r.t -= 0.03; });
  const WheelOptions configured;
  WheelCalibration learnt = calib(configured);
  learnt.T_body_wheel = d.T_body_wheel;
  learnt.time_offset_s = 0.03;
  expectTruth(solveWheelStart(s.readings, learnt, s.imu, 1.95, kG, configured), d, 1.95, 1e-3,
              1e-4);
  const auto up = wheelInertialUp(s.readings, learnt, s.imu, 1.95, d.bg, kG, configured);
  ASSERT_TRUE(up.has_value());
  EXPECT_LT((*up - d.R_world_body(1.95).transpose() * d.up).norm(), 1e-3);
  // The configured one (identity) takes the wheels' yaw rate about the body's z, 0.36 rad from
  // the wheel frame's: 0.14 rad/s of the gyro rate unexplained.
  EXPECT_STREQ(solveWheelStart(s.readings, calib(configured), s.imu, 1.95, kG, configured).failure,
               "gyro rate and the wheels' yaw rate disagree");
}

TEST(WheelStart, RefusesWheelsWhoseYawRateTheGyroscopeDenies) {
  // The left wheel spins: the odometry turns 0.15 rad/s more than the body does.
  Drive d;
  const Streams s = record(d, 1.0, 1.0, [](WheelOdometrySample& r) { r.yaw_rad += 0.15 * r.t; });
  const WheelStart start =
      solveWheelStart(s.readings, calib(WheelOptions{}), s.imu, 1.0, kG, WheelOptions{});
  EXPECT_STREQ(start.failure, "gyro rate and the wheels' yaw rate disagree");
}

TEST(WheelStart, RefusesASpeedTheAccelerometerDenies) {
  // Straight at 0.5 m/s; from 0.7 s the wheels report 0.3 m/s more (both wheels spinning
  // without traction), while the IMU feels no acceleration: the window's first half (0.65 to
  // 0.8 s) says 2 m/s^2 forward, the second none. (A speed error growing steadily through the
  // window would tilt gravity unnoticed: 1 m/s^2 over the window, 0.1 rad.)
  Drive d;
  d.w = 0.0;
  const Streams s = record(d, 1.0, 1.0, [](WheelOdometrySample& r) {
    if (r.t > 0.7) r.x_m += 0.3 * (r.t - 0.7);
  });
  const WheelStart start =
      solveWheelStart(s.readings, calib(WheelOptions{}), s.imu, 1.0, kG, WheelOptions{});
  EXPECT_STREQ(start.failure, "gravity from the two halves of the window disagrees");
}

TEST(WheelStart, WaitsForReadingsAndImuCoveringTheWindow) {
  Drive d;
  const Streams s = record(d, 1.0);
  const WheelOptions opt;  // 0.4 s window
  EXPECT_STREQ(solveWheelStart(s.readings, calib(opt), s.imu, 0.3, kG, opt).failure,
               "wheel readings shorter than the window");
  EXPECT_STREQ(solveWheelStart({}, calib(opt), s.imu, 1.0, kG, opt).failure, "no wheel readings");
  // The frame 0.2 s after the newest reading: more than reading_lag_s (0.1 s).
  Streams late = record(d, 1.2);
  while (late.readings.back().t > 1.0) late.readings.pop_back();
  EXPECT_STREQ(solveWheelStart(late.readings, calib(opt), late.imu, 1.2, kG, opt).failure,
               "the wheel readings lag the frame");
}

TEST(WheelInertialUp, SeesTheRampThatTheWindowStatesMayNot) {
  // Straight up a 0.1 rad ramp (the drive's x axis climbs): gravity leans back in the drive's
  // frame. With the window's gyroscope bias the wheels and the IMU give "up" in the body frame.
  Drive d;
  d.w = 0.0;
  d.T_body_wheel = mountedWheels();
  d.up = kG * Eigen::Vector3d(-std::sin(0.1), 0.0, std::cos(0.1));
  const Streams s = record(d, 1.0);
  WheelOptions opt;
  opt.T_body_wheel = d.T_body_wheel;
  opt.ground_plane_sigma_m = 0.01;
  const auto up = wheelInertialUp(s.readings, calib(opt), s.imu, 1.0, d.bg, kG, opt);
  ASSERT_TRUE(up.has_value());
  EXPECT_LT((*up - d.R_world_body(1.0).transpose() * d.up).norm(), 1e-9);
  // The gate: the tilt alone is (sin 0.1 / 0.02)^2 = 24.9 > 11.3, off the plane, which ends.
  GroundPlanes plane;
  plane.current = 0.0;
  plane.known = {0.0};
  EXPECT_FALSE(judgeGroundContact(up, 0.0, &plane, opt).has_value());
  EXPECT_FALSE(plane.current.has_value());
  // Turning on the level floor, its "up" is the wheel frame's: on the plane (a new one, at
  // the frame's height when there is none).
  Drive level;
  level.T_body_wheel = mountedWheels();
  const Streams l = record(level, 1.0);
  const auto up_level = wheelInertialUp(l.readings, calib(opt), l.imu, 1.0, level.bg, kG, opt);
  ASSERT_TRUE(up_level.has_value());
  const Eigen::Vector3d n = opt.T_body_wheel.rotation() * Eigen::Vector3d::UnitZ();
  EXPECT_LT(n.cross(up_level->normalized()).norm(), 1e-4);
  EXPECT_DOUBLE_EQ(judgeGroundContact(up_level, 0.08, &plane, opt).value(), 0.08);
  EXPECT_DOUBLE_EQ(plane.current.value(), 0.08);
}

TEST(GroundContact, HeightAndTiltAgainstTheGate) {
  WheelOptions opt;  // tilt 0.02 rad, gate 11.3
  opt.ground_plane_sigma_m = 0.01;
  const std::optional<Eigen::Vector3d> upright = Eigen::Vector3d(0.0, 0.0, kG);
  GroundPlanes planes;
  // The first level frame starts the plane at its height.
  EXPECT_DOUBLE_EQ(judgeGroundContact(upright, 0.2, &planes, opt).value(), 0.2);
  // 3 cm above it: chi2 9, on; 4 cm: 16, off, and the plane ends.
  EXPECT_DOUBLE_EQ(judgeGroundContact(upright, 0.23, &planes, opt).value(), 0.2);
  EXPECT_FALSE(judgeGroundContact(upright, 0.24, &planes, opt).has_value());
  EXPECT_FALSE(planes.current.has_value());
  // Level at 0.24 m: 4 cm from the known plane (chi2 16): a new plane there.
  EXPECT_DOUBLE_EQ(judgeGroundContact(upright, 0.24, &planes, opt).value(), 0.24);
  // Tilted by 0.06 rad 2 cm above it: (sin 0.06 / 0.02)^2 + 4 = 12.98 > 11.3, off.
  const std::optional<Eigen::Vector3d> tilted =
      kG * Eigen::Vector3d(std::sin(0.06), 0.0, std::cos(0.06));
  EXPECT_FALSE(judgeGroundContact(tilted, 0.26, &planes, opt).has_value());
  // Level again at 0.215 m: the nearest known plane is 0.2 (chi2 2.25, passes): the floor
  // again, not a new plane; 0.235 m is nearer 0.24 (chi2 0.25): that one.
  EXPECT_DOUBLE_EQ(judgeGroundContact(upright, 0.215, &planes, opt).value(), 0.2);
  EXPECT_FALSE(judgeGroundContact(tilted, 0.26, &planes, opt).has_value());
  EXPECT_DOUBLE_EQ(judgeGroundContact(upright, 0.235, &planes, opt).value(), 0.24);
  EXPECT_EQ(planes.known, (std::vector<double>{0.2, 0.24}));
  // The same 0.06 rad tilt alone (8.98) starts a plane where none is near.
  planes = {};
  EXPECT_DOUBLE_EQ(judgeGroundContact(tilted, 0.02, &planes, opt).value(), 0.02);
  // Without the wheel-inertial "up" (readings missing, |g| off): off.
  EXPECT_FALSE(judgeGroundContact(std::nullopt, 0.02, &planes, opt).has_value());
  EXPECT_FALSE(planes.current.has_value());
  // No gate (0): every frame on the first plane.
  opt.ground_plane_gate_chi2 = 0.0;
  planes = {};
  EXPECT_DOUBLE_EQ(judgeGroundContact(std::nullopt, 0.5, &planes, opt).value(), 0.5);
  EXPECT_DOUBLE_EQ(judgeGroundContact(tilted, 0.9, &planes, opt).value(), 0.5);
}

}  // namespace
}  // namespace rgbdi::estimator
