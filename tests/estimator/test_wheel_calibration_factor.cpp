// The wheel factor with the online calibration (doc/wheels.md "Online calibration"): analytic vs
// numeric Jacobians of every block (planar and 3-D), the time-offset derivative against cutting
// the readings again, and a known-answer window in which a wrong extrinsic yaw and a wrong time
// offset are recovered from exact readings.
#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include <deque>
#include <random>

#include "factor_jacobians.h"
#include "rgbdi/common/so3.h"
#include "rgbdi/estimator/pose_manifold.h"
#include "rgbdi/estimator/wheel_calibration_factor.h"
#include "rgbdi/estimator/wheel_factor.h"
#include "rgbdi/estimator/wheel_options.h"
#include "rgbdi/estimator/wheel_preintegration.h"

namespace rgbdi::estimator {
namespace {

using test::analyticJacobian;
using test::numericJacobian;
using test::Params;
using test::poseBlock;

Eigen::Matrix3d rotZ(double a) { return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()).matrix(); }

/// A robot that speeds up and slows down and turns left and right: speed 0.3 + 0.2 sin(t)
/// [m/s], yaw rate 0.4 cos(0.7 t) [rad/s]; its planar pose (x, y, yaw) integrated with 0.1 ms
/// midpoint steps (1e-9 m accurate), tabulated every 1 ms from 0 to 10 s.
class VaryingDrive {
 public:
  VaryingDrive() {
    double x = 0.0, y = 0.0, yaw = 0.0;
    const double h = 1e-4;
    for (int k = 0; k <= 100000; ++k) {
      if (k % 10 == 0) table_.push_back(Eigen::Vector3d(x, y, yaw));
      const double tm = (k + 0.5) * h;
      const double v = 0.3 + 0.2 * std::sin(tm), w = 0.4 * std::cos(0.7 * tm);
      const double yaw_m = yaw + 0.5 * h * 0.4 * std::cos(0.7 * k * h);
      x += h * v * std::cos(yaw_m);
      y += h * v * std::sin(yaw_m);
      yaw += h * w;
    }
  }
  /// The pose at t, a whole number of milliseconds.
  Eigen::Vector3d at(double t) const {
    return table_[static_cast<std::size_t>(std::lround(t * 1000.0))];
  }
  Eigen::Isometry3d wheelPose(double t) const {
    const Eigen::Vector3d p = at(t);
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = rotZ(p.z());
    T.translation() = Eigen::Vector3d(p.x(), p.y(), 0.0);
    return T;
  }
  /// Readings at 50 Hz on the wheel clock: stamp = IMU-clock time - td.
  std::deque<WheelOdometrySample> readings(double td) const {
    std::deque<WheelOdometrySample> r;
    for (int k = 0; k * 20 <= 9000; ++k) {
      WheelOdometrySample w;
      w.t = k * 0.02;
      const Eigen::Vector3d p = at(w.t + td);
      w.x_m = p.x();
      w.y_m = p.y();
      w.yaw_rad = std::remainder(p.z(), 2.0 * M_PI);
      r.push_back(w);
    }
    return r;
  }

 private:
  std::vector<Eigen::Vector3d> table_;
};

void expectJacobiansMatch(const ceres::CostFunction& f, const Params& p) {
  for (int b = 0; b < 6; ++b) {
    const Eigen::MatrixXd Ja = analyticJacobian(f, p, b);
    const Eigen::MatrixXd Jn = numericJacobian(f, p, b);
    EXPECT_LT((Ja - Jn).norm(), 1e-5 * std::max(1.0, Jn.norm())) << "block " << b << "\n"
                                                                 << Ja << "\n\n"
                                                                 << Jn;
  }
}

Params randomParams(std::mt19937_64& rng, const Params& base) {
  std::normal_distribution<double> n(0.0, 0.1);
  Params p = base;
  test::perturbPoses(p, rng, n);
  p[2][0] = 1.0 + n(rng);
  p[3][0] = 1.0 + n(rng);
  p[4][0] = n(rng);
  p[5][0] = 0.3 * n(rng);
  return p;
}

Eigen::Isometry3d bodyToWheel(double yaw) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = expSO3(Eigen::Vector3d(0.02, -0.01, 0.3)) * rotZ(yaw);
  T.translation() = Eigen::Vector3d(0.1, 0.05, -0.2);
  return T;
}

TEST(WheelCalibrationFactor, PlanarJacobiansMatchNumeric) {
  const VaryingDrive drive;
  const auto pre = WheelPreintegration::between(drive.readings(0.0), 2.0, 3.4, 0.0, WheelNoise());
  ASSERT_TRUE(pre.has_value());
  EXPECT_GT(pre->cutRates().v_start.norm(), 0.3);  // the slopes at the cuts are there
  EXPECT_NE(pre->cutRates().w_start, pre->cutRates().w_end);
  const WheelCalibrationFactor f(*pre, bodyToWheel(0.0));
  const Params base = {
      poseBlock(drive.wheelPose(2.0)), poseBlock(drive.wheelPose(3.4)), {1.0}, {1.0}, {0.0}, {0.0}};
  std::mt19937_64 rng(11);
  for (int trial = 0; trial < 5; ++trial) expectJacobiansMatch(f, randomParams(rng, base));
}

