// Re-ordering rules of TimeOrderingBuffer: windows, duplicates, cross-kind lateness, tie order.
#include <gtest/gtest.h>

#include <vector>

#include "rgbdi/io/time_ordering_buffer.h"

namespace rgbdi::io {
namespace {

using V = TimeOrderingBuffer::Verdict;

Measurement imu(double t) {
  ImuSample s;
  s.t = t;
  return s;
}
Measurement frame(double t) {
  RgbdFrame f;
  f.t = t;
  return f;
}

/// Everything the buffer releases now, as (t, is_imu) pairs.
std::vector<std::pair<double, bool>> drain(TimeOrderingBuffer& b) {
  std::vector<std::pair<double, bool>> out;
  TimeOrderingBuffer::Item it;
  while (b.pop(it)) out.emplace_back(measurementTime(it.m), isImu(it.m));
  return out;
}

TEST(TimeOrderingBuffer, ReordersWithinWindowAndDropsOlder) {
  TimeOrderingBuffer b(0.05, 0.1);
  EXPECT_EQ(b.push(imu(1.00), 0), V::Accepted);
  EXPECT_EQ(b.push(imu(1.02), 1), V::Accepted);
  EXPECT_EQ(b.push(imu(1.01), 2), V::Reordered);  // 0.01 s late: within 0.05
  EXPECT_EQ(b.push(imu(0.96), 3), V::TooLate);    // 0.06 s older than the newest IMU
  EXPECT_EQ(b.push(imu(1.02), 4), V::Duplicate);
  EXPECT_TRUE(drain(b).empty());  // nothing is 0.1 s old yet
  EXPECT_EQ(b.size(), 3u);
  b.finish();
  const auto out = drain(b);
  ASSERT_EQ(out.size(), 3u);
  EXPECT_EQ(out[0].first, 1.00);
  EXPECT_EQ(out[1].first, 1.01);
  EXPECT_EQ(out[2].first, 1.02);
}

TEST(TimeOrderingBuffer, ReleasesOnlyDataOlderThanTheLargestWindow) {
  // Binary fractions keep the arithmetic exact.
  TimeOrderingBuffer b(0.0625, 0.125);
  for (int i = 0; i <= 20; ++i) b.push(imu(1.0 + i / 64.0), static_cast<size_t>(i));  // .. 1.3125
  const auto out = drain(b);
  // Released: t <= 1.3125 - 0.125 = 1.1875 = 1 + 12/64 -> 13 samples.
  ASSERT_EQ(out.size(), 13u);
  EXPECT_EQ(out.back().first, 1.1875);
  EXPECT_EQ(b.size(), 8u);
}

TEST(TimeOrderingBuffer, LateFrameIsMergedInTimeOrderAcrossKinds) {
  TimeOrderingBuffer b(0.05, 0.1);
  const auto t = [](int i) { return 2.0 + 0.01 * i; };
  for (int i = 0; i < 10; ++i) b.push(imu(t(i)), 0);   // 2.00 .. 2.09
  EXPECT_EQ(b.push(frame(t(3)), 1), V::Accepted);      // 0.06 s behind the IMU: fine
  for (int i = 10; i < 30; ++i) b.push(imu(t(i)), 2);  // .. 2.29
  auto out = drain(b);                                 // releases t <= 2.19
  ASSERT_EQ(out.size(), 21u);
  // A frame 0.21 s older than the newest data: behind what was already released.
  EXPECT_EQ(b.push(frame(t(8)), 3), V::BehindOutput);
  b.finish();
  const auto rest = drain(b);
  out.insert(out.end(), rest.begin(), rest.end());
  ASSERT_EQ(out.size(), 31u);
  for (size_t i = 1; i < out.size(); ++i) EXPECT_LE(out[i - 1].first, out[i].first);
  EXPECT_TRUE(out[3].second);  // equal stamps: the IMU sample first ...
  EXPECT_EQ(out[3].first, t(3));
  EXPECT_FALSE(out[4].second);  // ... then the frame
  EXPECT_EQ(out[4].first, t(3));
}

TEST(TimeOrderingBuffer, InvalidStampsAreRejected) {
  TimeOrderingBuffer b(0.05, 0.1);
  EXPECT_EQ(b.push(imu(0.0), 0), V::InvalidStamp);
  EXPECT_EQ(b.push(frame(-1.0), 0), V::InvalidStamp);
  EXPECT_EQ(b.push(imu(std::numeric_limits<double>::quiet_NaN()), 0), V::InvalidStamp);
  EXPECT_EQ(b.size(), 0u);
}

TEST(TimeOrderingBuffer, DuplicateOfAReleasedStampIsDetected) {
  TimeOrderingBuffer b(0.0, 0.0);  // zero windows: release immediately, never reorder
  EXPECT_EQ(b.push(frame(5.0), 0), V::Accepted);
  EXPECT_EQ(drain(b).size(), 1u);
  EXPECT_EQ(b.push(frame(5.0), 1), V::Duplicate);
  EXPECT_EQ(b.push(imu(5.0), 2), V::Accepted);  // other kind, same stamp: fine
  EXPECT_EQ(b.push(frame(4.9), 3), V::TooLate);
}

}  // namespace
}  // namespace rgbdi::io
