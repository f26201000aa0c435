// The 3-D wheel pre-integration (directions from the gyroscope, doc/wheels.md "Blind frames"):
// known answers on a ramp (where the planar one is metres off), the noise model it gets, the
// factor's zero at the truth and its analytic vs numeric Jacobians, and the option that picks it.
#include <gtest/gtest.h>

#include <deque>
#include <random>

#include "factor_jacobians.h"
#include "rgbdi/common/so3.h"
#include "rgbdi/estimator/pose_manifold.h"
#include "rgbdi/estimator/wheel_factor.h"
#include "rgbdi/estimator/wheel_options.h"
#include "rgbdi/estimator/wheel_preintegration.h"

namespace rgbdi::estimator {
namespace {

using test::analyticJacobian;
using test::numericJacobian;
using test::Params;
using test::poseBlock;

/// Readings at 50 Hz of a robot whose odometry goes straight along x at `speed(t)` [m/s] over
/// [0, T] (piecewise constant between readings, so the readings' x is exact).
std::deque<WheelOdometrySample> straightReadings(double T, double (*speed)(double)) {
  std::deque<WheelOdometrySample> r;
  double x = 0.0;
  for (int k = 0; k <= static_cast<int>(T * 50.0 + 0.5); ++k) {
    WheelOdometrySample w;
    w.t = k / 50.0;
    w.x_m = x;
    r.push_back(w);
    x += speed(w.t) / 50.0;
  }
  return r;
}

/// 1 m/s for 1 s, standing still for 0.2 s, 1 m/s for 1 s.
double driveStopDrive(double t) { return t < 0.999 || t > 1.199 ? 1.0 : 0.0; }

/// Gyroscope at 200 Hz: `rate` [rad/s] about the body's y axis during [1.05, 1.15) s (the robot
/// stands on the ramp's start and tilts), nothing else; plus a constant bias.
std::vector<ImuSample> pitchWhileStanding(double rate, const Eigen::Vector3d& bias) {
  std::vector<ImuSample> s;
  for (int k = 0; k <= 440; ++k) {
    ImuSample m;
    m.t = k / 200.0;
    m.gyr = bias;
    if (m.t >= 1.05 - 1e-9 && m.t < 1.15 - 1e-9) m.gyr.y() += rate;
    s.push_back(m);
  }
  return s;
}

TEST(WheelPreintegration3d, RampStartKnownAnswerWherePlanarIsWrong) {
  // 1 m on the flat, a 0.2 s stop in which the robot pitches nose-up by 0.15 rad (a rotation of
  // -0.15 rad about y), 1 m up the ramp: the motion in the start frame is
  // (1 + cos 0.15, 0, sin 0.15); the planar pre-integration says (2, 0, 0).
  const auto readings = straightReadings(2.2, driveStopDrive);
  const Eigen::Vector3d bias(0.01, -0.02, 0.03);
  const std::vector<ImuSample> imu = pitchWhileStanding(-1.5, bias);
  WheelGyro gyro;
  gyro.samples = &imu;
  gyro.bias = bias;
  const WheelNoise noise;
  const auto pre = WheelPreintegration::between(readings, 0.0, 2.2, 0.0, noise, 0.0, &gyro);
  ASSERT_TRUE(pre.has_value());
  EXPECT_TRUE(pre->threeD());
  Eigen::Vector3d dp, ddp_dsw;
  double dyaw = 1.0;
  pre->motion(1.0, 1.0, &dp, &dyaw, &ddp_dsw);
  EXPECT_NEAR(dp.x(), 1.0 + std::cos(0.15), 1e-12);
  EXPECT_NEAR(dp.y(), 0.0, 1e-12);
  EXPECT_NEAR(dp.z(), std::sin(0.15), 1e-12);
  EXPECT_EQ(dyaw, 0.0);
  EXPECT_EQ(ddp_dsw, Eigen::Vector3d::Zero());  // the directions do not depend on s_w
  pre->motion(1.03, 0.9, &dp, nullptr);         // the forward scale scales it all
  EXPECT_NEAR(dp.x(), 1.03 * (1.0 + std::cos(0.15)), 1e-12);
  EXPECT_NEAR(dp.z(), 1.03 * std::sin(0.15), 1e-12);

  const auto planar = WheelPreintegration::between(readings, 0.0, 2.2, 0.0, noise);
  ASSERT_TRUE(planar.has_value());
  EXPECT_FALSE(planar->threeD());
  planar->motion(1.0, 1.0, &dp, nullptr);
  EXPECT_NEAR(dp.x(), 2.0, 1e-12);
  EXPECT_EQ(dp.z(), 0.0);

  // A wheel frame yawed by 90 degrees in the body: the body's y is the wheel's -x, so the same
  // gyroscope rate tilts the wheel frame about its x axis (a roll): the wheel path stays flat.
  gyro.R_body_wheel = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).matrix();
  const auto rolled = WheelPreintegration::between(readings, 0.0, 2.2, 0.0, noise, 0.0, &gyro);
  rolled->motion(1.0, 1.0, &dp, nullptr);
  EXPECT_NEAR(dp.x(), 2.0, 1e-12);
  EXPECT_NEAR(dp.z(), 0.0, 1e-12);
}

TEST(WheelPreintegration3d, RotationRowsHaveNoWeightAndTheTranslationThePlanarSigmas) {
  const auto readings = straightReadings(2.2, driveStopDrive);
  const std::vector<ImuSample> imu = pitchWhileStanding(-1.5, Eigen::Vector3d::Zero());
  WheelGyro gyro;
  gyro.samples = &imu;
  WheelNoise noise;
  noise.vertical_sigma_per_sqrt_m = 0.07;
  const auto pre = WheelPreintegration::between(readings, 0.0, 2.2, 0.0, noise, 0.0, &gyro);
  const auto planar = WheelPreintegration::between(readings, 0.0, 2.2, 0.0, noise);
  const Eigen::Matrix<double, 6, 1>& w = pre->sqrtInformation();
  EXPECT_EQ(w.head<3>(), planar->sqrtInformation().head<3>());
  EXPECT_NEAR(w[2], 1.0 / (0.07 * std::sqrt(2.0)), 1e-9);  // 2 m travelled
  EXPECT_EQ(w.tail<3>(), Eigen::Vector3d::Zero());
}

TEST(WheelFactor3d, ZeroAtTheTruthOnTheRampAndJacobiansMatchNumeric) {
  const auto readings = straightReadings(2.2, driveStopDrive);
  const std::vector<ImuSample> imu = pitchWhileStanding(-1.5, Eigen::Vector3d::Zero());
  Eigen::Isometry3d T_body_wheel = Eigen::Isometry3d::Identity();
  T_body_wheel.translation() = Eigen::Vector3d(0.1, 0.0, -0.2);
  WheelGyro gyro;
  gyro.samples = &imu;
  const auto pre = WheelPreintegration::between(readings, 0.0, 2.2, 0.0, WheelNoise(), 0.0, &gyro);
  ASSERT_TRUE(pre.has_value());
  // The wheel frame in a world whose x-y plane is not the ground's: at a, and on the ramp at b.
  const Eigen::Isometry3d T_world_wa =
      Eigen::Translation3d(1.0, -2.0, 0.5) * Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ());
  const Eigen::Matrix3d R_ramp = Eigen::AngleAxisd(-0.15, Eigen::Vector3d::UnitY()).matrix();
  Eigen::Isometry3d T_wa_wb = Eigen::Isometry3d::Identity();
  T_wa_wb.linear() = R_ramp;
  T_wa_wb.translation() = Eigen::Vector3d(1.0, 0.0, 0.0) + R_ramp * Eigen::Vector3d(1.0, 0.0, 0.0);
  const WheelFactor f(*pre, T_body_wheel);
  Params params = {poseBlock(T_world_wa * T_body_wheel.inverse()),
                   poseBlock(T_world_wa * T_wa_wb * T_body_wheel.inverse()),
                   {1.0},
                   {1.0}};
  const Eigen::Matrix<double, 6, 1> e = f.error(params[0].data(), params[1].data(), 1.0, 1.0);
  EXPECT_LT(e.head<3>().norm(), 1e-12);
  EXPECT_NEAR(e[4], -0.15, 1e-12);  // the pitch is there, unweighted: the IMU factor's business
  EXPECT_LT(test::evaluateResidual(f, params).norm(), 1e-9);

