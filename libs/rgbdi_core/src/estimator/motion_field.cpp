#include "rgbdi/estimator/motion_field.h"

namespace rgbdi::estimator {

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

}  // namespace rgbdi::estimator
