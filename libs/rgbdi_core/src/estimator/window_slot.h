// One frame of the sliding window: its optimisation variables (pose, speed and biases; their
// arrays are the solver's and the marginalisation prior's parameter blocks) and the IMU interval
// that leads to it from the previous frame.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "rgbdi/frontend/feature_frame.h"
#include "rgbdi/imu/preintegration.h"

namespace rgbdi::estimator {

struct WindowSlot {
  double t = 0.0;        ///< IMU-clock time [s]
  double t_image = 0.0;  ///< image stamp [s]
  std::uint64_t frame_index = 0;
  double pose[7] = {0, 0, 0, 0, 0, 0, 1};       ///< T_world_body: [p, q(x, y, z, w)]
  double sb[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};   ///< [v_world, bias_acc, bias_gyr]
  std::unique_ptr<imu::Preintegration> preint;  ///< previous slot -> this slot (null for slot 0)
  /// [s] of the interval from the previous slot carried by the IMU alone (blind frames in it)
  double bridged_s = 0.0;
  /// Camera pose of this frame relative to the first frame of a moving initialisation (PnP).
  Eigen::Isometry3d T_c0_c = Eigen::Isometry3d::Identity();
  std::vector<frontend::FeatureObservation> raw_features;  ///< for the starts (PnP, SfM)
  /// Ground plane ([wheel] ground_plane_sigma_m): judged once, when the frame is new; the height
  /// [m] of the plane its wheel frame is held on, none when it is off the plane.
  bool ground_judged = false;
  std::optional<double> ground_z;

  Eigen::Vector3d p() const { return Eigen::Vector3d(pose[0], pose[1], pose[2]); }
  Eigen::Quaterniond q() const { return Eigen::Quaterniond(pose[6], pose[3], pose[4], pose[5]); }
  Eigen::Vector3d v() const { return Eigen::Vector3d(sb[0], sb[1], sb[2]); }
  Eigen::Vector3d ba() const { return Eigen::Vector3d(sb[3], sb[4], sb[5]); }
  Eigen::Vector3d bg() const { return Eigen::Vector3d(sb[6], sb[7], sb[8]); }
  Eigen::Isometry3d T() const {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = q().normalized().toRotationMatrix();
    T.translation() = p();
    return T;
  }
  void setPose(const Eigen::Vector3d& p, const Eigen::Quaterniond& q) {
    const Eigen::Quaterniond qn = q.normalized();
    pose[0] = p.x();
    pose[1] = p.y();
    pose[2] = p.z();
    pose[3] = qn.x();
    pose[4] = qn.y();
    pose[5] = qn.z();
    pose[6] = qn.w();
  }
  void setV(const Eigen::Vector3d& v) {
    sb[0] = v.x();
    sb[1] = v.y();
    sb[2] = v.z();
  }
  void setBiases(const Eigen::Vector3d& ba, const Eigen::Vector3d& bg) {
    for (int i = 0; i < 3; ++i) {
      sb[3 + i] = ba[i];
      sb[6 + i] = bg[i];
    }
  }
};

}  // namespace rgbdi::estimator
