// Building and solving the window problem at each update: IMU factors between consecutive
// slots, wheel factors of the intervals the wheel odometry covers ([wheel] enable) with the
// prior of the scale factors while it lasts, reprojection factors of the usable tracks (Cauchy
// loss), the gauge prior on the oldest pose, the start prior while it lasts, the priors of verified
// depths, and the marginalisation prior, solved by WindowSolver (window_solver.h) with the inverse
// depths eliminated.
//
// The solver, the reprojection factors and the work buffers are kept from update to update (one
// problem of ~1,100 residuals per frame: reallocating them cost more than reusing them).
#pragma once

#include <memory>
#include <vector>

#include "estimator/window_cost_model.h"
#include "rgbdi/estimator/estimator_options.h"
#include "rgbdi/estimator/reprojection_factor.h"
#include "rgbdi/estimator/rolling_shutter_reprojection_factor.h"
#include "rgbdi/estimator/window_solver.h"

namespace rgbdi::estimator {

struct WindowState;

/// What an update did.
struct WindowUpdate {
  int n_features_used = 0;      ///< tracks in the problem
  int n_depth_verified = 0;     ///< of which with a verified depth
  int n_wheel_factors = 0;      ///< wheel-odometry intervals in the problem
  bool single_step = false;     ///< limited to one solver iteration
  WindowSolverSummary summary;  ///< the solver's
};

class WindowOptimisation {
 public:
  WindowOptimisation(const EstimatorOptions& opt, const WindowCostModel& model);

  /// Solves the window in place (states, time offset, readout when estimated, inverse depths);
  /// `single_step`: the
  /// second-newest frame is no keyframe and leaves the window afterwards (one iteration, when
  /// the window holds depth-verified features).
  WindowUpdate run(WindowState& state, bool single_step);

 private:
  EstimatorOptions opt_;
  WindowCostModel model_;
  WindowSolver solver_;
  /// The reprojection factors, reset (not reallocated) from update to update.
  std::vector<std::unique_ptr<ReprojectionFactor>> reprojection_factors_;
  /// The same with the readout as a parameter (estimate_rolling_shutter_readout).
  std::vector<std::unique_ptr<RollingShutterReprojectionFactor>> rs_reprojection_factors_;
  std::vector<double*> residual_blocks_;  ///< one residual's parameter blocks
  std::vector<double> inv_depth_params_;  ///< the solved inverse depths during run()
};

}  // namespace rgbdi::estimator
