// The Shi-Tomasi corner response (CornerResponse), its local maxima (CornerCandidates) and the
// texture check that stops at the first rows with a corner (CornerResponse::reaches), against
// direct computations.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>
#include <vector>

#include "rgbdi/frontend/corner_detector.h"
#include "synthetic_scene.h"

using namespace rgbdi::frontend;
using namespace rgbdi::test;

namespace {

/// The CV_16SC2 Scharr derivatives cv::buildOpticalFlowPyramid stores for its base image.
cv::Mat pyramidDerivatives(const cv::Mat& grey) {
  std::vector<cv::Mat> pyramid;
  cv::buildOpticalFlowPyramid(grey, pyramid, cv::Size(15, 15), 1, true);
  return pyramid[1].clone();
}

}  // namespace

TEST(CornerResponse, IsTheSmallerStructureTensorEigenvalue) {
  const cv::Mat grey = toGrey8(randomRectangleTexture(160, 120, 12));
  CornerResponse computer;
  cv::Mat response;
  const float strongest = computer.compute(pyramidDerivatives(grey), 3, response);
  ASSERT_EQ(response.type(), CV_32FC1);
  ASSERT_EQ(response.size(), grey.size());
  cv::Mat dx, dy;
  cv::Scharr(grey, dx, CV_64F, 1, 0);
  cv::Scharr(grey, dy, CV_64F, 0, 1);
  double expected_strongest = 0.0;
  for (int v = 0; v < grey.rows; ++v)
    for (int u = 0; u < grey.cols; ++u) {
      const float r = response.at<float>(v, u);
      if (v < 1 || u < 1 || v + 1 >= grey.rows || u + 1 >= grey.cols) {
        EXPECT_EQ(r, 0.0f) << "border pixel " << u << "," << v;
        continue;
      }
      double a = 0, b = 0, c = 0;
      for (int j = -1; j <= 1; ++j)
        for (int i = -1; i <= 1; ++i) {
          const double x = dx.at<double>(v + j, u + i), y = dy.at<double>(v + j, u + i);
          a += x * x;
          b += x * y;
          c += y * y;
        }
      const double expected = 0.5 * (a + c) - std::sqrt(0.25 * (a - c) * (a - c) + b * b);
      EXPECT_NEAR(r, expected, 1e-5 * (a + c) + 1e-3) << u << "," << v;
      expected_strongest = std::max(expected_strongest, double(r));
    }
  EXPECT_EQ(strongest, static_cast<float>(expected_strongest));
  EXPECT_GT(strongest, 0.0f);
}

TEST(CornerResponse, AReusedResponseImageIsOverwrittenBorderIncluded) {
  // The response image is reused from frame to frame: only its border is zeroed explicitly,
  // every other pixel must be written. Odd and even blocks (even ones have one border row and
  // column fewer at the top and left).
  const cv::Mat grey = toGrey8(randomRectangleTexture(160, 120, 13));
  const cv::Mat derivatives = pyramidDerivatives(grey);
  for (int block : {3, 4, 5}) {
    CornerResponse computer;
    cv::Mat fresh, reused(grey.size(), CV_32FC1, cv::Scalar(7.0f));
    computer.compute(derivatives, block, fresh);
    computer.compute(derivatives, block, reused);
    EXPECT_EQ(cv::countNonZero(reused != fresh), 0) << "block " << block;
    // Pixels with a complete window: rows block-1-half .. h-1-half, columns half .. w-1-half.
    const int half = block / 2;
    for (int v = 0; v < grey.rows; ++v)
      for (int u = 0; u < grey.cols; ++u) {
        const bool inside = v >= block - 1 - half && v <= grey.rows - 1 - half && u >= half &&
                            u <= grey.cols - 1 - half;
        if (!inside)
          ASSERT_EQ(reused.at<float>(v, u), 0.0f)
              << "block " << block << " border pixel " << u << "," << v;
      }
  }
}

