// RollingShutterReprojectionFactor (the readout as a parameter, [estimator]
// estimate_rolling_shutter_readout): known answers and analytic vs numeric Jacobians.
#include <gtest/gtest.h>

#include <random>

#include "factor_jacobians.h"
#include "rgbdi/common/rolling_shutter.h"
#include "rgbdi/common/so3.h"
#include "rgbdi/estimator/reprojection_factor.h"
#include "rgbdi/estimator/rolling_shutter_reprojection_factor.h"

using namespace rgbdi;
using namespace rgbdi::estimator;
using rgbdi::test::analyticJacobian;
using rgbdi::test::evaluateResidual;
using rgbdi::test::numericJacobian;
using rgbdi::test::Params;

namespace {

constexpr double kReadout = 0.033;       // [s] the true readout
constexpr double kEntryReadout = 0.010;  // [s] the estimate the observations entered with
constexpr double kTd = 0.004;            // [s] the time offset (equal to the stamping one)

/// Two camera poses (as body poses with extrinsic T_bc), a point seen in both, and the two
/// observations as the window holds them: seen at their rows' times (row fractions 0.3 and
/// -0.2 of a 33 ms readout, moving with the given image velocities), moved to the stamp at entry
/// with a 10 ms readout estimate.
struct Scene {
  Eigen::Isometry3d T_bc = Eigen::Isometry3d::Identity();
  Params params;
  FeatureMeasurement oi, oj;
};

Scene makeScene(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Scene s;
  s.T_bc.linear() = expSO3(Eigen::Vector3d(-1.2, 0.1, -1.5));
  s.T_bc.translation() << 0.02, 0.015, -0.01;
  Eigen::Isometry3d Ti = Eigen::Isometry3d::Identity();
  Ti.linear() = expSO3(Eigen::Vector3d(n(rng), n(rng), n(rng)) * 0.5);
  Ti.translation() << n(rng), n(rng), n(rng);
  Eigen::Isometry3d Tj = Ti;
  Tj.linear() = Ti.rotation() * expSO3(Eigen::Vector3d(0.05, -0.03, 0.08));
  Tj.translation() += Eigen::Vector3d(0.2, -0.1, 0.05);
  const Eigen::Vector3d p_ci(0.3 + 0.1 * n(rng), -0.2 + 0.1 * n(rng), 2.5);
  const Eigen::Vector3d p_cj = (Tj * s.T_bc).inverse() * ((Ti * s.T_bc) * p_ci);
  const Eigen::Vector2d vi(0.3, -0.1), vj(-0.2, 0.4);
  const double fi = 0.3, fj = -0.2;
  auto observed = [&](const Eigen::Vector3d& p, const Eigen::Vector2d& v, double f) {
    FeatureMeasurement o;
    const Eigen::Vector2d xn_stamp = p.head<2>() / p.z();
    const Eigen::Vector2d xn_row = xn_stamp + kReadout * f * v;  // seen at its row's time
    o.xn << xn_row - kEntryReadout * f * v, 1.0;                 // moved at entry
    o.velocity = v;
    o.td_at_stamp = kTd;
    o.row_fraction = f;
    o.readout_at_stamp_s = kEntryReadout;
    return o;
  };
  s.oi = observed(p_ci, vi, fi);
  s.oj = observed(p_cj, vj, fj);
  auto pose = [](const Eigen::Isometry3d& T) {
    const Eigen::Quaterniond q(T.rotation());
    return std::vector<double>{
        T.translation().x(), T.translation().y(), T.translation().z(), q.x(), q.y(), q.z(), q.w()};
  };
  s.params = {pose(Ti), pose(Tj), {1.0 / p_ci.z()}, {kTd}, {kReadout}};
  return s;
}

}  // namespace

TEST(RollingShutterReprojectionFactor, ZeroResidualAtTheTrueReadoutOnly) {
  std::mt19937_64 rng(11);
  for (int trial = 0; trial < 10; ++trial) {
    Scene s = makeScene(rng);
    RollingShutterReprojectionFactor f(s.oi, s.oj, s.T_bc, 460.0 / 1.5);
    EXPECT_LT(evaluateResidual(f, s.params).norm(), 1e-9);
    // At the entry readout the residual is what the 23 ms the observations still lack cost.
    s.params[4][0] = kEntryReadout;
    EXPECT_GT(evaluateResidual(f, s.params).norm(), 1e-3);
  }
}

