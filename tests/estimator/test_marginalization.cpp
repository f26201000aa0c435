// Marginalisation with the inverse depths eliminated first (diagonal Schur complement) against a
// reference computed independently: Ceres' own evaluation of the stacked, loss-corrected Jacobian
// of every residual, H = J^T J, b = J^T r, and a dense Schur complement with an explicit inverse.
#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <memory>
#include <random>
#include <vector>

#include "rgbdi/common/so3.h"
#include "rgbdi/estimator/marginalization.h"
#include "rgbdi/estimator/pose_manifold.h"
#include "rgbdi/estimator/reprojection_factor.h"
#include "rgbdi/estimator/scalar_prior.h"

using namespace rgbdi;
using namespace rgbdi::estimator;

namespace {

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

struct Term {
  std::shared_ptr<ceres::CostFunction> cost;
  std::shared_ptr<ceres::LossFunction> loss;
  std::vector<double*> blocks;
};

/// The marginal prior's information and gradient, A = H_rr - H_rm H_mm^-1 H_mr and
/// b = g_r - H_rm H_mm^-1 g_m, from Ceres' Jacobian of all terms (columns: removed blocks, then
/// `kept` in the order given).
void referencePrior(const std::vector<Term>& terms, const std::vector<double*>& removed,
                    const std::vector<double*>& kept, const std::vector<double*>& constant,
                    const std::vector<double*>& poses, Eigen::MatrixXd* A, Eigen::VectorXd* b) {
  ceres::Problem::Options po;
  po.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  po.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(po);
  PoseManifold manifold;
  for (const Term& t : terms) problem.AddResidualBlock(t.cost.get(), t.loss.get(), t.blocks);
  for (double* p : poses) problem.SetManifold(p, &manifold);
  for (double* c : constant) problem.SetParameterBlockConstant(c);
  std::vector<double*> order = removed;
  order.insert(order.end(), kept.begin(), kept.end());
  ceres::Problem::EvaluateOptions eo;
  eo.parameter_blocks = order;
  std::vector<double> residuals;
  ceres::CRSMatrix crs;
  ASSERT_TRUE(problem.Evaluate(eo, nullptr, &residuals, nullptr, &crs));
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(crs.num_rows, crs.num_cols);
  for (int r = 0; r < crs.num_rows; ++r)
    for (int k = crs.rows[static_cast<size_t>(r)]; k < crs.rows[static_cast<size_t>(r) + 1]; ++k)
      J(r, crs.cols[static_cast<size_t>(k)]) = crs.values[static_cast<size_t>(k)];
  const Eigen::VectorXd res = Eigen::Map<const Eigen::VectorXd>(residuals.data(), crs.num_rows);
  const Eigen::MatrixXd H = J.transpose() * J;
  const Eigen::VectorXd g = J.transpose() * res;
  int m = 0;
  for (double* p : removed) m += problem.ParameterBlockTangentSize(p);
  const int n = crs.num_cols - m;
  const Eigen::MatrixXd Hmm_inv = H.topLeftCorner(m, m).inverse();
  *A = H.bottomRightCorner(n, n) - H.bottomLeftCorner(n, m) * Hmm_inv * H.topRightCorner(m, n);
  *b = g.tail(n) - H.bottomLeftCorner(n, m) * Hmm_inv * g.head(m);
}

/// A window-like problem: 4 frames (pose + speed/bias), the time offset, features anchored in
/// frame 0 seen by frames 1-3 (Cauchy loss), depth priors on some, dense couplings between
/// consecutive frames and a dense term on the kept blocks (the previous prior).
struct WindowProblem {
  double pose[4][7];
  double sb[4][9];
  double td[1] = {0.003};
  std::vector<double> inv_depth;
  std::vector<Term> terms;

