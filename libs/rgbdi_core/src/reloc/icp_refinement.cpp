// GeometricRelocaliser::refine: the point-to-plane ICP that turns a plan fit (5 cm cells,
// 1 deg) into a centimetre one, with the submap's height drift and tilt as nuisance unknowns.
#include <Eigen/Eigenvalues>
#include <cmath>

#include "rgbdi/common/so3.h"
#include "rgbdi/reloc/geometric_relocaliser.h"

namespace rgbdi::reloc {
namespace {
Eigen::Matrix3d yawRotation(double yaw) {
  return Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
}
}  // namespace

GeometricRelocaliser::Refinement GeometricRelocaliser::refine(
    const std::vector<Eigen::Vector3d>& local, const PointIndex& map, const Eigen::Isometry3d& T0,
    double max_distance_m, int iterations, double huber_m, const std::vector<double>& path_m,
    double drift_sigma_per_m, bool horizontal, const RefineExtras& extras) {
  // Point-to-plane: each local point's distance along the normal of its nearest map point,
  // linearised about the current estimate in (yaw step, tx, ty, tz[, height drift per metre]
  // [, tilt about x, y]); T stays yaw + translation. Pairs farther than huber_m weigh
  // huber_m / |r| (Huber): surfaces the map saw differently must not drag the fit sideways.
  // The tilt: the submap's gravity is the odometry's, off by a degree or more after fast
  // rotations (a tracked robot over a step); a small rotation Rt about the anchor (where T0
  // puts it, fixed) levels it: p' = a + Rt (T l + b s z - a).
  using Matrix7d = Eigen::Matrix<double, 7, 7>;
  using Vector7d = Eigen::Matrix<double, 7, 1>;
  const bool drift = drift_sigma_per_m > 0.0 && path_m.size() == local.size();
  const bool tilt = extras.tilt_sigma_rad > 0.0;
  const bool sides = extras.min_view_cos > -1.0 && extras.local_views.size() == local.size() &&
                     map.views().size() == map.points().size();
  const Eigen::Vector3d a = T0 * extras.anchor_part;
  Refinement out;
  Eigen::Isometry3d T = T0;
  Eigen::Matrix3d Rt = Eigen::Matrix3d::Identity();
  double b = 0.0;  // height drift per metre of path
  const std::vector<Eigen::Vector3d>& mp = map.points();
  const std::vector<Eigen::Vector3d>& mn = map.normals();
  for (int it = 0; it < iterations; ++it) {
    Matrix7d H = Matrix7d::Zero();
    Vector7d g = Vector7d::Zero();
    Eigen::Matrix2d nn = Eigen::Matrix2d::Zero();
    double sq = 0.0;
    int n = 0, other_side = 0;
    for (std::size_t k = 0; k < local.size(); ++k) {
      const double s = drift ? path_m[k] : 0.0;
      const Eigen::Vector3d p = T * local[k] + Eigen::Vector3d(0.0, 0.0, b * s);
      const Eigen::Vector3d q = a + Rt * (p - a);
      const long i = map.nearest(q, max_distance_m);
      if (i < 0 || mn[static_cast<std::size_t>(i)].isZero()) continue;
      const Eigen::Vector3d& nrm = mn[static_cast<std::size_t>(i)];
      if (sides && nrm.dot(Rt * T.linear() * extras.local_views[k]) < extras.min_view_cos) {
        ++other_side;
        continue;
      }
      const double r = nrm.dot(q - mp[static_cast<std::size_t>(i)]);
      // d q / d (yaw, t, b) = Rt d p / d (...); d p / d yaw = z x (p - t) (rotation about the
      // vertical through T's origin); d q / d w = w x (q - a) (Rt <- exp(w) Rt).
      const Eigen::Vector3d nt = Rt.transpose() * nrm;
      const Eigen::Vector3d d = p - T.translation();
      const Eigen::Vector3d e = q - a;
      Vector7d J;
      J << nt.dot(Eigen::Vector3d(-d.y(), d.x(), 0.0)), nt.x(), nt.y(), nt.z(), nt.z() * s,
          nrm.dot(Eigen::Vector3d(0.0, -e.z(), e.y())),
          nrm.dot(Eigen::Vector3d(e.z(), 0.0, -e.x()));
      const double w = std::abs(r) > huber_m ? huber_m / std::abs(r) : 1.0;
      H += w * J * J.transpose();
      g += w * J * r;
      nn += nrm.head<2>() * nrm.head<2>().transpose();
      sq += r * r;
      ++n;
    }
    out.pairs = n;
    out.other_side = other_side;
    out.rms_m = n > 0 ? std::sqrt(sq / n) : 0.0;
    out.horizontal_constraint =
        nn.trace() > 0.0
            ? Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(nn / nn.trace()).eigenvalues()(0)
            : 0.0;
    if (n < 10) break;
    // The priors (drift and tilt ~ 0 +- sigma), each as one pair whose noise is huber_m.
    const Eigen::Vector3d tilt_now = Eigen::AngleAxisd(Rt).angle() * Eigen::AngleAxisd(Rt).axis();
    if (drift) {
      const double prior = (huber_m / drift_sigma_per_m) * (huber_m / drift_sigma_per_m);
      H(4, 4) += prior;
      g(4) += prior * b;
    }
    if (tilt) {
      const double prior = (huber_m / extras.tilt_sigma_rad) * (huber_m / extras.tilt_sigma_rad);
      for (int k = 0; k < 2; ++k) {
        H(5 + k, 5 + k) += prior;
        g(5 + k) += prior * tilt_now(k);
      }
    }
    // The unknowns solved: yaw, x, y unless only the height is refined; z; drift; tilt.
    std::vector<int> active;
    for (int k = horizontal ? 0 : 3; k < 4; ++k) active.push_back(k);
    if (drift) active.push_back(4);
    if (tilt) {
      active.push_back(5);
      active.push_back(6);
    }
    const int m = static_cast<int>(active.size());
    Eigen::MatrixXd Hs(m, m);
    Eigen::VectorXd gs(m);
    for (int r = 0; r < m; ++r) {
      gs(r) = g(active[r]);
      for (int c = 0; c < m; ++c) Hs(r, c) = H(active[r], active[c]);
    }
    const Eigen::VectorXd sub = -Hs.ldlt().solve(gs);
    Vector7d step = Vector7d::Zero();
    for (int r = 0; r < m; ++r) step(active[r]) = sub(r);
    if (!step.allFinite()) break;
    Eigen::Isometry3d next = Eigen::Isometry3d::Identity();
    next.linear() = yawRotation(step(0)) * T.linear();
    next.translation() = T.translation() + step.segment<3>(1);
    T = next;
    b += step(4);
    Rt = expSO3(Eigen::Vector3d(step(5), step(6), 0.0)) * Rt;
    if (step.segment<3>(1).norm() < 1e-7 && std::abs(step(0)) < 1e-8 && std::abs(step(4)) < 1e-8 &&
        step.tail<2>().norm() < 1e-8)
      break;
  }
  // The result stays yaw + translation (the pose graph's 4 DOF): the yaw of Rt R_T, and the
  // anchor where the tilted fit puts it.
  const Eigen::Matrix3d R = Rt * T.linear();
  Eigen::Isometry3d T_out = Eigen::Isometry3d::Identity();
  T_out.linear() = yawRotation(std::atan2(R(1, 0), R(0, 0)));
  T_out.translation() = a + Rt * (T * extras.anchor_part - a) - T_out.linear() * extras.anchor_part;
  out.T = T_out;
  out.height_drift_per_m = b;
  const Eigen::Vector3d up = Rt * Eigen::Vector3d::UnitZ();
  out.tilt_rad = std::acos(std::min(1.0, up.z()));
  return out;
}

}  // namespace rgbdi::reloc
