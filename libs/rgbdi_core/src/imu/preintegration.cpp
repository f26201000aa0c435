#include "rgbdi/imu/preintegration.h"

#include <Eigen/Cholesky>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "imu/quaternion_log.h"
#include "rgbdi/common/so3.h"

namespace rgbdi::imu {
namespace {

using Matrix9d = Eigen::Matrix<double, 9, 9>;
using Matrix9x6d = Eigen::Matrix<double, 9, 6>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Vector6d = Eigen::Matrix<double, 6, 1>;

// Column offsets inside the 6 bias columns [ba, bg] of the error state.
constexpr int kBiasA = kIdxBa - 9;
constexpr int kBiasG = kIdxBg - 9;
static_assert(kBiasA == 0 && kBiasG == 3, "bias blocks follow the 9 delta rows");

bool allFinite(const Eigen::Vector3d& v) { return v.allFinite(); }

std::string formatTime(double t) {
  std::ostringstream os;
  os.precision(9);
  os << std::fixed << t;
  return os.str();
}

}  // namespace

Preintegration::Preintegration(const Eigen::Vector3d& ba_lin, const Eigen::Vector3d& bg_lin,
                               const ImuNoise& noise)
    : ba_lin_(ba_lin), bg_lin_(bg_lin), noise_(noise) {
  const double values[] = {noise.acc_nd, noise.gyr_nd, noise.acc_rw, noise.gyr_rw};
  for (double v : values) {
    if (!std::isfinite(v) || v < 0.0)
      throw std::invalid_argument("Preintegration: IMU noise values must be finite and >= 0 (got " +
                                  std::to_string(v) + ")");
  }
  if (!allFinite(ba_lin) || !allFinite(bg_lin))
    throw std::invalid_argument("Preintegration: linearisation biases must be finite");
}

double Preintegration::startTime() const {
  if (samples_.empty()) throw std::logic_error("Preintegration::startTime: no sample pushed");
  return samples_.front().t;
}

double Preintegration::endTime() const {
  if (samples_.empty()) throw std::logic_error("Preintegration::endTime: no sample pushed");
  return samples_.back().t;
}

void Preintegration::push(double t, const Eigen::Vector3d& acc, const Eigen::Vector3d& gyr) {
  if (!std::isfinite(t) || !allFinite(acc) || !allFinite(gyr))
    throw std::invalid_argument("Preintegration::push: IMU sample at t=" + formatTime(t) +
                                " s has a non-finite value");
  if (!samples_.empty() && !(t > samples_.back().t))
    throw std::invalid_argument(
        "Preintegration::push: IMU sample at t=" + formatTime(t) +
        " s is not after the previous sample at t=" + formatTime(samples_.back().t) + " s");
  ImuSample s;
  s.t = t;
  s.acc = acc;
  s.gyr = gyr;
  samples_.push_back(s);
  ++revision_;
  if (samples_.size() >= 2) integrateStep(samples_[samples_.size() - 2], samples_.back());
}

void Preintegration::resetIntegration() {
  sum_dt_ = 0.0;
  dp_.setZero();
  dv_.setZero();
  dq_.setIdentity();
  cov_.setZero();
  jac_.setIdentity();
}

void Preintegration::repropagate(const Eigen::Vector3d& ba, const Eigen::Vector3d& bg) {
  if (!allFinite(ba) || !allFinite(bg))
    throw std::invalid_argument("Preintegration::repropagate: biases must be finite");
  ba_lin_ = ba;
  bg_lin_ = bg;
  ++revision_;
  resetIntegration();
  for (std::size_t k = 1; k < samples_.size(); ++k) integrateStep(samples_[k - 1], samples_[k]);
}

bool Preintegration::needsRepropagation(const Eigen::Vector3d& ba, const Eigen::Vector3d& bg,
                                        double acc_thresh, double gyr_thresh) const {
  return (ba - ba_lin_).norm() > acc_thresh || (bg - bg_lin_).norm() > gyr_thresh;
}

// One midpoint step over h = t1 - t0. The error-state transition F is the exact first-order
// linearisation of this discrete step (not a small-angle approximation of it), so that the bias
// Jacobian equals the derivative of re-integration. The noise of the step is one mean
// acceleration / rate perturbation over [t0, t1] with covariance density^2 / h (continuous white
// noise averaged over the step) and a bias random walk with covariance rw^2 * h.
void Preintegration::integrateStep(const ImuSample& s0, const ImuSample& s1) {
  const double h = s1.t - s0.t;
  const Eigen::Vector3d rate = 0.5 * (s0.gyr + s1.gyr) - bg_lin_;
  const Eigen::Vector3d phi = rate * h;
  const Eigen::Matrix3d R_step = expSO3(phi);
  const Eigen::Matrix3d R0 = dq_.toRotationMatrix();
  const Eigen::Quaterniond q1 = (dq_ * expQuat(phi)).normalized();
  const Eigen::Matrix3d R1 = q1.toRotationMatrix();
  const Eigen::Vector3d f0 = s0.acc - ba_lin_;
  const Eigen::Vector3d f1 = s1.acc - ba_lin_;
  const Eigen::Vector3d acc_mean = 0.5 * (R0 * f0 + R1 * f1);

  dp_ += dv_ * h + 0.5 * h * h * acc_mean;
  dv_ += acc_mean * h;
  dq_ = q1;
  sum_dt_ += h;

  // Derivatives of the rotation error at t1 and of acc_mean.
  const Eigen::Matrix3d dth1_dth0 = R_step.transpose();
  const Eigen::Matrix3d dth1_dbg = -rightJacobianSO3(phi) * h;
  const Eigen::Matrix3d R1_f1x = R1 * skew(f1);
  const Eigen::Matrix3d da_dth0 = -0.5 * (R0 * skew(f0) + R1_f1x * dth1_dth0);
  const Eigen::Matrix3d da_dba = -0.5 * (R0 + R1);
  const Eigen::Matrix3d da_dbg = -0.5 * R1_f1x * dth1_dbg;
  const Eigen::Matrix3d I3 = Eigen::Matrix3d::Identity();
  const double hh2 = 0.5 * h * h;

  // F = [A B; 0 I]: the 9 delta rows [dp, dtheta, dv] depend on the deltas (A) and on the biases
  // (B); the bias rows are the identity. Propagating by blocks avoids the dense 15x15 products.
  Matrix9d A = Matrix9d::Identity();
  A.block<3, 3>(kIdxP, kIdxR) = hh2 * da_dth0;
  A.block<3, 3>(kIdxP, kIdxV) = h * I3;
  A.block<3, 3>(kIdxR, kIdxR) = dth1_dth0;
  A.block<3, 3>(kIdxV, kIdxR) = h * da_dth0;
  Matrix9x6d B = Matrix9x6d::Zero();
  B.block<3, 3>(kIdxP, kBiasA) = hh2 * da_dba;
  B.block<3, 3>(kIdxP, kBiasG) = hh2 * da_dbg;
  B.block<3, 3>(kIdxR, kBiasG) = dth1_dbg;
  B.block<3, 3>(kIdxV, kBiasA) = h * da_dba;
  B.block<3, 3>(kIdxV, kBiasG) = h * da_dbg;

  // Measurement noise enters like a bias error of opposite sign (Jacobian -B, covariance
  // density^2 / h); the random walk moves the biases (covariance rw^2 * h).
  Vector6d meas_var;
  meas_var.head<3>().setConstant(noise_.acc_nd * noise_.acc_nd / h);
  meas_var.tail<3>().setConstant(noise_.gyr_nd * noise_.gyr_nd / h);
  Vector6d walk_var;
  walk_var.head<3>().setConstant(noise_.acc_rw * noise_.acc_rw * h);
  walk_var.tail<3>().setConstant(noise_.gyr_rw * noise_.gyr_rw * h);

  // Bias Jacobian: the bias rows of jac_ stay [0 I].
  jac_.topRightCorner<9, 6>() = (A * jac_.topRightCorner<9, 6>() + B).eval();
  jac_.topLeftCorner<9, 9>() = (A * jac_.topLeftCorner<9, 9>()).eval();

  // Covariance F P F^T + G Q G^T with P = [Pxx Pxb; Pxb^T Pbb].
  const Matrix9d Pxx = cov_.topLeftCorner<9, 9>();
  const Matrix9x6d Pxb = cov_.topRightCorner<9, 6>();
  const Matrix6d Pbb = cov_.bottomRightCorner<6, 6>();
  const Matrix9x6d Pxb_new = A * Pxb + B * Pbb;
  const Matrix9d Pxx_new = (A * Pxx + B * Pxb.transpose()) * A.transpose() +
                           Pxb_new * B.transpose() + B * meas_var.asDiagonal() * B.transpose();
  cov_.topLeftCorner<9, 9>() = 0.5 * (Pxx_new + Pxx_new.transpose());  // exact symmetry
  cov_.topRightCorner<9, 6>() = Pxb_new;
  cov_.bottomLeftCorner<6, 9>() = Pxb_new.transpose();
  cov_.bottomRightCorner<6, 6>().diagonal() += walk_var;
  // The mean-noise model above gives position the variance nd^2 h^3 / 4 of a constant
  // perturbation; continuous white noise integrated twice over the step gives nd^2 h^3 / 3. Adding
  // the difference (isotropic, so independent of the rotation) keeps [dp, dv] positive definite
  // even for an interval of a single step.
  cov_.block<3, 3>(kIdxP, kIdxP).diagonal().array() +=
      noise_.acc_nd * noise_.acc_nd * h * h * h / 12.0;
}

Eigen::Vector3d Preintegration::correctedDeltaP(const Eigen::Vector3d& ba,
                                                const Eigen::Vector3d& bg) const {
  return dp_ + jac_.block<3, 3>(kIdxP, kIdxBa) * (ba - ba_lin_) +
         jac_.block<3, 3>(kIdxP, kIdxBg) * (bg - bg_lin_);
}

Eigen::Vector3d Preintegration::correctedDeltaV(const Eigen::Vector3d& ba,
                                                const Eigen::Vector3d& bg) const {
  return dv_ + jac_.block<3, 3>(kIdxV, kIdxBa) * (ba - ba_lin_) +
         jac_.block<3, 3>(kIdxV, kIdxBg) * (bg - bg_lin_);
}

Eigen::Quaterniond Preintegration::correctedDeltaQ(const Eigen::Vector3d& bg) const {
  return (dq_ * expQuat(jac_.block<3, 3>(kIdxR, kIdxBg) * (bg - bg_lin_))).normalized();
}

bool Preintegration::trySqrtInformation(Matrix15d* sqrt_info) const {
  const Eigen::LLT<Matrix15d> llt_cov(cov_);
  if (llt_cov.info() != Eigen::Success) return false;
  Matrix15d info = llt_cov.solve(Matrix15d::Identity());
  info = 0.5 * (info + info.transpose()).eval();
  const Eigen::LLT<Matrix15d> llt_info(info);
  if (llt_info.info() != Eigen::Success) return false;
  *sqrt_info = llt_info.matrixU();
  return sqrt_info->allFinite();
}

Matrix15d Preintegration::sqrtInformation() const {
  Matrix15d u;
  if (!trySqrtInformation(&u)) {
    std::ostringstream os;
    os << "Preintegration: covariance is not positive definite (" << samples_.size()
       << " samples over " << sum_dt_ << " s; at least two samples and non-zero noise are needed)";
    throw std::runtime_error(os.str());
  }
  return u;
}

Vector15d Preintegration::residual(const Eigen::Vector3d& Pi, const Eigen::Quaterniond& Qi,
                                   const Eigen::Vector3d& Vi, const Eigen::Vector3d& Bai,
                                   const Eigen::Vector3d& Bgi, const Eigen::Vector3d& Pj,
                                   const Eigen::Quaterniond& Qj, const Eigen::Vector3d& Vj,
                                   const Eigen::Vector3d& Baj, const Eigen::Vector3d& Bgj,
                                   const Eigen::Vector3d& g_w) const {
  const double T = sum_dt_;
  const Eigen::Quaterniond qi = Qi.normalized();
  const Eigen::Quaterniond qj = Qj.normalized();
  const Eigen::Matrix3d RiT = qi.toRotationMatrix().transpose();
  const Eigen::Quaterniond dq_c = correctedDeltaQ(Bgi);

  Vector15d r;
  r.segment<3>(kIdxP) = RiT * (Pj - Pi - Vi * T - 0.5 * g_w * T * T) - correctedDeltaP(Bai, Bgi);
  r.segment<3>(kIdxR) = detail::logQuat(dq_c.inverse() * qi.inverse() * qj);
  r.segment<3>(kIdxV) = RiT * (Vj - Vi - g_w * T) - correctedDeltaV(Bai, Bgi);
  r.segment<3>(kIdxBa) = Baj - Bai;
  r.segment<3>(kIdxBg) = Bgj - Bgi;
  return r;
}

void Preintegration::predict(const Eigen::Vector3d& Pi, const Eigen::Quaterniond& Qi,
                             const Eigen::Vector3d& Vi, const Eigen::Vector3d& g_w,
                             Eigen::Vector3d& Pj, Eigen::Quaterniond& Qj,
                             Eigen::Vector3d& Vj) const {
  const double T = sum_dt_;
  const Eigen::Quaterniond qi = Qi.normalized();
  const Eigen::Matrix3d Ri = qi.toRotationMatrix();
  Pj = Pi + Vi * T + 0.5 * g_w * T * T + Ri * dp_;
  Vj = Vi + g_w * T + Ri * dv_;
  Qj = (qi * dq_).normalized();
}

}  // namespace rgbdi::imu
