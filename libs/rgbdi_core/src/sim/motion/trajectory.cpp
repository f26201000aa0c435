#include "rgbdi/sim/trajectory.h"

#include <stdexcept>
#include <string>

namespace rgbdi::sim {

void MotionJet::rotate(int axis, const Taylor<2>& angle) {
  if (rotation_count >= kMaxRotations)
    throw std::logic_error("MotionJet::rotate: more than " + std::to_string(kMaxRotations) +
                           " rotation factors");
  if (axis < 0 || axis > 2) throw std::logic_error("MotionJet::rotate: axis must be 0, 1 or 2");
  rotations[rotation_count++] = AxisRotation{axis, angle};
}

Eigen::Vector3d KinematicState::specificForce(double gravity) const {
  return T_world_body.linear().transpose() * (a_world + Eigen::Vector3d(0.0, 0.0, gravity));
}

KinematicState stateFromJet(double t, const MotionJet& jet) {
  KinematicState s;
  s.t = t;
  Eigen::Vector3d p;
  for (int i = 0; i < 3; ++i) {
    const Taylor<3>& c = jet.position[static_cast<size_t>(i)];
    p[i] = c.value();
    s.v_world[i] = c.derivative(1);
    s.a_world[i] = c.derivative(2);
  }

  // R = R_0 R_1 ... R_{n-1}. With omega_i the rate of the partial product R_0..R_i expressed in
  // frame i: omega_i = R_i^T omega_{i-1} + angle_i' e_axis(i). Carrying omega as a first-order
  // series gives its time derivative too.
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  TaylorVec3<1> omega{};
  for (std::size_t k = 0; k < jet.rotation_count; ++k) {
    const AxisRotation& r = jet.rotations[k];
    const Taylor<1> angle = r.angle.truncated<1>();
    omega = rotateAboutAxis(r.axis, -angle, omega);
    omega[static_cast<size_t>(r.axis)] += r.angle.differentiated();
    R = R * Eigen::AngleAxisd(r.angle.value(), Eigen::Vector3d::Unit(r.axis)).toRotationMatrix();
  }
  for (int i = 0; i < 3; ++i) {
    s.omega_body[i] = omega[static_cast<size_t>(i)].value();
    s.omega_dot_body[i] = omega[static_cast<size_t>(i)].derivative(1);
  }
  s.T_world_body.linear() = R;
  s.T_world_body.translation() = p;
  return s;
}

}  // namespace rgbdi::sim
