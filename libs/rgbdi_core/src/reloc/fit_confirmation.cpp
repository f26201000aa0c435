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

}  // namespace rgbdi::reloc
