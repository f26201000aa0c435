// The depth samples of loop keyframes (their coarse depth grids) as 3-D points with the camera
// centre that saw them: what PlanGrid and the ICP refinement are built from, for the saved map
// (map frame) and for a run's latest keyframes (its odometry frame).
#pragma once

#include <Eigen/Geometry>
#include <vector>

#include "rgbdi/common/camera.h"
#include "rgbdi/loop/loop_keyframe.h"
#include "rgbdi/reloc/plan_grid.h"

namespace rgbdi::reloc {

/// Appends every sample of kf's depth grid (depth > 0) placed by T_world_body; `cam` is the
/// colour camera the grid was sampled from. A keyframe without a grid adds nothing.
void appendDepthSamples(const loop::LoopKeyframe& kf, const Eigen::Isometry3d& T_world_body,
                        const PinholeCamera& cam, const Eigen::Isometry3d& T_body_cam,
                        std::vector<DepthSample>* out);

}  // namespace rgbdi::reloc
