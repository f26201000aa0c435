// Reprojection factor, pose manifold and marginalisation: analytic vs numeric Jacobians and
// known-answer checks.
#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include <random>

#include "factor_jacobians.h"
#include "rgbdi/common/so3.h"
#include "rgbdi/estimator/gauge_prior.h"
#include "rgbdi/estimator/marginalization.h"
#include "rgbdi/estimator/pose_manifold.h"
#include "rgbdi/estimator/reprojection_factor.h"
#include "rgbdi/estimator/scalar_prior.h"

using namespace rgbdi;
using namespace rgbdi::estimator;
using rgbdi::test::analyticJacobian;
using rgbdi::test::numericJacobian;

namespace {

Eigen::Matrix<double, 7, 1> randomPose(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Matrix<double, 7, 1> x;
  x.head<3>() << n(rng), n(rng), n(rng);
  const Eigen::Quaterniond q = expQuat(Eigen::Vector3d(n(rng), n(rng), n(rng)) * 0.5);
  x.tail<4>() = q.coeffs();
  return x;
}

}  // namespace

TEST(PoseManifold, PlusMinusRoundTrip) {
  std::mt19937_64 rng(3);
  PoseManifold m;
  for (int t = 0; t < 20; ++t) {
    auto x = randomPose(rng);
    Eigen::Matrix<double, 6, 1> d;
    d << 0.1, -0.2, 0.3, 0.05, -0.4, 0.2;
    Eigen::Matrix<double, 7, 1> y;
    m.Plus(x.data(), d.data(), y.data());
    Eigen::Matrix<double, 6, 1> back;
    m.Minus(y.data(), x.data(), back.data());
    EXPECT_TRUE(back.isApprox(d, 1e-12));
    EXPECT_NEAR(Eigen::Map<Eigen::Quaterniond>(y.data() + 3).norm(), 1.0, 1e-12);
  }
}

TEST(ReprojectionFactor, ZeroResidualAtTruthAndJacobiansMatchNumeric) {
  std::mt19937_64 rng(7);
  Eigen::Isometry3d T_bc = Eigen::Isometry3d::Identity();
  T_bc.linear() = expSO3(Eigen::Vector3d(-1.2, 0.1, -1.5));
  T_bc.translation() << 0.02, 0.015, -0.01;
  for (int trial = 0; trial < 20; ++trial) {
    auto pi = randomPose(rng), pj = randomPose(rng);
    // Place a point in front of camera i, express its observation in camera j.
    Eigen::Isometry3d Ti = Eigen::Isometry3d::Identity(), Tj = Eigen::Isometry3d::Identity();
    Ti.linear() = Eigen::Quaterniond(pi.tail<4>()).toRotationMatrix();
    Ti.translation() = pi.head<3>();
    // Camera j close to camera i so the point is visible in both.
    Tj.linear() = Ti.rotation() * expSO3(Eigen::Vector3d(0.05, -0.03, 0.08));
    Tj.translation() = Ti.translation() + Eigen::Vector3d(0.2, -0.1, 0.05);
    pj.head<3>() = Tj.translation();
    pj.tail<4>() = Eigen::Quaterniond(Tj.rotation()).coeffs();
    const Eigen::Vector3d p_ci(0.3, -0.2, 2.5);
    const Eigen::Vector3d p_cj = (Tj * T_bc).inverse() * ((Ti * T_bc) * p_ci);
    ASSERT_GT(p_cj.z(), 0.5);
    FeatureMeasurement oi, oj;
    oi.xn = p_ci / p_ci.z();
    oj.xn = p_cj / p_cj.z();
    oi.velocity << 0.3, -0.1;
    oj.velocity << -0.2, 0.4;
    oi.td_at_stamp = 0.004;
    oj.td_at_stamp = 0.004;
    ReprojectionFactor f(oi, oj, T_bc, 460.0 / 1.5);
    std::vector<std::vector<double>> params = {std::vector<double>(pi.data(), pi.data() + 7),
                                               std::vector<double>(pj.data(), pj.data() + 7),
                                               {1.0 / p_ci.z()},
                                               {0.004}};
    // At the truth (td equal to the stamping offset) the residual is zero.
    std::vector<const double*> ptrs;
    for (auto& v : params) ptrs.push_back(v.data());
    Eigen::Vector2d r;
    f.Evaluate(ptrs.data(), r.data(), nullptr);
    EXPECT_LT(r.norm(), 1e-9);
    // Jacobians at a perturbed point.
    params[2][0] *= 1.1;
    params[3][0] = 0.011;
    // A factor made for other measurements and another extrinsic, then reset to these, is this
    // factor value for value (the estimator reuses its factors from update to update).
    FeatureMeasurement other;
    other.xn = Eigen::Vector3d(0.1, 0.2, 1.0);
    ReprojectionFactor reused(other, other, Eigen::Isometry3d::Identity(), 1.0);
    reused.reset(oi, oj, T_bc, 460.0 / 1.5);
    for (int b = 0; b < 4; ++b) {
      const Eigen::MatrixXd Ja = analyticJacobian(f, params, b);
      const Eigen::MatrixXd Jn = numericJacobian(f, params, b);
      EXPECT_LT((Ja - Jn).norm(), 1e-5 * std::max(1.0, Jn.norm())) << "block " << b << "\n"
                                                                   << Ja << "\n"
                                                                   << Jn;
      EXPECT_EQ(analyticJacobian(reused, params, b), Ja) << "block " << b;
    }
  }
}

