#include "rgbdi/system/slam_summary.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <set>
#include <sstream>
#include <utility>
#include <vector>

namespace rgbdi::system {

namespace {
/// [s] a first pose later than this after the first image is explained in the run report (a
/// static start takes the first two images, a moving start about init_min_frames).
constexpr double kReportInitWaitsAfter_s = 1.0;
/// Reasons of the wait listed on the console (summary.json has them all).
constexpr std::size_t kReportedInitWaitReasons = 3;

eval::EvalResult evaluateThrough(const Trajectory& gt, const Trajectory& est,
                                 const Eigen::Isometry3d& T_gt_world) {
  Trajectory moved;
  moved.reserve(est.size());
  for (const StampedPose& p : est)
    moved.push_back(StampedPose::fromIsometry(p.t, T_gt_world * p.isometry()));
  eval::EvalOptions eo;
  eo.align = eval::AlignMode::None;
  return eval::evaluate(gt, moved, eo);
}
}  // namespace

RunEvaluation evaluateRun(const SlamSystem& sys, const Trajectory& gt) {
  RunEvaluation ev;
  try {
    const Trajectory final_traj = sys.finalTrajectory();
    if (sys.hasMap() && final_traj.empty())
      throw std::runtime_error(
          "the run never relocalised in the loaded map: no pose in the map's frame "
          "(trajectory.tum is empty; the odometry alone is in trajectory_odometry.tum)");
    eval::EvalOptions eo;
    eo.align = eval::AlignMode::PosYaw;
    ev.final_posyaw = eval::evaluate(gt, final_traj, eo);
    ev.online = eval::evaluate(gt, sys.onlineTrajectory(), eo);
    ev.odometry = eval::evaluate(gt, sys.odometryTrajectory(), eo);
    eo.align = eval::AlignMode::Sim3;
    ev.final_sim3 = eval::evaluate(gt, final_traj, eo);
    const map::MapData* m = sys.loadedMap();
    if (m && m->manifest.has_groundtruth_alignment) {
      ev.final_in_map = evaluateThrough(gt, final_traj, m->manifest.T_groundtruth_world);
      ev.online_in_map =
          evaluateThrough(gt, sys.onlineTrajectory(), m->manifest.T_groundtruth_world);
    }
  } catch (const std::exception& e) {
    ev.error = e.what();
  }
  return ev;
}

nlohmann::json loopSummary(const SlamSystem& sys) {
  nlohmann::json j;
  j["enabled"] = sys.config().loop.enable;
  const loop::LoopCloser* lc = sys.loopCloser();
  if (!lc) return j;
  const loop::LoopStats& st = lc->stats();
  const loop::PlaceRecognitionStats& ps = lc->placeStats();
  nlohmann::json rejected = nlohmann::json::object();
  for (loop::LoopRejection r : loop::kAllLoopRejections)
    if (r != loop::LoopRejection::Accepted)
      rejected[loop::toString(r)] = st.rejected[static_cast<std::size_t>(r)];
  const double n_kf = std::max<double>(1.0, static_cast<double>(st.keyframes));
  const double n_ver = std::max<double>(1.0, static_cast<double>(st.verified));
  j["keyframes_queried"] = st.keyframes;
  j["place_recognition"] = {{"above_threshold", ps.above_threshold},
                            {"temporally_consistent", ps.temporally_consistent},
                            {"proximity", ps.proximity},
                            {"no_reference", ps.no_reference}};
  j["candidates"] = st.candidates;
  j["candidates_by_proximity"] = st.candidates_by_proximity;
  j["verified"] = st.verified;
  j["rejected"] = rejected;
  j["accepted"] = st.accepted;
  j["external"] = st.external;
  j["rolled_back"] = st.rolled_back;
  j["active_loops"] = st.accepted + st.external - st.rolled_back;
  j["within_odometry_uncertainty"] = st.within_odometry_uncertainty;
  double max_sigmas = 0.0;  // of the loops the gate judged (within one segment)
  for (const loop::LoopRecord& r : lc->loops())
    max_sigmas = std::max(max_sigmas, r.disagreement_sigmas);
  j["max_disagreement_sigmas"] = max_sigmas;
  j["correcting"] = lc->correcting();
  j["solves"] = st.solves;
  j["timing_ms"] = {{"features_per_keyframe", st.features_ms_total / n_kf},
                    {"recognition_per_keyframe", st.recognition_ms_total / n_kf},
                    {"verification_per_candidate", st.verification_ms_total / n_ver},
                    {"solve_total", st.solve_ms_total},
                    {"solve_max", st.solve_ms_max}};
  j["solver_iterations_total"] = st.solver_iterations_total;
  j["memory_bytes"] = lc->memoryBytes();
  nlohmann::json segs = nlohmann::json::array();
  for (const loop::SegmentState& seg : lc->graph().segments()) {
    const Eigen::Isometry3d D = lc->graph().drift(seg.segment);
    segs.push_back({{"segment", seg.segment},
                    {"keyframes", seg.nodes},
                    {"connected_to_first_segment", seg.connected_to_origin},
                    {"final_drift_correction_m", D.translation().norm()},
                    {"final_drift_correction_yaw_deg",
                     std::atan2(D.linear()(1, 0), D.linear()(0, 0)) * 180.0 / M_PI}});
  }
  j["segments"] = segs;
  return j;
}

nlohmann::json mapSessionSummary(const SlamSystem& sys, const RunInfo& run) {
  nlohmann::json j;
  const bool have_t = !std::isnan(run.stream_t0);
  j["loaded_from"] =
      run.map_loaded_from.empty() ? nlohmann::json() : nlohmann::json(run.map_loaded_from);
  j["mode"] =
      !sys.hasMap() ? "new map" : (sys.options().localize_only ? "localize-only" : "mapping");
  j["state"] = toString(sys.mapState());
  const loop::LoopCloser* lc = sys.loopCloser();
  j["map_keyframes_loaded"] = lc ? lc->mapKeyframes() : 0;
  const double t_reloc = sys.firstRelocalisationTime();
  j["relocalised_at_s"] =
      t_reloc >= 0 && have_t ? nlohmann::json(t_reloc - run.stream_t0) : nlohmann::json();
  const double t_online = sys.firstOnlinePoseInMapTime();
  j["online_in_map_from_s"] =
      t_online >= 0 && have_t ? nlohmann::json(t_online - run.stream_t0) : nlohmann::json();
  nlohmann::json joins = nlohmann::json::array();
  if (lc)
    for (const loop::JoinRecord& jr : lc->joins())
      joins.push_back({{"segment", jr.segment},
                       {"joined_segment", jr.to_segment},
                       {"time_s", have_t ? jr.t_query - run.stream_t0 : jr.t_query},
                       {"keyframe", jr.query_id},
                       {"loop_edges", jr.loop_edges},
                       {"free_space_compared", jr.check_compared},
                       {"free_space_conflicts", jr.check_conflicts},
                       {"by", jr.geometric ? "geometry" : "views"}});
  j["joins"] = joins;
  if (lc)
    j["join_matches"] = {{"too_few_inliers", lc->stats().join_matches_weak},
                         {"ambiguous_decisions", lc->stats().joins_ambiguous},
                         {"refused_by_free_space", lc->stats().joins_refused_free_space},
                         {"unconfirmed", lc->stats().join_matches_dropped}};
  if (const GeoRelocStage* g = sys.geoReloc()) {
    const GeoRelocReport r = g->report();
    j["geometric"] = {
        {"attempts", r.attempts},
        {"results", r.results},
        {"too_little_structure", r.too_little},
        {"no_place", r.no_place},
        {"ambiguous", r.ambiguous},
        {"no_height", r.no_height},
        {"not_confirmed_by_icp", r.unrefined},
        {"fits", r.fits},
        {"disagreements", r.disagreements},
        {"confirmed", r.confirmed},
        {"joined", r.joined},
        {"refused_by_free_space", lc ? lc->stats().geometric_refused_free_space : 0},
        {"refused_no_map_keyframe_near", lc ? lc->stats().geometric_refused_no_neighbour : 0},
        {"last_outcome", r.last_outcome},
        {"last_places", r.last_places},
        {"max_places", r.max_places},
        {"ms_per_attempt_mean",
         r.searched > 0 ? r.ms_total / static_cast<double>(r.searched) : 0.0},
        {"ms_per_attempt_max", r.ms_max},
        {"map_plan_build_ms", r.map_build_ms},
        {"tracking",
         {{"attempts", r.track_attempts},
          {"results", r.track_results},
          {"fits", r.track_fits},
          {"not_confirmed_by_icp", r.track_unrefined},
          {"too_far_from_present_pose", r.track_too_far},
          {"too_little_depth", r.track_too_little},
          {"edges_added_by", lc ? lc->stats().tracking_fits : 0},
          {"refused_by_free_space", lc ? lc->stats().tracking_refused_free_space : 0},
          {"refused_no_map_keyframe_near", lc ? lc->stats().tracking_refused_no_neighbour : 0},
          {"largest_correction_m", r.track_correction_max_m},
          {"ms_per_fit_mean",
           r.track_results > 0 ? r.track_ms_total / static_cast<double>(r.track_results) : 0.0},
          {"ms_per_fit_max", r.track_ms_max}}}};
    // Every search whose result was taken: when, what it found, where it put the part.
    nlohmann::json list = nlohmann::json::array();
    for (const reloc::RelocFit& f : g->taken()) {
      nlohmann::json e = {{"time_s", have_t ? f.t_query - run.stream_t0 : f.t_query},
                          {"outcome", reloc::toString(f.outcome)},
                          {"local_obstacle_cells", f.local_obstacles},
                          {"submap_path_m", f.submap_path_m},
                          {"candidates", f.candidates},
                          {"places", f.places},
                          {"ms", f.ms}};
      if (!f.place_poses.empty()) {
        nlohmann::json places = nlohmann::json::array();
        for (std::size_t i = 0; i < f.place_poses.size(); ++i)
          places.push_back({{"x", f.place_poses[i].x()},
                            {"y", f.place_poses[i].y()},
                            {"yaw", f.place_poses[i].z()},
                            {"score", f.place_scores[i]}});
        e["places_in_map"] = places;
      }
      if (f.outcome == reloc::FitOutcome::kFit || f.outcome == reloc::FitOutcome::kUnrefined) {
        e["overlap"] = f.overlap;
        e["conflict_fraction"] = f.conflict_fraction;
        e["refine_pairs"] = f.refine_pairs;
        e["refine_samples"] = f.refine_samples;
        e["refine_rms_m"] = f.refine_rms_m;
        e["refine_horizontal_constraint"] = f.refine_horizontal_constraint;
        e["height_drift_per_m"] = f.height_drift_per_m;
        e["tilt_deg"] = f.tilt_rad * 180.0 / M_PI;
      }
      if (f.outcome == reloc::FitOutcome::kFit) {
        const Eigen::Isometry3d P = f.T_map_part * f.T_anchor;  // the anchor in the map
        e["T_map_body_xyz_yaw"] = {P.translation().x(), P.translation().y(), P.translation().z(),
                                   std::atan2(P.linear()(1, 0), P.linear()(0, 0))};
        e["stamp"] = f.t_query;
      }
      list.push_back(e);
    }
    j["geometric"]["searches"] = list;
  }
  j["first_keyframe_id"] = sys.firstKeyframeId();
  j["saved_to"] = run.map_saved_to.empty() ? nlohmann::json() : nlohmann::json(run.map_saved_to);
  j["note"] = run.map_save_note.empty() ? nlohmann::json() : nlohmann::json(run.map_save_note);
  return j;
}

namespace {
/// The wheel gate's left-out episodes, times since the stream's start [s].
nlohmann::json wheelEpisodes(const estimator::EstimatorStats& st, double t0) {
  nlohmann::json list = nlohmann::json::array();
  for (const auto& e : st.wheel_fault_episodes)
    list.push_back({{"kind", e.kind}, {"start_s", e.t_start - t0}, {"end_s", e.t_end - t0}});
  return list;
}
}  // namespace

nlohmann::json slamSummary(const SlamSystem& sys, const RunInfo& run, const RunEvaluation& ev,
                           const nlohmann::json& outputs) {
  const VioSystem& vio = sys.odometry();
  const auto& st = vio.estimatorStats();
  const auto& tm = vio.timings();
  const SystemConfig& cfg = sys.config();
  const bool have_t = !std::isnan(run.stream_t0);
  nlohmann::json s;
  s["input"] = run.input;
  s["config"] = cfg.source;
  s["mode"] = run.no_depth ? "mono-inertial (--no-depth)" : "rgbd-inertial";
  s["interrupted"] = run.interrupted;
  s["read_error"] = run.read_error.empty() ? nlohmann::json() : nlohmann::json(run.read_error);
  s["frames"] = vio.framesReceived();
  s["frames_dropped"] = vio.framesDropped();
  s["poses"] = sys.frames().size();
  s["stream_start_s"] = have_t ? nlohmann::json(run.stream_t0) : nlohmann::json();
  s["stream_duration_s"] = have_t ? run.stream_t_last - run.stream_t0 : 0.0;
  s["first_pose_time_s"] = st.first_pose_t_image < 0 || !have_t
                               ? nlohmann::json()
                               : nlohmann::json(st.first_pose_t_image - run.stream_t0);
  s["resets"] = st.resets;
  s["static_initialisations"] = st.static_initialisations;
  s["moving_initialisations"] = st.moving_initialisations;
  s["initialisation_waits"] = st.init_waits;
  s["time_offset_s"] = vio.timeOffset();
  if (cfg.estimator.estimate_rolling_shutter_readout) {  // absent when the readout is a constant
    nlohmann::json history = nlohmann::json::array();
    for (const auto& [t, readout] : vio.readoutHistory())
      history.push_back({have_t ? t - run.stream_t0 : t, readout});
    s["rolling_shutter_readout"] = {{"configured_s", cfg.camera.rolling_shutter_readout_s},
                                    {"estimated_s", vio.rollingShutterReadout()},
                                    {"history_s", history}};
  }
  if (cfg.estimator.wheel.enable)  // doc/wheels.md; absent when the wheels are not fused
    s["wheel"] = {{"intervals_used", st.wheel_intervals_used},
                  {"intervals_left_out",
                   {{"stream_gap", st.wheel_intervals_gap},
                    {"slip", st.wheel_intervals_slip},
                    {"stuck", st.wheel_intervals_stuck},
                    {"lifted", st.wheel_intervals_lifted}}},
                  {"factors_solved", st.wheel_factors_solved},
                  {"factors_gated", st.wheel_factors_gated},
                  {"scale_forward", st.wheel_scale_v},
                  {"scale_yaw_rate", st.wheel_scale_w},
                  {"scale_estimated", cfg.estimator.wheel.estimate_scale},
                  {"extrinsic_yaw_correction_rad", st.wheel_extrinsic_yaw_rad},
                  {"extrinsic_yaw_estimated", cfg.estimator.wheel.estimate_extrinsic_yaw},
                  {"time_offset_s", st.wheel_time_offset_s},
                  {"time_offset_estimated", cfg.estimator.wheel.estimate_time_offset},
                  {"initialisations", st.wheel_initialisations},
                  {"left_out_episodes", wheelEpisodes(st, have_t ? run.stream_t0 : 0.0)}};
  if (cfg.estimator.wheel.enable && cfg.estimator.wheel.ground_plane_sigma_m > 0.0)
    s["wheel"]["ground_plane"] = {{"frames_used", st.ground_plane_used},
                                  {"frames_gated", st.ground_plane_gated}};
  s["wall_time_s"] = run.wall_s;
  s["frames_per_s"] = run.wall_s > 0 ? run.frames / run.wall_s : 0.0;
  const double n_tr = std::max(1, tm.frames_tracked), n_est = std::max(1, tm.frames_estimated);
  s["timing_ms_per_frame"] = {{"tracking", tm.tracking_ms / n_tr},
                              {"preintegration", tm.preintegration_ms / n_est},
                              {"optimisation", tm.optimisation_ms / n_est},
                              {"marginalisation", tm.marginalisation_ms / n_est}};
  const mapping::Mapper& map = sys.mapper();
  const auto& ms = map.pointMap().stats();
  const auto& mst = map.stats();
  s["map"] = {{"keyframes", map.store().size()},
              {"keyframes_adding_points", mst.keyframes_adding_points},
              {"grid_points", ms.grid_points},
              {"points_with_depth_in_range", ms.candidates},
              {"rejected_full_leaf", ms.rejected_full_leaf},
              {"points", map.pointMap().pointCount()},
              {"leaves", map.pointMap().leafCount()},
              {"memory_bytes", map.memoryBytes()},
              {"point_octree_bytes", map.pointMap().memoryBytes()},
              {"keyframe_store_bytes", map.store().memoryBytes()},
              {"occupancy_bytes", map.occupancy() ? map.occupancy()->memoryBytes() : 0},
              {"mapping_ms_total", mst.insert_ms_total},
              {"corrections", mst.corrections},
              {"correction_ms_total", mst.correction_ms_total},
              {"correction_ms_max", mst.correction_ms_max},
              {"occupancy_rebuild_ms", mst.occupancy_rebuild_ms}};
  std::set<int> segments;  // of this run (a loaded map is segment 0 of the graph, not counted)
  for (const auto& k : sys.keyframeStates()) segments.insert(k.state.segment);
  s["keyframes"] = sys.keyframeStates().size();
  s["segments"] = segments.size();
  s["loop"] = loopSummary(sys);
  s["map_session"] = mapSessionSummary(sys, run);
  s["stream_diagnostics"] = run.stream_diagnostics;
  s["outputs"] = outputs;
  if (ev.final_posyaw && ev.final_sim3 && ev.online && ev.odometry) {
    s["evaluation"] = eval::toJson(*ev.final_posyaw);
    s["evaluation_sim3"] = eval::toJson(*ev.final_sim3);
    s["evaluation_online"] = eval::toJson(*ev.online);
    s["evaluation_odometry"] = eval::toJson(*ev.odometry);
    if (ev.final_in_map) {
      s["evaluation_in_map_frame"] = eval::toJson(*ev.final_in_map);
      s["evaluation_online_in_map_frame"] = eval::toJson(*ev.online_in_map);
    }
  } else if (!ev.error.empty()) {
    s["evaluation_error"] = ev.error;
  }
  return s;
}

std::string initWaitsLine(const nlohmann::json& waits) {
  if (waits.empty()) return "nothing: no frame reached a start";
  // JSON objects iterate in key order; the stable sort keeps it among equal counts.
  std::vector<std::pair<std::string, int>> sorted;
  for (const auto& [reason, n] : waits.items()) sorted.emplace_back(reason, n.get<int>());
  std::stable_sort(sorted.begin(), sorted.end(),
                   [](const auto& a, const auto& b) { return a.second > b.second; });
  std::string out;
  for (std::size_t i = 0; i < sorted.size() && i < kReportedInitWaitReasons; ++i) {
    if (!out.empty()) out += "; ";
    out += sorted[i].first + " (" + std::to_string(sorted[i].second) +
           (sorted[i].second == 1 ? " frame)" : " frames)");
  }
  return out;
}

namespace {
/// True when a stream warning is about an externally stored image (MRPT's lazy-load files).
bool mentionsExternalImages(const nlohmann::json& diagnostics) {
  if (!diagnostics.is_object() || !diagnostics.contains("warnings")) return false;
  for (const auto& w : diagnostics["warnings"])
    if (w.is_string() && w.get<std::string>().find("external images folder") != std::string::npos)
      return true;
  return false;
}
}  // namespace

std::string noPoseReason(const RunInfo& run, const nlohmann::json& waits) {
  const nlohmann::json& d = run.stream_diagnostics;
  const auto count = [&](const char* key) -> std::size_t {
    return d.is_object() && d.contains(key) && d[key].is_number() ? d[key].get<std::size_t>() : 0;
  };
  const auto stream = [&](const char* kind, const char* key) -> double {
    return d.is_object() && d.contains(kind) && d[kind].contains(key) ? d[kind][key].get<double>()
                                                                      : 0.0;
  };
  const auto imuSamples = [&]() -> std::size_t {
    return d.is_object() && d.contains("imu") ? d["imu"].value("delivered", std::size_t{0}) : 0;
  };
  if (run.frames == 0) {
    if (run.interrupted) return "stopped (Ctrl-C) before the first colour+depth frame";
    if (count("unusable") > 0) {
      std::string why =
          "no colour+depth frame could be read: " + std::to_string(count("unusable")) +
          " observations were unusable";
      // The usual cause: a rawlog copied or moved without its external images folder (the
      // reader names the folder only when it found one; the per-frame messages say 'external').
      if (d.value("images_directory", std::string()).empty() && mentionsExternalImages(d)) {
        namespace fs = std::filesystem;
        fs::path stem = fs::path(run.input).filename();
        if (stem.extension() == ".gz") stem = stem.stem();
        if (stem.extension() == ".rawlog") stem = stem.stem();
        const fs::path dir = fs::path(run.input).parent_path();
        why += ", the rawlog's external images folder does not exist (looked for " +
               (dir / (stem.string() + "_Images")).string() + " and " + (dir / "Images").string() +
               ")";
      }
      return why + " (listed above; summary.json: stream_diagnostics)";
    }
    // A stream refused (accelerometer in g) or damaged before its first frame: the input may
    // well hold frames, so say what stopped it.
    if (!run.read_error.empty())
      return "the input stopped before its first colour+depth frame: " + run.read_error;
    return "the input has no colour+depth frame (CObservation3DRangeScan)";
  }
  if (imuSamples() == 0)
    return "the input has no IMU samples (CObservationIMU): the odometry needs them to start";
  if (waits.empty()) {
    // Both kinds present, yet no frame reached a start: their times do not overlap.
    const double imu0 = stream("imu", "first_t"), imu1 = stream("imu", "last_t");
    const double img0 = stream("images", "first_t"), img1 = stream("images", "last_t");
    if (imu1 < img0 || img1 < imu0) {
      std::ostringstream os;
      os << std::fixed << std::setprecision(3) << "the IMU samples (" << imu0 << " .. " << imu1
         << " s) and the colour+depth frames (" << img0 << " .. " << img1
         << " s) do not overlap in time";
      return os.str();
    }
  }
  return "the odometry never initialised; it waited for: " + initWaitsLine(waits) +
         " (summary.json: initialisation_waits, resets, stream_diagnostics)";
}

std::string formatRunReport(const nlohmann::json& s, const RunEvaluation& ev,
                            const std::string& gt_path) {
  std::ostringstream os;
  if (ev.final_posyaw && ev.final_sim3 && ev.online && ev.odometry) {
    os << "Accuracy against " << gt_path << " (position+yaw alignment):\n"
       << eval::formatReport(*ev.final_posyaw)
       << "Scale (Sim(3) alignment): " << std::setprecision(6) << ev.final_sim3->alignment.scale
       << "\n";
    os << std::fixed << std::setprecision(4) << "ATE RMSE [m]   final (trajectory.tum) "
       << ev.final_posyaw->ate.rmse << "   online (trajectory_online.tum) " << ev.online->ate.rmse
       << "   odometry (trajectory_odometry.tum) " << ev.odometry->ate.rmse << "\n";
    if (ev.final_in_map)
      os << "ATE RMSE [m] in the map's frame (through the map's ground-truth alignment, none "
            "of its own)   final "
         << ev.final_in_map->ate.rmse << "   online " << ev.online_in_map->ate.rmse << "\n";
    os.unsetf(std::ios::floatfield);
  } else if (!ev.error.empty()) {
    os << "Evaluation failed: " << ev.error << "\n";
  }
  os << "Processed " << s["frames"].get<std::size_t>() << " frames in " << std::setprecision(3)
     << s["wall_time_s"].get<double>() << " s (" << s["frames_per_s"].get<double>()
     << " frames/s), " << s["poses"].get<std::size_t>() << " poses, "
     << s["keyframes"].get<std::size_t>() << " keyframes, " << s["resets"].get<int>() << " resets, "
     << (s["loop"].contains("active_loops") ? s["loop"]["active_loops"].get<std::uint64_t>() : 0)
     << " loops" << (s["interrupted"].get<bool>() ? " (interrupted)" : "") << "\n";
  if (s.contains("stream_diagnostics") && s["stream_diagnostics"].is_object() &&
      s["stream_diagnostics"].value("frames_rate_limited", std::size_t{0}) > 0)
    os << "Skipped " << s["stream_diagnostics"]["frames_rate_limited"].get<std::size_t>()
       << " frames undecoded ([stream] image_rate_limit_hz): they have no pose\n";
  const nlohmann::json& loop = s["loop"];
  if (loop.contains("correcting") && !loop["correcting"].get<bool>() &&
      loop["accepted"].get<std::uint64_t>() > 0)
    os << "Every loop agreed with the odometry within its own uncertainty ([loop] "
          "correction_gate_sigma): trajectory.tum is the odometry\n";
  if (s["first_pose_time_s"].is_number() &&
      s["first_pose_time_s"].get<double>() > kReportInitWaitsAfter_s)
    os << "First pose " << std::setprecision(3) << s["first_pose_time_s"].get<double>()
       << " s after the first image; the odometry waited for: "
       << initWaitsLine(s["initialisation_waits"]) << "\n";
  const nlohmann::json& ms = s["map_session"];
  if (!ms["loaded_from"].is_null()) {
    os << "Map " << ms["loaded_from"].get<std::string>() << " (" << ms["mode"].get<std::string>()
       << "): " << ms["state"].get<std::string>();
    if (!ms["relocalised_at_s"].is_null())
      os << ", relocalised on the view " << std::setprecision(3)
         << ms["relocalised_at_s"].get<double>() << " s after the start";
    if (!ms["online_in_map_from_s"].is_null())
      os << ", online poses in the map's frame from " << std::setprecision(3)
         << ms["online_in_map_from_s"].get<double>() << " s";
    os << "\n";
  }
  if (!ms["saved_to"].is_null()) os << "Map saved to " << ms["saved_to"].get<std::string>() << "\n";
  if (!ms["note"].is_null()) os << "Map: " << ms["note"].get<std::string>() << "\n";
  if (!s["read_error"].is_null())
    os << "Input ended early: " << s["read_error"].get<std::string>() << "\n";
  os << "Outputs:\n";
  for (const auto& [name, path] : s["outputs"].items())
    os << "  " << path.get<std::string>() << "\n";
  return os.str();
}

}  // namespace rgbdi::system
