#include "rgbdi/loop/four_dof.h"

#include "rgbdi/loop/yaw_manifold.h"

namespace rgbdi::loop {

FourDofDelta fourDofDelta(const Eigen::Matrix3d& R_tilt_from, const Eigen::Isometry3d& T_from_to) {
  // R_w_from = Rz(yaw_from) * R_tilt_from, so Rz(yaw_from)^T * R_w_from * x = R_tilt_from * x,
  // and left-multiplying by Rz adds to the ZYX yaw, so yawOf(R_tilt_from * R_from_to) is the
  // heading of `to` relative to `from`.
  FourDofDelta d;
  d.t_m = R_tilt_from * T_from_to.translation();
  d.yaw_rad = wrapAngle(yawOf(R_tilt_from * T_from_to.linear()));
  return d;
}

Eigen::Isometry3d fourDofCorrection(const Eigen::Vector3d& t_a, double yaw_a,
                                    const Eigen::Vector3d& t_b, double yaw_b) {
  Eigen::Isometry3d C = Eigen::Isometry3d::Identity();
  C.linear() = rotZ(wrapAngle(yaw_a - yaw_b));
  C.translation() = t_a - C.linear() * t_b;
  return C;
}

}  // namespace rgbdi::loop