namespace {
/// r = A x - b on one 2-D block and one 1-D block: a linear problem with a known marginal.
class LinearCost final : public ceres::SizedCostFunction<3, 2, 1> {
 public:
  LinearCost(const Eigen::Matrix<double, 3, 3>& A, const Eigen::Vector3d& b) : A_(A), b_(b) {}
  bool Evaluate(double const* const* p, double* res, double** jac) const override {
    const Eigen::Vector3d x(p[0][0], p[0][1], p[1][0]);
    Eigen::Map<Eigen::Vector3d> r(res);
    r = A_ * x - b_;
    if (jac) {
      if (jac[0]) {
        Eigen::Map<Eigen::Matrix<double, 3, 2, Eigen::RowMajor>> J0(jac[0]);
        J0 = A_.leftCols<2>();
      }
      if (jac[1]) {
        Eigen::Map<Eigen::Vector3d> J1(jac[1]);
        J1 = A_.col(2);
      }
    }
    return true;
  }

 private:
  Eigen::Matrix<double, 3, 3> A_;
  Eigen::Vector3d b_;
};
}  // namespace

TEST(Marginalization, SchurComplementOfLinearProblemIsExact) {
  Eigen::Matrix3d A;
  A << 2, 1, 0.5, -1, 3, 1, 0.2, 0.4, 1.5;
  const Eigen::Vector3d b(1, -2, 0.5);
  double x2[2] = {0.3, -0.1};  // kept
  double x1[1] = {0.7};        // removed
  MarginalizationInfo info;
  info.add({std::make_shared<LinearCost>(A, b), nullptr, {x2, x1}});
  ASSERT_TRUE(info.marginalize({x1}, {}));
  // Expected: H = A^T A; prior Hessian on x2 = H22 - H21 H11^-1 H12 (x1 is the 3rd variable).
  const Eigen::Matrix3d H = A.transpose() * A;
  const Eigen::Matrix2d expected = H.topLeftCorner<2, 2>() - H.topRightCorner<2, 1>() *
                                                                 (1.0 / H(2, 2)) *
                                                                 H.bottomLeftCorner<1, 2>();
  const Eigen::MatrixXd Jp = info.jacobian();
  EXPECT_TRUE((Jp.transpose() * Jp).isApprox(expected, 1e-9));
  // The prior's minimum equals the minimiser of the full problem over x2.
  const Eigen::Vector3d x_full = A.colPivHouseholderQr().solve(b);
  MarginalizationFactor prior(std::make_shared<MarginalizationInfo>(info));
  double y[2] = {x_full[0], x_full[1]};
  const double* ptr[1] = {y};
  Eigen::VectorXd r(prior.num_residuals());
  prior.Evaluate(ptr, r.data(), nullptr);
  EXPECT_LT(r.norm(), 1e-9);
}

TEST(Marginalization, ConstantBlocksAreNotMarginalised) {
  Eigen::Matrix3d A;
  A << 1, 0, 2, 0, 1, -1, 1, 1, 1;
  const Eigen::Vector3d b(0.5, 0.1, -0.3);
  double x2[2] = {0.0, 0.0};
  double c[1] = {0.4};  // held constant
  MarginalizationInfo info;
  info.add({std::make_shared<LinearCost>(A, b), nullptr, {x2, c}});
  ASSERT_TRUE(info.marginalize({}, {c}));
  // With c constant the prior is the plain least-squares Hessian of x2: A[:, :2]^T A[:, :2].
  const Eigen::MatrixXd Jp = info.jacobian();
  const Eigen::Matrix2d expected = A.leftCols<2>().transpose() * A.leftCols<2>();
  EXPECT_TRUE((Jp.transpose() * Jp).isApprox(expected, 1e-9));
  ASSERT_EQ(info.keptBlocks().size(), 1u);
}

TEST(GaugePrior, ZeroAtAnchorAndJacobianMatchesNumeric) {
  std::mt19937_64 rng(5);
  for (int t = 0; t < 10; ++t) {
    auto x = randomPose(rng);
    GaugePrior f(x.data(), 100.0);
    std::vector<std::vector<double>> params = {std::vector<double>(x.data(), x.data() + 7)};
    std::vector<const double*> ptrs = {params[0].data()};
    Eigen::Vector4d r;
    f.Evaluate(ptrs.data(), r.data(), nullptr);
    EXPECT_LT(r.norm(), 1e-12);
    // Roll/pitch changes about world x leave position and yaw residuals at zero to first order
    // only when level; check the Jacobian numerically at a perturbed state instead.
    params[0][0] += 0.1;
    const Eigen::MatrixXd Ja = analyticJacobian(f, params, 0);
    const Eigen::MatrixXd Jn = numericJacobian(f, params, 0);
    EXPECT_LT((Ja - Jn).norm(), 1e-4 * Jn.norm()) << Ja << "\n" << Jn;
  }
}
