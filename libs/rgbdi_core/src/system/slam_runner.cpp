#include "rgbdi/system/slam_runner.h"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <optional>
#include <sstream>

#include "rgbdi/eval/evaluate.h"
#include "rgbdi/eval/tum_reader.h"
#include "rgbdi/io/mrpt_conversions.h"
#include "rgbdi/io/rawlog_source.h"
#include "rgbdi/mapping/keyframe_store.h"
#include "rgbdi/mapping/map_export.h"
#include "rgbdi/mapping/occupancy_map.h"
#include "rgbdi/mapping/point_map.h"
#include "rgbdi/mapping/trajectory_plot.h"
#include "rgbdi/mapping/viewpoint_index.h"
#include "rgbdi/output/pose_graph.h"
#include "rgbdi/output/summary_json.h"
#include "rgbdi/output/tum_writer.h"
#include "rgbdi/system/system_config.h"
#include "rgbdi/system/vio_system.h"

namespace rgbdi::system {
namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;

void prepareOutputDir(const std::string& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw UserError(dir + ": cannot create output directory: " + ec.message());
  const std::string probe = dir + "/.rgbdi_write_test";
  std::ofstream f(probe);
  if (!f) throw UserError(dir + ": output directory is not writable");
  f.close();
  fs::remove(probe, ec);
}

/// Progress line on stderr: frames, rate, stream time, state (rewritten in place).
class Progress {
 public:
  Progress(std::ostream& os, bool quiet, double interval_s)
      : os_(os), quiet_(quiet), interval_s_(interval_s), start_(Clock::now()), last_(start_) {}
  void update(std::size_t frames, double stream_t, double stream_t0, double fraction,
              const char* state, bool force = false) {
    if (quiet_) return;
    const auto now = Clock::now();
    if (!force && std::chrono::duration<double>(now - last_).count() < interval_s_) return;
    last_ = now;
    const double wall = std::chrono::duration<double>(now - start_).count();
    std::ostringstream line;
    line << std::fixed << std::setprecision(1) << "\r[rgbdi-slam] " << 100.0 * fraction << " %, "
         << frames << " frames, " << (wall > 0 ? frames / wall : 0.0) << " frames/s, ETA ";
    if (fraction > 0.01)
      line << std::setprecision(0) << wall * (1.0 - fraction) / fraction << " s";
    else
      line << "?";
    line << std::setprecision(1) << ", stream " << (stream_t - stream_t0) << " s, " << state
         << "   ";
    os_ << line.str() << std::flush;
    printed_ = true;
  }
  void finish() {
    if (printed_) os_ << "\n";
  }

 private:
  std::ostream& os_;
  bool quiet_;
  double interval_s_;
  Clock::time_point start_, last_;
  bool printed_ = false;
};

/// keyframes.tum and pose_graph.graph: keyframe nodes and odometry edges between consecutive
/// keyframes (loop edges are added by loop closure).
void writeKeyframeOutputs(const std::vector<estimator::KeyframeState>& kfs,
                          const output::OutputOptions& oo, const std::string& kf_path,
                          const std::string& graph_path) {
  Trajectory kf_traj;
  std::vector<output::PoseGraphNode> nodes;
  std::vector<output::PoseGraphEdge> edges;
  Eigen::Matrix<double, 6, 1> info_diag;
  info_diag << Eigen::Vector3d::Constant(
      1.0 / (oo.graph_translation_sigma_m * oo.graph_translation_sigma_m)),
      Eigen::Vector3d::Constant(1.0 / (oo.graph_rotation_sigma_rad * oo.graph_rotation_sigma_rad));
  for (const auto& kf : kfs) {
    if (!kf_traj.empty() && kf.t_imu <= kf_traj.back().t) continue;  // after a reset: keep order
    kf_traj.push_back(StampedPose::fromIsometry(kf.t_imu, kf.T_world_body));
    nodes.push_back({kf.frame_index, kf.t_imu, kf.T_world_body});
    if (nodes.size() >= 2) {
      const auto& a = nodes[nodes.size() - 2];
      const auto& b = nodes.back();
      output::PoseGraphEdge e;
      e.from = a.id;
      e.to = b.id;
      e.T_from_to = a.T_world_body.inverse() * b.T_world_body;
      e.information = info_diag.asDiagonal();
      e.kind = "odometry";
      edges.push_back(e);
    }
  }
  output::writeTum(kf_path, kf_traj);
  if (!nodes.empty()) output::writePoseGraph(graph_path, nodes, edges);
}

}  // namespace

