// 4-DOF algebra, the wrapping yaw manifold and the pose-graph edge residual: known answers and
// analytic vs numeric Jacobians.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>

#include "rgbdi/common/so3.h"
#include "rgbdi/loop/four_dof.h"
#include "rgbdi/loop/four_dof_factor.h"
#include "rgbdi/loop/yaw_manifold.h"

using namespace rgbdi;
using namespace rgbdi::loop;

namespace {

Eigen::Isometry3d tiltedPose(double x, double y, double z, double yaw, double pitch, double roll) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  T.translation() << x, y, z;
  return T;
}

// State of one edge: x_i, x_j = [px, py, pz, yaw].
struct EdgeState {
  Eigen::Vector4d x_i, x_j;
};

Eigen::Matrix<double, 4, 8> analytic(const FourDofEdgeFactor& f, const EdgeState& s) {
  const double* params[2] = {s.x_i.data(), s.x_j.data()};
  Eigen::Matrix<double, 4, 4, Eigen::RowMajor> Ji, Jj;
  double* jac[2] = {Ji.data(), Jj.data()};
  Eigen::Vector4d r;
  EXPECT_TRUE(f.Evaluate(params, r.data(), jac));
  Eigen::Matrix<double, 4, 8> J;
  J << Ji, Jj;
  return J;
}

// Central differences through NodeStateManifold::Plus.
Eigen::Matrix<double, 4, 8> numeric(const FourDofEdgeFactor& f, const EdgeState& s) {
  const NodeStateManifold m;
  const double h = 1e-6;
  Eigen::Matrix<double, 4, 8> J;
  for (int k = 0; k < 8; ++k) {
    EdgeState plus = s, minus = s;
    Eigen::Vector4d d = Eigen::Vector4d::Zero();
    d[k % 4] = h;
    const Eigen::Vector4d& x = k < 4 ? s.x_i : s.x_j;
    Eigen::Vector4d& xp = k < 4 ? plus.x_i : plus.x_j;
    Eigen::Vector4d& xm = k < 4 ? minus.x_i : minus.x_j;
    m.Plus(x.data(), d.data(), xp.data());
    d = -d;
    m.Plus(x.data(), d.data(), xm.data());
    J.col(k) = (f.residual(plus.x_i.data(), plus.x_j.data()) -
                f.residual(minus.x_i.data(), minus.x_j.data())) /
               (2 * h);
  }
  return J;
}

}  // namespace

TEST(WrapAngle, MapsEveryAngleIntoTheHalfOpenIntervalMinusPiToPi) {
  EXPECT_EQ(wrapAngle(0.3), 0.3);
  EXPECT_EQ(wrapAngle(M_PI), -M_PI);
  EXPECT_EQ(wrapAngle(-M_PI), -M_PI);
  EXPECT_NEAR(wrapAngle(1.5 * M_PI), -0.5 * M_PI, 1e-15);
  EXPECT_NEAR(wrapAngle(-7.0), -7.0 + 2.0 * M_PI, 1e-15);
  EXPECT_NEAR(wrapAngle(20.0 * M_PI + 0.25), 0.25, 1e-13);
  for (double a = -50.0; a < 50.0; a += 0.0137) {
    const double w = wrapAngle(a);
    EXPECT_GE(w, -M_PI);
    EXPECT_LT(w, M_PI);
    EXPECT_NEAR(std::remainder(w - a, 2.0 * M_PI), 0.0, 1e-12);
  }
  // Just below -pi rounds onto +pi in the naive formula; it must come back to -pi.
  EXPECT_LT(wrapAngle(std::nextafter(-M_PI, -4.0)), M_PI);
}

TEST(YawManifold, PlusAndMinusWrapAcrossPlusMinusPi) {
  const YawManifold m;
  EXPECT_EQ(m.AmbientSize(), 1);
  EXPECT_EQ(m.TangentSize(), 1);
  const double x = 3.1, d = 0.1;
  double y = 0.0;
  m.Plus(&x, &d, &y);
  EXPECT_NEAR(y, 3.2 - 2.0 * M_PI, 1e-15);
  double back = 0.0;
  m.Minus(&y, &x, &back);  // the short way round: +0.1, not 0.1 - 2 pi
  EXPECT_NEAR(back, 0.1, 1e-15);
  const double a = -3.1, b = 3.1;
  double diff = 0.0;
  m.Minus(&a, &b, &diff);
  EXPECT_NEAR(diff, 2.0 * M_PI - 6.2, 1e-15);
  double jp = 0.0, jm = 0.0;
  m.PlusJacobian(&x, &jp);
  m.MinusJacobian(&x, &jm);
  EXPECT_EQ(jp, 1.0);
  EXPECT_EQ(jm, 1.0);
}

TEST(NodeStateManifold, AddsPositionsAndWrapsTheYaw) {
  const NodeStateManifold m;
  EXPECT_EQ(m.AmbientSize(), 4);
  EXPECT_EQ(m.TangentSize(), 4);
  const Eigen::Vector4d x(1, 2, 3, 3.0), d(0.5, -1, 0, 0.3);
  Eigen::Vector4d y;
  m.Plus(x.data(), d.data(), y.data());
  EXPECT_EQ(y.head<3>(), Eigen::Vector3d(1.5, 1, 3));
  EXPECT_NEAR(y[3], 3.3 - 2.0 * M_PI, 1e-15);
  Eigen::Vector4d back;
  m.Minus(y.data(), x.data(), back.data());
  EXPECT_TRUE(back.isApprox(d, 1e-14));
}

