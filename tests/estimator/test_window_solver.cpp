// The window solver against ceres::Solve on the same problems (the window-like problem of the
// marginalisation tests, with and without a marginalisation prior), against the closed-form
// solution of a linear problem, and on its bounds, step limit, failures and refusals.
#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <memory>
#include <random>
#include <set>
#include <stdexcept>
#include <vector>

#include "rgbdi/estimator/marginalization.h"
#include "rgbdi/estimator/pose_manifold.h"
#include "rgbdi/estimator/scalar_prior.h"
#include "rgbdi/estimator/window_solver.h"
#include "window_problem.h"

using namespace rgbdi;
using namespace rgbdi::estimator;
using rgbdi::test::RandomLinearCost;
using rgbdi::test::Term;
using rgbdi::test::WindowProblem;

namespace {

/// Every value of the problem's variables, for comparisons.
Eigen::VectorXd values(const WindowProblem& w) {
  std::vector<double> v;
  for (const auto& p : w.pose) v.insert(v.end(), p, p + 7);
  for (const auto& b : w.sb) v.insert(v.end(), b, b + 9);
  v.push_back(w.td[0]);
  v.insert(v.end(), w.inv_depth.begin(), w.inv_depth.end());
  return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}

void addToSolver(WindowProblem& w, WindowSolver& solver) {
  for (auto& p : w.pose) solver.addFrameBlock(p, 7);
  for (auto& b : w.sb) solver.addFrameBlock(b, 9);
  solver.addFrameBlock(w.td, 1);
  for (double& d : w.inv_depth) solver.addEliminatedScalar(&d);
  for (const Term& t : w.terms) solver.addResidual(t.cost.get(), t.loss.get(), t.blocks);
}

/// Ceres on the same problem, converged tightly; returns its final cost.
double solveWithCeres(WindowProblem& w, const std::shared_ptr<MarginalizationInfo>& prior) {
  ceres::Problem::Options po;
  po.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  po.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(po);
  PoseManifold manifold;
  for (const Term& t : w.terms) problem.AddResidualBlock(t.cost.get(), t.loss.get(), t.blocks);
  MarginalizationFactor prior_factor(prior ? prior : std::make_shared<MarginalizationInfo>());
  if (prior) problem.AddResidualBlock(&prior_factor, nullptr, prior->keptBlocks());
  for (auto& p : w.pose) problem.SetManifold(p, &manifold);
  ceres::Solver::Options so;
  so.linear_solver_type = ceres::DENSE_SCHUR;
  so.max_num_iterations = 100;
  so.function_tolerance = 1e-10;
  so.gradient_tolerance = 1e-14;
  so.parameter_tolerance = 1e-12;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  EXPECT_EQ(summary.termination_type, ceres::CONVERGENCE) << summary.BriefReport();
  return summary.final_cost;
}

WindowSolverOptions tight() {
  WindowSolverOptions o;
  o.max_iterations = 100;
  o.function_tolerance = 1e-10;
  o.gradient_tolerance = 1e-14;
  o.parameter_tolerance = 1e-12;
  return o;
}

/// A prior made by marginalising frame 0 and every inverse depth of another instance of the
/// same problem, moved onto `w`'s blocks.
std::shared_ptr<MarginalizationInfo> priorFor(WindowProblem& w, int n_features,
                                              std::uint64_t seed) {
  WindowProblem other(n_features, seed);
  auto info = std::make_shared<MarginalizationInfo>();
  std::set<const double*> remove{other.pose[0], other.sb[0]};
  for (double& d : other.inv_depth) remove.insert(&d);
  for (const Term& t : other.terms) info->add({t.cost, t.loss, t.blocks});
  EXPECT_TRUE(info->marginalize(remove, {}));
  std::unordered_map<const double*, double*> remap;
  for (int f = 0; f < 4; ++f) {
    remap[other.pose[f]] = w.pose[f];
    remap[other.sb[f]] = w.sb[f];
  }
  remap[other.td] = w.td;
  info->remapBlocks(remap);
  return info;
}

}  // namespace