nlohmann::json runSlam(const SlamRunOptions& opt, std::ostream& log) {
  if (opt.input.empty()) throw UserError("no input given (--input SEQ.rawlog)");
  if (!fs::exists(opt.input)) throw UserError(opt.input + ": input file does not exist");
  SystemConfig cfg;
  try {
    cfg = SystemConfig::load(opt.config_path);
  } catch (const ConfigError& e) {
    throw UserError(std::string("configuration error: ") + e.what());
  }
  // Ground truth is read before the run, so a bad file is reported at once.
  Trajectory gt;
  if (!opt.gt_path.empty()) {
    if (!fs::exists(opt.gt_path))
      throw UserError(opt.gt_path + ": ground-truth file does not exist");
    try {
      gt = eval::readTum(opt.gt_path);
    } catch (const std::exception& e) {
      throw UserError(e.what());
    }
  }
  prepareOutputDir(opt.out_dir);

  std::unique_ptr<io::RawlogSource> source;
  try {
    source = std::make_unique<io::RawlogSource>(opt.input, cfg.streamConfig());
  } catch (const std::exception& e) {
    throw UserError(e.what());
  }
  source->setMinLoggingLevel(mrpt::system::LVL_ERROR);  // warnings go into the diagnostics

  VioSystem vio(cfg, !opt.no_depth);

  // Mapping: every keyframe whose pose is final goes into the point octree (and the occupancy
  // map); the store keeps its kept points and features for later pose-graph updates.
  mapping::PointMap point_map(cfg.mapping);
  std::unique_ptr<mapping::OccupancyMap> occupancy;
  if (cfg.output.write_octomap) occupancy = std::make_unique<mapping::OccupancyMap>(cfg.mapping);
  mapping::KeyframeStore store;
  mapping::ViewpointIndex viewpoints(cfg.mapping.view_update_distance_m,
                                     cfg.mapping.view_update_angle_deg);
  std::vector<mapping::SimpleMapEntry> simplemap;
  double mapping_ms = 0.0;
  const Eigen::Isometry3d T_bc = cfg.extrinsic.T_body_cam;
  vio.setKeyframeCallback([&](const estimator::KeyframeState& kf, const RgbdFrame& frame,
                              const frontend::FeatureFrame& ff) {
    if (store.contains(kf.frame_index)) return;
    const auto t_map = Clock::now();
    mapping::Keyframe k;
    k.id = kf.frame_index;
    k.frame_index = kf.frame_index;
    k.t = frame.t;
    k.T_world_cam = kf.T_world_body * T_bc;
    for (const auto& f : ff.features) {
      mapping::KeyframeFeature kfe;
      kfe.id = f.id;
      kfe.uv = f.uv;
      kfe.has_position = f.depth_m > 0.0;
      if (kfe.has_position) kfe.p_cam = Eigen::Vector3d(f.xn.x(), f.xn.y(), 1.0) * f.depth_m;
      k.features.push_back(kfe);
    }
    // A keyframe seen from where the map was already seen adds no points (bounded memory on
    // repeated routes); it is still stored with its features for the pose graph.
    if (frame.hasDepth() && !viewpoints.covered(k.T_world_cam)) {
      k.points = point_map.insertKeyframe(frame, k.T_world_cam);
      viewpoints.add(k.T_world_cam);
    }
    if (occupancy) occupancy->insertPoints(k.points, k.T_world_cam);
    if (opt.save_simplemap) simplemap.push_back({kf.T_world_body, io::toMrpt(frame, T_bc, "RGBD")});
    store.add(std::move(k));
    mapping_ms += std::chrono::duration<double, std::milli>(Clock::now() - t_map).count();
  });
  Progress progress(log, opt.quiet, cfg.output.progress_interval_s);
  const auto wall0 = Clock::now();
  double t0 = NAN, t_last = NAN;
  std::size_t frames = 0;
  bool interrupted = false;
  std::string read_error;
  try {
    io::Measurement m;
    while (true) {
      if (opt.stop && opt.stop->load()) {
        interrupted = true;
        break;
      }
      if (!source->next(m)) break;
      const double t = io::measurementTime(m);
      if (std::isnan(t0)) t0 = t;
      t_last = t;
      if (const auto* imu = std::get_if<ImuSample>(&m)) {
        vio.feedImu(*imu);
      } else {
        vio.feedRgbd(std::get<RgbdFrame>(m));
        ++frames;
        progress.update(frames, t, t0, source->progress(), estimator::toString(vio.status()));
      }
    }
  } catch (const io::RawlogError& e) {
    read_error = e.what();  // everything before the damage was processed
  }
  vio.endOfStream();
  progress.update(frames, std::isnan(t_last) ? 0 : t_last, std::isnan(t0) ? 0 : t0,
                  source->progress(), estimator::toString(vio.status()), true);
  progress.finish();
  const double wall_s = std::chrono::duration<double>(Clock::now() - wall0).count();

  // --- outputs -------------------------------------------------------------------------------
  const std::string traj_path = opt.out_dir + "/trajectory.tum";
  const std::string traj_cam_path = opt.out_dir + "/trajectory_cam.tum";
  output::writeTum(traj_path, vio.trajectoryBody());
  output::writeTum(traj_cam_path, vio.trajectoryCamera());
  const std::string kf_path = opt.out_dir + "/keyframes.tum";
  const std::string graph_path = opt.out_dir + "/pose_graph.graph";
  writeKeyframeOutputs(vio.keyframes(), cfg.output, kf_path, graph_path);

  // Map outputs.
  nlohmann::json outputs_map;
  // Evaluation against ground truth, once: its position+yaw alignment also places the ground
  // truth in the estimate's frame for the plot and the scene.
  std::optional<eval::EvalResult> eval_posyaw, eval_sim3;
  std::string eval_error;
  if (!opt.gt_path.empty()) {
    try {
      eval::EvalOptions eo;
      eo.align = eval::AlignMode::PosYaw;
      eval_posyaw = eval::evaluate(gt, vio.trajectoryBody(), eo);
      eo.align = eval::AlignMode::Sim3;
      eval_sim3 = eval::evaluate(gt, vio.trajectoryBody(), eo);
    } catch (const std::exception& e) {
      eval_error = e.what();
    }
  }
  const auto t_out = Clock::now();
  if (cfg.output.write_ply) {
    outputs_map["map_ply"] = opt.out_dir + "/map.ply";
    mapping::writePly(outputs_map["map_ply"], point_map);
  }
  outputs_map["map_pointsmap"] = opt.out_dir + "/map.pointsmap";
  mapping::writePointsMap(outputs_map["map_pointsmap"], point_map);
  if (occupancy) {
    outputs_map["map_bt"] = opt.out_dir + "/map.bt";
    occupancy->write(outputs_map["map_bt"]);
  }
  if (opt.save_simplemap) {
    outputs_map["keyframes_simplemap"] = opt.out_dir + "/keyframes.simplemap";
    mapping::writeSimpleMap(outputs_map["keyframes_simplemap"], simplemap);
  }
  // Ground truth expressed in the estimate's frame (position + yaw alignment) for the plot/scene.
  Trajectory gt_in_est;
  if (eval_posyaw) {
    const Eigen::Isometry3d T_est_gt = eval_posyaw->alignment.rigid().inverse();
    for (const auto& g : gt)
      gt_in_est.push_back(StampedPose::fromIsometry(g.t, T_est_gt * g.isometry()));
  }
  if (cfg.output.write_scene) {
    outputs_map["scene"] = opt.out_dir + "/scene.3Dscene";
    mapping::writeScene(outputs_map["scene"], point_map, vio.trajectoryBody(), store,
                        cfg.mapping.scene, gt_in_est.empty() ? nullptr : &gt_in_est);
  }
  if (cfg.output.write_plot && vio.trajectoryBody().size() >= 2) {
    outputs_map["plot"] = opt.out_dir + "/trajectory.png";
    mapping::plotTrajectory(outputs_map["plot"], vio.trajectoryBody(),
                            gt_in_est.empty() ? nullptr : &gt_in_est, cfg.mapping.plot);
  }
  const double output_ms = std::chrono::duration<double, std::milli>(Clock::now() - t_out).count();

  const auto& st = vio.estimatorStats();
  const auto& tm = vio.timings();
  nlohmann::json summary;
  summary["input"] = opt.input;
  summary["config"] = cfg.source;
  summary["mode"] = opt.no_depth ? "mono-inertial (--no-depth)" : "rgbd-inertial";
  summary["interrupted"] = interrupted;
  summary["read_error"] = read_error.empty() ? nlohmann::json() : nlohmann::json(read_error);
  summary["frames"] = vio.framesReceived();
  summary["frames_dropped"] = vio.framesDropped();
  summary["poses"] = vio.trajectoryBody().size();
  summary["stream_start_s"] = std::isnan(t0) ? nlohmann::json() : nlohmann::json(t0);
  summary["stream_duration_s"] = std::isnan(t0) ? 0.0 : t_last - t0;
  summary["first_pose_time_s"] =
      st.first_pose_t_image < 0 ? nlohmann::json() : nlohmann::json(st.first_pose_t_image - t0);
  summary["resets"] = st.resets;
  summary["static_initialisations"] = st.static_initialisations;
  summary["moving_initialisations"] = st.moving_initialisations;
  summary["time_offset_s"] = vio.estimator().timeOffset();
  summary["wall_time_s"] = wall_s;
  summary["frames_per_s"] = wall_s > 0 ? frames / wall_s : 0.0;
  const double n_tr = std::max(1, tm.frames_tracked), n_est = std::max(1, tm.frames_estimated);
  summary["timing_ms_per_frame"] = {{"tracking", tm.tracking_ms / n_tr},
                                    {"preintegration", tm.preintegration_ms / n_est},
                                    {"optimisation", tm.optimisation_ms / n_est},
                                    {"marginalisation", tm.marginalisation_ms / n_est}};
  const auto& ms = point_map.stats();
  summary["map"] = {{"keyframes", store.size()},
                    {"keyframes_adding_points", viewpoints.size()},
                    {"grid_points", ms.grid_points},
                    {"points_with_depth_in_range", ms.candidates},
                    {"rejected_full_leaf", ms.rejected_full_leaf},
                    {"points", point_map.pointCount()},
                    {"leaves", point_map.leafCount()},
                    {"memory_bytes", point_map.memoryBytes() + store.memoryBytes()},
                    {"point_octree_bytes", point_map.memoryBytes()},
                    {"keyframe_store_bytes", store.memoryBytes()},
                    {"occupancy_bytes", occupancy ? occupancy->memoryBytes() : 0},
                    {"mapping_ms_total", mapping_ms},
                    {"output_ms", output_ms}};
  summary["stream_diagnostics"] = nlohmann::json::parse(source->diagnostics().toJson());
  summary["keyframes"] = vio.keyframes().size();
  summary["outputs"] = {{"trajectory", traj_path},
                        {"trajectory_cam", traj_cam_path},
                        {"keyframes", kf_path},
                        {"pose_graph", graph_path}};
  for (const auto& [k, v] : outputs_map.items()) summary["outputs"][k] = v;

  if (eval_posyaw && eval_sim3) {
    summary["evaluation"] = eval::toJson(*eval_posyaw);
    summary["evaluation_sim3"] = eval::toJson(*eval_sim3);
    log << "Accuracy against " << opt.gt_path << " (position+yaw alignment):\n"
        << eval::formatReport(*eval_posyaw) << "Scale (Sim(3) alignment): " << std::setprecision(6)
        << eval_sim3->alignment.scale << "\n";
  } else if (!eval_error.empty()) {
    summary["evaluation_error"] = eval_error;
    log << "Evaluation failed: " << eval_error << "\n";
  }
  const std::string summary_path = opt.out_dir + "/summary.json";
  summary["outputs"]["summary"] = summary_path;
  output::writeSummaryJson(summary_path, summary);

  log << "Processed " << frames << " frames in " << std::setprecision(3) << wall_s << " s ("
      << summary["frames_per_s"].get<double>() << " frames/s), " << vio.trajectoryBody().size()
      << " poses, " << st.resets << " resets" << (interrupted ? " (interrupted)" : "") << "\n";
  if (!read_error.empty()) log << "Input ended early: " << read_error << "\n";
  log << "Outputs:\n";
  for (const auto& [name, path] : summary["outputs"].items())
    log << "  " << path.get<std::string>() << "\n";
  return summary;
}

}  // namespace rgbdi::system