TEST(WheelCalibrationFactor, ThreeDJacobiansMatchNumeric) {
  // Increments with directions from a gyroscope (a ramp's start and a turn): the yaw block moves
  // them, the time offset does not.
  std::vector<Eigen::Vector2d> d;
  std::vector<double> a;
  std::vector<Eigen::Matrix3d> R;
  for (int k = 0; k < 20; ++k) {
    d.emplace_back(0.02 + 0.001 * k, 0.002);
    a.push_back(0.01);
    R.push_back(expSO3(Eigen::Vector3d(0.0, -0.01 * k, 0.012 * k)));
  }
  const WheelPreintegration pre(d, a, WheelNoise(), R);
  const WheelCalibrationFactor f(pre, bodyToWheel(0.0));
  const Params base = {
      poseBlock(Eigen::Isometry3d::Identity()),
      poseBlock(Eigen::Translation3d(0.5, 0.1, 0.05) * Eigen::Isometry3d::Identity()),
      {1.0},
      {1.0},
      {0.0},
      {0.0}};
  std::mt19937_64 rng(12);
  for (int trial = 0; trial < 5; ++trial) expectJacobiansMatch(f, randomParams(rng, base));
  const CalibratedWheelMotion m = pre.calibratedMotion(1.0, 1.0, 0.0, 0.05);
  EXPECT_EQ(m.ddp_dtd.norm(), 0.0);
  // At yaw 0 it is the uncorrected 3-D motion.
  Eigen::Vector3d dp;
  pre.motion(1.0, 1.0, &dp, nullptr);
  EXPECT_LT((m.dp - dp).norm(), 1e-15);
}

TEST(WheelCalibrationFactor, TimeOffsetDerivativeIsThatOfCuttingAgain) {
  // d motion / d td at the cut = the derivative of the motion pre-integrated with the readings
  // cut at td +- h (the cuts stay inside one reading interval: piecewise linear there).
  const VaryingDrive drive;
  const auto readings = drive.readings(0.0);
  const double ta = 2.005, tb = 3.405, h = 1e-4, sv = 1.02;
  const auto pre = WheelPreintegration::between(readings, ta, tb, 0.0, WheelNoise());
  const auto plus = WheelPreintegration::between(readings, ta, tb, h, WheelNoise());
  const auto minus = WheelPreintegration::between(readings, ta, tb, -h, WheelNoise());
  ASSERT_TRUE(pre && plus && minus);
  // Exact at yaw scale 1; with another one, the pre-integration turns each increment by the
  // scaled yaw at the increment's start and the correction by the continuous one: 1e-4 apart
  // at a 3 % yaw scale.
  for (const double sw : {1.0, 0.97}) {
    const CalibratedWheelMotion m = pre->calibratedMotion(sv, sw, 0.0, 0.0);
    Eigen::Vector3d pp, pm;
    double yp = 0.0, ym = 0.0;
    plus->motion(sv, sw, &pp, &yp);
    minus->motion(sv, sw, &pm, &ym);
    const double tol = sw == 1.0 ? 1e-6 : 1e-4 * m.ddp_dtd.norm();
    EXPECT_LT((m.ddp_dtd - (pp - pm) / (2 * h)).norm(), tol) << m.ddp_dtd.transpose();
    EXPECT_NEAR(m.ddyaw_dtd, (yp - ym) / (2 * h), 1e-8);
  }
  const double sw = 0.97;
  const CalibratedWheelMotion m = pre->calibratedMotion(sv, sw, 0.0, 0.0);
  // First order: 20 ms off the cut, the correction leaves (a dt^2)-sized errors only.
  const auto far = WheelPreintegration::between(readings, ta, tb, 0.02, WheelNoise());
  Eigen::Vector3d pf;
  far->motion(sv, sw, &pf, nullptr);
  EXPECT_LT((pre->calibratedMotion(sv, sw, 0.0, 0.02).dp - pf).norm(), 2e-4);
  EXPECT_GT((m.dp - pf).norm(), 2e-3);  // uncorrected: 10 times that
}