TEST(RollingShutterReprojectionFactor, EqualsTheReprojectionFactorAtTheEntryReadout) {
  // With the readout where the observations were moved to, nothing is left to shift: the residual
  // and the Jacobians of the blocks both factors share are ReprojectionFactor's.
  std::mt19937_64 rng(12);
  Scene s = makeScene(rng);
  s.params[3][0] = 0.011;  // a time offset other than the stamping one
  s.params[4][0] = kEntryReadout;
  RollingShutterReprojectionFactor f(s.oi, s.oj, s.T_bc, 460.0 / 1.5);
  const ReprojectionFactor g(s.oi, s.oj, s.T_bc, 460.0 / 1.5);
  const Params shared(s.params.begin(), s.params.begin() + 4);
  EXPECT_LT((evaluateResidual(f, s.params) - evaluateResidual(g, shared)).norm(), 1e-12);
  for (int b = 0; b < 4; ++b)
    EXPECT_LT((analyticJacobian(f, s.params, b) - analyticJacobian(g, shared, b)).norm(), 1e-9)
        << "block " << b;
}

TEST(RollingShutterReprojectionFactor, JacobiansMatchNumeric) {
  std::mt19937_64 rng(13);
  for (int trial = 0; trial < 20; ++trial) {
    Scene s = makeScene(rng);
    // Away from the truth in every block.
    s.params[2][0] *= 1.1;
    s.params[3][0] = 0.011;
    s.params[4][0] = 0.021;
    RollingShutterReprojectionFactor f(s.oi, s.oj, s.T_bc, 460.0 / 1.5);
    // A factor made for other measurements, then reset to these, is this factor.
    FeatureMeasurement other;
    other.xn = Eigen::Vector3d(0.1, 0.2, 1.0);
    RollingShutterReprojectionFactor reused(other, other, Eigen::Isometry3d::Identity(), 1.0);
    reused.reset(s.oi, s.oj, s.T_bc, 460.0 / 1.5);
    for (int b = 0; b < 5; ++b) {
      const Eigen::MatrixXd Ja = analyticJacobian(f, s.params, b);
      const Eigen::MatrixXd Jn = numericJacobian(f, s.params, b);
      EXPECT_LT((Ja - Jn).norm(), 1e-5 * std::max(1.0, Jn.norm())) << "block " << b << "\n"
                                                                   << Ja << "\n"
                                                                   << Jn;
      EXPECT_EQ(analyticJacobian(reused, s.params, b), Ja) << "block " << b;
    }
  }
}

TEST(RollingShutterReprojectionFactor, ReadoutJacobianIsTheRowShareOfTheOffsetOne) {
  // Known answer: with both row fractions equal to 1 the readout moves the observations exactly
  // as the time offset does.
  std::mt19937_64 rng(14);
  Scene s = makeScene(rng);
  s.oi.row_fraction = 1.0;
  s.oj.row_fraction = 1.0;
  RollingShutterReprojectionFactor f(s.oi, s.oj, s.T_bc, 460.0 / 1.5);
  EXPECT_LT((analyticJacobian(f, s.params, 4) - analyticJacobian(f, s.params, 3)).norm(), 1e-12);
}

TEST(RollingShutter, RowFractionIsTheRowsShareOfTheReadout) {
  RollingShutter rs;
  rs.rows = 480;
  rs.readout_s = 0.0;  // defined for a zero readout too (the estimate may start there)
  EXPECT_DOUBLE_EQ(rs.rowFraction(239.5), 0.0);
  EXPECT_DOUBLE_EQ(rs.rowFraction(479.5), 0.5);
  EXPECT_DOUBLE_EQ(rs.rowFraction(-0.5), -0.5);
  rs.readout_s = 0.033;
  EXPECT_DOUBLE_EQ(rs.rowTime(100.0), 0.033 * rs.rowFraction(100.0));
  rs.bottom_to_top = true;
  EXPECT_DOUBLE_EQ(rs.rowFraction(479.5), -0.5);
  rs.reference_middle = false;  // stamped at the first row read, the last one
  EXPECT_DOUBLE_EQ(rs.rowFraction(479.0), 0.0);
  EXPECT_DOUBLE_EQ(rs.rowFraction(-1.0), 1.0);
}
