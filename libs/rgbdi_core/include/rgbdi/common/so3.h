// SO(3) helpers (header-only): hat, exp, log and the right Jacobian, used by pre-integration,
// the simulator and the estimator.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>

namespace rgbdi {

inline Eigen::Matrix3d skew(const Eigen::Vector3d& w) {
  Eigen::Matrix3d S;
  S << 0, -w.z(), w.y(), w.z(), 0, -w.x(), -w.y(), w.x(), 0;
  return S;
}

/// Exponential map: rotation vector -> rotation matrix (Rodrigues), stable near zero.
inline Eigen::Matrix3d expSO3(const Eigen::Vector3d& phi) {
  const double th = phi.norm();
  if (th < 1e-10) return Eigen::Matrix3d::Identity() + skew(phi);
  return Eigen::AngleAxisd(th, phi / th).toRotationMatrix();
}

inline Eigen::Quaterniond expQuat(const Eigen::Vector3d& phi) {
  const double th = phi.norm();
  if (th < 1e-10)
    return Eigen::Quaterniond(1.0, 0.5 * phi.x(), 0.5 * phi.y(), 0.5 * phi.z()).normalized();
  return Eigen::Quaterniond(Eigen::AngleAxisd(th, phi / th));
}

/// Logarithm map: rotation matrix -> rotation vector with norm in [0, pi].
inline Eigen::Vector3d logSO3(const Eigen::Matrix3d& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}

/// Right Jacobian of SO(3): exp(phi + d) ~= exp(phi) exp(Jr(phi) d).
inline Eigen::Matrix3d rightJacobianSO3(const Eigen::Vector3d& phi) {
  const double th = phi.norm();
  const Eigen::Matrix3d W = skew(phi);
  if (th < 1e-6) return Eigen::Matrix3d::Identity() - 0.5 * W + W * W / 6.0;
  const double th2 = th * th;
  return Eigen::Matrix3d::Identity() - (1.0 - std::cos(th)) / th2 * W +
         (th - std::sin(th)) / (th2 * th) * W * W;
}

/// Inverse of the right Jacobian of SO(3).
inline Eigen::Matrix3d rightJacobianInvSO3(const Eigen::Vector3d& phi) {
  const double th = phi.norm();
  const Eigen::Matrix3d W = skew(phi);
  if (th < 1e-6) return Eigen::Matrix3d::Identity() + 0.5 * W + W * W / 12.0;
  const double th2 = th * th;
  return Eigen::Matrix3d::Identity() + 0.5 * W +
         (1.0 / th2 - (1.0 + std::cos(th)) / (2.0 * th * std::sin(th))) * W * W;
}

/// Two orthonormal vectors spanning the tangent plane of the sphere at direction g (the 2-DOF
/// gravity-direction correction of the initialisations).
inline Eigen::Matrix<double, 3, 2> sphereTangentBasis(const Eigen::Vector3d& g) {
  const Eigen::Vector3d a = g.normalized();
  // The axis of a's smallest component is the furthest from a: never parallel to it.
  Eigen::Index i;
  a.cwiseAbs().minCoeff(&i);
  const Eigen::Vector3d b = a.cross(Eigen::Vector3d::Unit(i)).normalized();
  Eigen::Matrix<double, 3, 2> B;
  B << b, a.cross(b);
  return B;
}

}  // namespace rgbdi
