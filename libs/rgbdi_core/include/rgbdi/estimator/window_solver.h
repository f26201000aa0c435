// Levenberg-Marquardt solver of the sliding-window problem: the inverse depths are eliminated
// by a Schur complement that is diagonal (each reprojection residual holds one inverse depth),
// the reduced system over the frame blocks (poses, speed/biases, time offset) is factorised
// densely.
//
// Why not ceres::Solve: the window problem is a new one at every update (~1,100 residual
// blocks), and Ceres' general machinery cost more than the arithmetic: building the problem and
// its program, a block-sparse Jacobian whose Schur eliminator locks a mutex per cell, and
// J^T J of the dense marginalisation prior at every iteration (doc/performance.md). The
// residuals stay the same ceres::CostFunction objects with their analytic Jacobians, robust
// losses are applied as Ceres' corrector does, and the step rule is Ceres' Levenberg-Marquardt
// trust region (Marquardt's diagonal, radius update by the gain ratio, its stopping rules).
//
// Conventions: a block of 7 doubles is a pose [p, q(x, y, z, w)] on PoseManifold (tangent:
// the first 6 Jacobian columns, as every rgbdi factor writes them, 7th column zero); other
// blocks are Euclidean. Blocks that are not added as variables are constants.
#pragma once

#include <ceres/cost_function.h>
#include <ceres/loss_function.h>

#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace rgbdi::estimator {

class MarginalizationInfo;

struct WindowSolverOptions {
  int max_iterations = 8;  ///< [count] steps tried, accepted or not
  /// [unitless] stop when a step changes the cost by at most this fraction of it
  double function_tolerance = 1e-6;
  double gradient_tolerance = 1e-10;  ///< [unitless] stop when max |gradient| is below this
  double parameter_tolerance = 1e-8;  ///< [unitless] stop when |step| <= tol * (|x| + tol)
  /// Its inverse is the first step's damping: 1e8 starts with (nearly) the Gauss-Newton step, as
  /// Ceres' dogleg does; LM's usual 1e4 damps the weakly observed directions (the monocular
  /// scale) so much that 8 iterations leave them unsolved (handheld 15 Hz mono ATE 4.5 -> 14.6 cm).
  double initial_trust_region_radius = 1e8;
  double max_trust_region_radius = 1e16;
  double min_trust_region_radius = 1e-32;
  double min_relative_decrease = 1e-3;  ///< [unitless] gain ratio that accepts a step
  double min_lm_diagonal = 1e-6;        ///< clamp of Marquardt's diagonal
  double max_lm_diagonal = 1e32;
  double max_time_s = 0.0;  ///< [s] wall-clock budget; 0 = none (deterministic)

  /// Empty when usable, else what is wrong.
  std::string problem() const;
};

struct WindowSolverSummary {
  enum class Termination { kConvergence, kNoConvergence, kFailure };
  Termination termination = Termination::kFailure;
  int successful_steps = 0;
  int unsuccessful_steps = 0;
  int factorisation_retries = 0;  ///< damped systems solved again with more damping
  double initial_cost = 0.0;      ///< 1/2 sum of the robustified squared residuals
  double final_cost = 0.0;
  std::string message;  ///< why it stopped
};

class WindowSolver {
 public:
  WindowSolver();
  ~WindowSolver();
  WindowSolver(const WindowSolver&) = delete;
  WindowSolver& operator=(const WindowSolver&) = delete;

  /// Removes every block and residual (buffers are kept for the next problem).
  void clear();
  /// A variable of the reduced system (7 doubles: a pose, see above).
  void addFrameBlock(double* x, int ambient_size);
  /// A scalar variable eliminated before the factorisation; the solution is projected onto
  /// x >= lower_bound. Every residual may hold at most one eliminated scalar.
  void addEliminatedScalar(double* x,
                           double lower_bound = -std::numeric_limits<double>::infinity());
  /// A residual on the given blocks (in the cost function's order); blocks must be added
  /// before, those not added are constant. The cost and the loss (may be null) stay the
  /// caller's and must outlive solve().
  void addResidual(const ceres::CostFunction* cost, const ceres::LossFunction* loss,
                   const std::vector<double*>& blocks);
  /// The linear marginalisation prior r = r0 + J (x - x0) on its kept blocks; its J^T J is
  /// formed once here instead of at every iteration.
  void addPrior(std::shared_ptr<const MarginalizationInfo> prior);

  /// Minimises in place. Throws std::invalid_argument on invalid options.
  WindowSolverSummary solve(const WindowSolverOptions& options);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rgbdi::estimator