TEST(WindowSolver, ReachesCeresMinimumOnAWindowProblem) {
  for (std::uint64_t seed : {21u, 22u, 23u}) {
    WindowProblem ours(40, seed, WindowProblem::PoseTerms::kPriors);
    WindowProblem ceres_run(40, seed, WindowProblem::PoseTerms::kPriors);
    ASSERT_EQ(values(ours), values(ceres_run));
    WindowSolver solver;
    addToSolver(ours, solver);
    const WindowSolverSummary s = solver.solve(tight());
    const double ceres_cost = solveWithCeres(ceres_run, nullptr);
    EXPECT_EQ(s.termination, WindowSolverSummary::Termination::kConvergence) << s.message;
    EXPECT_LT(s.final_cost, s.initial_cost);
    EXPECT_NEAR(s.final_cost, ceres_cost, 1e-9 * ceres_cost) << "seed " << seed;
    // Both stop on the function tolerance (1e-10): values agree to what that leaves open along
    // the weakest direction (the time offset and far inverse depths).
    EXPECT_LE((values(ours) - values(ceres_run)).cwiseAbs().maxCoeff(), 3e-5) << "seed " << seed;
  }
}

TEST(WindowSolver, ReachesCeresMinimumWithAMarginalisationPrior) {
  WindowProblem ours(30, 31), ceres_run(30, 31);
  // The prior is linearised elsewhere; move the problem away from it so that it pulls.
  for (WindowProblem* w : {&ours, &ceres_run}) {
    w->pose[2][0] += 0.05;
    w->sb[3][4] -= 0.1;
    w->td[0] += 0.002;
  }
  const auto prior_ours = priorFor(ours, 30, 32);
  const auto prior_ceres = priorFor(ceres_run, 30, 32);
  WindowSolver solver;
  addToSolver(ours, solver);
  solver.addPrior(prior_ours);
  const WindowSolverSummary s = solver.solve(tight());
  const double ceres_cost = solveWithCeres(ceres_run, prior_ceres);
  EXPECT_EQ(s.termination, WindowSolverSummary::Termination::kConvergence) << s.message;
  EXPECT_NEAR(s.final_cost, ceres_cost, 1e-9 * ceres_cost);
  EXPECT_LE((values(ours) - values(ceres_run)).cwiseAbs().maxCoeff(), 3e-5);
}

