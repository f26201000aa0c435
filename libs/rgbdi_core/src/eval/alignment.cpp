#include "rgbdi/eval/alignment.h"

#include <Eigen/SVD>
#include <cmath>
#include <stdexcept>

#include "rgbdi/eval/eval_error.h"

namespace rgbdi::eval {

std::string alignModeName(AlignMode mode) {
  switch (mode) {
    case AlignMode::None:
      return "none";
    case AlignMode::Se3:
      return "se3";
    case AlignMode::Sim3:
      return "sim3";
    case AlignMode::PosYaw:
      return "posyaw";
  }
  return "unknown";
}

AlignMode parseAlignMode(const std::string& name) {
  for (const AlignMode m : {AlignMode::None, AlignMode::Se3, AlignMode::Sim3, AlignMode::PosYaw}) {
    if (name == alignModeName(m)) return m;
  }
  throw std::invalid_argument("unknown alignment '" + name +
                              "' (expected se3, sim3, posyaw or none)");
}

std::size_t minimumPairs(AlignMode mode) {
  switch (mode) {
    case AlignMode::None:
      return 1;
    case AlignMode::PosYaw:
      return 2;
    case AlignMode::Se3:
    case AlignMode::Sim3:
      return 3;
  }
  return 3;
}

namespace {

struct Centered {
  Eigen::Vector3d mean_est = Eigen::Vector3d::Zero();
  Eigen::Vector3d mean_gt = Eigen::Vector3d::Zero();
  Eigen::Matrix3d cross = Eigen::Matrix3d::Zero();  // (1/n) sum (gt - mean_gt)(est - mean_est)^T
  double var_est = 0.0;                             // (1/n) sum |est - mean_est|^2
};

Centered centre(const std::vector<Eigen::Vector3d>& est, const std::vector<Eigen::Vector3d>& gt) {
  Centered c;
  const double n = static_cast<double>(est.size());
  for (std::size_t k = 0; k < est.size(); ++k) {
    c.mean_est += est[k];
    c.mean_gt += gt[k];
  }
  c.mean_est /= n;
  c.mean_gt /= n;
  for (std::size_t k = 0; k < est.size(); ++k) {
    const Eigen::Vector3d de = est[k] - c.mean_est;
    const Eigen::Vector3d dg = gt[k] - c.mean_gt;
    c.cross += dg * de.transpose();
    c.var_est += de.squaredNorm();
  }
  c.cross /= n;
  c.var_est /= n;
  return c;
}

// Umeyama's closed form; the sign correction keeps R a proper rotation when the best orthogonal
// matrix would be a reflection (noisy or planar data).
void umeyama(const Centered& c, bool with_scale, Alignment& a) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(c.cross, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Vector3d s(1.0, 1.0, 1.0);
  if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0.0) s(2) = -1.0;
  a.R = svd.matrixU() * s.asDiagonal() * svd.matrixV().transpose();
  a.scale = with_scale ? svd.singularValues().dot(s) / c.var_est : 1.0;
}

// Rotation about z maximising sum gt_c . Rz(theta) est_c over the centred points.
void yawOnly(const Centered& c, Alignment& a) {
  // With cross = sum dg de^T: sum (gx ex + gy ey) and sum (gy ex - gx ey).
  const double cos_term = c.cross(0, 0) + c.cross(1, 1);
  const double sin_term = c.cross(1, 0) - c.cross(0, 1);
  const double yaw = std::atan2(sin_term, cos_term);
  a.R = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  a.scale = 1.0;
}

}  // namespace

Alignment alignPositions(const std::vector<Eigen::Vector3d>& est,
                         const std::vector<Eigen::Vector3d>& gt, AlignMode mode) {
  if (est.size() != gt.size()) {
    throw std::invalid_argument("alignPositions: estimate and ground truth differ in length");
  }
  if (est.size() < minimumPairs(mode)) {
    throw EvalError("only " + std::to_string(est.size()) + " associated pose pair(s); " +
                    alignModeName(mode) + " alignment needs at least " +
                    std::to_string(minimumPairs(mode)));
  }
  Alignment a;
  a.mode = mode;
  if (mode == AlignMode::None) return a;

  const Centered c = centre(est, gt);
  switch (mode) {
    case AlignMode::Se3:
      umeyama(c, false, a);
      break;
    case AlignMode::Sim3:
      if (!(c.var_est > 0.0)) {
        throw EvalError(
            "sim3 alignment: all associated estimate positions coincide, scale undefined");
      }
      umeyama(c, true, a);
      break;
    case AlignMode::PosYaw:
      yawOnly(c, a);
      break;
    case AlignMode::None:
      break;
  }
  a.t = c.mean_gt - a.scale * (a.R * c.mean_est);
  return a;
}

}  // namespace rgbdi::eval
