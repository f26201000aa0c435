// IMU synthesis from an analytic trajectory: specific force (gravity included) and body rates,
// plus white noise, bias random walk and initial biases.
//
// Noise model (Kalibr convention, continuous-time densities): white noise with discrete sigma
// density * sqrt(rate); the bias is a random walk b(k+1) = b(k) + random_walk * sqrt(dt) * n(k),
// starting from a bias uniform in +-bias_max per axis. The measurement at sample k is
// truth(t_k) + b(k) + white noise; with ImuErrorOptions set, Q(T truth(t_k) + b(k) + white
// noise) with T the scale / misalignment (and g-sensitivity) of imu_error_model.h, b including
// the Gauss-Markov bias instability and Q the quantisation. Every random number is a pure function
// of (seed, sample), so samples can be generated in any order with identical results.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <vector>

#include "rgbdi/common/ini_reader.h"
#include "rgbdi/common/types.h"
#include "rgbdi/sim/imu_error_model.h"
#include "rgbdi/sim/trajectory.h"

namespace rgbdi::sim {

/// The TRUE IMU noise of the simulation ([sim] section).
struct ImuSynthOptions {
  double rate_hz = 200.0;            ///< [Hz]
  double gravity_m_s2 = 9.81;        ///< [m/s^2], world z up, gravity along -z
  double acc_noise_density = 0.02;   ///< [m/s^2/sqrt(Hz)]
  double gyr_noise_density = 0.002;  ///< [rad/s/sqrt(Hz)]
  double acc_random_walk = 4e-4;     ///< [m/s^3/sqrt(Hz)]
  double gyr_random_walk = 2e-5;     ///< [rad/s^2/sqrt(Hz)]
  double acc_bias_max = 0.1;         ///< [m/s^2] initial bias uniform in +-this per axis
  double gyr_bias_max = 0.005;       ///< [rad/s] same for the gyro
  /// Scale, misalignment, g-sensitivity, bias instability, quantisation (default none).
  ImuErrorOptions errors;
  /// [Hz] separate accelerometer and gyroscope streams at these rates, merged into combined
  /// samples on the gyro stamps as rawlog-convert merges a D435i's (ImuSplitStream); 0 and 0 =
  /// combined samples at rate_hz. Used by SimulatedSequence, not by ImuSynthesizer.
  double accel_rate_hz = 0.0;
  double gyro_rate_hz = 0.0;

  /// Reads [sim] imu_rate_hz, gravity_m_s2, acc/gyr_noise_density, acc/gyr_random_walk,
  /// acc/gyr_bias_max, imu_accel_rate_hz, imu_gyro_rate_hz and the ImuErrorOptions keys.
  static ImuSynthOptions load(IniReader& ini);
  /// The same rate and gravity without any noise or bias (ideal sensor).
  ImuSynthOptions noiseFree() const;
};

struct ImuBias {
  Eigen::Vector3d acc = Eigen::Vector3d::Zero();  ///< [m/s^2]
  Eigen::Vector3d gyr = Eigen::Vector3d::Zero();  ///< [rad/s]
};

class ImuSynthesizer {
 public:
  /// Samples k = 0, 1, ... at t_k = k / rate_hz cover [0, trajectory.duration()].
  /// Throws std::invalid_argument on a non-positive rate or negative noise values.
  ImuSynthesizer(std::shared_ptr<const BodyTrajectory> trajectory, const ImuSynthOptions& options,
                 std::uint64_t seed);

  std::size_t sampleCount() const { return biases_.size(); }
  /// [s] sequence time of sample k.
  double sampleTime(std::size_t k) const { return static_cast<double>(k) / options_.rate_hz; }
  /// Noise-free measurement (no bias) at sample k, stamped with sequence time.
  ImuSample ideal(std::size_t k) const;
  /// Noise-free measurement at any time t [s].
  ImuSample idealAt(double t) const;
  /// The simulated measurement of sample k, stamped with sequence time.
  ImuSample measured(std::size_t k) const;
  /// True bias at sample k, and at any time (linear between samples, clamped to the ends).
  const ImuBias& biasAtSample(std::size_t k) const { return biases_.at(k); }
  ImuBias biasAt(double t) const;

  const ImuSynthOptions& options() const { return options_; }
  const BodyTrajectory& trajectory() const { return *trajectory_; }

 private:
  std::shared_ptr<const BodyTrajectory> trajectory_;
  ImuSynthOptions options_;
  std::uint64_t seed_;
  std::unique_ptr<ImuErrorModel> errors_;  ///< null when no ImuErrorOptions error is on
  std::vector<ImuBias> biases_;            ///< 48 bytes per sample (about 35 MB per hour at 200 Hz)
};

}  // namespace rgbdi::sim
