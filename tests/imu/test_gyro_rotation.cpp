// gyroRotation: the body rotation between two times from buffered gyroscope samples.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <functional>

#include "rgbdi/common/so3.h"
#include "rgbdi/imu/gyro_rotation.h"

using rgbdi::ImuSample;
using rgbdi::imu::gyroRotation;
using rgbdi::imu::ImuBuffer;

namespace {

ImuBuffer samples(double t_first, double t_last, double dt,
                  const std::function<Eigen::Vector3d(double)>& rate) {
  ImuBuffer b;
  for (double t = t_first; t <= t_last + 1e-12; t += dt) {
    ImuSample s;
    s.t = t;
    s.gyr = rate(t);
    b.push(s);
  }
  return b;
}

double angleBetween(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  return a.angularDistance(b);
}

}  // namespace

TEST(GyroRotation, ConstantRateMinusBiasIsExact) {
  const Eigen::Vector3d w(0.3, -1.2, 2.5), bias(0.01, 0.02, -0.03);
  const ImuBuffer b = samples(10.0, 11.0, 0.005, [&](double) { return w; });
  // Inside the buffer, between samples (interpolated ends).
  const Eigen::Quaterniond q = gyroRotation(b, 10.1234, 10.4567, bias);
  const Eigen::Quaterniond expected = rgbdi::expQuat((w - bias) * (10.4567 - 10.1234));
  EXPECT_LT(angleBetween(q, expected), 1e-12);
  // Beyond the newest sample (an image before its IMU) the newest rate is held; before the
  // oldest, the oldest rate.
  EXPECT_LT(angleBetween(gyroRotation(b, 10.9, 11.2, bias), rgbdi::expQuat((w - bias) * 0.3)),
            1e-12);
  EXPECT_LT(angleBetween(gyroRotation(b, 9.5, 10.5, bias), rgbdi::expQuat((w - bias) * 1.0)),
            1e-12);
  EXPECT_LT(angleBetween(gyroRotation(b, 12.0, 12.5, bias), rgbdi::expQuat((w - bias) * 0.5)),
            1e-12);
}

TEST(GyroRotation, RateRampAboutAFixedAxisIsIntegratedExactly) {
  // w(t) = (a + c t) n: the angle is the integral a T + c (t1^2 - t0^2) / 2, and the mean of two
  // samples is exact for a linear rate.
  const Eigen::Vector3d n = Eigen::Vector3d(1, 2, -2).normalized();
  const double a = 0.5, c = 3.0;
  const ImuBuffer b = samples(0.0, 2.0, 0.01, [&](double t) { return (a + c * t) * n; });
  const double t0 = 0.333, t1 = 1.777;
  const double angle = a * (t1 - t0) + 0.5 * c * (t1 * t1 - t0 * t0);
  const Eigen::Quaterniond q = gyroRotation(b, t0, t1, Eigen::Vector3d::Zero());
  EXPECT_LT(angleBetween(q, rgbdi::expQuat(angle * n)), 1e-9);
}

TEST(GyroRotation, RotationsComposeInTimeOrder) {
  // Rates about different axes do not commute: R(t0, t2) = R(t0, t1) R(t1, t2).
  const ImuBuffer b = samples(0.0, 1.0, 0.005, [](double t) {
    return Eigen::Vector3d(std::sin(3 * t), 2.0 * std::cos(2 * t), 1.0 + t);
  });
  const Eigen::Vector3d bias(0.02, 0.0, -0.01);
  const Eigen::Quaterniond whole = gyroRotation(b, 0.1, 0.9, bias);
  const Eigen::Quaterniond parts =
      gyroRotation(b, 0.1, 0.5, bias) * gyroRotation(b, 0.5, 0.9, bias);
  EXPECT_LT(angleBetween(whole, parts), 1e-12);
  // And they do not commute: the reversed product is measurably different.
  EXPECT_GT(angleBetween(whole, gyroRotation(b, 0.5, 0.9, bias) * gyroRotation(b, 0.1, 0.5, bias)),
            1e-3);
}

TEST(GyroRotation, EmptyBufferOrEmptyIntervalIsIdentity) {
  EXPECT_LT(angleBetween(gyroRotation(ImuBuffer(), 0.0, 1.0, Eigen::Vector3d::Zero()),
                         Eigen::Quaterniond::Identity()),
            1e-15);
  const ImuBuffer b = samples(0.0, 1.0, 0.01, [](double) { return Eigen::Vector3d(1, 0, 0); });
  EXPECT_LT(angleBetween(gyroRotation(b, 0.5, 0.5, Eigen::Vector3d::Zero()),
                         Eigen::Quaterniond::Identity()),
            1e-15);
  EXPECT_LT(angleBetween(gyroRotation(b, 0.6, 0.5, Eigen::Vector3d::Zero()),
                         Eigen::Quaterniond::Identity()),
            1e-15);
}

