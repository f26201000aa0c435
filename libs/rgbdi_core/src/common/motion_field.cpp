#include "rgbdi/common/motion_field.h"

#include <algorithm>

namespace rgbdi {

Eigen::Vector2d motionFieldVelocity(const Eigen::Vector2d& xn, double depth_m,
                                    const Eigen::Vector3d& omega_cam,
                                    const Eigen::Vector3d& v_cam) {
  // A static point P = z (x, y, 1) in the camera moves as dP/dt = -omega x P - v; the quotient
  // rule on (P_x / P_z, P_y / P_z) gives the classic rotational and translational terms.
  const double x = xn.x(), y = xn.y();
  const double wx = omega_cam.x(), wy = omega_cam.y(), wz = omega_cam.z();
  Eigen::Vector2d v(x * y * wx - (1.0 + x * x) * wy + y * wz,
                    (1.0 + y * y) * wx - x * y * wy - x * wz);
  if (depth_m > 0.0) {
    v.x() += (x * v_cam.z() - v_cam.x()) / depth_m;
    v.y() += (y * v_cam.z() - v_cam.y()) / depth_m;
  }
  return v;
}

CameraVelocity cameraVelocity(const Eigen::Isometry3d& T_body_cam, const Eigen::Vector3d& v_body,
                              const Eigen::Vector3d& omega_body) {
  const Eigen::Matrix3d R_cb = T_body_cam.rotation().transpose();
  CameraVelocity c;
  c.omega_cam = R_cb * omega_body;
  c.v_cam = R_cb * (v_body + omega_body.cross(T_body_cam.translation()));
  return c;
}

double typicalDepth(std::vector<double> depths_m) {
  depths_m.erase(
      std::remove_if(depths_m.begin(), depths_m.end(), [](double z) { return !(z > 0.0); }),
      depths_m.end());
  if (depths_m.empty()) return 0.0;
  std::nth_element(depths_m.begin(), depths_m.begin() + depths_m.size() / 2, depths_m.end());
  return depths_m[depths_m.size() / 2];
}

}  // namespace rgbdi
