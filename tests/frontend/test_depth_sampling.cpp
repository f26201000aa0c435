// sampleDepth: exact value on smooth depth, rejection of holes, edges and out-of-range depth.
#include <gtest/gtest.h>

#include <opencv2/core.hpp>

#include "rgbdi/frontend/depth_sampling.h"

using rgbdi::frontend::FrontendOptions;
using rgbdi::frontend::sampleDepth;

namespace {

/// z(u, v) = a + b u + c v: bilinear interpolation reproduces an affine field exactly.
cv::Mat affineDepth(double a, double b, double c, int w = 64, int h = 48) {
  cv::Mat d(h, w, CV_32FC1);
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) d.at<float>(v, u) = static_cast<float>(a + b * u + c * v);
  return d;
}

}  // namespace

TEST(SampleDepth, PlanarDepthGivesTheExactValueAtSubPixelPositions) {
  const FrontendOptions o;
  const cv::Mat d = affineDepth(1.5, 0.002, -0.001);
  for (const Eigen::Vector2d& uv : {Eigen::Vector2d(20.0, 20.0), Eigen::Vector2d(31.25, 17.6),
                                    Eigen::Vector2d(10.5, 40.49), Eigen::Vector2d(50.9, 3.01)}) {
    const double expected = 1.5 + 0.002 * uv.x() - 0.001 * uv.y();
    EXPECT_NEAR(sampleDepth(d, uv, o), expected, 2e-6) << uv.transpose();
  }
}

TEST(SampleDepth, ConstantDepthIsReturnedUnchanged) {
  const FrontendOptions o;
  const cv::Mat d(48, 64, CV_32FC1, cv::Scalar(2.345f));
  EXPECT_FLOAT_EQ(static_cast<float>(sampleDepth(d, {30.3, 22.7}, o)), 2.345f);
}

TEST(SampleDepth, NearestPixelWhenTheNeighbourhoodIsZero) {
  FrontendOptions o;
  o.depth_neighbourhood_px = 0;
  const cv::Mat d = affineDepth(1.0, 0.01, 0.0);
  EXPECT_NEAR(sampleDepth(d, {10.4, 5.0}, o), 1.10, 1e-6);  // pixel 10
  EXPECT_NEAR(sampleDepth(d, {10.6, 5.0}, o), 1.11, 1e-6);  // pixel 11
}

TEST(SampleDepth, AHoleAnywhereInTheWindowRejects) {
  const FrontendOptions o;  // window half-size 2
  cv::Mat d(48, 64, CV_32FC1, cv::Scalar(2.0f));
  d.at<float>(22, 32) = 0.0f;  // two pixels right and down of (30, 20)
  EXPECT_EQ(sampleDepth(d, {30.0, 20.0}, o), 0.0);
  EXPECT_EQ(sampleDepth(d, {30.4, 20.4}, o), 0.0);
  // Three pixels away the hole is outside the window.
  EXPECT_DOUBLE_EQ(sampleDepth(d, {29.0, 19.0}, o), 2.0);
  // NaN counts as a hole too.
  d.at<float>(22, 32) = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(sampleDepth(d, {30.0, 20.0}, o), 0.0);
}

TEST(SampleDepth, AStepEdgeInTheWindowRejects) {
  const FrontendOptions o;  // spread 3 %
  cv::Mat d(48, 64, CV_32FC1, cv::Scalar(1.0f));
  d.colRange(34, 64).setTo(1.5f);                          // step edge between u = 33 and u = 34
  EXPECT_EQ(sampleDepth(d, {32.0, 20.0}, o), 0.0);         // window u 30..34 spans the edge
  EXPECT_DOUBLE_EQ(sampleDepth(d, {31.0, 20.0}, o), 1.0);  // window u 29..33 does not
  EXPECT_DOUBLE_EQ(sampleDepth(d, {36.0, 20.0}, o), 1.5);
  // A small step (2 % < 3 %) is surface relief, not an edge.
  d.colRange(34, 64).setTo(1.02f);
  EXPECT_NEAR(sampleDepth(d, {32.0, 20.0}, o), 1.0, 1e-6);
}

TEST(SampleDepth, OutOfRangeDepthRejects) {
  FrontendOptions o;
  o.depth_min_m = 0.5;
  o.depth_max_m = 3.0;
  EXPECT_EQ(sampleDepth(cv::Mat(48, 64, CV_32FC1, cv::Scalar(0.3f)), {20, 20}, o), 0.0);
  EXPECT_EQ(sampleDepth(cv::Mat(48, 64, CV_32FC1, cv::Scalar(3.2f)), {20, 20}, o), 0.0);
  EXPECT_NEAR(sampleDepth(cv::Mat(48, 64, CV_32FC1, cv::Scalar(2.9f)), {20, 20}, o), 2.9, 1e-6);
}

TEST(SampleDepth, WindowLeavingTheImageRejects) {
  const FrontendOptions o;
  const cv::Mat d(48, 64, CV_32FC1, cv::Scalar(2.0f));
  EXPECT_EQ(sampleDepth(d, {1.0, 20.0}, o), 0.0);
  EXPECT_EQ(sampleDepth(d, {62.0, 20.0}, o), 0.0);
  EXPECT_EQ(sampleDepth(d, {30.0, 46.2}, o), 0.0);
  EXPECT_EQ(sampleDepth(d, {-5.0, 20.0}, o), 0.0);
  EXPECT_EQ(sampleDepth(d, {1e30, 20.0}, o), 0.0);
  EXPECT_EQ(sampleDepth(d, {std::nan(""), 20.0}, o), 0.0);
  EXPECT_DOUBLE_EQ(sampleDepth(d, {2.0, 2.0}, o), 2.0);
}

TEST(SampleDepth, WrongImageTypeThrows) {
  const FrontendOptions o;
  EXPECT_THROW(sampleDepth(cv::Mat(48, 64, CV_16UC1, cv::Scalar(2000)), {20, 20}, o),
               std::invalid_argument);
}
