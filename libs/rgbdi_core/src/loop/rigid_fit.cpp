#include "rgbdi/loop/rigid_fit.h"

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

}  // namespace rgbdi::loop
