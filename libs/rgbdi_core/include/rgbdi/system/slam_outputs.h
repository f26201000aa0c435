// Result files of a SLAM run, written from a finished SlamSystem: the trajectories (best
// estimate, online, odometry; body and camera frames), keyframes.tum, pose_graph.graph, the maps,
// the scene, the plot. Every file is written atomically; the returned JSON maps output names to
// paths (only files actually written are listed).
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "rgbdi/common/types.h"
#include "rgbdi/output/pose_graph.h"
#include "rgbdi/system/slam_system.h"

namespace rgbdi::system {

/// `gt_in_est`: ground truth expressed in the estimate's frame (for the plot and the scene), or
/// nullptr. `write_simplemap`: also keyframes.simplemap (needs keep_observations).
nlohmann::json writeSlamOutputs(const SlamSystem& system, const std::string& dir,
                                const Trajectory* gt_in_est, bool write_simplemap);

/// The pose graph of the run: one node per keyframe at its final pose, odometry edges between
/// consecutive keyframes of the same segment (never across a reset), and the loop edges.
output::PoseGraph slamPoseGraph(const SlamSystem& system);

}  // namespace rgbdi::system
