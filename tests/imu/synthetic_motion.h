// Test helper: a smooth analytic body trajectory with its exact IMU readings.
// Position and rotation vector are sums of sinusoids, so velocity, acceleration and body rate are
// known in closed form: R = Exp(theta(t)), body rate = Jr(theta) theta'(t),
// specific force = R^T (p''(t) - g_w).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <vector>

#include "rgbdi/common/so3.h"
#include "rgbdi/common/types.h"
#include "rgbdi/imu/imu_noise.h"

namespace rgbdi::test {

/// Gravity of the synthetic tests (world z up).
inline const Eigen::Vector3d kTestGravity(0.0, 0.0, -9.81);

/// The [sim] default noise of the project (true noise of a D435i-class IMU).
inline imu::ImuNoise simImuNoise() {
  imu::ImuNoise n;
  n.acc_nd = 0.02;
  n.gyr_nd = 0.002;
  n.acc_rw = 4e-4;
  n.gyr_rw = 2e-5;
  return n;
}

struct TrueState {
  Eigen::Vector3d p;
  Eigen::Quaterniond q;  // R_world_body
  Eigen::Vector3d v;
};

class SyntheticMotion {
 public:
  explicit SyntheticMotion(const Eigen::Vector3d& g_w) : g_w_(g_w) {}

  TrueState state(double t) const { return {position(t), expQuat(rotationVector(t)), velocity(t)}; }

  /// Noise-free IMU sample at t with the given biases added to the readings.
  ImuSample sample(double t, const Eigen::Vector3d& ba = Eigen::Vector3d::Zero(),
                   const Eigen::Vector3d& bg = Eigen::Vector3d::Zero()) const {
    const Eigen::Vector3d th = rotationVector(t);
    const Eigen::Matrix3d R = expSO3(th);
    ImuSample s;
    s.t = t;
    s.gyr = rightJacobianSO3(th) * rotationRate(t) + bg;
    s.acc = R.transpose() * (acceleration(t) - g_w_) + ba;
    return s;
  }

  /// Samples at t0, t0 + 1/rate, ... up to and including t1 (t1 - t0 a multiple of 1/rate).
  std::vector<ImuSample> samples(double t0, double t1, double rate_hz,
                                 const Eigen::Vector3d& ba = Eigen::Vector3d::Zero(),
                                 const Eigen::Vector3d& bg = Eigen::Vector3d::Zero()) const {
    const int n = static_cast<int>(std::lround((t1 - t0) * rate_hz));
    std::vector<ImuSample> out;
    for (int k = 0; k <= n; ++k) out.push_back(sample(t0 + k / rate_hz, ba, bg));
    return out;
  }

  const Eigen::Vector3d& gravity() const { return g_w_; }

 private:
  // Amplitudes/frequencies of a ground robot swerving at ~1 m/s with moderate rotation.
  static Eigen::Vector3d position(double t) {
    return {1.0 * t + 0.5 * std::sin(1.3 * t), 0.8 * std::cos(0.9 * t), 0.1 * std::sin(2.1 * t)};
  }
  static Eigen::Vector3d velocity(double t) {
    return {1.0 + 0.65 * std::cos(1.3 * t), -0.72 * std::sin(0.9 * t), 0.21 * std::cos(2.1 * t)};
  }
  static Eigen::Vector3d acceleration(double t) {
    return {-0.845 * std::sin(1.3 * t), -0.648 * std::cos(0.9 * t), -0.441 * std::sin(2.1 * t)};
  }
  static Eigen::Vector3d rotationVector(double t) {
    return {0.2 * std::sin(1.7 * t), 0.15 * std::sin(1.1 * t + 0.3),
            0.4 * t + 0.3 * std::sin(0.7 * t)};
  }
  static Eigen::Vector3d rotationRate(double t) {
    return {0.34 * std::cos(1.7 * t), 0.165 * std::cos(1.1 * t + 0.3),
            0.4 + 0.21 * std::cos(0.7 * t)};
  }

  Eigen::Vector3d g_w_;
};

}  // namespace rgbdi::test
