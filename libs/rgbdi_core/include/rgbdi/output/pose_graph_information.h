// Conversion of edge information matrices between the rgbdi tangent convention (x y z, rotation
// vector right-multiplied; see pose_graph.h) and MRPT's CPose3DPDFGaussianInf convention
// (x y z yaw pitch roll, additive). With R(ypr) = Rz(yaw) Ry(pitch) Rx(roll), a small change
// d(ypr) rotates by dtheta = E(pitch, roll) d(ypr) in the body frame, so
//   info_mrpt = B^T info_rgbdi B,  B = diag(I3, E)   and   info_rgbdi = B^-T info_mrpt B^-1.
#pragma once

#include <Eigen/Core>

namespace rgbdi::output {

using Matrix6d = Eigen::Matrix<double, 6, 6>;

/// E: columns are the body-frame rotation vectors produced by unit changes of yaw, pitch, roll.
Eigen::Matrix3d yawPitchRollToRotationVectorJacobian(double pitch, double roll);

/// Yaw, pitch, roll of R exactly as MRPT's CPose3D computes them.
Eigen::Vector3d mrptYawPitchRoll(const Eigen::Matrix3d& R);

/// rgbdi information of an edge with rotation R -> MRPT information.
Matrix6d informationToMrpt(const Matrix6d& info, const Eigen::Matrix3d& R);

/// MRPT information of an edge with rotation R -> rgbdi information. Throws std::domain_error
/// within 0.01 deg of pitch +-90 deg, where E is singular.
Matrix6d informationFromMrpt(const Matrix6d& info_mrpt, const Eigen::Matrix3d& R);

/// |cos(pitch)| below this is treated as gimbal lock (about 0.0057 deg from +-90 deg): the
/// conversion would lose more than 4 of the 17 written digits.
constexpr double kMinCosPitch = 1e-4;

}  // namespace rgbdi::output
