// A small analytic world for estimator tests without images: a smooth trajectory (circle with a
// still start, height and attitude oscillations), exact IMU samples, and 3-D landmarks observed
// as FeatureFrames (what the front end would output).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <vector>

#include "rgbdi/common/so3.h"
#include "rgbdi/common/types.h"
#include "rgbdi/frontend/feature_frame.h"

namespace rgbdi::test {

struct SyntheticWorld {
  double radius = 2.0;     ///< [m] circle radius
  double omega = 0.2;      ///< [rad/s] final angular speed around the circle
  double start_s = 1.5;    ///< logistic speed-up centre [s]
  double steepness = 5.0;  ///< [1/s] of the speed-up
  double gravity = 9.81;
  Eigen::Isometry3d T_bc = Eigen::Isometry3d::Identity();
  std::vector<Eigen::Vector3d> landmarks;

  /// Angle along the circle: omega * softplus, so the platform is (almost) still at the start.
  double angle(double t) const {
    return omega * std::log1p(std::exp(steepness * (t - start_s))) / steepness;
  }
  Eigen::Isometry3d pose(double t) const {
    const double a = angle(t);
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() << radius * std::cos(a), radius * std::sin(a), 0.3 + 0.05 * std::sin(3.0 * a);
    // Facing along the tangent, with small roll/pitch oscillations (real 6-DOF motion).
    const double yaw = a + M_PI / 2;
    T.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                  Eigen::AngleAxisd(0.05 * std::sin(2.0 * a), Eigen::Vector3d::UnitY()) *
                  Eigen::AngleAxisd(0.04 * std::cos(5.0 * a), Eigen::Vector3d::UnitX()))
                     .toRotationMatrix();
    return T;
  }
  Eigen::Vector3d velocity(double t) const {
    const double h = 1e-4;
    return (pose(t + h).translation() - pose(t - h).translation()) / (2 * h);
  }
  ImuSample imu(double t) const {
    const double h = 1e-3;
    const Eigen::Isometry3d T0 = pose(t - h), T1 = pose(t), T2 = pose(t + h);
    const Eigen::Vector3d acc_w =
        (T2.translation() - 2 * T1.translation() + T0.translation()) / (h * h);
    ImuSample s;
    s.t = t;
    s.acc = T1.rotation().transpose() * (acc_w - Eigen::Vector3d(0, 0, -gravity));
    s.gyr = logSO3(T0.rotation().transpose() * T2.rotation()) / (2 * h);
    return s;
  }
  /// Landmarks on a textured "wall" cylinder around the circle, and on the floor.
  void makeLandmarks(std::uint64_t seed, int n) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> ang(0, 2 * M_PI), h(0.0, 1.5), r(0.0, 1.0);
    for (int i = 0; i < n; ++i) {
      const double a = ang(rng);
      if (i % 4 == 0) {  // floor
        const double rr = 0.5 + 3.0 * std::sqrt(r(rng));
        landmarks.emplace_back(rr * std::cos(a), rr * std::sin(a), 0.0);
      } else {
        const double rr = 3.5 + 0.3 * r(rng);
        landmarks.emplace_back(rr * std::cos(a), rr * std::sin(a), h(rng));
      }
    }
  }
  /// Observations at time t: every landmark in front of the camera within the image. With a
  /// rolling shutter (readout_s > 0: 480 rows read top to bottom, t at the middle row) each
  /// landmark is seen at its row's time (the row found by fixed-point iteration).
  frontend::FeatureFrame observe(double t, std::uint64_t index, double depth_noise_sigma,
                                 std::mt19937_64& rng, double pixel_sigma = 0.0,
                                 double readout_s = 0.0) const {
    frontend::FeatureFrame f;
    f.t = t;
    f.frame_index = index;
    const Eigen::Isometry3d T_cw = (pose(t) * T_bc).inverse();
    std::normal_distribution<double> n(0.0, 1.0);
    for (std::size_t i = 0; i < landmarks.size(); ++i) {
      Eigen::Vector3d p = T_cw * landmarks[i];
      if (readout_s > 0.0 && p.z() > 0.0) {
        for (int k = 0; k < 4; ++k) {
          const double row = 600 * p.y() / p.z() + 240;
          const double t_row = t + (row - 239.5) * readout_s / 480.0;
          p = (pose(t_row) * T_bc).inverse() * landmarks[i];
        }
      }
      if (p.z() < 0.3 || p.z() > 8.0) continue;
      Eigen::Vector2d xn = p.head<2>() / p.z();
      xn += Eigen::Vector2d(n(rng), n(rng)) * (pixel_sigma / 600.0);
      const Eigen::Vector2d uv(600 * xn.x() + 320, 600 * xn.y() + 240);
      if (uv.x() < 0 || uv.x() > 639 || uv.y() < 0 || uv.y() > 479) continue;
      frontend::FeatureObservation o;
      o.id = i;
      o.uv = uv;
      o.xn = xn;
      // The depth image is a global-shutter image at t.
      const double z = (T_cw * landmarks[i]).z();
      o.depth_m = z <= 3.0 ? z + depth_noise_sigma * z * z * n(rng) : 0.0;
      f.features.push_back(o);
    }
    return f;
  }
};

}  // namespace rgbdi::test
