#include "rgbdi/loop/pose_graph.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <numeric>
#include <stdexcept>
#include <string>

#include "rgbdi/loop/four_dof_factor.h"

namespace rgbdi::loop {
namespace {

// Accepting caller data (rounding, not tuning): R^T R = I within this.
constexpr double kRotationTolerance = 1e-6;

bool isRigid(const Eigen::Isometry3d& T) {
  if (!T.matrix().allFinite()) return false;
  const Eigen::Matrix3d& R = T.linear();
  return (R.transpose() * R - Eigen::Matrix3d::Identity()).norm() < kRotationTolerance &&
         R.determinant() > 0.0;
}

double deg2rad(double deg) { return deg * M_PI / 180.0; }

std::unique_ptr<ceres::LossFunction> makeLoss(const PoseGraphOptions& o) {
  if (o.loss == RobustLoss::kCauchy) return std::make_unique<ceres::CauchyLoss>(o.loss_scale_sigma);
  return std::make_unique<ceres::HuberLoss>(o.loss_scale_sigma);
}

}  // namespace

PoseGraph4Dof::PoseGraph4Dof(const PoseGraphOptions& options) : options_(options) {
  options_.validate();
}

void PoseGraph4Dof::appendNode(std::uint64_t id, int segment, const Eigen::Isometry3d& T,
                               bool fixed, double bridged_s, const char* caller) {
  const std::string who = std::string(caller) + ": node " + std::to_string(id);
  if (!nodes_.empty() && id <= nodes_.back().id)
    throw std::invalid_argument(who + ": ids must increase, the last node is " +
                                std::to_string(nodes_.back().id));
  if (segment < 0)
    throw std::invalid_argument(who + ": negative segment " + std::to_string(segment));
  if (!segments_.empty() && segment < segments_.back().segment)
    throw std::invalid_argument(who + ": segment " + std::to_string(segment) +
                                " is lower than the current segment " +
                                std::to_string(segments_.back().segment));
  if (!isRigid(T))
    throw std::invalid_argument(who + (fixed ? ": pose" : ": odometry pose") +
                                " is not finite and rigid");
  if (!(std::isfinite(bridged_s) && bridged_s >= 0.0))
    throw std::invalid_argument(who + ": IMU-only time " + std::to_string(bridged_s) +
                                " s is not finite and non-negative");
  if (fixed && !nodes_.empty() && !nodes_.back().fixed)
    throw std::invalid_argument(who + ": fixed nodes (a loaded map) come before every free node");
  const bool new_segment = segments_.empty() || segments_.back().segment != segment;
  if (!new_segment && nodes_.back().fixed != fixed)
    throw std::invalid_argument(who + ": segment " + std::to_string(segment) +
                                " mixes fixed and free nodes");

  GraphNode n;
  n.id = id;
  n.segment = segment;
  n.fixed = fixed;
  n.T_world_body_odom = T;
  n.yaw_odom_rad = yawOf(T.linear());
  n.R_tilt = tiltOf(T.linear());
  if (!new_segment) {
    const GraphNode& prev = nodes_.back();
    n.odom_path_m =
        prev.odom_path_m + (T.translation() - prev.T_world_body_odom.translation()).norm();
    n.odom_rotation_rad =
        prev.odom_rotation_rad +
        Eigen::AngleAxisd(prev.T_world_body_odom.linear().transpose() * T.linear()).angle();
    n.odom_bridged_s = prev.odom_bridged_s + bridged_s;
  }
  if (new_segment || fixed) {
    n.xyz_yaw << T.translation(), n.yaw_odom_rad;
  } else {
    // Start where the segment's current correction puts it, so the initial guess is good.
    const Eigen::Isometry3d C = drift(segment);
    n.xyz_yaw << C * T.translation(), wrapAngle(n.yaw_odom_rad + yawOf(C.linear()));
  }
  if (new_segment) {
    segments_.push_back({segment, nodes_.size(), nodes_.size()});
    solved_labels_.push_back(segments_.size() - 1);
  }
  nodes_.push_back(n);
  segments_.back().end = nodes_.size();
}

void PoseGraph4Dof::addFixedNode(std::uint64_t id, int segment,
                                 const Eigen::Isometry3d& T_world_body) {
  appendNode(id, segment, T_world_body, true, 0.0, "PoseGraph4Dof::addFixedNode");
}

void PoseGraph4Dof::addNode(std::uint64_t id, int segment,
                            const Eigen::Isometry3d& T_world_body_odom, double bridged_s) {
  appendNode(id, segment, T_world_body_odom, false, bridged_s, "PoseGraph4Dof::addNode");
  const std::size_t index = nodes_.size() - 1;
  const std::size_t first = segments_.back().begin;

  // Odometry edges to the newest predecessors of the same segment, never across segments.
  const std::size_t n_edges =
      std::min<std::size_t>(static_cast<std::size_t>(options_.sequential_edges), index - first);
  for (std::size_t k = index - n_edges; k < index; ++k) {
    const GraphNode& from = nodes_[k];
    GraphEdge e;
    e.id = static_cast<int>(edges_.size());
    e.kind = EdgeKind::kSequential;
    e.from = from.id;
    e.to = id;
    e.from_index = k;
    e.to_index = index;
    e.T_from_to = from.T_world_body_odom.inverse() * T_world_body_odom;
    e.measured = fourDofDelta(from.R_tilt, e.T_from_to);
    const auto [sigma_pos, sigma_yaw] =
        sequentialSigmas(options_, nodes_[index].odom_path_m - from.odom_path_m,
                         nodes_[index].odom_rotation_rad - from.odom_rotation_rad,
                         nodes_[index].odom_bridged_s - from.odom_bridged_s);
    e.sigma_pos_m = sigma_pos;
    e.sigma_yaw_rad = sigma_yaw;
    edges_.push_back(e);
  }
}

std::pair<double, double> PoseGraph4Dof::sequentialSigmas(const PoseGraphOptions& o, double path_m,
                                                          double rotation_rad, double bridged_s) {
  // Variances of a random walk in path length and rotation; the n overlapping edges of each
  // keyframe share the odometry's information: n (n + 1) / 2 edges span every step (an edge
  // over k steps spans k of them, for k = 1..n), so each gets that multiple of the variance.
  const double n = static_cast<double>(o.sequential_edges);
  const double share = 0.5 * n * (n + 1.0);
  // IMU-only time: an acceleration error integrates twice (position sigma ~ t^1.5), a gyro bias
  // once (yaw sigma ~ t).
  const double bridged_pos = o.odom_bridge_pos_sigma_m * bridged_s * std::sqrt(bridged_s);
  const double bridged_yaw = deg2rad(o.odom_bridge_yaw_sigma_deg) * bridged_s;
  const double var_pos = o.odom_pos_sigma_floor_m * o.odom_pos_sigma_floor_m +
                         o.odom_pos_sigma_per_sqrt_m * o.odom_pos_sigma_per_sqrt_m * path_m +
                         bridged_pos * bridged_pos;
  const double yaw_floor = deg2rad(o.odom_yaw_sigma_floor_deg);
  const double yaw_m = deg2rad(o.odom_yaw_sigma_per_sqrt_m_deg);
  const double yaw_rad = deg2rad(o.odom_yaw_sigma_per_sqrt_rad_deg);
  const double var_yaw = yaw_floor * yaw_floor + yaw_m * yaw_m * path_m +
                         yaw_rad * yaw_rad * rotation_rad + bridged_yaw * bridged_yaw;
  return {std::sqrt(share * var_pos), std::sqrt(share * var_yaw)};
}

int PoseGraph4Dof::addLoopEdge(std::uint64_t from_id, std::uint64_t to_id,
                               const Eigen::Isometry3d& T_from_to) {
  return addLoopEdge(from_id, to_id, T_from_to, options_.loop_sigma_pos_m,
                     deg2rad(options_.loop_sigma_yaw_deg));
}

int PoseGraph4Dof::addLoopEdge(std::uint64_t from_id, std::uint64_t to_id,
                               const Eigen::Isometry3d& T_from_to, double sigma_pos_m,
                               double sigma_yaw_rad) {
  const std::string who =
      "PoseGraph4Dof::addLoopEdge " + std::to_string(from_id) + " -> " + std::to_string(to_id);
  if (!hasNode(from_id))
    throw std::invalid_argument(who + ": unknown node " + std::to_string(from_id));
  if (!hasNode(to_id)) throw std::invalid_argument(who + ": unknown node " + std::to_string(to_id));
  if (from_id == to_id) throw std::invalid_argument(who + ": an edge needs two nodes");
  if (!isRigid(T_from_to)) throw std::invalid_argument(who + ": pose is not finite and rigid");
  if (!(std::isfinite(sigma_pos_m) && sigma_pos_m > 0.0 && std::isfinite(sigma_yaw_rad) &&
        sigma_yaw_rad > 0.0))
    throw std::invalid_argument(who + ": sigmas must be positive, got " +
                                std::to_string(sigma_pos_m) + " m, " +
                                std::to_string(sigma_yaw_rad) + " rad");
  GraphEdge e;
  e.id = static_cast<int>(edges_.size());
  e.kind = EdgeKind::kLoop;
  e.from = from_id;
  e.to = to_id;
  e.from_index = indexOf(from_id);
  e.to_index = indexOf(to_id);
  e.T_from_to = T_from_to;
  e.measured = fourDofDelta(nodes_[e.from_index].R_tilt, T_from_to);
  e.sigma_pos_m = sigma_pos_m;
  e.sigma_yaw_rad = sigma_yaw_rad;
  edges_.push_back(e);
  return e.id;
}

void PoseGraph4Dof::resetToOdometry() {
  for (GraphNode& n : nodes_)
    if (!n.fixed) n.xyz_yaw << n.T_world_body_odom.translation(), n.yaw_odom_rad;
  for (std::size_t s = 0; s < solved_labels_.size(); ++s) solved_labels_[s] = s;
  updateResiduals();
}

PoseGraphSolveReport PoseGraph4Dof::solve() {
  PoseGraphSolveReport report;
  report.nodes = nodes_.size();

  std::vector<Eigen::Vector4d> before(nodes_.size());
  for (std::size_t i = 0; i < nodes_.size(); ++i) before[i] = nodes_[i].xyz_yaw;
  const std::vector<std::size_t> labels_before = solved_labels_;
  auto restore = [&] {
    for (std::size_t i = 0; i < nodes_.size(); ++i) nodes_[i].xyz_yaw = before[i];
    solved_labels_ = labels_before;
  };

  // Every re-solve after a rollback starts again from the poses at this call, so it equals a
  // solve of the graph that never had the rolled-back edges (initial placement included).
  std::vector<std::size_t> labels = components();
  prepare(labels);
  solved_labels_ = labels;

  const std::unique_ptr<ceres::LossFunction> loss = makeLoss(options_);
  ceres::Solver::Options so;
  so.minimizer_type = ceres::TRUST_REGION;
  so.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  so.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  // Eigen's sparse Cholesky: single-threaded by construction (SuiteSparse may call a threaded
  // BLAS) and as fast here (bench_pose_graph).
  so.sparse_linear_algebra_library_type = ceres::EIGEN_SPARSE;
  so.num_threads = 1;
  so.max_num_iterations = options_.max_iterations;
  so.function_tolerance = options_.function_tolerance;
  so.gradient_tolerance = options_.gradient_tolerance;
  so.parameter_tolerance = options_.parameter_tolerance;
  so.logging_type = ceres::SILENT;
  so.minimizer_progress_to_stdout = false;

  for (;;) {
    // Components that contain an active loop edge are optimised; the others were set to their
    // odometry by prepare(), which is their exact optimum.
    std::vector<bool> optimised(segments_.size(), false);
    for (const GraphEdge& e : edges_)
      if (e.kind == EdgeKind::kLoop && e.active)
        optimised[labels[segmentIndexOfNode(e.from_index)]] = true;
    const bool any = std::any_of(optimised.begin(), optimised.end(), [](bool b) { return b; });
    if (!any) break;

    ceres::Problem::Options po;
    po.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    ceres::Problem problem(po);
    std::size_t free_nodes = 0;
    for (std::size_t s = 0; s < segments_.size(); ++s) {
      if (!optimised[labels[s]]) continue;
      for (std::size_t i = segments_[s].begin; i < segments_[s].end; ++i) {
        GraphNode& n = nodes_[i];
        problem.AddParameterBlock(n.xyz_yaw.data(), 4, &state_manifold_);
        if (n.fixed || (s == labels[s] && i == segments_[s].begin)) {  // map or anchor
          problem.SetParameterBlockConstant(n.xyz_yaw.data());
        } else {
          ++free_nodes;
        }
      }
    }
    for (const GraphEdge& e : edges_) {
      if (!e.active || !optimised[labels[segmentIndexOfNode(e.from_index)]]) continue;
      GraphNode& a = nodes_[e.from_index];
      GraphNode& b = nodes_[e.to_index];
      problem.AddResidualBlock(new FourDofEdgeFactor(e.measured, e.sigma_pos_m, e.sigma_yaw_rad),
                               e.kind == EdgeKind::kLoop ? loss.get() : nullptr, a.xyz_yaw.data(),
                               b.xyz_yaw.data());
    }

    ceres::Solver::Summary summary;
    ceres::Solve(so, &problem, &summary);
    if (!summary.IsSolutionUsable()) {
      restore();
      for (int id : report.rolled_back_loop_edges)
        edges_[static_cast<std::size_t>(id)].active = true;
      throw std::runtime_error("PoseGraph4Dof::solve: Ceres failed on " +
                               std::to_string(nodes_.size()) + " nodes: " + summary.message);
    }
    if (report.solver_runs == 0) report.initial_cost = summary.initial_cost;
    ++report.solver_runs;
    report.iterations += static_cast<int>(summary.iterations.size());
    report.solver_time_s += summary.total_time_in_seconds;
    report.final_cost = summary.final_cost;
    report.free_nodes = free_nodes;
    if (summary.termination_type != ceres::CONVERGENCE) report.converged = false;

    updateResiduals();
    int worst = -1;
    for (const GraphEdge& e : edges_)
      if (e.kind == EdgeKind::kLoop && e.active &&
          (worst < 0 ||
           e.normalised_residual > edges_[static_cast<std::size_t>(worst)].normalised_residual))
        worst = e.id;
    if (worst < 0 ||
        edges_[static_cast<std::size_t>(worst)].normalised_residual <=
            options_.rollback_gate_sigma ||
        static_cast<int>(report.rolled_back_loop_edges.size()) >= options_.max_rollbacks_per_solve)
      break;

    // Roll the worst loop back and solve again from the poses at this call.
    edges_[static_cast<std::size_t>(worst)].active = false;
    report.rolled_back_loop_edges.push_back(worst);
    restore();
    labels = components();
    prepare(labels);
    solved_labels_ = labels;
  }

  updateResiduals();
  for (const GraphEdge& e : edges_)
    if (e.kind == EdgeKind::kLoop && e.active) report.active_loop_edges.push_back(e.id);
  for (std::size_t s = 0; s < segments_.size(); ++s)
    if (labels[s] != labels[0]) ++report.separate_segments;
  return report;
}

void PoseGraph4Dof::prepare(const std::vector<std::size_t>& labels) {
  const std::size_t n_seg = segments_.size();
  std::vector<bool> has_loop(n_seg, false);
  for (const GraphEdge& e : edges_)
    if (e.kind == EdgeKind::kLoop && e.active)
      has_loop[labels[segmentIndexOfNode(e.from_index)]] = true;

  for (std::size_t comp = 0; comp < n_seg; ++comp) {
    if (labels[comp] != comp) continue;  // not a component label
    if (!has_loop[comp]) {
      // A lone segment without loops: its odometry is the exact optimum.
      for (std::size_t i = segments_[comp].begin; i < segments_[comp].end; ++i) {
        nodes_[i].xyz_yaw << nodes_[i].T_world_body_odom.translation(), nodes_[i].yaw_odom_rad;
      }
      continue;
    }
    // Groups: segments of this component that were solved together (solved_labels_). The
    // anchor's group is put back onto the anchor's odometry pose (a component that lost its
    // link to the origin returns to where its own odometry put it).
    auto moveGroup = [&](std::size_t group, const Eigen::Isometry3d& C) {
      for (std::size_t s = 0; s < n_seg; ++s)
        if (labels[s] == comp && solved_labels_[s] == group) applyCorrection(C, s);
    };
    GraphNode& anchor = nodes_[segments_[comp].begin];
    if (anchor.p_world_body_m() != anchor.T_world_body_odom.translation() ||
        anchor.yaw_rad() != anchor.yaw_odom_rad) {
      moveGroup(solved_labels_[comp],
                fourDofCorrection(anchor.T_world_body_odom.translation(), anchor.yaw_odom_rad,
                                  anchor.p_world_body_m(), anchor.yaw_rad()));
      anchor.xyz_yaw << anchor.T_world_body_odom.translation(), anchor.yaw_odom_rad;
    }
    // Groups newly joined by loops are moved rigidly onto the first loop that ties them to an
    // already placed group (edge order, so deterministic).
    std::vector<bool> placed(n_seg, false);
    placed[solved_labels_[comp]] = true;
    for (bool changed = true; changed;) {
      changed = false;
      for (const GraphEdge& e : edges_) {
        if (e.kind != EdgeKind::kLoop || !e.active) continue;
        const std::size_t sa = segmentIndexOfNode(e.from_index);
        const std::size_t sb = segmentIndexOfNode(e.to_index);
        if (labels[sa] != comp) continue;
        const std::size_t ga = solved_labels_[sa], gb = solved_labels_[sb];
        if (placed[ga] == placed[gb]) continue;
        const GraphNode& a = nodes_[e.from_index];
        const GraphNode& b = nodes_[e.to_index];
        if (placed[ga]) {  // move b's group: b = a (+) measured
          const double yaw_b = wrapAngle(a.yaw_rad() + e.measured.yaw_rad);
          const Eigen::Vector3d p_b = a.p_world_body_m() + rotZ(a.yaw_rad()) * e.measured.t_m;
          moveGroup(gb, fourDofCorrection(p_b, yaw_b, b.p_world_body_m(), b.yaw_rad()));
          placed[gb] = true;
        } else {  // move a's group: a = b (-) measured
          const double yaw_a = wrapAngle(b.yaw_rad() - e.measured.yaw_rad);
          const Eigen::Vector3d p_a = b.p_world_body_m() - rotZ(yaw_a) * e.measured.t_m;
          moveGroup(ga, fourDofCorrection(p_a, yaw_a, a.p_world_body_m(), a.yaw_rad()));
          placed[ga] = true;
        }
        changed = true;
      }
    }
  }
}

void PoseGraph4Dof::applyCorrection(const Eigen::Isometry3d& C, std::size_t segment_index) {
  const double dyaw = yawOf(C.linear());
  for (std::size_t i = segments_[segment_index].begin; i < segments_[segment_index].end; ++i) {
    GraphNode& n = nodes_[i];
    n.xyz_yaw << C * n.p_world_body_m(), wrapAngle(n.yaw_rad() + dyaw);
  }
}

void PoseGraph4Dof::updateResiduals() {
  for (GraphEdge& e : edges_) {
    const GraphNode& a = nodes_[e.from_index];
    const GraphNode& b = nodes_[e.to_index];
    const FourDofEdgeFactor f(e.measured, e.sigma_pos_m, e.sigma_yaw_rad);
    e.normalised_residual = f.residual(a.xyz_yaw.data(), b.xyz_yaw.data()).norm();
  }
}

std::vector<std::size_t> PoseGraph4Dof::components() const {
  std::vector<std::size_t> parent(segments_.size());
  std::iota(parent.begin(), parent.end(), std::size_t{0});
  auto find = [&parent](std::size_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (const GraphEdge& e : edges_) {
    if (e.kind != EdgeKind::kLoop || !e.active) continue;
    const std::size_t ra = find(segmentIndexOfNode(e.from_index));
    const std::size_t rb = find(segmentIndexOfNode(e.to_index));
    // The lower index becomes the root, so a label is the component's lowest segment index.
    if (ra < rb) parent[rb] = ra;
    if (rb < ra) parent[ra] = rb;
  }
  std::vector<std::size_t> labels(segments_.size());
  for (std::size_t s = 0; s < segments_.size(); ++s) labels[s] = find(s);
  return labels;
}

Eigen::Isometry3d PoseGraph4Dof::pose(std::uint64_t id) const {
  const GraphNode& n = nodes_[indexOf(id)];
  // Uncorrected: the odometry pose itself (composing yaw and tilt again would round it).
  if (n.p_world_body_m() == n.T_world_body_odom.translation() && n.yaw_rad() == n.yaw_odom_rad)
    return n.T_world_body_odom;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = rotZ(n.yaw_rad()) * n.R_tilt;
  T.translation() = n.p_world_body_m();
  return T;
}

Eigen::Isometry3d PoseGraph4Dof::drift(int segment) const {
  for (const SegmentRange& r : segments_) {
    if (r.segment != segment) continue;
    const GraphNode& n = nodes_[r.end - 1];
    return fourDofCorrection(n.p_world_body_m(), n.yaw_rad(), n.T_world_body_odom.translation(),
                             n.yaw_odom_rad);
  }
  throw std::out_of_range("PoseGraph4Dof::drift: segment " + std::to_string(segment) +
                          " has no node");
}

bool PoseGraph4Dof::connected(int segment_a, int segment_b) const {
  auto find = [this](int seg) {
    for (std::size_t s = 0; s < segments_.size(); ++s)
      if (segments_[s].segment == seg) return static_cast<long>(s);
    return -1L;
  };
  const long a = find(segment_a), b = find(segment_b);
  if (a < 0 || b < 0) return false;
  const std::vector<std::size_t> labels = components();
  return labels[static_cast<std::size_t>(a)] == labels[static_cast<std::size_t>(b)];
}

std::vector<SegmentState> PoseGraph4Dof::segments() const {
  const std::vector<std::size_t> labels = components();
  std::vector<SegmentState> out;
  for (std::size_t s = 0; s < segments_.size(); ++s) {
    SegmentState st;
    st.segment = segments_[s].segment;
    st.first_id = nodes_[segments_[s].begin].id;
    st.last_id = nodes_[segments_[s].end - 1].id;
    st.nodes = segments_[s].end - segments_[s].begin;
    st.component = segments_[labels[s]].segment;
    st.connected_to_origin = labels[s] == labels[0];
    out.push_back(st);
  }
  return out;
}

std::size_t PoseGraph4Dof::memoryBytes() const {
  return sizeof(*this) + nodes_.capacity() * sizeof(GraphNode) +
         edges_.capacity() * sizeof(GraphEdge) + segments_.capacity() * sizeof(SegmentRange) +
         solved_labels_.capacity() * sizeof(std::size_t);
}

bool PoseGraph4Dof::hasNode(std::uint64_t id) const {
  const auto it = std::lower_bound(nodes_.begin(), nodes_.end(), id,
                                   [](const GraphNode& n, std::uint64_t v) { return n.id < v; });
  return it != nodes_.end() && it->id == id;
}

std::size_t PoseGraph4Dof::indexOf(std::uint64_t id) const {
  const auto it = std::lower_bound(nodes_.begin(), nodes_.end(), id,
                                   [](const GraphNode& n, std::uint64_t v) { return n.id < v; });
  if (it == nodes_.end() || it->id != id)
    throw std::out_of_range("PoseGraph4Dof: unknown node " + std::to_string(id));
  return static_cast<std::size_t>(it - nodes_.begin());
}

std::size_t PoseGraph4Dof::segmentIndexOfNode(std::size_t node_index) const {
  const auto it =
      std::upper_bound(segments_.begin(), segments_.end(), node_index,
                       [](std::size_t v, const SegmentRange& r) { return v < r.begin; });
  return static_cast<std::size_t>(it - segments_.begin()) - 1;
}

}  // namespace rgbdi::loop
