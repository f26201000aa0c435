// IMU errors beyond white noise and bias random walk (D435i / BMI055 class sensors), all off by
// default:
// - per-axis scale factor errors and axis misalignment: measured = (I + S)(I + M) truth, S
//   diagonal, M with zero diagonal (non-orthogonal axes); entries drawn once per sequence from
//   the seed, uniform in +-max;
// - gyroscope g-sensitivity: + G f (rad/s per m/s^2 of specific force), G's entries uniform in
//   +-max, drawn once;
// - bias instability: a first-order Gauss-Markov term per axis, b(k+1) = phi b(k) +
//   sigma sqrt(1 - phi^2) n(k), phi = exp(-dt / tau), started from its stationary distribution
//   (standard deviation sigma at every sample); it is part of the true bias;
// - quantisation: the output rounded to a multiple of the LSB (after bias and noise).
// Every number is a pure function of (seed, stream, index), as in ImuSynthesizer.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "rgbdi/common/ini_reader.h"

namespace rgbdi::sim {

struct ImuErrorOptions {
  double acc_scale_max = 0.0;             ///< [unitless] per-axis scale error in +-this
  double gyr_scale_max = 0.0;             ///< [unitless]
  double acc_misalignment_max_rad = 0.0;  ///< [rad] off-diagonal coupling in +-this
  double gyr_misalignment_max_rad = 0.0;  ///< [rad]
  double gyr_g_sensitivity_max = 0.0;     ///< [rad/s per m/s^2] entries of G in +-this
  double acc_bias_instability = 0.0;      ///< [m/s^2] stationary sigma of the Gauss-Markov bias
  double gyr_bias_instability = 0.0;      ///< [rad/s]
  double bias_instability_tau_s = 100.0;  ///< [s] its correlation time
  double acc_lsb = 0.0;                   ///< [m/s^2] quantisation step; 0 = none
  double gyr_lsb = 0.0;                   ///< [rad/s]

  /// Whether any error is on (otherwise the synthesiser's output is as without this model).
  bool any() const;
  /// Reads [sim] imu_acc_scale_max, imu_gyr_scale_max, imu_acc_misalignment_max_rad,
  /// imu_gyr_misalignment_max_rad, imu_gyr_g_sensitivity_max, imu_acc_bias_instability,
  /// imu_gyr_bias_instability, imu_bias_instability_tau_s, imu_acc_lsb, imu_gyr_lsb.
  static ImuErrorOptions load(IniReader& ini);
  /// Throws std::invalid_argument on negative or non-finite values or tau <= 0.
  void validate() const;
};

class ImuErrorModel {
 public:
  /// Draws the sequence's constant errors (scale, misalignment, g-sensitivity) from the seed.
  ImuErrorModel(const ImuErrorOptions& options, std::uint64_t seed);

  const ImuErrorOptions& options() const { return options_; }
  const Eigen::Matrix3d& accMatrix() const { return acc_matrix_; }  ///< (I + S)(I + M)
  const Eigen::Matrix3d& gyrMatrix() const { return gyr_matrix_; }
  const Eigen::Matrix3d& gSensitivity() const { return g_sensitivity_; }

  /// The deterministic part of the measurement: T_acc f and T_gyr w + G f.
  Eigen::Vector3d accel(const Eigen::Vector3d& specific_force) const;
  Eigen::Vector3d gyro(const Eigen::Vector3d& rate, const Eigen::Vector3d& specific_force) const;
  /// Rounds every component to a multiple of lsb (lsb 0: unchanged).
  static Eigen::Vector3d quantise(const Eigen::Vector3d& v, double lsb);

  /// Gauss-Markov bias of samples 0..n-1 taken every dt seconds: (acc, gyr) per sample.
  void gaussMarkov(std::size_t n, double dt, std::vector<Eigen::Vector3d>& acc,
                   std::vector<Eigen::Vector3d>& gyr) const;

 private:
  ImuErrorOptions options_;
  std::uint64_t seed_;
  Eigen::Matrix3d acc_matrix_, gyr_matrix_, g_sensitivity_;
};

}  // namespace rgbdi::sim
