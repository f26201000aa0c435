// Conversions between MRPT observations and rgbdi's plain sensor structs.
//
// Frame convention (SPEC section 5): MRPT's CObservation3DRangeScan places its coordinate origin
// on the depth camera with +X forward, +Y left, +Z up ("MRPT depth frame"), not in the optical
// frame (x right, y down, z forward) that rgbdi uses for every camera. The fixed rotation
//   T_mrptdepth_depthoptical = CPose3D(0,0,0, -90deg, 0, -90deg)
// maps the depth optical frame into the MRPT depth frame. relativePoseIntensityWRTDepth is the pose
// of the intensity (colour) camera OPTICAL frame in the MRPT depth frame, so for coinciding cameras
// it equals that fixed rotation. sensorPose is the pose of the MRPT depth frame on the robot
// (body). Hence:
//   T_color_depth      = relativePoseIntensityWRTDepth^-1 * T_mrptdepth_depthoptical
//   source_T_body_cam  = sensorPose * relativePoseIntensityWRTDepth      (colour optical in body)
//   T_body_depthoptical = sensorPose * T_mrptdepth_depthoptical
#pragma once

#include <mrpt/core/Clock.h>
#include <mrpt/img/TCamera.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/poses/CPose3D.h>

#include <Eigen/Geometry>
#include <stdexcept>
#include <string>

#include "rgbdi/common/types.h"
#include "rgbdi/common/wheel_odometry.h"

namespace rgbdi::io {

/// Thrown when an MRPT observation cannot be represented (missing data, unsupported format).
class ConversionError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Seconds (UNIX epoch, double) <-> mrpt::Clock; a double keeps sub-microsecond resolution for
/// present-day epochs (spacing 2.4e-7 s), the Clock itself has 100 ns ticks.
double toSeconds(mrpt::Clock::time_point t);
mrpt::Clock::time_point fromSeconds(double t);

/// CPose3D <-> Eigen isometry (same T_a_b meaning: the pose of frame b in frame a).
Eigen::Isometry3d toIsometry(const mrpt::poses::CPose3D& p);
mrpt::poses::CPose3D toCPose3D(const Eigen::Isometry3d& T);

/// Pose of the depth camera's optical frame in MRPT's +X-forward depth frame: the pure rotation
/// (yaw -90deg, pitch 0, roll -90deg), the value MRPT uses for coinciding cameras.
Eigen::Isometry3d mrptDepthFromOptical();

/// TCamera (k1 k2 p1 p2 k3 in dist[0..4]) <-> PinholeCamera. fromMrpt throws ConversionError when
/// the higher-order coefficients dist[5..7] (rational / fisheye model) are not zero.
PinholeCamera fromMrpt(const mrpt::img::TCamera& cam, const std::string& label);
mrpt::img::TCamera toMrpt(const PinholeCamera& cam);

/// RGB-D observation -> RgbdFrame. Loads externally stored images/range matrices first (the
/// caller must have set CImage::setImagesPathBase to the rawlog's image directory). Colour is
/// converted from MRPT's BGR storage to RGB; grey images are replicated to 3 channels. Ranges
/// with range_is_depth == false are converted to depth along the optical axis. `label` (e.g.
/// "file.rawlog record 12") becomes source_label and prefixes every error message.
/// Throws ConversionError when the observation has neither colour nor depth, or has data that
/// cannot be represented (unsupported pixel format, missing external file).
RgbdFrame fromMrpt(const mrpt::obs::CObservation3DRangeScan& obs, const std::string& label);

/// Exact inverse of fromMrpt: `T_body_cam` is the colour camera optical frame in the body frame
/// and becomes sensorPose (combined with frame.T_color_depth). Throws ConversionError when
/// frame.depth_aligned_to_color is set but T_color_depth is not the identity.
mrpt::obs::CObservation3DRangeScan::Ptr toMrpt(const RgbdFrame& frame,
                                               const Eigen::Isometry3d& T_body_cam,
                                               const std::string& sensorLabel);

/// IMU observation -> sample (acc from IMU_X/Y/Z_ACC, gyro from IMU_WX/WY/WZ, body frame).
/// Throws ConversionError naming the sensor label and stamp when acc or gyro data is missing.
ImuSample fromMrpt(const mrpt::obs::CObservationIMU& obs);
mrpt::obs::CObservationIMU::Ptr toMrpt(const ImuSample& imu, const std::string& sensorLabel);

/// Wheel-odometry observation -> sample: the cumulative 2-D pose, velocityLocal (vx, vy, omega)
/// when hasVelocities, the encoder ticks when hasEncodersInfo. Throws ConversionError naming the
/// sensor label and stamp when a presence flag is damaged (values are taken as stored: see
/// isFinite()).
WheelOdometrySample fromMrpt(const mrpt::obs::CObservationOdometry& obs);
mrpt::obs::CObservationOdometry::Ptr toMrpt(const WheelOdometrySample& wheel,
                                            const std::string& sensorLabel);

}  // namespace rgbdi::io
