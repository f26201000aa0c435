// The part both wheel factors share (WheelFactor, WheelCalibrationFactor): the wheel frame's
// motion between two body poses against a pre-integrated one, and its Jacobians with respect to
// the two poses. The factors add their own parameters' Jacobians (scale factors, extrinsic yaw,
// time offset) from what this returns.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace rgbdi::estimator {

using WheelResidual = Eigen::Matrix<double, 6, 1>;

/// What the factors' own Jacobians need of the residual.
struct WheelRelativePose {
  Eigen::Vector3d r_p;                                   ///< [m] position part (unweighted)
  Eigen::Vector3d r_theta;                               ///< [rad] rotation part (unweighted)
  Eigen::Matrix3d E = Eigen::Matrix3d::Identity();       ///< the rotation error, Exp(r_theta)
  Eigen::Matrix3d Jr_inv = Eigen::Matrix3d::Identity();  ///< inverse right Jacobian at r_theta
};

/// parameters[0], [1]: the poses (p, q: x y z, qx qy qz qw) of the frames a and b; R_bw, p_bw:
/// the body-to-wheel extrinsic; dp [m], dyaw [rad]: the wheel frame's pre-integrated motion in
/// its frame at a; w: the residual's weights (square-root information). Writes the weighted
/// residual (6) and, for each non-null jacobians[0] / [1], the weighted 6x7 row-major Jacobian
/// of the residual with respect to that pose (Jr_inv is computed only then).
WheelRelativePose wheelRelativePose(double const* const* parameters, const Eigen::Matrix3d& R_bw,
                                    const Eigen::Vector3d& p_bw, const Eigen::Vector3d& dp,
                                    double dyaw, const WheelResidual& w, double* residuals,
                                    double** jacobians);

}  // namespace rgbdi::estimator
