// IMU pre-integration between two frames (on-manifold, midpoint rule, first-order bias correction).
//
// Conventions (doc/imu.md): body = IMU frame; the accelerometer measures
// a_m = R_wb^T (a_w - g_w) + b_a + n_a and the gyroscope w_m = w_b + b_g + n_g.
// The pre-integrated deltas are expressed in the body frame at the first sample:
//   dq = q_wb(t0)^-1 q_wb(t1),
//   dv = R_wb(t0)^T (v1 - v0 - g_w T),
//   dp = R_wb(t0)^T (p1 - p0 - v0 T - 0.5 g_w T^2).
// Error state (15): [dp (3), dtheta (3), dv (3), dba (3), dbg (3)] with the rotation error on the
// right: dq_true = dq_est * Exp(dtheta).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "rgbdi/common/types.h"
#include "rgbdi/imu/imu_noise.h"

namespace rgbdi::imu {

using Matrix15d = Eigen::Matrix<double, 15, 15>;
using Vector15d = Eigen::Matrix<double, 15, 1>;

/// Offsets of the blocks of the 15-dim error state and of the IMU residual.
constexpr int kIdxP = 0;
constexpr int kIdxR = 3;
constexpr int kIdxV = 6;
constexpr int kIdxBa = 9;
constexpr int kIdxBg = 12;

class Preintegration {
 public:
  /// ba_lin, bg_lin: biases the samples are integrated with (the linearisation point).
  /// Throws std::invalid_argument for negative or non-finite noise values or non-finite biases.
  Preintegration(const Eigen::Vector3d& ba_lin, const Eigen::Vector3d& bg_lin,
                 const ImuNoise& noise);

  /// Adds a sample. The first one sets the start time; each later one integrates [t_prev, t]
  /// with the midpoint rule. Throws std::invalid_argument when t is not strictly after the
  /// previous sample or a value is not finite.
  void push(double t, const Eigen::Vector3d& acc, const Eigen::Vector3d& gyr);
  void push(const ImuSample& s) { push(s.t, s.acc, s.gyr); }

  double dt() const { return sum_dt_; }  ///< integrated duration [s]
  /// Start / end stamps; throw std::logic_error when no sample was pushed.
  double startTime() const;
  double endTime() const;
  const Eigen::Vector3d& deltaP() const { return dp_; }
  const Eigen::Vector3d& deltaV() const { return dv_; }
  const Eigen::Quaterniond& deltaQ() const { return dq_; }
  /// Covariance of the error state [dp, dtheta, dv, dba, dbg] (the bias rows hold the random
  /// walk accumulated over dt()).
  const Matrix15d& covariance() const { return cov_; }
  /// d(error state at the end)/d(error state at the start); its columns kIdxBa and kIdxBg are
  /// the bias Jacobians of the deltas.
  const Matrix15d& jacobian() const { return jac_; }
  const Eigen::Vector3d& biasAcc() const { return ba_lin_; }
  const Eigen::Vector3d& biasGyr() const { return bg_lin_; }
  const ImuNoise& noise() const { return noise_; }
  const std::vector<ImuSample>& samples() const { return samples_; }
  /// Incremented by every push() and repropagate(): lets users of the covariance (ImuFactor)
  /// cache derived matrices and notice when they are stale.
  std::uint64_t revision() const { return revision_; }

  /// Re-integrates the stored samples with new linearisation biases.
  void repropagate(const Eigen::Vector3d& ba, const Eigen::Vector3d& bg);
  /// True when |ba - biasAcc()| > acc_thresh or |bg - biasGyr()| > gyr_thresh.
  bool needsRepropagation(const Eigen::Vector3d& ba, const Eigen::Vector3d& bg, double acc_thresh,
                          double gyr_thresh) const;

  /// Deltas corrected to first order for biases (ba, bg) that differ from the linearisation point.
  Eigen::Vector3d correctedDeltaP(const Eigen::Vector3d& ba, const Eigen::Vector3d& bg) const;
  Eigen::Vector3d correctedDeltaV(const Eigen::Vector3d& ba, const Eigen::Vector3d& bg) const;
  Eigen::Quaterniond correctedDeltaQ(const Eigen::Vector3d& bg) const;

  /// Upper Cholesky factor U of the information matrix (U^T U = covariance()^-1).
  /// Throws std::runtime_error when the covariance is not positive definite (fewer than two
  /// samples or zero noise).
  Matrix15d sqrtInformation() const;
  /// Same, without throwing: false when the covariance is not positive definite.
  bool trySqrtInformation(Matrix15d* sqrt_info) const;

  /// Unwhitened residual [r_p, r_theta, r_v, r_ba, r_bg] between body states i and j
  /// (q: R_world_body, v in world). r_theta = Log(dq_corrected^-1 q_i^-1 q_j).
  Vector15d residual(const Eigen::Vector3d& Pi, const Eigen::Quaterniond& Qi,
                     const Eigen::Vector3d& Vi, const Eigen::Vector3d& Bai,
                     const Eigen::Vector3d& Bgi, const Eigen::Vector3d& Pj,
                     const Eigen::Quaterniond& Qj, const Eigen::Vector3d& Vj,
                     const Eigen::Vector3d& Baj, const Eigen::Vector3d& Bgj,
                     const Eigen::Vector3d& g_w) const;

  /// Propagates state i over dt() with the linearisation biases (the residual of the result is
  /// zero when the biases of both states equal biasAcc()/biasGyr()).
  void predict(const Eigen::Vector3d& Pi, const Eigen::Quaterniond& Qi, const Eigen::Vector3d& Vi,
               const Eigen::Vector3d& g_w, Eigen::Vector3d& Pj, Eigen::Quaterniond& Qj,
               Eigen::Vector3d& Vj) const;

 private:
  void resetIntegration();
  void integrateStep(const ImuSample& s0, const ImuSample& s1);

  Eigen::Vector3d ba_lin_;
  Eigen::Vector3d bg_lin_;
  ImuNoise noise_;
  std::vector<ImuSample> samples_;

  std::uint64_t revision_ = 0;
  double sum_dt_ = 0.0;
  Eigen::Vector3d dp_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d dv_ = Eigen::Vector3d::Zero();
  Eigen::Quaterniond dq_ = Eigen::Quaterniond::Identity();
  Matrix15d cov_ = Matrix15d::Zero();
  Matrix15d jac_ = Matrix15d::Identity();
};

}  // namespace rgbdi::imu
