// The motion field against a numeric derivative of the projection of a static point.
#include <gtest/gtest.h>

#include <random>

#include "rgbdi/common/motion_field.h"
#include "rgbdi/common/so3.h"

using namespace rgbdi;

namespace {

/// Normalised projection of world point p_w at time t for a camera T_w_c(t) = T0 * [Exp(w t), v t]
/// (constant body-frame twist).
Eigen::Vector2d projectAt(double t, const Eigen::Isometry3d& T0, const Eigen::Vector3d& w,
                          const Eigen::Vector3d& v, const Eigen::Vector3d& p_w) {
  // Constant twist in the camera frame to first order: T(t) = T0 * (R = Exp(w t), p = v t).
  // The derivative at t = 0 only needs the first-order motion, which this gives exactly.
  Eigen::Isometry3d dT = Eigen::Isometry3d::Identity();
  dT.linear() = expSO3(w * t);
  dT.translation() = v * t;
  const Eigen::Vector3d p_c = (T0 * dT).inverse() * p_w;
  return p_c.head<2>() / p_c.z();
}

}  // namespace

TEST(MotionField, MatchesNumericDerivativeOfTheProjection) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 50; ++trial) {
    Eigen::Isometry3d T0 = Eigen::Isometry3d::Identity();
    T0.linear() = expSO3(Eigen::Vector3d(u(rng), u(rng), u(rng)));
    T0.translation() << u(rng), u(rng), u(rng);
    const Eigen::Vector3d w(u(rng), u(rng), u(rng)), v(u(rng), u(rng), u(rng));
    const Eigen::Vector3d p_c(0.8 * u(rng), 0.6 * u(rng), 1.5 + u(rng));
    const Eigen::Vector3d p_w = T0 * p_c;
    const double h = 1e-6;
    const Eigen::Vector2d numeric =
        (projectAt(h, T0, w, v, p_w) - projectAt(-h, T0, w, v, p_w)) / (2 * h);
    const Eigen::Vector2d analytic = motionFieldVelocity(p_c.head<2>() / p_c.z(), p_c.z(), w, v);
    EXPECT_LT((analytic - numeric).norm(), 1e-7) << trial;
  }
}

TEST(MotionField, KnownAnswers) {
  // Pure yaw about the optical axis: the image rotates about the principal point.
  const Eigen::Vector2d r = motionFieldVelocity({0.2, -0.1}, 2.0, {0, 0, 0.5}, {0, 0, 0});
  EXPECT_NEAR(r.x(), -0.1 * 0.5, 1e-15);
  EXPECT_NEAR(r.y(), -0.2 * 0.5, 1e-15);
  // Moving forward: points flow away from the centre at x v_z / z.
  const Eigen::Vector2d f = motionFieldVelocity({0.2, -0.1}, 2.0, {0, 0, 0}, {0, 0, 1.0});
  EXPECT_NEAR(f.x(), 0.1, 1e-15);
  EXPECT_NEAR(f.y(), -0.05, 1e-15);
  // Unknown depth: the translational part is left out.
  const Eigen::Vector2d n = motionFieldVelocity({0.2, -0.1}, 0.0, {0, 0, 0}, {0, 0, 1.0});
  EXPECT_EQ(n, Eigen::Vector2d::Zero());
}

TEST(MotionField, TheCameraCentreMovesWithTheLeverArm) {
  // Camera 0.1 m ahead of the body (body x), looking along body x (camera z = body x).
  Eigen::Isometry3d T_body_cam = Eigen::Isometry3d::Identity();
  T_body_cam.linear() << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  T_body_cam.translation() << 0.1, 0.0, 0.0;
  // The body turns at 2 rad/s about its z axis and moves 0.5 m/s forward (body frame).
  const CameraVelocity c = cameraVelocity(T_body_cam, {0.5, 0.0, 0.0}, {0.0, 0.0, 2.0});
  // Body z is camera -y; the centre moves 0.5 forward (camera z) and 0.2 to the body's left
  // (body y = camera -x).
  EXPECT_NEAR((c.omega_cam - Eigen::Vector3d(0.0, -2.0, 0.0)).norm(), 0.0, 1e-15);
  EXPECT_NEAR((c.v_cam - Eigen::Vector3d(-0.2, 0.0, 0.5)).norm(), 0.0, 1e-15);
}

TEST(MotionField, TheTypicalDepthIsTheMedianOfTheKnownOnes) {
  EXPECT_EQ(typicalDepth({}), 0.0);
  EXPECT_EQ(typicalDepth({0.0, -1.0}), 0.0);
  EXPECT_EQ(typicalDepth({3.0, 0.0, 1.0, 2.0}), 2.0);
  EXPECT_EQ(typicalDepth({4.0, 1.0, 0.0, 2.0, 3.0}), 3.0);  // the upper of two middles
}
