// A ConversionSink that records everything a converter delivers, for the converter tests.
#pragma once

#include <gtest/gtest.h>

#include <utility>
#include <vector>

#include "rgbdi/bag/conversion_sink.h"

namespace rgbdi::test {

struct RecordingSink : bag::ConversionSink {
  /// The IMU stream the source can deliver: bags give combined samples; TUM folders have no
  /// gyroscope and give accelerometer-only samples. The other kind is reported as a failure.
  enum class ImuKind { kCombined, kAccelerometerOnly };
  explicit RecordingSink(ImuKind kind = ImuKind::kCombined) : kind_(kind) {}

  std::vector<ImuSample> imus;
  std::vector<std::pair<double, Eigen::Vector3d>> accel;
  std::vector<RgbdFrame> frames;
  std::vector<StampedPose> poses;
  std::vector<WheelOdometrySample> wheels;

  void imu(const ImuSample& s) override {
    if (kind_ != ImuKind::kCombined) ADD_FAILURE() << "combined IMU sample from a gyro-less source";
    imus.push_back(s);
  }
  void accelerometer(double t, const Eigen::Vector3d& a) override {
    if (kind_ != ImuKind::kAccelerometerOnly) ADD_FAILURE() << "unexpected accelerometer-only data";
    accel.emplace_back(t, a);
  }
  void frame(const RgbdFrame& f) override { frames.push_back(f); }
  void groundTruth(const StampedPose& p) override { poses.push_back(p); }
  void wheel(const WheelOdometrySample& w) override { wheels.push_back(w); }

 private:
  ImuKind kind_;
};

}  // namespace rgbdi::test
