// The live 4-DOF pose graph of loop closure (x, y, z, yaw per keyframe; roll and pitch stay the
// odometry's). Keyframes are added as they arrive, each tied by odometry edges to its last few
// predecessors of the same odometry segment; verified loops add loop edges. solve() runs Ceres
// to convergence, then rolls back loop edges the solved graph cannot agree with (normalised
// residual above the gate): the worst one is deactivated for good and the graph solved again
// from the poses it had when solve() was called, so the result equals a solve of the graph that
// never had that edge. A component without any active loop is exactly its odometry.
//
// Gauge and segments: segments (odometry restarted after a reset) are never joined by odometry
// edges. Segments joined by active loop edges form a component; the component of the first
// node's segment (the origin) keeps that node fixed at its odometry pose, any other component
// keeps the first node of its lowest segment fixed at its odometry pose, so a segment with no
// loop to the origin stays where its own odometry put it. When a loop joins a component to
// another one, the joined part is first moved rigidly onto the loop (a good initial guess), then
// optimised with the rest.
//
// Fixed nodes (a loaded map, map_data.h): their pose is held constant by every solve and they
// have no odometry edges. The map is loaded as the first segment, so it is the origin and a new
// run's segment that a verified loop joins to it is moved into the map's frame.
//
// Not thread-safe: one thread owns the object (the loop-closure thread).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "rgbdi/loop/four_dof.h"
#include "rgbdi/loop/four_dof_factor.h"
#include "rgbdi/loop/pose_graph_options.h"

namespace rgbdi::loop {

enum class EdgeKind { kSequential, kLoop };

struct GraphNode {
  std::uint64_t id = 0;
  int segment = 0;
  Eigen::Isometry3d T_world_body_odom = Eigen::Isometry3d::Identity();  ///< as added
  Eigen::Matrix3d R_tilt = Eigen::Matrix3d::Identity();  ///< roll/pitch part of the odometry
  double yaw_odom_rad = 0.0;                             ///< [rad] heading of the odometry
  /// [m] odometry path length from the first node of the segment (sum of the straight
  /// distances between consecutive nodes)
  double odom_path_m = 0.0;
  /// [rad] odometry rotation from the first node of the segment (sum of the rotation angles
  /// between consecutive nodes' attitudes)
  double odom_rotation_rad = 0.0;
  /// [s] odometry time from the first node of the segment carried by the IMU alone
  double odom_bridged_s = 0.0;
  bool fixed = false;  ///< held constant by solve() (a loaded map's keyframe)
  /// Corrected state [x, y, z] [m] and yaw [rad, in [-pi, pi)]: one Ceres parameter block.
  Eigen::Vector4d xyz_yaw = Eigen::Vector4d::Zero();

  Eigen::Vector3d p_world_body_m() const { return xyz_yaw.head<3>(); }  ///< [m] corrected
  double yaw_rad() const { return xyz_yaw[3]; }                         ///< [rad] corrected heading
};

struct GraphEdge {
  int id = 0;  ///< index in PoseGraph4Dof::edges()
  EdgeKind kind = EdgeKind::kSequential;
  std::uint64_t from = 0, to = 0;            ///< node ids
  std::size_t from_index = 0, to_index = 0;  ///< node indices in PoseGraph4Dof::nodes()
  /// Body-frame relative pose as measured (odometry or verified loop); only `measured` is used.
  Eigen::Isometry3d T_from_to = Eigen::Isometry3d::Identity();
  FourDofDelta measured;
  double sigma_pos_m = 0.0;    ///< [m]
  double sigma_yaw_rad = 0.0;  ///< [rad]
  bool active = true;          ///< false once rolled back (loop edges only)
  /// [sigma] sqrt(r^T Sigma^-1 r) at the poses of the last solve (0 before any solve)
  double normalised_residual = 0.0;
};

struct SegmentState {
  int segment = 0;
  std::uint64_t first_id = 0, last_id = 0;
  std::size_t nodes = 0;
  int component = 0;  ///< lowest segment of the segments joined to this one by active loops
  bool connected_to_origin = false;  ///< in the component of the first node's segment
};

struct PoseGraphSolveReport {
  int solver_runs = 0;         ///< Ceres runs: 1 + one per rollback; 0 when no component has a loop
  int iterations = 0;          ///< [count] summed over the runs
  double solver_time_s = 0.0;  ///< [s] wall-clock time spent in Ceres, summed over the runs
  double initial_cost = 0.0;   ///< Ceres cost (0.5 sum rho(|r|^2)) before the first run
  double final_cost = 0.0;     ///< after the last run
  bool converged = true;       ///< every run stopped on a tolerance, not on max_iterations
  std::size_t nodes = 0;
  std::size_t free_nodes = 0;               ///< nodes optimised in the last run
  std::vector<int> active_loop_edges;       ///< edge ids
  std::vector<int> rolled_back_loop_edges;  ///< edge ids deactivated by this solve, in order
  int separate_segments = 0;  ///< segments not connected to the origin after this solve
};

class PoseGraph4Dof {
 public:
  /// Throws ConfigError when the options are out of range.
  explicit PoseGraph4Dof(const PoseGraphOptions& options = PoseGraphOptions{});

