// Result files of a SLAM run, written from a finished SlamSystem: the trajectories (best
// estimate, online, odometry; body and camera frames), keyframes.tum, pose_graph.graph, the maps,
// the scene, the plot. Every file is written atomically; the returned JSON maps output names to
// paths (only files actually written are listed). Each TUM file states its frame and clock in
// its header lines.
#pragma once

#include <deque>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "rgbdi/common/types.h"
#include "rgbdi/output/pose_graph.h"
#include "rgbdi/system/slam_system.h"

namespace rgbdi::system {

/// The TUM trajectories of a run (each also as a colour-camera twin, except the keyframes).
enum class TumOutput { kFinal, kOnline, kOdometry, kKeyframes };

/// Where a run's poses live, for the header lines of its TUM files.
struct TumFrames {
  bool camera = false;      ///< colour camera optical frame (else body = IMU frame)
  bool loaded_map = false;  ///< the run started in a saved map (--load-map)
  bool live = false;        ///< stamps of live sensors (else of the input rawlog)
};

/// The header lines of a TUM output (writeTum's frame_and_clock): the frame of the poses, the
/// frame they are in (the run's world frame, or the loaded map's), the clock of the stamps (IMU
/// time or image stamps) and the kind of pose (optimised, online, odometry, keyframes).
std::string tumFrameAndClock(TumOutput what, const TumFrames& frames);

/// `body` (stamps on the IMU clock, each the t_imu of one of `frames`, in order; a subsequence
/// of them, as a run in a loaded map keeps only its frames placed in the map) as poses of the
/// colour camera, T_world_cam = T_world_body * T_body_cam, with the image stamps of the same
/// frames. Throws std::logic_error for a stamp that is no frame's.
Trajectory cameraTwin(const Trajectory& body, const std::deque<FrameRecord>& frames,
                      const Eigen::Isometry3d& T_body_cam);

/// The text under trajectory.png: how the ground truth drawn beside the estimate was aligned.
std::string plotAlignmentText(bool ground_truth_aligned);

/// `gt_in_est`: ground truth expressed in the estimate's frame (for the plot and the scene), or
/// nullptr. `write_simplemap`: also keyframes.simplemap (needs keep_observations). With [navmap]
/// enable, the navigation maps too (navmap.*; their figures into `navmap_summary` when given).
nlohmann::json writeSlamOutputs(const SlamSystem& system, const std::string& dir,
                                const Trajectory* gt_in_est, bool write_simplemap,
                                nlohmann::json* navmap_summary = nullptr);

/// The pose graph of the run: one node per keyframe at its final pose, odometry edges between
/// consecutive keyframes of the same segment (never across a reset), and the loop edges.
output::PoseGraph slamPoseGraph(const SlamSystem& system);

}  // namespace rgbdi::system
