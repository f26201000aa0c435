// A window-like least-squares problem for the marginalisation and window-solver tests: 4 frames
// (pose + speed/bias), the time offset, features anchored in frame 0 seen by frames 1-3 (Cauchy
// loss), depth priors on some, dense random couplings between consecutive frames and a dense
// term on the later blocks (standing in for the IMU factors and a previous prior).
#pragma once

#include <ceres/ceres.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <memory>
#include <random>
#include <vector>

#include "rgbdi/common/so3.h"
#include "rgbdi/estimator/reprojection_factor.h"
#include "rgbdi/estimator/scalar_prior.h"

namespace rgbdi::test {

using estimator::FeatureMeasurement;
using estimator::ReprojectionFactor;
using estimator::ScalarPrior;

using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// r = sum_k A_k x_k - c with fixed random A_k (pose blocks: the 7th column is zero, the
/// convention of every rgbdi factor); a stand-in for the IMU factor and other dense couplings.
class RandomLinearCost final : public ceres::CostFunction {
 public:
  RandomLinearCost(const std::vector<int>& sizes, int rows, std::mt19937_64& rng) {
    std::normal_distribution<double> n(0.0, 1.0);
    set_num_residuals(rows);
    for (int s : sizes) {
      mutable_parameter_block_sizes()->push_back(s);
      RowMajor A(rows, s);
      for (int i = 0; i < rows; ++i)
        for (int j = 0; j < s; ++j) A(i, j) = (s == 7 && j == 6) ? 0.0 : n(rng);
      A_.push_back(A);
    }
    c_ = Eigen::VectorXd(rows);
    for (int i = 0; i < rows; ++i) c_[i] = n(rng);
  }
  bool Evaluate(double const* const* p, double* res, double** jac) const override {
    Eigen::Map<Eigen::VectorXd> r(res, num_residuals());
    r = -c_;
    for (size_t k = 0; k < A_.size(); ++k) {
      r += A_[k] * Eigen::Map<const Eigen::VectorXd>(p[k], A_[k].cols());
      if (jac && jac[k]) Eigen::Map<RowMajor>(jac[k], A_[k].rows(), A_[k].cols()) = A_[k];
    }
    return true;
  }

 private:
  std::vector<RowMajor> A_;
  Eigen::VectorXd c_;
};

/// r = [p - p0; 2 vec(q0^-1 q)] / sigma on a pose block, with the Jacobian of a right-multiplied
/// rotation perturbation (PoseManifold's tangent), so that the problem is consistent and a
/// solver converges quadratically near its minimum.
class PosePrior final : public ceres::SizedCostFunction<6, 7> {
 public:
  PosePrior(const Eigen::Vector3d& p0, const Eigen::Quaterniond& q0, double sigma)
      : p0_(p0), q0_(q0), w_(1.0 / sigma) {}
  bool Evaluate(double const* const* x, double* r, double** J) const override {
    const Eigen::Vector3d p(x[0][0], x[0][1], x[0][2]);
    const Eigen::Quaterniond q(x[0][6], x[0][3], x[0][4], x[0][5]);
    const Eigen::Quaterniond e = q0_.conjugate() * q;
    Eigen::Map<Eigen::Matrix<double, 6, 1>> res(r);
    res.head<3>() = w_ * (p - p0_);
    res.tail<3>() = 2.0 * w_ * e.vec();
    if (J && J[0]) {
      Eigen::Map<Eigen::Matrix<double, 6, 7, Eigen::RowMajor>> Jp(J[0]);
      Jp.setZero();
      Jp.block<3, 3>(0, 0) = w_ * Eigen::Matrix3d::Identity();
      Jp.block<3, 3>(3, 3) = w_ * (e.w() * Eigen::Matrix3d::Identity() + skew(e.vec()));
    }
    return true;
  }

 private:
  Eigen::Vector3d p0_;
  Eigen::Quaterniond q0_;
  double w_;
};

struct Term {
  std::shared_ptr<ceres::CostFunction> cost;
  std::shared_ptr<ceres::LossFunction> loss;
  std::vector<double*> blocks;
};

struct WindowProblem {
  double pose[4][7];
  double sb[4][9];
  double td[1] = {0.003};
  std::vector<double> inv_depth;
  std::vector<Term> terms;

  /// kLinear: random linear terms on poses too (a stand-in that is linear in the quaternion's
  /// numbers, enough for linearisation tests); kPriors: consistent pose priors instead, random
  /// linear terms only on speed/bias and time offset (for solver tests that iterate).
  enum class PoseTerms { kLinear, kPriors };

