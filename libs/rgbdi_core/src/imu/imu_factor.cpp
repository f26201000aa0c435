#include "rgbdi/imu/imu_factor.h"

#include <Eigen/Geometry>
#include <stdexcept>

#include "rgbdi/common/so3.h"

namespace rgbdi::imu {
namespace {

using PoseJacobian = Eigen::Matrix<double, 15, kPoseBlockSize, Eigen::RowMajor>;
using SpeedBiasJacobian = Eigen::Matrix<double, 15, kSpeedBiasBlockSize, Eigen::RowMajor>;

// Offsets inside a speed-bias block.
constexpr int kSbV = 0;
constexpr int kSbBa = 3;
constexpr int kSbBg = 6;

}  // namespace

ImuFactor::ImuFactor(const Preintegration* preintegration, const Eigen::Vector3d& g_w)
    : preint_(preintegration), g_w_(g_w), info_revision_(0), sqrt_info_(Matrix15d::Zero()) {
  if (preint_ == nullptr) throw std::invalid_argument("ImuFactor: null pre-integration");
  if (!g_w.allFinite()) throw std::invalid_argument("ImuFactor: gravity vector is not finite");
  // Fails early (with the reason) instead of inside the solver, where an exception cannot pass.
  sqrt_info_ = preint_->sqrtInformation();
  info_revision_ = preint_->revision();
}

bool ImuFactor::Evaluate(double const* const* parameters, double* residuals,
                         double** jacobians) const {
  const Eigen::Map<const Eigen::Vector3d> Pi(parameters[0]);
  const Eigen::Quaterniond Qi =
      Eigen::Map<const Eigen::Quaterniond>(parameters[0] + 3).normalized();
  const Eigen::Map<const Eigen::Vector3d> Vi(parameters[1] + kSbV);
  const Eigen::Map<const Eigen::Vector3d> Bai(parameters[1] + kSbBa);
  const Eigen::Map<const Eigen::Vector3d> Bgi(parameters[1] + kSbBg);
  const Eigen::Map<const Eigen::Vector3d> Pj(parameters[2]);
  const Eigen::Quaterniond Qj =
      Eigen::Map<const Eigen::Quaterniond>(parameters[2] + 3).normalized();
  const Eigen::Map<const Eigen::Vector3d> Vj(parameters[3] + kSbV);
  const Eigen::Map<const Eigen::Vector3d> Baj(parameters[3] + kSbBa);
  const Eigen::Map<const Eigen::Vector3d> Bgj(parameters[3] + kSbBg);

  // Evaluate may run on several threads: a stale cache is bypassed, never updated here.
  Matrix15d fresh_sqrt_info;
  const bool cache_valid = preint_->revision() == info_revision_;
  if (!cache_valid && !preint_->trySqrtInformation(&fresh_sqrt_info)) return false;
  const Matrix15d& sqrt_info = cache_valid ? sqrt_info_ : fresh_sqrt_info;
  const Vector15d r = preint_->residual(Pi, Qi, Vi, Bai, Bgi, Pj, Qj, Vj, Baj, Bgj, g_w_);
  Eigen::Map<Vector15d> residual_out(residuals);
  residual_out = sqrt_info * r;
  if (jacobians == nullptr) return true;

  const double T = preint_->dt();
  const Matrix15d& J = preint_->jacobian();
  const Eigen::Matrix3d Ri = Qi.toRotationMatrix();
  const Eigen::Matrix3d RiT = Ri.transpose();
  const Eigen::Matrix3d Rj = Qj.toRotationMatrix();
  const Eigen::Matrix3d I3 = Eigen::Matrix3d::Identity();
  const Eigen::Vector3d alpha = Pj - Pi - Vi * T - 0.5 * g_w_ * T * T;
  const Eigen::Vector3d beta = Vj - Vi - g_w_ * T;
  const Eigen::Vector3d r_theta = r.segment<3>(kIdxR);
  const Eigen::Matrix3d Jr_inv = rightJacobianInvSO3(r_theta);
  // Residual rotation E = dq_c^-1 q_i^-1 q_j, so E^T = R_j^T R_i dR_c.
  const Eigen::Vector3d phi_bg = J.block<3, 3>(kIdxR, kIdxBg) * (Bgi - preint_->biasGyr());
  const Eigen::Matrix3d dR_c = preint_->correctedDeltaQ(Bgi).toRotationMatrix();
  const Eigen::Matrix3d ET = Rj.transpose() * Ri * dR_c;

  if (jacobians[0] != nullptr) {
    PoseJacobian jp = PoseJacobian::Zero();
    jp.block<3, 3>(kIdxP, 0) = -RiT;
    jp.block<3, 3>(kIdxP, 3) = skew(RiT * alpha);
    jp.block<3, 3>(kIdxR, 3) = -Jr_inv * Rj.transpose() * Ri;
    jp.block<3, 3>(kIdxV, 3) = skew(RiT * beta);
    Eigen::Map<PoseJacobian> out(jacobians[0]);
    out = sqrt_info * jp;
  }
  if (jacobians[1] != nullptr) {
    SpeedBiasJacobian js = SpeedBiasJacobian::Zero();
    js.block<3, 3>(kIdxP, kSbV) = -RiT * T;
    js.block<3, 3>(kIdxP, kSbBa) = -J.block<3, 3>(kIdxP, kIdxBa);
    js.block<3, 3>(kIdxP, kSbBg) = -J.block<3, 3>(kIdxP, kIdxBg);
    js.block<3, 3>(kIdxR, kSbBg) =
        -Jr_inv * ET * rightJacobianSO3(phi_bg) * J.block<3, 3>(kIdxR, kIdxBg);
    js.block<3, 3>(kIdxV, kSbV) = -RiT;
    js.block<3, 3>(kIdxV, kSbBa) = -J.block<3, 3>(kIdxV, kIdxBa);
    js.block<3, 3>(kIdxV, kSbBg) = -J.block<3, 3>(kIdxV, kIdxBg);
    js.block<3, 3>(kIdxBa, kSbBa) = -I3;
    js.block<3, 3>(kIdxBg, kSbBg) = -I3;
    Eigen::Map<SpeedBiasJacobian> out(jacobians[1]);
    out = sqrt_info * js;
  }
  if (jacobians[2] != nullptr) {
    PoseJacobian jp = PoseJacobian::Zero();
    jp.block<3, 3>(kIdxP, 0) = RiT;
    jp.block<3, 3>(kIdxR, 3) = Jr_inv;
    Eigen::Map<PoseJacobian> out(jacobians[2]);
    out = sqrt_info * jp;
  }
  if (jacobians[3] != nullptr) {
    SpeedBiasJacobian js = SpeedBiasJacobian::Zero();
    js.block<3, 3>(kIdxV, kSbV) = RiT;
    js.block<3, 3>(kIdxBa, kSbBa) = I3;
    js.block<3, 3>(kIdxBg, kSbBg) = I3;
    Eigen::Map<SpeedBiasJacobian> out(jacobians[3]);
    out = sqrt_info * js;
  }
  return true;
}

}  // namespace rgbdi::imu
