#include "rgbdi/estimator/initializer.h"

#include <Eigen/Dense>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

#include "rgbdi/common/so3.h"
#include "rgbdi/imu/preintegration.h"

namespace rgbdi::estimator {

std::optional<PnpResult> relativePoseByPnP(const std::vector<Eigen::Vector3d>& pts_prev_cam,
                                           const std::vector<Eigen::Vector2d>& xn_curr,
                                           const PnpOptions& opt) {
  if (pts_prev_cam.size() != xn_curr.size() ||
      static_cast<int>(pts_prev_cam.size()) < std::max(opt.min_inliers, 6)) {
    return std::nullopt;
  }
  std::vector<cv::Point3d> obj;
  std::vector<cv::Point2d> img;
  for (size_t i = 0; i < pts_prev_cam.size(); ++i) {
    obj.emplace_back(pts_prev_cam[i].x(), pts_prev_cam[i].y(), pts_prev_cam[i].z());
    img.emplace_back(xn_curr[i].x(), xn_curr[i].y());
  }
  // Normalised coordinates: identity camera matrix, threshold on the normalised plane.
  const cv::Mat K = cv::Mat::eye(3, 3, CV_64F);
  cv::Mat rvec, tvec;
  std::vector<int> inliers;
  // OpenCV's RANSAC uses cv::theRNG(); seed it so results are repeatable run to run.
  cv::theRNG().state = opt.seed;
  const bool ok = cv::solvePnPRansac(
      obj, img, K, cv::noArray(), rvec, tvec, false, opt.ransac_iterations,
      static_cast<float>(opt.ransac_threshold_norm), 0.99, inliers, cv::SOLVEPNP_EPNP);
  if (!ok || static_cast<int>(inliers.size()) < opt.min_inliers) return std::nullopt;
  // Refine on the inliers (Levenberg-Marquardt from the RANSAC estimate).
  std::vector<cv::Point3d> obj_in;
  std::vector<cv::Point2d> img_in;
  for (int i : inliers) {
    obj_in.push_back(obj[static_cast<size_t>(i)]);
    img_in.push_back(img[static_cast<size_t>(i)]);
  }
  cv::solvePnP(obj_in, img_in, K, cv::noArray(), rvec, tvec, true, cv::SOLVEPNP_ITERATIVE);

  Eigen::Vector3d r, t;
  cv::cv2eigen(rvec, r);
  cv::cv2eigen(tvec, t);
  PnpResult res;
  res.T_curr_prev.linear() = expSO3(r);  // the exponential map of the rotation vector
  res.T_curr_prev.translation() = t;
  // Cheirality: on shallow scenes EPnP can return the mirrored pose with the points behind the
  // camera, which still reprojects well. Require the inliers in front of the current camera.
  int in_front = 0;
  for (int i : inliers)
    if ((res.T_curr_prev * pts_prev_cam[static_cast<size_t>(i)]).z() > 0.0) ++in_front;
  if (in_front < opt.min_inliers) return std::nullopt;
  res.inliers = static_cast<int>(inliers.size());
  res.inlier_indices = inliers;
  return res;
}

Eigen::Matrix3d attitudeFromGravity(const Eigen::Vector3d& mean_acc_body, double yaw) {
  // At rest the accelerometer measures -g expressed in the body frame, i.e. "up".
  const Eigen::Vector3d up_body = mean_acc_body.normalized();
  // Rotation taking the body's "up" onto world +z (minimal rotation), then set the yaw.
  const Eigen::Matrix3d R0 =
      Eigen::Quaterniond::FromTwoVectors(up_body, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const double yaw_now = yawOf(R0);
  return Eigen::AngleAxisd(yaw - yaw_now, Eigen::Vector3d::UnitZ()).toRotationMatrix() * R0;
}

double yawOf(const Eigen::Matrix3d& R) { return std::atan2(R(1, 0), R(0, 0)); }

Eigen::Matrix3d worldFromGravity(const Eigen::Vector3d& g_ref, const Eigen::Matrix3d& R_ref_body0,
                                 double yaw0) {
  const Eigen::Matrix3d R0 =
      Eigen::Quaterniond::FromTwoVectors(g_ref.normalized(), -Eigen::Vector3d::UnitZ())
          .toRotationMatrix();
  const double yaw_now = yawOf(R0 * R_ref_body0);
  return Eigen::AngleAxisd(yaw0 - yaw_now, Eigen::Vector3d::UnitZ()).toRotationMatrix() * R0;
}

namespace {

/// Builds and solves the linear system. Unknowns: v_0..v_n (reference frame) then either the full
/// gravity vector (3) or, when g_fixed is given, a 2-DOF correction w: g = g_fixed + B w.
bool solveLinear(const std::vector<Eigen::Isometry3d>& T,
                 const std::vector<const imu::Preintegration*>& pre, const Eigen::Vector3d* g_fixed,
                 std::vector<Eigen::Vector3d>* v, Eigen::Vector3d* g, double* rms) {
  const int n = static_cast<int>(T.size());
  const int ng = g_fixed ? 2 : 3;
  const int N = 3 * n + ng;
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(6 * (n - 1), N);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(6 * (n - 1));
  const Eigen::Matrix<double, 3, 2> B =
      g_fixed ? sphereTangentBasis(*g_fixed) : Eigen::Matrix<double, 3, 2>::Zero();
  for (int k = 0; k + 1 < n; ++k) {
    const imu::Preintegration& P = *pre[static_cast<size_t>(k + 1)];
    const double dt = P.dt();
    const Eigen::Matrix3d RkT = T[static_cast<size_t>(k)].rotation().transpose();
    const Eigen::Vector3d dp =
        T[static_cast<size_t>(k + 1)].translation() - T[static_cast<size_t>(k)].translation();
    const int r = 6 * k;
    // alpha = R_k^T (p_{k+1} - p_k - v_k dt - 0.5 g dt^2)
    A.block<3, 3>(r, 3 * k) = RkT * dt;
    Eigen::Matrix3d Gp = 0.5 * RkT * dt * dt;
    Eigen::Vector3d rhs_p = RkT * dp - P.deltaP();
    // beta = R_k^T (v_{k+1} - v_k - g dt)
    A.block<3, 3>(r + 3, 3 * k) = RkT;
    A.block<3, 3>(r + 3, 3 * (k + 1)) = -RkT;
    Eigen::Matrix3d Gv = RkT * dt;
    Eigen::Vector3d rhs_v = -P.deltaV();
    if (g_fixed) {
      A.block<3, 2>(r, 3 * n) = Gp * B;
      A.block<3, 2>(r + 3, 3 * n) = Gv * B;
      rhs_p -= Gp * (*g_fixed);
      rhs_v -= Gv * (*g_fixed);
    } else {
      A.block<3, 3>(r, 3 * n) = Gp;
      A.block<3, 3>(r + 3, 3 * n) = Gv;
    }
    b.segment<3>(r) = rhs_p;
    b.segment<3>(r + 3) = rhs_v;
  }
  const Eigen::MatrixXd AtA = A.transpose() * A;
  Eigen::LDLT<Eigen::MatrixXd> ldlt(AtA);
  if (ldlt.info() != Eigen::Success) return false;
  const Eigen::VectorXd x = ldlt.solve(A.transpose() * b);
  if (!x.allFinite()) return false;
  v->resize(static_cast<size_t>(n));
  for (int k = 0; k < n; ++k) (*v)[static_cast<size_t>(k)] = x.segment<3>(3 * k);
  *g = g_fixed ? Eigen::Vector3d(*g_fixed + B * x.tail<2>()) : Eigen::Vector3d(x.tail<3>());
  *rms = std::sqrt((A * x - b).squaredNorm() / std::max<Eigen::Index>(1, b.size()));
  return true;
}

}  // namespace

std::optional<AlignmentResult> alignVelocitiesAndGravity(
    const std::vector<Eigen::Isometry3d>& T_ref_body,
    const std::vector<const imu::Preintegration*>& preint, double g_norm) {
  if (T_ref_body.size() < 3 || preint.size() != T_ref_body.size()) return std::nullopt;
  AlignmentResult res;
  if (!solveLinear(T_ref_body, preint, nullptr, &res.v_ref, &res.g_ref, &res.residual_rms))
    return std::nullopt;
  // The unconstrained gravity must be roughly the right size, else the data are inconsistent.
  if (std::abs(res.g_ref.norm() - g_norm) > 0.25 * g_norm) return std::nullopt;
  // Refinement with known magnitude: iterate the 2-DOF tangent correction (the linearisation of
  // the sphere constraint), renormalising each time.
  Eigen::Vector3d g = res.g_ref.normalized() * g_norm;
  for (int it = 0; it < 4; ++it) {
    Eigen::Vector3d g_new;
    if (!solveLinear(T_ref_body, preint, &g, &res.v_ref, &g_new, &res.residual_rms))
      return std::nullopt;
    g = g_new.normalized() * g_norm;
  }
  res.g_ref = g;
  return res;
}

}  // namespace rgbdi::estimator
