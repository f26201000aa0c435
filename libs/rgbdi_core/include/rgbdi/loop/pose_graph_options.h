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

  // --- odometry (sequential) edges: a random walk of the odometry's drift ---
  // The position variance of an edge grows linearly with the path length, its yaw variance with
  // the path length and the rotation of the odometry between its two keyframes (summed over the
  // keyframes in between), so a loop's correction is spread in proportion to where the odometry can
  // have drifted: along the distance travelled and in the turns (heading errors of a gyro scale or
  // camera-IMU misalignment grow with the angle turned), not per keyframe. Every sequential edge's
  // variance is multiplied by n (n + 1) / 2 for n = sequential_edges: the n overlapping edges
  // of a keyframe carry the information of the odometry once, as a single chain would.
  /// [m] position sigma of an edge between two keyframes at the same place and attitude
  double odom_pos_sigma_floor_m = 0.001;
  /// [m/sqrt(m)] position sigma after 1 m of path (sigma = this * sqrt(path / 1 m))
  double odom_pos_sigma_per_sqrt_m = 0.015;
  /// [deg] yaw sigma of an edge between two keyframes at the same place and attitude
  double odom_yaw_sigma_floor_deg = 0.01;
  /// [deg/sqrt(m)] yaw sigma after 1 m of path
  double odom_yaw_sigma_per_sqrt_m_deg = 0.5;
  /// [deg/sqrt(rad)] yaw sigma after turning 1 rad (rotation angle of the odometry attitude)
  double odom_yaw_sigma_per_sqrt_rad_deg = 0.3;
  // Odometry the IMU carried alone (blind frames: a blackout, a bare wall, motion blur) drifts
  // by centimetres per second: its edges get these sigmas on top, so loops after the blind
  // stretch re-align what follows it rather than spreading the jump along the path.
  /// [m] position sigma after 1 s carried by the IMU alone (sigma = this * (t / 1 s)^1.5)
  double odom_bridge_pos_sigma_m = 0.1;
  /// [deg] yaw sigma after 1 s carried by the IMU alone (sigma = this * t / 1 s)
  double odom_bridge_yaw_sigma_deg = 0.5;

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