  WindowProblem(int n_features, std::uint64_t seed, PoseTerms pose_terms = PoseTerms::kLinear)
      : inv_depth(static_cast<size_t>(n_features)) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> n(0.0, 1.0);
    Eigen::Isometry3d T_bc = Eigen::Isometry3d::Identity();
    T_bc.linear() = expSO3(Eigen::Vector3d(-1.2, 0.0, -1.2));
    T_bc.translation() << 0.03, 0.01, -0.02;
    std::vector<Eigen::Isometry3d> T(4);
    for (int f = 0; f < 4; ++f) {
      T[f] = Eigen::Isometry3d::Identity();
      T[f].linear() = expSO3(Eigen::Vector3d(0.02 * f, -0.03 * f, 0.05 * f));
      T[f].translation() << 0.1 * f, 0.05 * f, 0.02 * f;
      const Eigen::Quaterniond q(T[f].rotation());
      const double x[7] = {T[f].translation().x(),
                           T[f].translation().y(),
                           T[f].translation().z(),
                           q.x(),
                           q.y(),
                           q.z(),
                           q.w()};
      std::copy(x, x + 7, pose[f]);
      for (double& v : sb[f]) v = 0.1 * n(rng);
    }
    auto cauchy = std::make_shared<ceres::CauchyLoss>(1.0);
    for (int i = 0; i < n_features; ++i) {
      const Eigen::Vector3d p_c0(0.8 * n(rng), 0.6 * n(rng), 2.0 + std::abs(n(rng)));
      const Eigen::Vector3d p_w = T[0] * T_bc * p_c0;
      // Perturbed depth and noisy observations: non-zero residuals, some in the robust range.
      inv_depth[static_cast<size_t>(i)] = (1.0 + 0.05 * n(rng)) / p_c0.z();
      FeatureMeasurement o0;
      o0.xn = p_c0 / p_c0.z();
      o0.velocity << 0.2 * n(rng), 0.2 * n(rng);
      for (int f = 1; f < 4; ++f) {
        const Eigen::Vector3d p_cf = (T[f] * T_bc).inverse() * p_w;
        FeatureMeasurement of;
        of.xn = p_cf / p_cf.z();
        of.xn.head<2>() += Eigen::Vector2d(n(rng), n(rng)) * (i % 5 == 0 ? 0.02 : 0.003);
        of.velocity << 0.2 * n(rng), 0.2 * n(rng);
        terms.push_back({std::make_shared<ReprojectionFactor>(o0, of, T_bc, 460.0 / 1.5),
                         cauchy,
                         {pose[0], pose[f], &inv_depth[static_cast<size_t>(i)], td}});
      }
      if (i % 3 == 0)
        terms.push_back({std::make_shared<ScalarPrior>(1.0 / p_c0.z(), 0.01),
                         nullptr,
                         {&inv_depth[static_cast<size_t>(i)]}});
    }
    if (pose_terms == PoseTerms::kPriors) {
      for (int f = 0; f < 4; ++f) {
        const Eigen::Vector3d dp(n(rng), n(rng), n(rng)), dth(n(rng), n(rng), n(rng));
        terms.push_back({std::make_shared<PosePrior>(
                             T[f].translation() + 0.02 * dp,
                             Eigen::Quaterniond(T[f].rotation() * expSO3(0.01 * dth)), 0.05),
                         nullptr,
                         {pose[f]}});
      }
      for (int f = 1; f < 4; ++f)
        terms.push_back({std::make_shared<RandomLinearCost>(std::vector<int>{9, 9}, 15, rng),
                         nullptr,
                         {sb[f - 1], sb[f]}});
      terms.push_back({std::make_shared<RandomLinearCost>(std::vector<int>{9, 9, 9, 1}, 40, rng),
                       nullptr,
                       {sb[0], sb[1], sb[2], td}});
      return;
    }
    for (int f = 1; f < 4; ++f)
      terms.push_back({std::make_shared<RandomLinearCost>(std::vector<int>{7, 9, 7, 9}, 15, rng),
                       nullptr,
                       {pose[f - 1], sb[f - 1], pose[f], sb[f]}});
    // Information on every kept block, so that the marginal is full rank (the reference inverts).
    terms.push_back(
        {std::make_shared<RandomLinearCost>(std::vector<int>{7, 9, 7, 9, 7, 9, 1}, 50, rng),
         nullptr,
         {pose[1], sb[1], pose[2], sb[2], pose[3], sb[3], td}});
  }
};

}  // namespace rgbdi::test