TEST(WheelCalibrationFactor, KnownAnswerWindowRecoversYawAndTimeOffset) {
  // True: the wheel frame turned by 0.05 rad about its z from the configured one, the wheel
  // clock 40 ms behind the IMU's. Configured: neither. Seven 1.2 s intervals of exact readings
  // and exact poses; the calibration solved with poses and scales held, the readings cut again
  // at each new estimate (as the window rebuilds its factors at every update).
  const VaryingDrive drive;
  const double yaw_true = 0.05, td_true = 0.04;
  const Eigen::Isometry3d T_bw_conf = bodyToWheel(0.0), T_bw_true = bodyToWheel(yaw_true);
  const auto readings = drive.readings(td_true);
  std::vector<std::vector<double>> poses;
  std::vector<double> times;
  for (int k = 0; k <= 7; ++k) {
    times.push_back(0.5 + 1.2 * k);
    poses.push_back(poseBlock(drive.wheelPose(times.back()) * T_bw_true.inverse()));
  }
  double sv = 1.0, sw = 1.0, yaw = 0.0, td = 0.0;
  // With the configured calibration the factors disagree with the poses.
  const auto first = WheelPreintegration::between(readings, times[0], times[1], td, WheelNoise());
  ASSERT_TRUE(first.has_value());
  EXPECT_GT(WheelCalibrationFactor(*first, T_bw_conf)
                .error(poses[0].data(), poses[1].data(), sv, sw, yaw, td)
                .head<2>()
                .norm(),
            0.02);
  for (int pass = 0; pass < 4; ++pass) {
    ceres::Problem problem;
    for (std::size_t k = 0; k + 1 < poses.size(); ++k) {
      const auto pre =
          WheelPreintegration::between(readings, times[k], times[k + 1], td, WheelNoise());
      ASSERT_TRUE(pre.has_value());
      problem.AddResidualBlock(new WheelCalibrationFactor(*pre, T_bw_conf), nullptr,
                               poses[k].data(), poses[k + 1].data(), &sv, &sw, &yaw, &td);
      problem.SetParameterBlockConstant(poses[k].data());
      problem.SetParameterBlockConstant(poses[k + 1].data());
    }
    problem.SetParameterBlockConstant(&sv);
    problem.SetParameterBlockConstant(&sw);
    ceres::Solver::Options o;
    o.max_num_iterations = 20;
    ceres::Solver::Summary s;
    ceres::Solve(o, &problem, &s);
  }
  EXPECT_NEAR(yaw, yaw_true, 1e-4);
  EXPECT_NEAR(td, td_true, 1e-4);
  // There, every factor agrees with the poses to the readings' chords.
  for (std::size_t k = 0; k + 1 < poses.size(); ++k) {
    const auto pre =
        WheelPreintegration::between(readings, times[k], times[k + 1], td, WheelNoise());
    EXPECT_LT(WheelCalibrationFactor(*pre, T_bw_conf)
                  .error(poses[k].data(), poses[k + 1].data(), sv, sw, yaw, td)
                  .norm(),
              2e-4);
  }
}

TEST(WheelCalibrationFactor, AtZeroCorrectionItIsTheWheelFactor) {
  const VaryingDrive drive;
  const auto pre = WheelPreintegration::between(drive.readings(0.0), 4.0, 5.0, 0.0, WheelNoise());
  ASSERT_TRUE(pre.has_value());
  const Params p = {poseBlock(drive.wheelPose(4.0)),
                    poseBlock(Eigen::Translation3d(0.01, 0.0, 0.0) * drive.wheelPose(5.0)),
                    {1.01},
                    {0.98},
                    {0.0},
                    {0.0}};
  const Eigen::Matrix<double, 6, 1> a = WheelCalibrationFactor(*pre, bodyToWheel(0.0))
                                            .error(p[0].data(), p[1].data(), 1.01, 0.98, 0.0, 0.0);
  const Eigen::Matrix<double, 6, 1> b =
      WheelFactor(*pre, bodyToWheel(0.0)).error(p[0].data(), p[1].data(), 1.01, 0.98);
  EXPECT_LT((a - b).norm(), 1e-14);
  EXPECT_GT(b.norm(), 1e-3);
}

TEST(WheelOptions, CalibrationKeysAreReadAndBadValuesNamed) {
  IniReader ini = IniReader::fromText(
      "[wheel]\nestimate_extrinsic_yaw = true\nextrinsic_yaw_prior_sigma_rad = 0.1\n"
      "estimate_time_offset = true\ntime_offset_prior_sigma_s = 0.02\n"
      "extrinsic_yaw_max_rad = 0.3\ntime_offset_max_change_s = 0.2\n");
  const WheelOptions o = WheelOptions::load(ini);
  EXPECT_TRUE(o.estimate_extrinsic_yaw);
  EXPECT_TRUE(o.estimate_time_offset);
  EXPECT_TRUE(o.calibrating());
  EXPECT_EQ(o.extrinsic_yaw_prior_sigma_rad, 0.1);
  EXPECT_EQ(o.time_offset_prior_sigma_s, 0.02);
  EXPECT_EQ(o.extrinsic_yaw_max_rad, 0.3);
  EXPECT_EQ(o.time_offset_max_change_s, 0.2);
  EXPECT_FALSE(WheelOptions().calibrating());  // off by default
  IniReader bad = IniReader::fromText("[wheel]\ntime_offset_prior_sigma_s = 0\n");
  try {
    WheelOptions::load(bad);
    FAIL() << "no error";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("time_offset_prior_sigma_s"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace rgbdi::estimator
