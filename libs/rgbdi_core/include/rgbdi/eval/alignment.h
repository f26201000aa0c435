// Least-squares alignment of estimated positions onto ground-truth positions (Umeyama 1991):
// p_gt ~= scale * R * p_est + t.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

namespace rgbdi::eval {

enum class AlignMode {
  None,    ///< identity: the estimate is already in the ground-truth frame
  Se3,     ///< rotation + translation
  Sim3,    ///< rotation + translation + scale (diagnosis of scale drift)
  PosYaw,  ///< translation + rotation about world z only: the 4 observable DOF of a VIO
};

/// "none", "se3", "sim3", "posyaw".
std::string alignModeName(AlignMode mode);
/// Inverse of alignModeName; throws std::invalid_argument listing the accepted names.
AlignMode parseAlignMode(const std::string& name);

struct Alignment {
  AlignMode mode = AlignMode::None;
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  double scale = 1.0;

  Eigen::Vector3d apply(const Eigen::Vector3d& p_est) const { return scale * (R * p_est) + t; }
  /// Rigid part as T_gt_est (the scale is not included).
  Eigen::Isometry3d rigid() const {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = R;
    T.translation() = t;
    return T;
  }
};

/// Minimum number of point pairs for which `mode` is determined (1 none, 2 posyaw, 3 se3/sim3).
std::size_t minimumPairs(AlignMode mode);

/// Aligns est onto gt (same length, index-matched). Throws EvalError when there are fewer than
/// minimumPairs(mode) points, or for sim3 when all estimate positions coincide (scale undefined).
Alignment alignPositions(const std::vector<Eigen::Vector3d>& est,
                         const std::vector<Eigen::Vector3d>& gt, AlignMode mode);

}  // namespace rgbdi::eval