TEST(WindowSolver, SolvesALinearProblemToItsClosedForm) {
  // r = A1 x1 + A2 x2 + a s - c over two Euclidean blocks and an eliminated scalar, plus scalar
  // terms on s: the minimum is the least-squares solution of the stacked system.
  std::mt19937_64 rng(5);
  double x1[3] = {0, 0, 0}, x2[4] = {0, 0, 0, 0}, s[1] = {0};
  RandomLinearCost joint({3, 4, 1}, 12, rng), on_s({1}, 2, rng);
  WindowSolver solver;
  solver.addFrameBlock(x1, 3);
  solver.addFrameBlock(x2, 4);
  solver.addEliminatedScalar(s);
  solver.addResidual(&joint, nullptr, {x1, x2, s});
  solver.addResidual(&on_s, nullptr, {s});
  // Gauss-Newton is exact on a linear problem: the first step lands within its damping (1e-8)
  // (checked below on the values after one step), each further one gains as much again.
  WindowSolverOptions one_step = tight();
  one_step.max_iterations = 1;
  ASSERT_EQ(solver.solve(one_step).successful_steps, 1);
  const Eigen::VectorXd after_one_step =
      (Eigen::VectorXd(8) << x1[0], x1[1], x1[2], x2[0], x2[1], x2[2], x2[3], s[0]).finished();
  const WindowSolverSummary summary = solver.solve(tight());
  ASSERT_NE(summary.termination, WindowSolverSummary::Termination::kFailure) << summary.message;
  EXPECT_LE(summary.successful_steps + summary.unsuccessful_steps, 4);

  // Closed form from the Jacobians (the cost is linear: J at any point, r at zero).
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(14, 8);
  Eigen::VectorXd r0(14);
  {
    double z1[3] = {0, 0, 0}, z2[4] = {0, 0, 0, 0}, zs[1] = {0};
    std::vector<double> Ja(36), Jb(48), Jc(12), Jd(2);
    double* jj[3] = {Ja.data(), Jb.data(), Jc.data()};
    const double* pj[3] = {z1, z2, zs};
    joint.Evaluate(pj, r0.data(), jj);
    double* jd[1] = {Jd.data()};
    const double* pd[1] = {zs};
    on_s.Evaluate(pd, r0.data() + 12, jd);
    for (int i = 0; i < 12; ++i) {
      for (int k = 0; k < 3; ++k) J(i, k) = Ja[static_cast<size_t>(i * 3 + k)];
      for (int k = 0; k < 4; ++k) J(i, 3 + k) = Jb[static_cast<size_t>(i * 4 + k)];
      J(i, 7) = Jc[static_cast<size_t>(i)];
    }
    J(12, 7) = Jd[0];
    J(13, 7) = Jd[1];
  }
  const Eigen::VectorXd x_star = J.colPivHouseholderQr().solve(-r0);
  Eigen::VectorXd x(8);
  x << x1[0], x1[1], x1[2], x2[0], x2[1], x2[2], x2[3], s[0];
  EXPECT_LE((x - x_star).cwiseAbs().maxCoeff(), 1e-9 * (1.0 + x_star.cwiseAbs().maxCoeff()));
  EXPECT_LE((after_one_step - x_star).cwiseAbs().maxCoeff(),
            1e-3 * (1.0 + x_star.cwiseAbs().maxCoeff()));
  EXPECT_NEAR(summary.final_cost, 0.5 * (J * x_star + r0).squaredNorm(), 1e-9);
}

TEST(WindowSolver, KeepsAnEliminatedScalarOnItsLowerBound) {
  // A prior pulls s to -1 through a coupling with a frame block; the bound holds it at 0.25.
  double x[1] = {1.0}, s[1] = {1.0};
  ScalarPrior pull_s(-1.0, 0.1), pull_x(2.0, 1.0);
  WindowSolver solver;
  solver.addFrameBlock(x, 1);
  solver.addEliminatedScalar(s, 0.25);
  solver.addResidual(&pull_s, nullptr, {s});
  solver.addResidual(&pull_x, nullptr, {x});
  solver.solve(tight());
  EXPECT_EQ(s[0], 0.25);
  EXPECT_NEAR(x[0], 2.0, 1e-3);  // its last step fell with the bounded one
}

TEST(WindowSolver, TakesOneStepWhenAllowedOne) {
  WindowProblem w(20, 41);
  const Eigen::VectorXd before = values(w);
  WindowSolver solver;
  addToSolver(w, solver);
  WindowSolverOptions o = tight();
  o.max_iterations = 1;
  const WindowSolverSummary s = solver.solve(o);
  EXPECT_EQ(s.successful_steps + s.unsuccessful_steps, 1);
  EXPECT_EQ(s.successful_steps, 1);
  EXPECT_EQ(s.termination, WindowSolverSummary::Termination::kNoConvergence);
  EXPECT_LT(s.final_cost, s.initial_cost);
  EXPECT_GT((values(w) - before).norm(), 0.0);
}

TEST(WindowSolver, StopsOnTheFunctionToleranceWithFewerSteps) {
  WindowProblem loose(40, 51, WindowProblem::PoseTerms::kPriors);
  WindowProblem strict(40, 51, WindowProblem::PoseTerms::kPriors);
  WindowSolver a, b;
  addToSolver(loose, a);
  addToSolver(strict, b);
  WindowSolverOptions o = tight();
  o.function_tolerance = 1e-3;
  const WindowSolverSummary sa = a.solve(o);
  const WindowSolverSummary sb = b.solve(tight());
  EXPECT_EQ(sa.termination, WindowSolverSummary::Termination::kConvergence);
  EXPECT_EQ(sa.message, "function tolerance reached");
  EXPECT_LT(sa.successful_steps, sb.successful_steps);
  EXPECT_LE(sa.final_cost, sb.final_cost * 1.01);
}