TEST(CornerResponse, ReachesAFloorExactlyWhenTheStrongestResponseDoes) {
  // Texture everywhere, only in the last rows (the early stop cannot decide in the first rows),
  // and none: reaches(floor) == (compute() >= floor) for floors around the strongest response,
  // exactly at it included.
  cv::Mat textured = toGrey8(randomRectangleTexture(320, 240, 31));
  cv::Mat bottom = textured.clone();
  bottom.rowRange(0, 200).setTo(100);
  const cv::Mat flat(240, 320, CV_8UC1, cv::Scalar(100));
  int decided_true = 0;
  for (const cv::Mat& grey : {textured, bottom, flat})
    for (int block : {3, 5}) {
      const cv::Mat derivatives = pyramidDerivatives(grey);
      CornerResponse computer;
      cv::Mat response;
      const float strongest = computer.compute(derivatives, block, response);
      const float inf = std::numeric_limits<float>::infinity();
      for (const float floor : {-1.0f, 0.0f, 0.5f * strongest, strongest,
                                std::nextafter(strongest, inf), 2.0f * strongest + 1.0f}) {
        const bool reached = computer.reaches(derivatives, block, floor);
        EXPECT_EQ(reached, strongest >= floor)
            << "block " << block << ", floor " << floor << ", strongest " << strongest;
        decided_true += reached;
      }
    }
  EXPECT_GT(decided_true, 10);
}

TEST(CornerCandidates, AreEveryLocalMaximumAboveTheFloorInScanOrderThenStrongestFirst) {
  const cv::Mat grey = toGrey8(randomRectangleTexture(320, 240, 13));
  CornerResponse computer;
  cv::Mat r;
  computer.compute(pyramidDerivatives(grey), 3, r);
  const float floor = static_cast<float>(CornerDetector::responseFloor(3, 2.0));
  EXPECT_EQ(floor, static_cast<float>(32.0 * 32.0 * 9 * 2.0 * 2.0));
  cv::Mat mask(r.size(), CV_8UC1, cv::Scalar(255));
  mask(cv::Rect(0, 0, r.cols / 2, r.rows)).setTo(0);  // the left half is taken
  for (const bool masked : {false, true}) {
    std::vector<CornerCandidate> expected;
    for (int v = 1; v + 1 < r.rows; ++v)
      for (int u = 1; u + 1 < r.cols; ++u) {
        const float x = r.at<float>(v, u);
        bool local_max = x >= floor && (!masked || mask.at<std::uint8_t>(v, u));
        for (int j = -1; j <= 1 && local_max; ++j)
          for (int i = -1; i <= 1; ++i)
            if (x < r.at<float>(v + j, u + i)) local_max = false;
        if (local_max) expected.push_back({x, u, v});
      }
    ASSERT_GT(expected.size(), 30u);
    CornerCandidates collector;
    std::vector<CornerCandidate> got;
    collector.collect(r, floor, masked ? &mask : nullptr, got);
    auto same = [&](const char* what) {
      ASSERT_EQ(got.size(), expected.size()) << what;
      for (std::size_t i = 0; i < expected.size(); ++i) {
        EXPECT_EQ(got[i].response, expected[i].response) << what << " " << i;
        EXPECT_EQ(got[i].u, expected[i].u) << what << " " << i;
        EXPECT_EQ(got[i].v, expected[i].v) << what << " " << i;
      }
    };
    same("scan order");
    // Strongest first; equal responses stay in scan order (row, then column).
    std::stable_sort(
        expected.begin(), expected.end(),
        [](const CornerCandidate& a, const CornerCandidate& b) { return a.response > b.response; });
    std::reverse(got.begin(), got.end());  // any input order gives the same sequence
    std::sort(got.begin(), got.end(), CornerCandidates::strongerFirst);
    same("strongest first");
  }
}

TEST(CornerCandidates, TiesAreOrderedByRowThenColumn) {
  std::vector<CornerCandidate> c = {{5.0f, 7, 2}, {9.0f, 1, 1}, {5.0f, 3, 2}, {5.0f, 9, 0}};
  std::sort(c.begin(), c.end(), CornerCandidates::strongerFirst);
  const int expected_u[] = {1, 9, 3, 7}, expected_v[] = {1, 0, 2, 2};
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(c[static_cast<std::size_t>(i)].u, expected_u[i]) << i;
    EXPECT_EQ(c[static_cast<std::size_t>(i)].v, expected_v[i]) << i;
  }
}