  /// Adds a keyframe with its odometry pose (body frame, in its segment's odometry frame) and
  /// odometry edges to up to options.sequential_edges predecessors of the same segment. The new
  /// node starts at drift(segment) * T_world_body_odom. Throws std::invalid_argument naming the
  /// id when the id is not greater than the last one, the segment is negative or lower than the
  /// last node's (segments only begin, they never resume), or the pose is not finite and rigid.
  /// `bridged_s` [s]: of the odometry since the previous node, the time the IMU carried alone
  /// (blind frames), which weakens the edges across it; negative or non-finite also throws.
  void addNode(std::uint64_t id, int segment, const Eigen::Isometry3d& T_world_body_odom,
               double bridged_s = 0.0);

  /// Adds a node whose pose stays T_world_body in every solve (a keyframe of a loaded map), with
  /// no odometry edge. Same id and segment rules as addNode; fixed nodes come before every free
  /// node and a segment is either all fixed or all free (std::invalid_argument otherwise).
  void addFixedNode(std::uint64_t id, int segment, const Eigen::Isometry3d& T_world_body);

  /// Adds an (active) loop edge; T_from_to maps points of the `to` body frame into the `from`
  /// body frame; only its x, y, z and yaw are used. Returns the edge id. Throws
  /// std::invalid_argument naming the ids when a node is unknown, from == to, or the pose is
  /// not finite and rigid. The edge has the options' loop_sigma_pos_m / loop_sigma_yaw_deg.
  int addLoopEdge(std::uint64_t from_id, std::uint64_t to_id, const Eigen::Isometry3d& T_from_to);
  /// The same with the edge's own sigmas ([m], [rad]; e.g. from the quality of the fit that
  /// measured it). Also throws std::invalid_argument when a sigma is not positive and finite.
  int addLoopEdge(std::uint64_t from_id, std::uint64_t to_id, const Eigen::Isometry3d& T_from_to,
                  double sigma_pos_m, double sigma_yaw_rad);

  /// Sigmas ([m], [rad]) of a sequential edge between two nodes of one segment whose odometry
  /// differs by `path_m` of path, `rotation_rad` of rotation and `bridged_s` of IMU-only time
  /// (see PoseGraphOptions).
  static std::pair<double, double> sequentialSigmas(const PoseGraphOptions& o, double path_m,
                                                    double rotation_rad, double bridged_s = 0.0);

  /// Optimises every component that has an active loop edge (others are set to their odometry),
  /// then rolls back wrong loops (see the file comment). Throws std::runtime_error when Ceres
  /// fails (poses and loop edges are then left as they were before the call).
  PoseGraphSolveReport solve();

  /// Every free node back at its odometry pose and every segment on its own: the poses of a
  /// graph never solved (edges kept as they are). For a loop closer whose remaining loops no
  /// longer show drift (loop/correction_gate.h).
  void resetToOdometry();

  /// Corrected body pose: optimised x, y, z, yaw and the odometry's roll/pitch. Throws
  /// std::out_of_range naming the id when it is unknown.
  Eigen::Isometry3d pose(std::uint64_t id) const;
  /// Correction T_corrected * T_odom^-1 of the newest node of `segment` (yaw about z plus a
  /// translation). Throws std::out_of_range naming the segment when it has no node.
  Eigen::Isometry3d drift(int segment) const;
  /// True when both segments exist and are joined by active loop edges (directly or through
  /// other segments), including edges added since the last solve.
  bool connected(int segment_a, int segment_b) const;
  std::vector<SegmentState> segments() const;

  bool hasNode(std::uint64_t id) const;
  const std::vector<GraphNode>& nodes() const { return nodes_; }  ///< ordered by id
  const std::vector<GraphEdge>& edges() const { return edges_; }  ///< ordered by id
  const PoseGraphOptions& options() const { return options_; }
  /// [B] memory held by the graph (node, edge and segment storage, allocated capacity).
  std::size_t memoryBytes() const;

 private:
  struct SegmentRange {
    int segment = 0;
    std::size_t begin = 0, end = 0;  ///< node indices [begin, end) (segments are contiguous)
  };

  void appendNode(std::uint64_t id, int segment, const Eigen::Isometry3d& T, bool fixed,
                  double bridged_s, const char* caller);
  std::size_t indexOf(std::uint64_t id) const;  ///< throws std::out_of_range
  std::size_t segmentIndexOfNode(std::size_t node_index) const;
  /// Component label per segment index (lowest segment index of its component).
  std::vector<std::size_t> components() const;
  /// Moves each component to its initial guess for `labels`; see solve().
  void prepare(const std::vector<std::size_t>& labels);
  void applyCorrection(const Eigen::Isometry3d& C, std::size_t segment_index);
  void updateResiduals();

  PoseGraphOptions options_;
  NodeStateManifold state_manifold_;
  std::vector<GraphNode> nodes_;
  std::vector<GraphEdge> edges_;
  std::vector<SegmentRange> segments_;
  /// Component label per segment index the current poses were optimised with (the grouping
  /// whose relative placement is already consistent); new segments get their own index.
  std::vector<std::size_t> solved_labels_;
};

}  // namespace rgbdi::loop