  std::mt19937_64 rng(11);
  std::normal_distribution<double> n(0.0, 0.1);
  for (int trial = 0; trial < 5; ++trial) {
    Params p = params;
    test::perturbPoses(p, rng, n);
    p[2][0] = 1.0 + n(rng);
    p[3][0] = 1.0 + n(rng);
    for (int b = 0; b < 4; ++b) {
      const Eigen::MatrixXd Ja = analyticJacobian(f, p, b);
      const Eigen::MatrixXd Jn = numericJacobian(f, p, b);
      EXPECT_LT((Ja - Jn).norm(), 1e-5 * std::max(1.0, Jn.norm())) << "block " << b;
    }
  }
}

TEST(WheelOptions, DirectionFromGyroIsReadAndABadValueIsNamed) {
  EXPECT_EQ(WheelOptions().direction_from_gyro, "blind");
  IniReader always = IniReader::fromText("[wheel]\ndirection_from_gyro = always\n", "w.ini");
  EXPECT_EQ(WheelOptions::load(always).direction_from_gyro, "always");
  IniReader bad = IniReader::fromText("[wheel]\ndirection_from_gyro = sometimes\n", "w.ini");
  try {
    WheelOptions::load(bad);
    ADD_FAILURE() << "no error";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("w.ini [wheel] direction_from_gyro"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace rgbdi::estimator
