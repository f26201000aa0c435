// Wheel pre-integration and the wheel factor: known answers (straight line, circle, scale
// factors, time offset, yaw wrap, gaps), zero residual at the truth with a wheel frame off the
// body origin, and analytic vs numeric Jacobians of every block.
#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include <random>

#include "factor_jacobians.h"
#include "rgbdi/common/so3.h"
#include "rgbdi/estimator/estimator_options.h"
#include "rgbdi/estimator/pose_manifold.h"
#include "rgbdi/estimator/wheel_factor.h"
#include "rgbdi/estimator/wheel_preintegration.h"
#include "testing/fixtures.h"

namespace rgbdi::estimator {
namespace {

using test::analyticJacobian;
using test::numericJacobian;
using test::Params;
using test::poseBlock;

/// Readings of a robot driving a circle of radius rho at speed v (rho = 0: straight along x),
/// from t0 at rate hz for n readings; its odometry frame starts at heading yaw0.
std::deque<WheelOdometrySample> circleReadings(double v, double rho, double t0, double hz, int n,
                                               double yaw0 = 0.0) {
  std::deque<WheelOdometrySample> r;
  for (int k = 0; k < n; ++k) {
    WheelOdometrySample w;
    w.t = t0 + k / hz;
    const double s = v * k / hz;
    const double a = rho == 0.0 ? 0.0 : s / rho;
    const Eigen::Vector2d local = rho == 0.0
                                      ? Eigen::Vector2d(s, 0.0)
                                      : Eigen::Vector2d(rho * std::sin(a), rho * (1 - std::cos(a)));
    const Eigen::Vector2d p = Eigen::Rotation2Dd(yaw0) * local;
    w.x_m = p.x();
    w.y_m = p.y();
    w.yaw_rad = std::remainder(yaw0 + a, 2.0 * M_PI);
    r.push_back(w);
  }
  return r;
}

TEST(WheelPreintegration, StraightLineAndScaleFactors) {
  const WheelNoise noise;
  const auto readings = circleReadings(0.5, 0.0, 10.0, 50.0, 101);  // 2 s, 1 m
  const auto pre = WheelPreintegration::between(readings, 10.3, 11.5, 0.0, noise);
  ASSERT_TRUE(pre.has_value());
  Eigen::Vector2d dp;
  double dyaw = 1.0;
  pre->delta(1.0, 1.0, &dp, &dyaw);
  EXPECT_NEAR(dp.x(), 0.6, 1e-12);
  EXPECT_NEAR(dp.y(), 0.0, 1e-12);
  EXPECT_EQ(dyaw, 0.0);
  EXPECT_NEAR(pre->distance(), 0.6, 1e-12);
  pre->delta(1.03, 0.9, &dp, &dyaw);
  EXPECT_NEAR(dp.x(), 0.618, 1e-12);
  // Noise: 0.02 m per sqrt(m) along and across, 0.05 off the plane, floors on the rotation.
  EXPECT_NEAR(pre->sqrtInformation()[0], 1.0 / (0.02 * std::sqrt(0.6)), 1e-9);
  EXPECT_NEAR(pre->sqrtInformation()[2], 1.0 / (0.05 * std::sqrt(0.6)), 1e-9);
  EXPECT_NEAR(pre->sqrtInformation()[5], 1.0 / (0.01 * std::sqrt(0.6)), 1e-9);
  // A time offset moves the cut: the readings' clock is 0.1 s behind the IMU's.
  const auto shifted = WheelPreintegration::between(readings, 10.4, 11.6, 0.1, noise);
  ASSERT_TRUE(shifted.has_value());
  shifted->delta(1.0, 1.0, &dp, &dyaw);
  EXPECT_NEAR(dp.x(), 0.6, 1e-12);
}

TEST(WheelPreintegration, CircleAcrossTheYawWrapGivesTheChord) {
  const WheelNoise noise;
  // Heading starts at 3 rad: the reported yaw wraps from +pi to -pi on the way.
  const auto readings = circleReadings(0.4, 2.0, 5.0, 50.0, 251, 3.0);
  const auto pre = WheelPreintegration::between(readings, 5.11, 9.97, 0.0, noise);
  ASSERT_TRUE(pre.has_value());
  Eigen::Vector2d dp;
  double dyaw = 0.0;
  pre->delta(1.0, 1.0, &dp, &dyaw);
  const double angle = 0.2 * (9.97 - 5.11);
  EXPECT_NEAR(dyaw, angle, 1e-12);
  // The interpolated ends lie on the chords between readings: within (v dt)^2 / (8 rho).
  const double chord_error = std::pow(0.4 / 50.0, 2) / 16.0;
  EXPECT_NEAR(dp.x(), 2.0 * std::sin(angle), 4 * chord_error);
  EXPECT_NEAR(dp.y(), 2.0 * (1.0 - std::cos(angle)), 4 * chord_error);
}

TEST(WheelPreintegration, YawScaleDerivativeMatchesNumeric) {
  const auto pre = WheelPreintegration::between(circleReadings(0.4, 1.5, 0.0, 20.0, 60), 0.2, 2.7,
                                                0.0, WheelNoise());
  ASSERT_TRUE(pre.has_value());
  Eigen::Vector2d dp, plus, minus, analytic;
  double dyaw = 0.0;
  pre->delta(1.1, 0.95, &dp, &dyaw, &analytic);
  EXPECT_NEAR(dyaw, 0.95 * pre->reportedYaw(), 1e-15);
  const double h = 1e-6;
  pre->delta(1.1, 0.95 + h, &plus, nullptr);
  pre->delta(1.1, 0.95 - h, &minus, nullptr);
  EXPECT_LT((analytic - (plus - minus) / (2 * h)).norm(), 1e-8);
}

TEST(WheelPreintegration, TheNewestIncrementGoesOnUpToTheExtrapolationLimit) {
  const auto readings = circleReadings(0.5, 0.0, 10.0, 50.0, 51);  // 10.0 .. 11.0, 0.01 m each
  EXPECT_FALSE(WheelPreintegration::between(readings, 10.5, 11.05, 0.0, WheelNoise(), 0.04));
  const auto pre = WheelPreintegration::between(readings, 10.5, 11.03, 0.0, WheelNoise(), 0.04);
  ASSERT_TRUE(pre.has_value());
  Eigen::Vector2d dp;
  pre->delta(1.0, 1.0, &dp, nullptr);
  EXPECT_NEAR(dp.x(), 0.265, 1e-12);
  // Both ends beyond the newest reading: only the extrapolated part.
  const auto beyond = WheelPreintegration::between(readings, 11.01, 11.03, 0.0, WheelNoise(), 0.04);
  ASSERT_TRUE(beyond.has_value());
  beyond->delta(1.0, 1.0, &dp, nullptr);
  EXPECT_NEAR(dp.x(), 0.01, 1e-12);
}

TEST(WheelPreintegration, IntervalNotCoveredIsAGap) {
  const auto readings = circleReadings(0.5, 0.0, 10.0, 50.0, 51);  // 10.0 .. 11.0
  EXPECT_FALSE(WheelPreintegration::between(readings, 9.99, 10.5, 0.0, WheelNoise()));
  EXPECT_FALSE(WheelPreintegration::between(readings, 10.5, 11.01, 0.0, WheelNoise()));
  EXPECT_FALSE(WheelPreintegration::between({}, 10.5, 10.6, 0.0, WheelNoise()));
  EXPECT_TRUE(WheelPreintegration::between(readings, 10.0, 11.0, 0.0, WheelNoise()));
}

TEST(WheelFactor, ZeroAtTheTruthAndJacobiansMatchNumeric) {
  // A circle of radius 2 at 0.4 m/s; the body is 0.2 m above and 0.1 m behind the wheel frame,
  // rotated by a small yaw about it; the world frame is tilted (a ramp).
  Eigen::Isometry3d T_body_wheel = Eigen::Isometry3d::Identity();
  T_body_wheel.linear() = expSO3(Eigen::Vector3d(0.0, 0.0, 0.05));
  T_body_wheel.translation() = Eigen::Vector3d(0.1, 0.0, -0.2);
  const Eigen::Isometry3d T_world_odo =
      Eigen::Translation3d(1.0, -2.0, 0.5) *
      Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 0).normalized());
  const auto readings = circleReadings(0.4, 2.0, 0.0, 50.0, 101);
  const double ta = 0.3, tb = 1.7;
  const auto pre = WheelPreintegration::between(readings, ta, tb, 0.0, WheelNoise());
  ASSERT_TRUE(pre.has_value());
  const auto wheelPose = [&](double t) {
    const double a = 0.4 * t / 2.0;
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()).matrix();
    T.translation() = Eigen::Vector3d(2.0 * std::sin(a), 2.0 * (1 - std::cos(a)), 0.0);
    return T_world_odo * T;
  };
  const WheelFactor f(*pre, T_body_wheel);
  Params params = {poseBlock(wheelPose(ta) * T_body_wheel.inverse()),
                   poseBlock(wheelPose(tb) * T_body_wheel.inverse()),
                   {1.0},
                   {1.0}};
  EXPECT_LT(f.error(params[0].data(), params[1].data(), 1.0, 1.0).norm(), 1e-4);  // chords
  // The wheels report 3 % too little distance and 5 % too much turning: the scales undo it.
  // Reported speed 0.4 / 1.03, yaw rate 0.2 * 1.05: radius 2 / (1.03 * 1.05).
  const auto scaled = circleReadings(0.4 / 1.03, 2.0 / (1.03 * 1.05), 0.0, 50.0, 101);
  const auto pre_wrong = WheelPreintegration::between(scaled, ta, tb, 0.0, WheelNoise());
  const WheelFactor fw(*pre_wrong, T_body_wheel);
  EXPECT_LT(fw.error(params[0].data(), params[1].data(), 1.03, 1.0 / 1.05).norm(), 1e-4);
  EXPECT_GT(fw.error(params[0].data(), params[1].data(), 1.0, 1.0).norm(), 5e-3);

  std::mt19937_64 rng(7);
  std::normal_distribution<double> n(0.0, 0.1);
  for (int trial = 0; trial < 5; ++trial) {
    Params p = params;
    for (int b = 0; b < 2; ++b) {
      PoseManifold m;
      const Eigen::Matrix<double, 6, 1> d =
          Eigen::Matrix<double, 6, 1>::NullaryExpr([&] { return n(rng); });
      std::vector<double> out(7);
      m.Plus(p[static_cast<std::size_t>(b)].data(), d.data(), out.data());
      p[static_cast<std::size_t>(b)] = out;
    }
    p[2][0] = 1.0 + n(rng);
    p[3][0] = 1.0 + n(rng);
    for (int b = 0; b < 4; ++b) {
      const Eigen::MatrixXd Ja = analyticJacobian(f, p, b);
      const Eigen::MatrixXd Jn = numericJacobian(f, p, b);
      EXPECT_LT((Ja - Jn).norm(), 1e-5 * std::max(1.0, Jn.norm())) << "block " << b << "\n"
                                                                   << Ja << "\n\n"
                                                                   << Jn;
    }
  }
}

