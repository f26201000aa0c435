// ImuBuffer: ordering, coverage, interpolation at interval ends, bounded storage.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "rgbdi/imu/imu_buffer.h"

using namespace rgbdi;
using namespace rgbdi::imu;

namespace {

// Readings linear in time, so interpolated samples have exact known values.
ImuSample linearSample(double t) {
  ImuSample s;
  s.t = t;
  s.acc = Eigen::Vector3d(1.0 + 2.0 * t, -3.0 * t, 9.81);
  s.gyr = Eigen::Vector3d(0.1 * t, 0.2, -0.5 * t);
  return s;
}

ImuBuffer bufferAt(std::initializer_list<double> stamps) {
  ImuBuffer b;
  for (double t : stamps) b.push(linearSample(t));
  return b;
}

}  // namespace

TEST(ImuBuffer, BetweenInsertsInterpolatedSamplesExactlyAtBothEnds) {
  const ImuBuffer b = bufferAt({0.0, 0.005, 0.010, 0.015, 0.020, 0.025});
  const auto s = b.between(0.007, 0.018);
  ASSERT_EQ(s.size(), 4u);
  EXPECT_EQ(s[0].t, 0.007);
  EXPECT_EQ(s[1].t, 0.010);
  EXPECT_EQ(s[2].t, 0.015);
  EXPECT_EQ(s[3].t, 0.018);
  for (const auto& x : s) {
    const ImuSample e = linearSample(x.t);
    EXPECT_LT((x.acc - e.acc).norm(), 1e-12) << x.t;
    EXPECT_LT((x.gyr - e.gyr).norm(), 1e-12) << x.t;
  }
}

TEST(ImuBuffer, SamplesFallingOnTheEndsAreNotDuplicated) {
  const ImuBuffer b = bufferAt({0.0, 0.005, 0.010, 0.015});
  const auto s = b.between(0.005, 0.015);
  ASSERT_EQ(s.size(), 3u);
  EXPECT_EQ(s[0].t, 0.005);
  EXPECT_EQ(s[1].t, 0.010);
  EXPECT_EQ(s[2].t, 0.015);
  // An interval inside one sample gap gives just its two interpolated ends.
  const auto inner = b.between(0.011, 0.012);
  ASSERT_EQ(inner.size(), 2u);
  EXPECT_EQ(inner[0].t, 0.011);
  EXPECT_EQ(inner[1].t, 0.012);
  // Consecutive intervals share their boundary sample, so they chain without gaps.
  const auto a = b.between(0.0, 0.007);
  const auto c = b.between(0.007, 0.015);
  EXPECT_EQ(a.back().t, c.front().t);
  EXPECT_EQ(a.back().acc, c.front().acc);
}

TEST(ImuBuffer, CoversNeedsSamplesOnBothSides) {
  ImuBuffer b;
  EXPECT_FALSE(b.covers(0.0, 0.0));
  EXPECT_THROW(b.oldestTime(), std::logic_error);
  b = bufferAt({1.0, 1.005, 1.010});
  EXPECT_TRUE(b.covers(1.0, 1.010));
  EXPECT_TRUE(b.covers(1.002, 1.003));
  EXPECT_FALSE(b.covers(0.999, 1.005));
  EXPECT_FALSE(b.covers(1.005, 1.011));
  EXPECT_FALSE(b.covers(1.006, 1.004));
  EXPECT_EQ(b.oldestTime(), 1.0);
  EXPECT_EQ(b.newestTime(), 1.010);
}

TEST(ImuBuffer, BetweenOutsideTheBufferNamesBothSpans) {
  const ImuBuffer b = bufferAt({1.0, 1.005, 1.010});
  try {
    b.between(1.002, 1.02);
    FAIL() << "expected std::out_of_range";
  } catch (const std::out_of_range& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("[1.002000000, 1.020000000]"), std::string::npos) << msg;
    EXPECT_NE(msg.find("[1.000000000, 1.010000000]"), std::string::npos) << msg;
  }
  EXPECT_THROW(b.between(1.005, 1.005), std::invalid_argument);
  EXPECT_THROW(b.between(1.006, 1.004), std::invalid_argument);
  EXPECT_THROW(b.interpolate(1.011), std::out_of_range);
}

TEST(ImuBuffer, PushRejectsOutOfOrderAndNonFiniteSamples) {
  ImuBuffer b = bufferAt({1.0, 1.005});
  try {
    b.push(linearSample(1.005));
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("not after"), std::string::npos) << e.what();
  }
  EXPECT_THROW(b.push(linearSample(1.001)), std::invalid_argument);
  ImuSample bad = linearSample(1.01);
  bad.gyr.y() = NAN;
  EXPECT_THROW(b.push(bad), std::invalid_argument);
  EXPECT_EQ(b.size(), 2u);
}

TEST(ImuBuffer, PopOlderThanKeepsTheSampleNeededToInterpolateAtT) {
  ImuBuffer b = bufferAt({0.0, 0.005, 0.010, 0.015, 0.020});
  EXPECT_EQ(b.popOlderThan(-1.0), 0u);
  EXPECT_EQ(b.popOlderThan(0.012), 2u);  // 0.0 and 0.005 dropped, 0.010 kept for t = 0.012
  EXPECT_EQ(b.oldestTime(), 0.010);
  EXPECT_TRUE(b.covers(0.012, 0.020));
  EXPECT_EQ(b.popOlderThan(0.015), 1u);  // a sample exactly at t is itself the one kept
  EXPECT_EQ(b.oldestTime(), 0.015);
  EXPECT_EQ(b.popOlderThan(1.0), 1u);  // only the newest remains
  EXPECT_EQ(b.size(), 1u);
  EXPECT_EQ(b.newestTime(), 0.020);
}
