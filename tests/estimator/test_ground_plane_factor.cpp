// The soft ground-plane constraint of a flat-floor robot (doc/wheels.md "Ground plane"): known
// residuals (height, roll, pitch of the wheel frame), its Mahalanobis distance (the gate's), the
// analytic vs numeric Jacobian, and its [wheel] keys.
#include <gtest/gtest.h>

#include <random>

#include "factor_jacobians.h"
#include "rgbdi/estimator/ground_plane_factor.h"
#include "rgbdi/estimator/pose_manifold.h"
#include "rgbdi/estimator/wheel_options.h"
#include "testing/options_load_error.h"

namespace rgbdi::estimator {
namespace {

std::vector<double> poseBlock(const Eigen::Vector3d& p, const Eigen::Matrix3d& R) {
  const Eigen::Quaterniond q(R);
  return {p.x(), p.y(), p.z(), q.x(), q.y(), q.z(), q.w()};
}

Eigen::Isometry3d wheelOffBody() {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(0.1, 0.0, -0.2);  // the axle 0.2 m below the IMU
  return T;
}

TEST(GroundPlaneFactor, HeightRollAndPitchOfTheWheelFrameAreTheResiduals) {
  const GroundPlaneFactor f(0.3, 0.01, 0.02, wheelOffBody());
  // Upright, any yaw, the IMU 0.2 m above the plane: zero.
  const Eigen::Matrix3d yawed = Eigen::AngleAxisd(2.0, Eigen::Vector3d::UnitZ()).matrix();
  const test::Params on = {poseBlock(Eigen::Vector3d(4.0, -1.0, 0.5), yawed)};
  EXPECT_LT(test::evaluateResidual(f, on).norm(), 1e-12);
  // 3 cm above the plane: 3 sigma in height, Mahalanobis distance 9.
  const test::Params above = {poseBlock(Eigen::Vector3d(4.0, -1.0, 0.53), yawed)};
  EXPECT_NEAR(test::evaluateResidual(f, above)[0], 3.0, 1e-9);
  EXPECT_NEAR(f.squaredNormalised(above[0].data()), 9.0, 1e-9);
  // Rolled by 0.1 rad about the (body = wheel) x axis at the axle's height: the up axis is
  // (0, -sin 0.1, cos 0.1), and the axle, 0.2 m below the IMU, comes up by 0.2 (1 - cos 0.1).
  const Eigen::Matrix3d rolled = Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitX()).matrix();
  const Eigen::VectorXd r =
      test::evaluateResidual(f, {poseBlock(Eigen::Vector3d(0, 0, 0.5), rolled)});
  EXPECT_NEAR(r[0], 0.2 * (1.0 - std::cos(0.1)) / 0.01, 1e-9);
  EXPECT_NEAR(r[1], 0.0, 1e-12);
  EXPECT_NEAR(r[2], -std::sin(0.1) / 0.02, 1e-9);
  // Pitched nose-up by 0.1 rad (-0.1 about y): the up axis leans back, n.x = -sin 0.1.
  const Eigen::Matrix3d pitched = Eigen::AngleAxisd(-0.1, Eigen::Vector3d::UnitY()).matrix();
  const Eigen::VectorXd s =
      test::evaluateResidual(f, {poseBlock(Eigen::Vector3d(0, 0, 0.5), pitched)});
  EXPECT_NEAR(s[1], -std::sin(0.1) / 0.02, 1e-9);
  EXPECT_NEAR(s[2], 0.0, 1e-12);
}

TEST(GroundPlaneFactor, AnalyticJacobianMatchesNumeric) {
  Eigen::Isometry3d T_body_wheel = wheelOffBody();
  T_body_wheel.linear() = Eigen::AngleAxisd(0.2, Eigen::Vector3d(1, 1, 0).normalized()).matrix();
  const GroundPlaneFactor f(0.3, 0.01, 0.02, T_body_wheel);
  std::mt19937_64 rng(5);
  std::normal_distribution<double> n(0.0, 0.3);
  for (int trial = 0; trial < 5; ++trial) {
    const Eigen::Vector3d axis = Eigen::Vector3d(n(rng), n(rng), n(rng));
    const test::Params p = {poseBlock(Eigen::Vector3d(n(rng), n(rng), 0.5 + n(rng)),
                                      Eigen::AngleAxisd(axis.norm(), axis.normalized()).matrix())};
    const Eigen::MatrixXd Ja = test::analyticJacobian(f, p, 0);
    const Eigen::MatrixXd Jn = test::numericJacobian(f, p, 0);
    EXPECT_LT((Ja - Jn).norm(), 1e-5 * std::max(1.0, Jn.norm())) << Ja << "\n\n" << Jn;
  }
}

TEST(WheelOptions, GroundPlaneKeysAreReadOnByDefaultAndBadValuesNamed) {
  EXPECT_EQ(WheelOptions().ground_plane_sigma_m, 0.01);
  IniReader off = IniReader::fromText("[wheel]\nground_plane_sigma_m = 0\n", "w.ini");
  EXPECT_EQ(WheelOptions::load(off).ground_plane_sigma_m, 0.0);
  IniReader on = IniReader::fromText(
      "[wheel]\nground_plane_sigma_m = 0.02\nground_plane_tilt_sigma_rad = 0.03\n"
      "ground_plane_gate_chi2 = 20\n",
      "w.ini");
  const WheelOptions o = WheelOptions::load(on);
  EXPECT_EQ(o.ground_plane_sigma_m, 0.02);
  EXPECT_EQ(o.ground_plane_tilt_sigma_rad, 0.03);
  EXPECT_EQ(o.ground_plane_gate_chi2, 20.0);
  const std::string error =
      rgbdi::test::optionsLoadError<WheelOptions>("[wheel]\nground_plane_sigma_m = -1\n", "w.ini");
  EXPECT_NE(error.find("w.ini [wheel] ground_plane_sigma_m"), std::string::npos) << error;
}

}  // namespace
}  // namespace rgbdi::estimator
