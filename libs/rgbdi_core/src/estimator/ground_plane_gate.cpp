#include "rgbdi/estimator/ground_plane_gate.h"

namespace rgbdi::estimator {

std::optional<double> judgeGroundContact(const std::optional<Eigen::Vector3d>& up_body,
                                         double wheel_z, std::optional<double>* plane_z,
                                         const WheelOptions& opt) {
  if (opt.ground_plane_gate_chi2 <= 0.0) {  // no gate: every frame on the first plane
    if (!*plane_z) *plane_z = wheel_z;
    return plane_z->value();
  }
  if (!up_body || up_body->norm() <= 0.0) {
    plane_z->reset();
    return std::nullopt;
  }
  const Eigen::Vector3d n = opt.T_body_wheel.rotation() * Eigen::Vector3d::UnitZ();
  const double sin_tilt = n.cross(up_body->normalized()).norm();
  const double chi2_tilt = sin_tilt * sin_tilt /
                           (opt.ground_plane_tilt_sigma_rad * opt.ground_plane_tilt_sigma_rad);
  const double gate = opt.ground_plane_gate_chi2;
  if (!*plane_z) {
    if (chi2_tilt > gate) return std::nullopt;
    *plane_z = wheel_z;  // level again: a new plane at this height
    return plane_z->value();
  }
  const double dz = (wheel_z - **plane_z) / opt.ground_plane_sigma_m;
  if (chi2_tilt + dz * dz > gate) {
    plane_z->reset();
    return std::nullopt;
  }
  return plane_z->value();
}

}  // namespace rgbdi::estimator
