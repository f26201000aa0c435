// The packets that flow between the stages of the SLAM system: odometry -> loop closing ->
// mapping. Each owns its data (images are reference-counted cv::Mat that no stage writes to), so
// a stage on another thread never reads state of the stage before it.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <utility>
#include <vector>

#include "rgbdi/common/types.h"
#include "rgbdi/estimator/sliding_window_estimator.h"
#include "rgbdi/frontend/feature_frame.h"
#include "rgbdi/mapping/keyframe.h"

namespace rgbdi::system {

/// A keyframe whose pose is final for the odometry (it left the window, or the run ended).
struct KeyframePacket {
  std::uint64_t id = 0;             ///< keyframe id: 0, 1, 2, ... in the order of the run
  estimator::KeyframeState state;   ///< odometry pose (body), stamp, segment, frame index
  RgbdFrame frame;                  ///< the source images
  frontend::FeatureFrame features;  ///< the tracked features of that image
  double travelled_m = 0.0;         ///< [m] odometry path length from the start of the run
};

/// Work for the mapping stage: a keyframe to insert, or corrected poses after a pose-graph solve.
struct MapPacket {
  bool is_correction = false;
  mapping::Keyframe keyframe;  ///< keyframe to insert (T_world_cam = best estimate now)
  RgbdFrame frame;             ///< its images
  /// Corrected colour-camera poses (keyframe id, T_world_cam) of every keyframe of the graph.
  std::vector<std::pair<std::uint64_t, Eigen::Isometry3d>> corrected_poses;
};

}  // namespace rgbdi::system
