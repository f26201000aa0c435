#include "rgbdi/estimator/rolling_shutter_compensation.h"

#include "rgbdi/common/motion_field.h"

namespace rgbdi::estimator {

void moveToReferenceTime(std::vector<frontend::FeatureObservation>& features,
                         const RollingShutter& rs) {
  if (rs.global()) return;
  for (frontend::FeatureObservation& f : features) f.xn -= rs.rowTime(f.uv.y()) * f.velocity_xn;
}

Eigen::Vector2d pixelAtReferenceTime(const Eigen::Vector2d& uv, const PinholeCamera& cam,
                                     const RollingShutter& rs, const Eigen::Vector3d& omega_cam,
                                     const Eigen::Vector3d& v_cam, double depth_m) {
  if (rs.global()) return uv;
  const Eigen::Vector2d v =
      motionFieldVelocity(cam.pixelToNormalized(uv), depth_m, omega_cam, v_cam);
  return uv - rs.rowTime(uv.y()) * Eigen::Vector2d(cam.fx * v.x(), cam.fy * v.y());
}

}  // namespace rgbdi::estimator
