#include "rgbdi/estimator/ground_plane_gate.h"

namespace rgbdi::estimator {

std::optional<double> judgeGroundContact(const std::optional<Eigen::Vector3d>& up_body,
                                         double wheel_z, GroundPlanes* planes,
                                         const WheelOptions& opt) {
  std::optional<double>& current = planes->current;
  const auto startPlane = [&](double z) {
    current = z;
    if (planes->known.empty() || planes->known.back() != z) planes->known.push_back(z);
    return z;
  };
  if (opt.ground_plane_gate_chi2 <= 0.0)  // no gate: every frame on the first plane
    return current ? *current : startPlane(wheel_z);
  if (!up_body || up_body->norm() <= 0.0) {
    current.reset();
    return std::nullopt;
  }
  const Eigen::Vector3d n = opt.T_body_wheel.rotation() * Eigen::Vector3d::UnitZ();
  const double sin_tilt = n.cross(up_body->normalized()).norm();
  const double chi2_tilt =
      sin_tilt * sin_tilt / (opt.ground_plane_tilt_sigma_rad * opt.ground_plane_tilt_sigma_rad);
  const double gate = opt.ground_plane_gate_chi2;
  const auto chi2 = [&](double z0) {
    const double dz = (wheel_z - z0) / opt.ground_plane_sigma_m;
    return chi2_tilt + dz * dz;
  };
  if (current) {
    if (chi2(*current) <= gate) return *current;
    current.reset();  // off the plane: it ends here
    return std::nullopt;
  }
  if (chi2_tilt > gate) return std::nullopt;
  // Level again: the nearest known plane that passes, else a new one at this height.
  const double* nearest = nullptr;
  for (const double& z0 : planes->known)
    if (!nearest || std::abs(wheel_z - z0) < std::abs(wheel_z - *nearest)) nearest = &z0;
  if (nearest && chi2(*nearest) <= gate) {
    current = *nearest;
    return *current;
  }
  return startPlane(wheel_z);
}

}  // namespace rgbdi::estimator
