// FrameRateLimiter: which frames of a camera faster than [stream] image_rate_limit_hz are used.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "rgbdi/io/frame_rate_limiter.h"

namespace rgbdi::io {
namespace {

constexpr double kT0 = 1700000000.0;

/// Indices of the frames of a camera at `camera_hz` (stamps kT0 + k / camera_hz, k < n) the
/// limiter uses.
std::vector<int> used(FrameRateLimiter& limiter, double camera_hz, int n) {
  std::vector<int> out;
  for (int k = 0; k < n; ++k)
    if (limiter.admit(kT0 + k / camera_hz)) out.push_back(k);
  return out;
}

TEST(FrameRateLimiter, NoLimitUsesEveryFrame) {
  for (double rate : {0.0, -5.0}) {
    FrameRateLimiter l(rate);
    EXPECT_EQ(used(l, 30.0, 6), (std::vector<int>{0, 1, 2, 3, 4, 5}));
    EXPECT_TRUE(l.admit(kT0 + 0.2));  // the same stamp again: passed on (the checker drops it)
    EXPECT_EQ(l.skipped(), 0u);
  }
}

TEST(FrameRateLimiter, ThirtyHertzCameraUnderFifteenHertzLimitUsesEverySecondFrame) {
  FrameRateLimiter l(15.0);
  EXPECT_EQ(used(l, 30.0, 9), (std::vector<int>{0, 2, 4, 6, 8}));
  EXPECT_EQ(l.skipped(), 4u);
}

TEST(FrameRateLimiter, LimitsBetweenCameraRatesUseWholeCameraPeriods) {
  // 0.9 / 20 Hz = 45 ms: frame 1 (33 ms) is too close, frame 2 (67 ms) is not.
  FrameRateLimiter twenty(20.0);
  EXPECT_EQ(used(twenty, 30.0, 7), (std::vector<int>{0, 2, 4, 6}));
  // 0.9 / 10 Hz = 90 ms: every third frame of a 30 Hz camera (100 ms apart).
  FrameRateLimiter ten(10.0);
  EXPECT_EQ(used(ten, 30.0, 10), (std::vector<int>{0, 3, 6, 9}));
}

TEST(FrameRateLimiter, CameraAtTheLimitKeepsEveryFrameDespiteJitter) {
  FrameRateLimiter l(15.0);
  // 15 Hz stamps with up to +-3 ms jitter (the slack is 10 % of 66.7 ms = 6.7 ms).
  const double jitter[] = {0.0, 0.003, -0.003, 0.002, -0.001, 0.003, -0.003};
  for (int k = 0; k < 7; ++k) EXPECT_TRUE(l.admit(kT0 + k / 15.0 + jitter[k])) << k;
  EXPECT_EQ(l.skipped(), 0u);
  // ...but not a frame 59 ms after the last one used (below 0.9 / 15 Hz = 60 ms).
  EXPECT_FALSE(l.admit(kT0 + 6 / 15.0 - 0.003 + 0.059));
  EXPECT_EQ(l.skipped(), 1u);
}

TEST(FrameRateLimiter, ReorderedFramesAreJudgedBySpacingEitherWay) {
  FrameRateLimiter l(15.0);
  EXPECT_TRUE(l.admit(kT0 + 1.0));
  EXPECT_FALSE(l.admit(kT0 + 1.0 - 0.033));  // arrived late, 33 ms before the last one used
  EXPECT_TRUE(l.admit(kT0 + 1.0 - 0.1));     // 100 ms before it: far enough
  EXPECT_FALSE(l.admit(kT0 + 1.0 - 0.1 + 0.05));
  EXPECT_EQ(l.skipped(), 2u);
}

TEST(FrameRateLimiter, NonFiniteStampsArePassedOnAndDoNotMoveTheReference) {
  FrameRateLimiter l(15.0);
  EXPECT_TRUE(l.admit(kT0));
  EXPECT_TRUE(l.admit(std::numeric_limits<double>::quiet_NaN()));
  EXPECT_TRUE(l.admit(std::numeric_limits<double>::infinity()));
  EXPECT_FALSE(l.admit(kT0 + 0.033));  // still judged against kT0
  EXPECT_TRUE(l.admit(kT0 + 0.067));
  EXPECT_EQ(l.skipped(), 1u);
}

}  // namespace
}  // namespace rgbdi::io
