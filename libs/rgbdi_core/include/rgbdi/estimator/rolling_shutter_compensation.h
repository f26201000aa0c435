// Rolling-shutter compensation of feature observations (first-order motion model).
//
// A rolling-shutter colour image exposes row y at t_ref + RollingShutter::rowTime(y). The
// estimator models every image at its reference time t_ref (the stamp), so an observation made at
// its row's time is moved to t_ref along its image velocity, as VINS-Mono does:
//   xn_ref = xn_row - rowTime(y) * velocity_xn
// (velocity in normalised-plane units per second). This is the same first-order shift the online
// camera-IMU time offset applies (ReprojectionFactor), with the row's share of the readout as the
// time. A feature without a velocity (newly detected) stays where it was seen.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "rgbdi/common/camera.h"
#include "rgbdi/common/rolling_shutter.h"
#include "rgbdi/frontend/feature_frame.h"

namespace rgbdi::estimator {

/// Moves each feature's xn from its row's exposure time to the image's reference time along its
/// tracked velocity. A global shutter (readout 0) leaves every feature untouched.
void moveToReferenceTime(std::vector<frontend::FeatureObservation>& features,
                         const RollingShutter& rs);

/// The pixel where a point seen at pixel uv (at its row's time) was at the image's reference
/// time, moved along the motion field (motion_field.h) of a camera turning at omega_cam [rad/s]
/// and moving at v_cam [m/s] (both in the camera frame) for a point at depth_m (0: the rotation's
/// part only): uv - rowTime(y) (fx vx, fy vy), the distortion neglected over the shift, as the
/// front end does. For keypoints that have no tracked velocity (loop closing's ORB keypoints).
Eigen::Vector2d pixelAtReferenceTime(const Eigen::Vector2d& uv, const PinholeCamera& cam,
                                     const RollingShutter& rs, const Eigen::Vector3d& omega_cam,
                                     const Eigen::Vector3d& v_cam, double depth_m);

}  // namespace rgbdi::estimator
