// PoseLatencyMeter: stamp -> pose and delivery -> pose latencies with exact known answers,
// images that never get a pose, the bound on remembered images.
#include <gtest/gtest.h>

#include "rgbdi/live_run/pose_latency.h"

using rgbdi::system::PoseLatencyMeter;

namespace {
// 1 ms bins: percentiles are bin edges (exact to one bin), maxima are exact.
constexpr double kBin = 1e-3;
}  // namespace

TEST(PoseLatencyMeter, MeasuresStampToPoseAndDeliveryToPoseForEachImage) {
  PoseLatencyMeter m(kBin, 10.0, 100);
  // Image at t = 100.000 delivered 40 ms later, posed 100 ms after its stamp; and so on.
  m.delivered(100.000, 100.040);
  m.delivered(100.100, 100.150);
  m.posed(100.000, 100.100);
  m.posed(100.100, 100.300);
  const auto s = m.summary();
  ASSERT_EQ(s.stamp_to_pose.count, 2u);
  EXPECT_NEAR(s.stamp_to_pose.max_s, 0.200, 1e-9);
  EXPECT_NEAR(s.stamp_to_pose.p50_s, 0.100, kBin);  // a bin edge: exact to one bin
  ASSERT_EQ(s.delivery_to_pose.count, 2u);
  EXPECT_NEAR(s.delivery_to_pose.max_s, 0.150, 1e-9);  // 100.300 - 100.150
  EXPECT_NEAR(s.delivery_to_pose.p50_s, 0.060, kBin);  // 100.100 - 100.040
}

TEST(PoseLatencyMeter, ImagesWithoutAPoseAreSkippedNotMatchedToALaterPose) {
  PoseLatencyMeter m(kBin, 10.0, 100);
  m.delivered(1.0, 1.010);  // never posed (initialising)
  m.delivered(2.0, 2.010);  // never posed
  m.delivered(3.0, 3.020);
  m.posed(3.0, 3.050);
  const auto s = m.summary();
  EXPECT_EQ(s.stamp_to_pose.count, 1u);
  ASSERT_EQ(s.delivery_to_pose.count, 1u);
  EXPECT_NEAR(s.delivery_to_pose.max_s, 0.030, 1e-9);  // matched to its own delivery only
  EXPECT_NEAR(s.stamp_to_pose.max_s, 0.050, 1e-9);
}

TEST(PoseLatencyMeter, APoseWhoseDeliveryWasForgottenCountsOnlyFromTheStamp) {
  PoseLatencyMeter m(kBin, 10.0, 2);  // remembers two images at most
  m.delivered(1.0, 1.001);
  m.delivered(2.0, 2.001);
  m.delivered(3.0, 3.001);  // 1.0 is forgotten
  m.posed(1.0, 1.500);
  m.posed(2.0, 2.004);
  const auto s = m.summary();
  EXPECT_EQ(s.stamp_to_pose.count, 2u);
  ASSERT_EQ(s.delivery_to_pose.count, 1u);
  EXPECT_NEAR(s.delivery_to_pose.max_s, 0.003, 1e-9);
  EXPECT_NEAR(s.stamp_to_pose.max_s, 0.500, 1e-9);
}

TEST(PoseLatencyMeter, NothingMeasuredGivesZeroCounts) {
  PoseLatencyMeter m(kBin, 10.0, 10);
  m.delivered(1.0, 1.1);
  const auto s = m.summary();
  EXPECT_EQ(s.stamp_to_pose.count, 0u);
  EXPECT_EQ(s.delivery_to_pose.count, 0u);
}
