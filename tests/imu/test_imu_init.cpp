// Initialisation helpers: attitude from gravity, gyro bias from vision rotations (synthetic).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <random>

#include "imu/synthetic_motion.h"
#include "rgbdi/common/so3.h"
#include "rgbdi/imu/imu_init.h"

using namespace rgbdi;
using namespace rgbdi::imu;

namespace {

const Eigen::Vector3d& kGravity = test::kTestGravity;
ImuNoise testNoise() { return test::simImuNoise(); }

double yawOf(const Eigen::Quaterniond& q) {
  const Eigen::Matrix3d R = q.toRotationMatrix();
  return std::atan2(R(1, 0), R(0, 0));
}

}  // namespace

TEST(GravityAlignedAttitude, LevelSensorGivesIdentity) {
  const Eigen::Quaterniond q = gravityAlignedAttitude(Eigen::Vector3d(0, 0, 9.81));
  EXPECT_LT(q.angularDistance(Eigen::Quaterniond::Identity()), 1e-12);
}

TEST(GravityAlignedAttitude, RecoversRollAndPitchWithZeroYaw) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.2, 1.2);
  for (int k = 0; k < 50; ++k) {
    const double roll = u(rng), pitch = u(rng), yaw = 2.5 * u(rng);
    const Eigen::Matrix3d R_true = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                                    Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                                    Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                                       .toRotationMatrix();
    // Reading at rest: R^T (a_w - g_w) with a_w = 0.
    const Eigen::Vector3d acc = R_true.transpose() * (-kGravity);
    const Eigen::Quaterniond q = gravityAlignedAttitude(acc);
    EXPECT_LT((q * acc - Eigen::Vector3d(0, 0, 9.81)).norm(), 1e-10);
    EXPECT_NEAR(yawOf(q), 0.0, 1e-12);
    // Same roll and pitch: equal to the truth up to a rotation about world z.
    const Eigen::Matrix3d R_no_yaw =
        Eigen::AngleAxisd(-yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix() * R_true;
    EXPECT_LT(q.angularDistance(Eigen::Quaterniond(R_no_yaw)), 1e-10) << "case " << k;
  }
}

TEST(GravityAlignedAttitude, HandlesUpsideDownAndRejectsZero) {
  const Eigen::Quaterniond q = gravityAlignedAttitude(Eigen::Vector3d(0, 0, -9.81));
  EXPECT_LT((q * Eigen::Vector3d(0, 0, -1) - Eigen::Vector3d(0, 0, 1)).norm(), 1e-12);
  EXPECT_THROW(gravityAlignedAttitude(Eigen::Vector3d::Zero()), std::invalid_argument);
  EXPECT_THROW(gravityAlignedAttitude(Eigen::Vector3d(NAN, 0, 1)), std::invalid_argument);
}

// Noise-free synthetic motion: the gyro bias is recovered up to the first-order remainder of the
// bias correction (the bias is small, so the solve is essentially exact).
TEST(SolveGyroBias, RecoversSyntheticBiasFromExactRotations) {
  const test::SyntheticMotion motion(kGravity);
  const Eigen::Vector3d bg_true(0.012, -0.02, 0.008);
  const Eigen::Vector3d bg_lin(0.002, 0.001, -0.001);  // estimator's current guess
  std::vector<std::unique_ptr<Preintegration>> pres;
  std::vector<GyroBiasPair> pairs;
  for (int k = 0; k < 10; ++k) {
    const double t0 = 0.5 + 0.1 * k, t1 = t0 + 0.1;
    pres.push_back(std::make_unique<Preintegration>(Eigen::Vector3d::Zero(), bg_lin, testNoise()));
    for (const auto& s : motion.samples(t0, t1, 200.0, Eigen::Vector3d::Zero(), bg_true))
      pres.back()->push(s);
    const Eigen::Quaterniond q_rel = motion.state(t0).q.inverse() * motion.state(t1).q;
    pairs.emplace_back(q_rel, pres.back().get());
  }
  const Eigen::Vector3d correction = solveGyroBias(pairs);
  std::printf("synthetic gyro bias error: %.3e rad/s\n", (bg_lin + correction - bg_true).norm());
  // The midpoint integration error of the 0.1 s intervals and the first-order correction limit
  // the recovery (measured 8.4e-7 rad/s).
  EXPECT_LT((bg_lin + correction - bg_true).norm(), 5e-6) << (bg_lin + correction).transpose();
}

TEST(SolveGyroBias, RejectsEmptyNullAndDegenerateInput) {
  EXPECT_THROW(solveGyroBias({}), std::invalid_argument);
  EXPECT_THROW(solveGyroBias({{Eigen::Quaterniond::Identity(), nullptr}}), std::invalid_argument);
  Preintegration single(Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), testNoise());
  single.push(0.0, Eigen::Vector3d(0, 0, 9.81), Eigen::Vector3d::Zero());
  EXPECT_THROW(solveGyroBias({{Eigen::Quaterniond::Identity(), &single}}), std::invalid_argument);
}
