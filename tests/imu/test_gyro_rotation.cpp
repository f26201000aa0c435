// gyroRotation: the body rotation between two times from buffered gyroscope samples.
#include <gtest/gtest.h>

#include <cmath>
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
