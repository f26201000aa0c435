#include "rgbdi/system/slam_outputs.h"

#include <map>
#include <set>

#include <cmath>

#include "rgbdi/mapping/map_export.h"
#include "rgbdi/mapping/trajectory_plot.h"
#include "rgbdi/output/pose_graph.h"
#include "rgbdi/output/tum_writer.h"

namespace rgbdi::system {

output::PoseGraph slamPoseGraph(const SlamSystem& sys) {
  const output::OutputOptions& oo = sys.config().output;
  Eigen::Matrix<double, 6, 1> info_diag;
  info_diag << Eigen::Vector3d::Constant(
      1.0 / (oo.graph_translation_sigma_m * oo.graph_translation_sigma_m)),
      Eigen::Vector3d::Constant(1.0 / (oo.graph_rotation_sigma_rad * oo.graph_rotation_sigma_rad));
  output::PoseGraph g;
  const auto& kfs = sys.keyframeStates();
  for (std::size_t i = 0; i < kfs.size(); ++i) {
    g.nodes.push_back({kfs[i].id, kfs[i].state.t_imu, sys.keyframePose(i)});
    if (i == 0 || kfs[i - 1].state.segment != kfs[i].state.segment) continue;
    output::PoseGraphEdge e;
    e.from = kfs[i - 1].id;
    e.to = kfs[i].id;
    e.T_from_to = kfs[i - 1].state.T_world_body.inverse() * kfs[i].state.T_world_body;
    e.information = info_diag.asDiagonal();
    e.kind = "odometry";
    g.edges.push_back(e);
  }
  // Verified loops that survived every solve, with the pose graph's loop-edge uncertainty (roll
  // and pitch, which the 4-DOF graph keeps from the odometry, take the odometry edges' value).
  if (const loop::LoopCloser* lc = sys.loopCloser()) {
    const auto& go = lc->graph().options();
    const double deg = M_PI / 180.0;
    Eigen::Matrix<double, 6, 1> loop_info;
    loop_info << Eigen::Vector3d::Constant(1.0 / (go.loop_sigma_pos_m * go.loop_sigma_pos_m)),
        1.0 / (oo.graph_rotation_sigma_rad * oo.graph_rotation_sigma_rad),
        1.0 / (oo.graph_rotation_sigma_rad * oo.graph_rotation_sigma_rad),
        1.0 / (go.loop_sigma_yaw_deg * deg * go.loop_sigma_yaw_deg * deg);
    // Loops into a loaded map bring the map keyframes they reach as nodes (at their map poses).
    std::set<std::uint64_t> map_nodes;
    const map::MapData* loaded = sys.loadedMap();
    for (const loop::LoopRecord& l : lc->loops())
      if (!l.rolled_back && loaded && l.constraint.from_id < sys.firstKeyframeId())
        map_nodes.insert(l.constraint.from_id);
    for (const loop::LoopKeyframe& p : loaded ? loaded->places : std::vector<loop::LoopKeyframe>{})
      if (map_nodes.count(p.id)) g.nodes.push_back({p.id, p.t, p.T_world_body});
    for (const loop::LoopRecord& l : lc->loops()) {
      if (l.rolled_back) continue;
      output::PoseGraphEdge e;
      e.from = l.constraint.from_id;
      e.to = l.constraint.to_id;
      e.T_from_to = l.constraint.T_from_to;
      e.information = loop_info.asDiagonal();
      e.kind = "loop";
      g.edges.push_back(e);
    }
  }
  if (!g.nodes.empty()) g.root = g.nodes.front().id;
  return g;
}

nlohmann::json writeSlamOutputs(const SlamSystem& sys, const std::string& dir,
                                const Trajectory* gt_in_est, bool write_simplemap) {
  const SystemConfig& cfg = sys.config();
  nlohmann::json out;
  const Trajectory final_body = sys.finalTrajectory();
  const Trajectory online_body = sys.onlineTrajectory();
  const Trajectory odom_body = sys.odometryTrajectory();
  auto tum = [&](const std::string& name, const Trajectory& t, const std::string& what) {
    const std::string path = dir + "/" + name + ".tum";
    output::writeTum(path, t, what);
    out[name] = path;
  };
  const std::string body = "body (IMU) frame in the world, IMU clock (image stamp + time offset)";
  const std::string cam = "colour camera optical frame in the world, image stamps (camera clock)";
  const std::string best = "best estimate after the last loop-closure solve";
  const std::string online = "online: corrections known at each frame's time";
  const std::string odom = "odometry alone, no loop correction";
  tum("trajectory", final_body, body + "; " + best);
  tum("trajectory_cam", sys.toCameraFrame(final_body), cam + "; " + best);
  tum("trajectory_online", online_body, body + "; " + online);
  tum("trajectory_online_cam", sys.toCameraFrame(online_body), cam + "; " + online);
  tum("trajectory_odometry", odom_body, body + "; " + odom);
  tum("trajectory_odometry_cam", sys.toCameraFrame(odom_body), cam + "; " + odom);

  Trajectory kf_traj;
  for (std::size_t i = 0; i < sys.keyframeStates().size(); ++i)
    kf_traj.push_back(
        StampedPose::fromIsometry(sys.keyframeStates()[i].state.t_imu, sys.keyframePose(i)));
  tum("keyframes", kf_traj, body + "; keyframes at their final poses");
  const output::PoseGraph graph = slamPoseGraph(sys);
  if (!graph.nodes.empty()) {
    out["pose_graph"] = dir + "/pose_graph.graph";
    output::writePoseGraph(out["pose_graph"], graph.nodes, graph.edges);
  }

  const mapping::Mapper& map = sys.mapper();
  if (cfg.output.write_ply) {
    out["map_ply"] = dir + "/map.ply";
    mapping::writePly(out["map_ply"], map.pointMap());
  }
  out["map_pointsmap"] = dir + "/map.pointsmap";
  mapping::writePointsMap(out["map_pointsmap"], map.pointMap());
  if (map.occupancy()) {
    out["map_bt"] = dir + "/map.bt";
    map.occupancy()->write(out["map_bt"]);
  }
  if (write_simplemap) {
    std::vector<mapping::SimpleMapEntry> entries;
    for (std::size_t i = 0; i < sys.observations().size(); ++i)
      entries.push_back({sys.keyframePose(i), sys.observations()[i]});
    out["keyframes_simplemap"] = dir + "/keyframes.simplemap";
    mapping::writeSimpleMap(out["keyframes_simplemap"], entries);
  }
  if (cfg.output.write_scene) {
    std::vector<mapping::SceneSegment> loop_lines;
    std::map<std::uint64_t, Eigen::Vector3d> node_position;  // ids: a loaded map's included
    for (const auto& n : graph.nodes) node_position[n.id] = n.T_world_body.translation();
    for (const output::PoseGraphEdge& e : graph.edges) {
      if (e.kind != "loop") continue;
      loop_lines.emplace_back(node_position.at(e.from), node_position.at(e.to));
    }
    out["scene"] = dir + "/scene.3Dscene";
    mapping::writeScene(out["scene"], map.pointMap(), final_body, map.store(), cfg.mapping.scene,
                        gt_in_est, &loop_lines);
  }
  if (cfg.output.write_plot && final_body.size() >= 2) {
    out["plot"] = dir + "/trajectory.png";
    mapping::plotTrajectory(
        out["plot"], final_body, gt_in_est, cfg.mapping.plot,
        gt_in_est ? "ground truth aligned by position + yaw" : "no alignment applied");
  }
  return out;
}

}  // namespace rgbdi::system
