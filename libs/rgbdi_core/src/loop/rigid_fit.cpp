#include "rgbdi/loop/rigid_fit.h"

#include <Eigen/Cholesky>
#include <Eigen/SVD>
#include <algorithm>

namespace rgbdi::loop {

bool fitRigidWeighted(const std::vector<Eigen::Vector3d>& src,
                      const std::vector<Eigen::Vector3d>& dst, const std::vector<double>& weights,
                      Eigen::Isometry3d& T_dst_src) {
  const std::size_t n = src.size();
  if (n < 3 || dst.size() != n || weights.size() != n) return false;
  double w_sum = 0.0;
  Eigen::Vector3d mu_s = Eigen::Vector3d::Zero(), mu_d = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    if (!(weights[i] > 0.0)) return false;
    w_sum += weights[i];
    mu_s += weights[i] * src[i];
    mu_d += weights[i] * dst[i];
  }
  mu_s /= w_sum;
  mu_d /= w_sum;
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();  // sum w (dst - mu_d)(src - mu_s)^T
  for (std::size_t i = 0; i < n; ++i)
    H += weights[i] * (dst[i] - mu_d) * (src[i] - mu_s).transpose();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Vector3d s = svd.singularValues();
  // Collinear points leave the rotation about their line undetermined: two singular values ~0.
  if (!(s(1) > 1e-12 * std::max(1.0, s(0)))) return false;
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  if ((svd.matrixU() * svd.matrixV().transpose()).determinant() < 0.0) D(2, 2) = -1.0;
  const Eigen::Matrix3d R = svd.matrixU() * D * svd.matrixV().transpose();
  T_dst_src.setIdentity();
  T_dst_src.linear() = R;
  T_dst_src.translation() = mu_d - R * mu_s;
  return true;
}

Eigen::Matrix3d rgbdPointCovariance(const RgbdPoint& point) {
  const double n = point.p.norm();
  const Eigen::Vector3d ray = n > 0.0 ? Eigen::Vector3d(point.p / n) : Eigen::Vector3d::UnitZ();
  const double lat2 = point.sigma_lateral_m * point.sigma_lateral_m;
  const double ray2 = point.sigma_ray_m * point.sigma_ray_m;
  return lat2 * Eigen::Matrix3d::Identity() + (ray2 - lat2) * ray * ray.transpose();
}

bool refineRigidAnisotropic(const std::vector<RgbdPoint>& src, const std::vector<RgbdPoint>& dst,
                            int iterations, Eigen::Isometry3d& T_dst_src) {
  if (src.size() != dst.size() || src.size() < 3) return false;
  std::vector<Eigen::Matrix3d> cov_src(src.size()), cov_dst(dst.size());
  for (std::size_t i = 0; i < src.size(); ++i) {
    cov_src[i] = rgbdPointCovariance(src[i]);
    cov_dst[i] = rgbdPointCovariance(dst[i]);
  }
  Eigen::Isometry3d T = T_dst_src;
  for (int it = 0; it < iterations; ++it) {
    // Left perturbation T <- exp([dtheta, dt]) T: d(T p)/d dtheta = -[T p]x, d/d dt = I.
    Eigen::Matrix<double, 6, 6> H = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> g = Eigen::Matrix<double, 6, 1>::Zero();
    const Eigen::Matrix3d R = T.linear();
    for (std::size_t i = 0; i < src.size(); ++i) {
      const Eigen::Vector3d q = T * src[i].p;
      const Eigen::Vector3d r = q - dst[i].p;
      const Eigen::Matrix3d C = cov_dst[i] + R * cov_src[i] * R.transpose();
      const Eigen::Matrix3d W = C.inverse();
      if (!W.allFinite()) return false;
      Eigen::Matrix<double, 3, 6> J;
      J.leftCols<3>() << 0.0, q.z(), -q.y(), -q.z(), 0.0, q.x(), q.y(), -q.x(), 0.0;
      J.rightCols<3>().setIdentity();
      H.noalias() += J.transpose() * W * J;
      g.noalias() += J.transpose() * W * r;
    }
    const Eigen::LDLT<Eigen::Matrix<double, 6, 6>> ldlt(H);
    if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) return false;
    const Eigen::Matrix<double, 6, 1> delta = -ldlt.solve(g);
    if (!delta.allFinite()) return false;
    Eigen::Isometry3d step = Eigen::Isometry3d::Identity();
    const double angle = delta.head<3>().norm();
    if (angle > 0.0)
      step.linear() = Eigen::AngleAxisd(angle, delta.head<3>() / angle).toRotationMatrix();
    step.translation() = delta.tail<3>();
    T = step * T;
    if (delta.norm() < 1e-12) break;
  }
  T_dst_src = T;
  return true;
}

}  // namespace rgbdi::loop
