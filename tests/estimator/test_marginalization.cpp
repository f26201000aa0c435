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
#include "window_problem.h"

using namespace rgbdi;
using namespace rgbdi::estimator;
using rgbdi::test::RandomLinearCost;
using rgbdi::test::Term;
using rgbdi::test::WindowProblem;

namespace {

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