  WindowProblem(int n_features, std::uint64_t seed) : inv_depth(static_cast<size_t>(n_features)) {
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

void expectSamePrior(const MarginalizationInfo& info, const Eigen::MatrixXd& A_ref,
                     const Eigen::VectorXd& b_ref) {
  const Eigen::MatrixXd& Jp = info.jacobian();
  const Eigen::MatrixXd A = Jp.transpose() * Jp;
  const Eigen::VectorXd b = Jp.transpose() * info.residual();
  ASSERT_EQ(A.rows(), A_ref.rows());
  EXPECT_LE((A - A_ref).norm(), 1e-9 * A_ref.norm());
  EXPECT_LE((b - b_ref).norm(), 1e-9 * std::max(1.0, b_ref.norm()));
}

}  // namespace

TEST(Marginalization, EliminatingInverseDepthsFirstEqualsTheDenseSchurComplement) {
  WindowProblem w(40, 11);
  MarginalizationInfo info;
  std::set<const double*> remove{w.pose[0], w.sb[0]};
  for (double& d : w.inv_depth) remove.insert(&d);
  for (const Term& t : w.terms) info.add({t.cost, t.loss, t.blocks});
  ASSERT_TRUE(info.marginalize(remove, {}));

  // Kept blocks in first-seen order: pose1, td, pose2, pose3, then the speed/bias blocks.
  const std::vector<double*> kept{w.pose[1], w.td, w.pose[2], w.pose[3], w.sb[1], w.sb[2], w.sb[3]};
  ASSERT_EQ(info.keptBlocks(), kept);
  std::vector<double*> removed{w.pose[0], w.sb[0]};
  for (double& d : w.inv_depth) removed.push_back(&d);
  Eigen::MatrixXd A_ref;
  Eigen::VectorXd b_ref;
  referencePrior(w.terms, removed, kept, {}, {w.pose[0], w.pose[1], w.pose[2], w.pose[3]}, &A_ref,
                 &b_ref);
  expectSamePrior(info, A_ref, b_ref);
}

TEST(Marginalization, ConstantInverseDepthsStayOutOfThePrior) {
  WindowProblem w(30, 12);
  MarginalizationInfo info;
  std::set<const double*> remove{w.pose[0], w.sb[0]};
  std::set<const double*> constant;
  std::vector<double*> removed{w.pose[0], w.sb[0]}, constant_list;
  for (size_t i = 0; i < w.inv_depth.size(); ++i) {
    if (i % 4 == 1) {
      constant.insert(&w.inv_depth[i]);
      constant_list.push_back(&w.inv_depth[i]);
    } else {
      remove.insert(&w.inv_depth[i]);
      removed.push_back(&w.inv_depth[i]);
    }
  }
  for (const Term& t : w.terms) info.add({t.cost, t.loss, t.blocks});
  ASSERT_TRUE(info.marginalize(remove, constant));
  const std::vector<double*> kept{w.pose[1], w.td, w.pose[2], w.pose[3], w.sb[1], w.sb[2], w.sb[3]};
  ASSERT_EQ(info.keptBlocks(), kept);
  Eigen::MatrixXd A_ref;
  Eigen::VectorXd b_ref;
  referencePrior(w.terms, removed, kept, constant_list,
                 {w.pose[0], w.pose[1], w.pose[2], w.pose[3]}, &A_ref, &b_ref);
  expectSamePrior(info, A_ref, b_ref);
}

TEST(Marginalization, RemovedScalarsSharingAResidualAreEliminatedDensely) {
  // Two removed inverse depths in one residual are not independent: both must go through the
  // dense elimination, and the result still equals the reference.
  WindowProblem w(20, 13);
  std::mt19937_64 rng(14);
  w.terms.push_back({std::make_shared<RandomLinearCost>(std::vector<int>{1, 1, 7}, 3, rng),
                     nullptr,
                     {&w.inv_depth[0], &w.inv_depth[1], w.pose[1]}});
  MarginalizationInfo info;
  std::set<const double*> remove{w.pose[0], w.sb[0]};
  std::vector<double*> removed{w.pose[0], w.sb[0]};
  for (double& d : w.inv_depth) {
    remove.insert(&d);
    removed.push_back(&d);
  }
  for (const Term& t : w.terms) info.add({t.cost, t.loss, t.blocks});
  ASSERT_TRUE(info.marginalize(remove, {}));
  const std::vector<double*> kept{w.pose[1], w.td, w.pose[2], w.pose[3], w.sb[1], w.sb[2], w.sb[3]};
  ASSERT_EQ(info.keptBlocks(), kept);
  Eigen::MatrixXd A_ref;
  Eigen::VectorXd b_ref;
  referencePrior(w.terms, removed, kept, {}, {w.pose[0], w.pose[1], w.pose[2], w.pose[3]}, &A_ref,
                 &b_ref);
  expectSamePrior(info, A_ref, b_ref);
}

TEST(Marginalization, APriorMarginalisedAgainEqualsTheDenseSchurComplement) {
  // The non-keyframe path: a pose removed from an earlier prior, the prior its only residual.
  WindowProblem w(25, 15);
  auto first = std::make_shared<MarginalizationInfo>();
  std::set<const double*> remove{w.pose[0], w.sb[0]};
  for (double& d : w.inv_depth) remove.insert(&d);
  for (const Term& t : w.terms) first->add({t.cost, t.loss, t.blocks});
  ASSERT_TRUE(first->marginalize(remove, {}));
  // Move away from the linearisation point so that the prior's residual is not zero.
  w.pose[2][0] += 0.01;
  w.sb[3][4] -= 0.02;
  auto prior_cost = std::make_shared<MarginalizationFactor>(first);
  MarginalizationInfo second;
  second.add({prior_cost, nullptr, first->keptBlocks()});
  ASSERT_TRUE(second.marginalize({w.pose[2]}, {}));
  const std::vector<double*> kept{w.pose[1], w.td, w.pose[3], w.sb[1], w.sb[2], w.sb[3]};
  ASSERT_EQ(second.keptBlocks(), kept);
  Eigen::MatrixXd A_ref;
  Eigen::VectorXd b_ref;
  referencePrior({{prior_cost, nullptr, first->keptBlocks()}}, {w.pose[2]}, kept, {},
                 {w.pose[1], w.pose[2], w.pose[3]}, &A_ref, &b_ref);
  expectSamePrior(second, A_ref, b_ref);
}
