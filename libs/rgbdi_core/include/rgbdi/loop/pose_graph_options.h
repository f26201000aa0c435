// Options of the 4-DOF pose graph (x, y, z, yaw per keyframe): the `graph_*` keys of the [loop]
// section. Edge uncertainties, robust loss on loop edges, solver limits and the rollback gate that
// removes loop edges the solved graph cannot agree with.
#pragma once

#include <string>

#include "rgbdi/common/ini_reader.h"

namespace rgbdi::loop {

enum class RobustLoss { kHuber, kCauchy };

/// Defaults equal share/config.ini.
struct PoseGraphOptions {
  /// [count] each new keyframe gets an odometry edge to this many predecessors of its segment
  int sequential_edges = 4;

  // --- odometry (sequential) edges: sigma = base + per_m * distance between the two keyframes ---
  double odom_sigma_pos_base_m = 0.02;    ///< [m] position sigma of an edge of zero length
  double odom_sigma_pos_per_m = 0.05;     ///< [m/m] position sigma growth per metre of edge
  double odom_sigma_yaw_base_deg = 0.2;   ///< [deg] yaw sigma of an edge of zero length
  double odom_sigma_yaw_per_m_deg = 1.0;  ///< [deg/m] yaw sigma growth per metre of edge

  // --- loop edges ---
  double loop_sigma_pos_m = 0.05;        ///< [m] position sigma of a verified loop
  double loop_sigma_yaw_deg = 1.0;       ///< [deg] yaw sigma of a verified loop
  RobustLoss loss = RobustLoss::kHuber;  ///< robust loss on loop edges (odometry edges: none)
  /// [sigma] the robust loss is quadratic up to this normalised residual
  double loss_scale_sigma = 1.0;

  // --- solver (Levenberg-Marquardt, sparse Cholesky, one thread) ---
  int max_iterations = 200;            ///< [count] per solve; the solver stops on convergence
  double function_tolerance = 1e-6;    ///< [unitless] relative cost decrease that ends a solve
  double gradient_tolerance = 1e-12;   ///< [unitless] max-norm of the projected gradient
  double parameter_tolerance = 1e-10;  ///< [unitless] relative step size that ends a solve

  // --- rollback of wrong loops ---
  /// [sigma] after a solve, the active loop edge with the largest normalised residual
  /// sqrt(r^T Sigma^-1 r) above this gate is deactivated and the graph solved again
  double rollback_gate_sigma = 3.0;
  int max_rollbacks_per_solve = 5;  ///< [count] loop edges rolled back at most in one solve()

  /// Throws ConfigError when a value is outside its range.
  void validate() const;
  /// Reads the graph_* keys of [loop]; missing keys keep the defaults above.
  static PoseGraphOptions load(IniReader& ini);
};

}  // namespace rgbdi::loop