TEST(WheelOptions, DefaultsEqualTheSharedConfigAndBadValuesAreNamed) {
  IniReader ini = IniReader::fromFile(rgbdi::test::sourceDir() + "/share/config.ini");
  const WheelOptions o = EstimatorOptions::load(ini).wheel;
  const WheelOptions d;
  EXPECT_EQ(o.enable, d.enable);
  EXPECT_FALSE(o.enable);  // off unless asked: runs without it stay as they were
  EXPECT_EQ(o.time_offset_s, d.time_offset_s);
  EXPECT_TRUE(o.T_body_wheel.isApprox(d.T_body_wheel));
  EXPECT_EQ(o.noise.forward_sigma_per_sqrt_m, d.noise.forward_sigma_per_sqrt_m);
  EXPECT_EQ(o.noise.lateral_sigma_per_sqrt_m, d.noise.lateral_sigma_per_sqrt_m);
  EXPECT_EQ(o.noise.vertical_sigma_per_sqrt_m, d.noise.vertical_sigma_per_sqrt_m);
  EXPECT_EQ(o.noise.yaw_sigma_per_sqrt_rad, d.noise.yaw_sigma_per_sqrt_rad);
  EXPECT_EQ(o.noise.yaw_sigma_per_sqrt_m, d.noise.yaw_sigma_per_sqrt_m);
  EXPECT_EQ(o.noise.tilt_sigma_per_sqrt_m, d.noise.tilt_sigma_per_sqrt_m);
  EXPECT_EQ(o.noise.min_sigma_m, d.noise.min_sigma_m);
  EXPECT_EQ(o.noise.min_sigma_rad, d.noise.min_sigma_rad);
  EXPECT_EQ(o.estimate_scale, d.estimate_scale);
  EXPECT_EQ(o.scale_prior_sigma, d.scale_prior_sigma);
  EXPECT_EQ(o.direction_from_gyro, d.direction_from_gyro);
  ini.acceptConfigSectionsExcept({"estimator", "wheel"});
  EXPECT_NO_THROW(ini.checkNoUnknownKeys());

  IniReader bad = IniReader::fromText("[wheel]\nR_body_wheel = 1 0 0  0 1 0  0 0 2\n", "w.ini");
  try {
    WheelOptions::load(bad);
    ADD_FAILURE() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("w.ini [wheel] R_body_wheel: not a rotation matrix"),
              std::string::npos)
        << e.what();
  }
  IniReader turned = IniReader::fromText(
      "[wheel]\nR_body_wheel = 0 -1 0  1 0 0  0 0 1\nt_body_wheel_m = 0.1 0 -0.2\n", "w.ini");
  const WheelOptions t = WheelOptions::load(turned);
  EXPECT_TRUE(t.T_body_wheel.linear().isApprox(
      Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).matrix(), 1e-12));
  EXPECT_EQ(t.T_body_wheel.translation(), Eigen::Vector3d(0.1, 0.0, -0.2));
}

}  // namespace
}  // namespace rgbdi::estimator