TEST(FourDof, YawAndTiltRecomposeTheRotation) {
  const Eigen::Isometry3d T = tiltedPose(1, 2, 3, 2.5, 0.2, -0.1);
  EXPECT_NEAR(yawOf(T.linear()), 2.5, 1e-14);
  EXPECT_TRUE((rotZ(yawOf(T.linear())) * tiltOf(T.linear())).isApprox(T.linear(), 1e-14));
  EXPECT_NEAR(yawOf(tiltOf(T.linear())), 0.0, 1e-15);
}

TEST(FourDof, RelativePoseReducesToTranslationInTheYawFrameAndYawDifference) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < 50; ++k) {
    const Eigen::Isometry3d A =
        tiltedPose(5 * u(rng), 5 * u(rng), u(rng), M_PI * u(rng), 0.3 * u(rng), 0.3 * u(rng));
    const Eigen::Isometry3d B =
        tiltedPose(5 * u(rng), 5 * u(rng), u(rng), M_PI * u(rng), 0.3 * u(rng), 0.3 * u(rng));
    const FourDofDelta d = fourDofDelta(tiltOf(A.linear()), A.inverse() * B);
    const double ya = yawOf(A.linear()), yb = yawOf(B.linear());
    EXPECT_TRUE(d.t_m.isApprox(rotZ(ya).transpose() * (B.translation() - A.translation()), 1e-12));
    EXPECT_NEAR(d.yaw_rad, wrapAngle(yb - ya), 1e-12);
  }
}

TEST(FourDof, CorrectionMapsOnePoseOntoTheOther) {
  const Eigen::Vector3d ta(1, 2, 3), tb(-2, 0.5, 1);
  const Eigen::Isometry3d C = fourDofCorrection(ta, 3.0, tb, -3.0);
  EXPECT_TRUE((C * tb).isApprox(ta, 1e-14));
  EXPECT_NEAR(yawOf(C.linear()), 6.0 - 2.0 * M_PI, 1e-14);
  EXPECT_NEAR(C.linear()(2, 2), 1.0, 1e-15);
}

TEST(FourDofEdgeFactor, KnownResidual) {
  FourDofDelta m;  // identity measurement
  const FourDofEdgeFactor f(m, 0.5, 0.1);
  const Eigen::Vector4d x_i(0, 0, 0, 0), x_j(1, 0, 0, M_PI / 2);
  const Eigen::Vector4d r = f.residual(x_i.data(), x_j.data());
  EXPECT_NEAR(r[0], 2.0, 1e-15);
  EXPECT_EQ(r[1], 0.0);
  EXPECT_EQ(r[2], 0.0);
  EXPECT_NEAR(r[3], M_PI / 2 / 0.1, 1e-12);
  // Translation is compared in i's yaw frame: i turned by 90 deg sees j at (0, -1, 0).
  const Eigen::Vector4d y_i(0, 0, 0, -M_PI / 2), y_j(0, -1, 0, -M_PI / 2);
  const Eigen::Vector4d r2 = f.residual(y_i.data(), y_j.data());
  EXPECT_NEAR(r2[0], 2.0, 1e-15);
  EXPECT_NEAR(r2[1], 0.0, 1e-15);
  EXPECT_EQ(r2[3], 0.0);
}

TEST(FourDofEdgeFactor, ZeroAtTheMeasuredRelativePoseWhateverTheTilt) {
  const Eigen::Isometry3d A = tiltedPose(1, -2, 0.3, 3.0, 0.1, -0.2);
  const Eigen::Isometry3d B = tiltedPose(2, -1, 0.5, -3.0, -0.15, 0.05);
  const FourDofEdgeFactor f(fourDofDelta(tiltOf(A.linear()), A.inverse() * B), 0.01, 0.001);
  Eigen::Vector4d x_a, x_b;
  x_a << A.translation(), yawOf(A.linear());
  x_b << B.translation(), yawOf(B.linear());
  const Eigen::Vector4d r = f.residual(x_a.data(), x_b.data());
  EXPECT_LT(r.norm(), 1e-10);
}

TEST(FourDofEdgeFactor, AnalyticJacobiansMatchNumericOnes) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int k = 0; k < 40; ++k) {
    FourDofDelta m;
    m.t_m << u(rng), u(rng), 0.2 * u(rng);
    m.yaw_rad = M_PI * u(rng);
    const FourDofEdgeFactor f(m, 0.05 + 0.1 * std::abs(u(rng)), 0.01 + 0.05 * std::abs(u(rng)));
    EdgeState s;
    s.x_i << 10 * u(rng), 10 * u(rng), 10 * u(rng), M_PI * u(rng);
    s.x_j << 10 * u(rng), 10 * u(rng), 10 * u(rng), M_PI * u(rng);
    // Includes headings near +-pi, where the manifold wraps.
    if (k % 4 == 0) s.x_i[3] = M_PI - 1e-4;
    if (k % 4 == 1) s.x_j[3] = -M_PI + 1e-4;
    const Eigen::Matrix<double, 4, 8> Ja = analytic(f, s), Jn = numeric(f, s);
    EXPECT_LT((Ja - Jn).cwiseAbs().maxCoeff(), 1e-6 * std::max(1.0, Ja.cwiseAbs().maxCoeff()))
        << "case " << k << "\nanalytic\n"
        << Ja << "\nnumeric\n"
        << Jn;
  }
}

TEST(FourDofEdgeFactor, RejectsNonPositiveSigmas) {
  EXPECT_THROW(FourDofEdgeFactor(FourDofDelta{}, 0.0, 0.1), std::invalid_argument);
  EXPECT_THROW(FourDofEdgeFactor(FourDofDelta{}, 0.1, std::nan("")), std::invalid_argument);
}
