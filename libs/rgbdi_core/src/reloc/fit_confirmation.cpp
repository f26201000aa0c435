#include "rgbdi/reloc/fit_confirmation.h"

#include <cmath>

namespace rgbdi::reloc {

bool FitConfirmation::agree(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b,
                            const Eigen::Vector3d& p) const {
  const Eigen::Matrix3d E = a.linear().transpose() * b.linear();
  const double yaw = std::abs(std::atan2(E(1, 0), E(0, 0)));
  return (a * p - b * p).norm() <= options_.confirm_max_disagreement_m &&
         yaw <= options_.confirm_max_disagreement_deg * M_PI / 180.0;
}

Eigen::Isometry3d FitConfirmation::mean(const std::vector<Eigen::Isometry3d>& alignments) {
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  double c = 0.0, s = 0.0;
  for (const Eigen::Isometry3d& A : alignments) {
    t += A.translation();
    const double yaw = std::atan2(A.linear()(1, 0), A.linear()(0, 0));
    c += std::cos(yaw);
    s += std::sin(yaw);
  }
  Eigen::Isometry3d M = Eigen::Isometry3d::Identity();
  if (alignments.empty()) return M;
  M.linear() = Eigen::AngleAxisd(std::atan2(s, c), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  M.translation() = t / static_cast<double>(alignments.size());
  return M;
}

}  // namespace rgbdi::reloc