TEST(DeadReckonedMotion, ConstantRateAndAccelerationOfAKnownPath) {
  // A body turning about its z axis at w while its specific force is constant in the body frame:
  // with gravity cancelled in the world's z, the world acceleration of the body is
  // R(t) a_xy, whose double integral is known in closed form. Pieces of 1 ms: midpoint attitude
  // integration errs by O(dt^2) per unit time.
  const double w = 0.8;
  const Eigen::Vector3d a_body(0.5, -0.2, 0.0), bias_g(0.01, -0.02, 0.03),
      bias_a(0.05, 0.04, -0.03), g(0.0, 0.0, -9.81);
  ImuBuffer b;
  for (double t = 0.0; t <= 2.0 + 1e-12; t += 0.001) {
    ImuSample s;
    s.t = t;
    s.gyr = Eigen::Vector3d(0.0, 0.0, w) + bias_g;
    s.acc = a_body - g + bias_a;  // the body stays level: gravity's reaction along its z
    b.push(s);
  }
  rgbdi::imu::BodyState start;
  start.v_world = Eigen::Vector3d(0.3, 0.1, 0.2);
  start.bias_gyr = bias_g;
  start.bias_acc = bias_a;
  const double t0 = 0.2, T = 1.3;
  rgbdi::imu::BodyState end;
  const Eigen::Isometry3d M = rgbdi::imu::deadReckonedMotion(b, t0, t0 + T, start, g, &end);
  // p(T) = v0 T + int_0^T int_0^s R(wu) a du ds; with c = a_x + i a_y:
  // int_0^s e^{iwu} c du = c (e^{iws} - 1) / (iw); int_0^T of that = c ((e^{iwT} - 1)/(iw) -
  // T)/(iw).
  const std::complex<double> c(a_body.x(), a_body.y()), iw(0.0, w);
  const std::complex<double> xy = c * ((std::exp(iw * T) - 1.0) / iw - T) / iw;
  const Eigen::Vector3d expected = start.v_world * T + Eigen::Vector3d(xy.real(), xy.imag(), 0.0);
  EXPECT_LT((M.translation() - expected).norm(), 1e-6) << M.translation().transpose();
  EXPECT_LT(Eigen::Quaterniond(M.linear())
                .angularDistance(rgbdi::expQuat(Eigen::Vector3d(0.0, 0.0, w * T))),
            1e-12);
  // The end state: v(T) = v0 + c (e^{iwT} - 1) / (iw), the attitude turned by w T, the biases
  // carried over.
  const std::complex<double> vxy = c * (std::exp(iw * T) - 1.0) / iw;
  EXPECT_LT((end.v_world - start.v_world - Eigen::Vector3d(vxy.real(), vxy.imag(), 0.0)).norm(),
            1e-6);
  EXPECT_LT(end.q_world_body.angularDistance(rgbdi::expQuat(Eigen::Vector3d(0.0, 0.0, w * T))),
            1e-12);
  EXPECT_EQ(end.bias_gyr, bias_g);
  EXPECT_EQ(end.bias_acc, bias_a);
}

TEST(GyroRate, InterpolatedInsideTheSpanHeldOutsideAndZeroWhenEmpty) {
  ImuBuffer b;
  for (int k = 0; k <= 2; ++k) {
    ImuSample s;
    s.t = 1.0 + 0.01 * k;
    s.gyr = Eigen::Vector3d(0.1 * k, -0.2 * k, 1.0);
    b.push(s);
  }
  const Eigen::Vector3d bias(0.0, 0.0, 0.5);
  EXPECT_LT((rgbdi::imu::gyroRate(b, 1.015, bias) - Eigen::Vector3d(0.15, -0.3, 0.5)).norm(),
            1e-12);
  EXPECT_EQ(rgbdi::imu::gyroRate(b, 0.5, bias), Eigen::Vector3d(0.0, 0.0, 0.5));
  EXPECT_EQ(rgbdi::imu::gyroRate(b, 2.0, bias), Eigen::Vector3d(0.2, -0.4, 0.5));
  EXPECT_EQ(rgbdi::imu::gyroRate(ImuBuffer(), 1.0, bias), Eigen::Vector3d::Zero());
}

TEST(DeadReckonedMotion, TranslationIsInTheStartBodyFrameAndEmptyIsIdentity) {
  // At rest (specific force = gravity's reaction) a body turned by 90 deg about z, moving along
  // the world's x at 1 m/s, moves along its own -y.
  ImuBuffer b;
  for (double t = 0.0; t <= 1.0 + 1e-12; t += 0.005) {
    ImuSample s;
    s.t = t;
    s.acc = Eigen::Vector3d(0.0, 0.0, 9.81);
    b.push(s);
  }
  rgbdi::imu::BodyState start;
  start.q_world_body = Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()));
  start.v_world = Eigen::Vector3d(1.0, 0.0, 0.0);
  const Eigen::Vector3d g(0.0, 0.0, -9.81);
  const Eigen::Isometry3d M = rgbdi::imu::deadReckonedMotion(b, 0.25, 0.75, start, g);
  EXPECT_LT((M.translation() - Eigen::Vector3d(0.0, -0.5, 0.0)).norm(), 1e-12);
  EXPECT_LT(Eigen::Quaterniond(M.linear()).angularDistance(Eigen::Quaterniond::Identity()), 1e-12);
  EXPECT_TRUE(rgbdi::imu::deadReckonedMotion(ImuBuffer(), 0.0, 1.0, start, g)
                  .isApprox(Eigen::Isometry3d::Identity()));
  EXPECT_TRUE(rgbdi::imu::deadReckonedMotion(b, 0.5, 0.5, start, g)
                  .isApprox(Eigen::Isometry3d::Identity()));
}
