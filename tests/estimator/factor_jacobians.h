// Analytic and numeric Jacobians of a Ceres cost function at given parameter blocks, for the
// factor tests (7-blocks are poses: the numeric Jacobian is taken along PoseManifold's tangent).
#pragma once

#include <ceres/cost_function.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <random>
#include <vector>

#include "rgbdi/estimator/pose_manifold.h"

namespace rgbdi::test {

using Params = std::vector<std::vector<double>>;

/// The pose parameter block of T (x y z qx qy qz qw, PoseManifold's layout).
inline std::vector<double> poseBlock(const Eigen::Isometry3d& T) {
  const Eigen::Quaterniond q(T.rotation());
  return {
      T.translation().x(), T.translation().y(), T.translation().z(), q.x(), q.y(), q.z(), q.w()};
}

/// Moves the first `count` blocks of p (poses) by a tangent step drawn from `n`, so that a
/// Jacobian is checked away from the point the data was made at.
template <class Rng>
void perturbPoses(Params& p, Rng& rng, std::normal_distribution<double>& n, std::size_t count = 2) {
  for (std::size_t b = 0; b < count; ++b) {
    rgbdi::estimator::PoseManifold m;
    const Eigen::Matrix<double, 6, 1> d =
        Eigen::Matrix<double, 6, 1>::NullaryExpr([&] { return n(rng); });
    std::vector<double> out(7);
    m.Plus(p[b].data(), d.data(), out.data());
    p[b] = out;
  }
}

inline Eigen::VectorXd evaluateResidual(const ceres::CostFunction& f, const Params& params) {
  std::vector<const double*> ptrs;
  for (const auto& v : params) ptrs.push_back(v.data());
  Eigen::VectorXd r(f.num_residuals());
  f.Evaluate(ptrs.data(), r.data(), nullptr);
  return r;
}

/// Central differences with step 1e-6 along each tangent direction of block b.
inline Eigen::MatrixXd numericJacobian(const ceres::CostFunction& f, const Params& params, int b) {
  const std::size_t bi = static_cast<std::size_t>(b);
  const int size = static_cast<int>(params[bi].size());
  const int tangent = size == 7 ? 6 : size;
  Eigen::MatrixXd J(f.num_residuals(), tangent);
  const double h = 1e-6;
  for (int k = 0; k < tangent; ++k) {
    Params plus = params, minus = params;
    Eigen::VectorXd d = Eigen::VectorXd::Zero(tangent);
    if (size == 7) {
      estimator::PoseManifold m;
      d[k] = h;
      m.Plus(params[bi].data(), d.data(), plus[bi].data());
      d[k] = -h;
      m.Plus(params[bi].data(), d.data(), minus[bi].data());
    } else {
      plus[bi][static_cast<std::size_t>(k)] += h;
      minus[bi][static_cast<std::size_t>(k)] -= h;
    }
    J.col(k) = (evaluateResidual(f, plus) - evaluateResidual(f, minus)) / (2 * h);
  }
  return J;
}

/// The cost function's own Jacobian of block b (the tangent columns of a pose block).
inline Eigen::MatrixXd analyticJacobian(const ceres::CostFunction& f, const Params& params, int b) {
  std::vector<const double*> ptrs;
  std::vector<std::vector<double>> jac;
  std::vector<double*> jptrs;
  for (const auto& v : params) {
    ptrs.push_back(v.data());
    jac.emplace_back(static_cast<std::size_t>(f.num_residuals()) * v.size());
  }
  for (auto& j : jac) jptrs.push_back(j.data());
  Eigen::VectorXd r(f.num_residuals());
  f.Evaluate(ptrs.data(), r.data(), jptrs.data());
  const std::size_t bi = static_cast<std::size_t>(b);
  const int size = static_cast<int>(params[bi].size());
  Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> J(
      jac[bi].data(), f.num_residuals(), size);
  return J.leftCols(size == 7 ? 6 : size);
}

}  // namespace rgbdi::test
