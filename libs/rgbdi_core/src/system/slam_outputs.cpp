#include "rgbdi/system/slam_outputs.h"

#include <chrono>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>

#include "rgbdi/mapping/map_export.h"
#include "rgbdi/mapping/trajectory_plot.h"
#include "rgbdi/navmap/navmap_files.h"
#include "rgbdi/output/pose_graph.h"
#include "rgbdi/output/tum_writer.h"
#include "rgbdi/system/slam_navmap.h"

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

std::string tumFrameAndClock(TumOutput what, const TumFrames& f) {
  std::string pose = f.camera ? "poses: colour camera optical frame (x right, y down, z forward)"
                              : "poses: body (IMU) frame";
  const std::string own_world =
      "this run's world frame (z up against gravity, origin and heading of the first pose)";
  std::string in;
  if (!f.loaded_map) {
    in = "in: " + own_world;
  } else if (what == TumOutput::kOdometry) {
    in = "in: " + own_world + ", not the loaded map's frame";
  } else if (what == TumOutput::kKeyframes) {
    in = "in: the frame of the map loaded with --load-map for keyframes of segments relocalised "
         "in it, their segment's odometry frame for the others";
  } else {
    in = "in: the frame of the map loaded with --load-map (only poses relocalised in it)";
  }
  const std::string clock = f.live ? "the live sensors' clock (doc/live.md)" : "the input's clock";
  const std::string stamps =
      f.camera ? "stamps: image stamps, " + clock
               : "stamps: IMU time (image stamp + estimated camera-IMU time offset), " + clock;
  std::string kind;
  switch (what) {
    case TumOutput::kFinal:
      kind = "optimised: best estimate after the last loop-closure (pose graph) solve";
      break;
    case TumOutput::kOnline:
      kind = "online: causal, with the loop corrections known at each frame's time";
      break;
    case TumOutput::kOdometry:
      kind = "odometry alone: no loop correction";
      break;
    case TumOutput::kKeyframes:
      kind = "keyframes at their final (loop-corrected) poses";
      break;
  }
  return pose + "\n" + in + "\n" + stamps + "\n" + kind;
}

Trajectory cameraTwin(const Trajectory& body, const std::deque<FrameRecord>& frames,
                      const Eigen::Isometry3d& T_body_cam) {
  // Both are in stamp order: one pass pairs each pose with the frame of the same IMU time.
  Trajectory out;
  out.reserve(body.size());
  std::size_t j = 0;
  for (const StampedPose& p : body) {
    while (j < frames.size() && frames[j].t_imu < p.t) ++j;
    if (j == frames.size() || frames[j].t_imu != p.t)
      throw std::logic_error("cameraTwin: pose stamp " + std::to_string(p.t) +
                             " is no frame's IMU time");
    out.push_back(StampedPose::fromIsometry(frames[j].t_image, p.isometry() * T_body_cam));
  }
  return out;
}

std::string plotAlignmentText(bool ground_truth_aligned) {
  return ground_truth_aligned ? "ground truth aligned to the estimate: position + yaw"
                              : "no alignment applied";
}

nlohmann::json writeSlamOutputs(const SlamSystem& sys, const std::string& dir,
                                const Trajectory* gt_in_est, bool write_simplemap,
                                nlohmann::json* navmap_summary) {
  const SystemConfig& cfg = sys.config();
  nlohmann::json out;
  const Trajectory final_body = sys.finalTrajectory();
  const Trajectory online_body = sys.onlineTrajectory();
  const Trajectory odom_body = sys.odometryTrajectory();
  TumFrames frames;
  frames.loaded_map = sys.hasMap();
  frames.live = sys.options().live;
  auto tum = [&](const std::string& name, const Trajectory& body, TumOutput what, bool twin) {
    frames.camera = false;
    const std::string path = dir + "/" + name + ".tum";
    output::writeTum(path, body, tumFrameAndClock(what, frames));
    out[name] = path;
    if (!twin) return;
    frames.camera = true;
    const std::string cam_path = dir + "/" + name + "_cam.tum";
    output::writeTum(cam_path, cameraTwin(body, sys.frames(), sys.T_body_cam()),
                     tumFrameAndClock(what, frames));
    out[name + "_cam"] = cam_path;
  };
  tum("trajectory", final_body, TumOutput::kFinal, true);
  tum("trajectory_online", online_body, TumOutput::kOnline, true);
  tum("trajectory_odometry", odom_body, TumOutput::kOdometry, true);

  Trajectory kf_traj;
  for (std::size_t i = 0; i < sys.keyframeStates().size(); ++i)
    kf_traj.push_back(
        StampedPose::fromIsometry(sys.keyframeStates()[i].state.t_imu, sys.keyframePose(i)));
  tum("keyframes", kf_traj, TumOutput::kKeyframes, false);
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
  // Navigation maps from the same points as map.ply and the best-estimate path.
  std::vector<mrpt::opengl::CRenderizable::Ptr> nav_objects;
  if (cfg.navmap.enable && !final_body.empty()) {
    const auto t0 = std::chrono::steady_clock::now();
    const navmap::NavMap nav = slamNavMap(sys, cfg.navmap);
    const double build_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    std::vector<Eigen::Vector3d> path;
    for (const StampedPose& p : final_body) path.push_back(p.p);
    for (const auto& [name, file] : navmap::writeNavMapFiles(nav, dir, &path)) out[name] = file;
    if (navmap_summary) *navmap_summary = navMapSummary(nav, build_ms);
    if (cfg.output.write_scene) nav_objects = navmap::sceneObjects(nav);
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
                        gt_in_est, &loop_lines, &nav_objects);
  }
  if (cfg.output.write_plot && final_body.size() >= 2) {
    out["plot"] = dir + "/trajectory.png";
    mapping::plotTrajectory(out["plot"], final_body, gt_in_est, cfg.mapping.plot,
                            plotAlignmentText(gt_in_est != nullptr));
  }
  return out;
}

}  // namespace rgbdi::system