namespace {

/// A residual that cannot be evaluated where its parameter is negative.
class FailsBelowZero final : public ceres::SizedCostFunction<1, 1> {
 public:
  bool Evaluate(double const* const* p, double* r, double** j) const override {
    if (p[0][0] < 0.0) return false;
    r[0] = p[0][0] - 3.0;
    if (j && j[0]) j[0][0] = 1.0;
    return true;
  }
};

}  // namespace

namespace {

/// r = w (x + s - 3): only the sum is observed, the difference is a direction without
/// information.
class SumCost final : public ceres::SizedCostFunction<1, 1, 1> {
 public:
  explicit SumCost(double w) : w_(w) {}
  bool Evaluate(double const* const* p, double* r, double** j) const override {
    r[0] = w_ * (p[0][0] + p[1][0] - 3.0);
    if (j && j[0]) j[0][0] = w_;
    if (j && j[1]) j[1][0] = w_;
    return true;
  }

 private:
  double w_;
};

}  // namespace

TEST(WindowSolver, DampsMoreWhenTheSystemDoesNotFactorise) {
  // With damping 1e-20 the reduced system of a direction without information is 0 in floating
  // point (not positive definite): the step is solved again with more damping.
  double x[1] = {0.0}, s[1] = {0.0};
  SumCost sum(1e10);
  WindowSolver solver;
  solver.addFrameBlock(x, 1);
  solver.addEliminatedScalar(s);
  solver.addResidual(&sum, nullptr, {x, s});
  WindowSolverOptions o = tight();
  o.initial_trust_region_radius = 1e20;
  o.max_trust_region_radius = 1e20;
  const WindowSolverSummary summary = solver.solve(o);
  EXPECT_GT(summary.factorisation_retries, 0);
  EXPECT_GE(summary.successful_steps, 1);
  EXPECT_NEAR(x[0] + s[0], 3.0, 1e-9);
}

TEST(WindowSolver, LeavesValuesUntouchedWhenTheStartCannotBeEvaluated) {
  double x[1] = {-1.0};
  FailsBelowZero cost;
  WindowSolver solver;
  solver.addFrameBlock(x, 1);
  solver.addResidual(&cost, nullptr, {x});
  const WindowSolverSummary s = solver.solve(tight());
  EXPECT_EQ(s.termination, WindowSolverSummary::Termination::kFailure);
  EXPECT_FALSE(s.message.empty());
  EXPECT_EQ(x[0], -1.0);
}

TEST(WindowSolver, RejectsMalformedProblemsAndOptions) {
  double a[1] = {0}, b[1] = {0}, p[7] = {0, 0, 0, 0, 0, 0, 1};
  std::mt19937_64 rng(1);
  RandomLinearCost two_scalars({1, 1}, 2, rng), one({1}, 1, rng);
  WindowSolver solver;
  solver.addEliminatedScalar(a);
  solver.addEliminatedScalar(b);
  EXPECT_THROW(solver.addEliminatedScalar(a), std::invalid_argument);
  EXPECT_THROW(solver.addResidual(&two_scalars, nullptr, {a, b}), std::invalid_argument);
  EXPECT_THROW(solver.addResidual(&one, nullptr, {a, b}), std::invalid_argument);
  solver.addFrameBlock(p, 7);
  EXPECT_THROW(solver.addResidual(&one, nullptr, {p}), std::invalid_argument);  // size 1 vs 7
  EXPECT_THROW(solver.addFrameBlock(p, 7), std::invalid_argument);
  WindowSolverOptions o;
  o.max_iterations = 0;
  EXPECT_THROW(solver.solve(o), std::invalid_argument);
  o = WindowSolverOptions{};
  o.min_relative_decrease = 1.5;
  EXPECT_THROW(solver.solve(o), std::invalid_argument);
  solver.clear();
  solver.addFrameBlock(p, 7);  // cleared: may be added again
}
