// Occlusion-boundary test of a feature window: inverse-depth plane fit (exact on any plane,
// residual equal to an independent least-squares solution), decisions on planes, steps, noise
// and holes.
#include <gtest/gtest.h>

#include <Eigen/QR>
#include <cmath>
#include <opencv2/core.hpp>
#include <random>

#include "rgbdi/frontend/occlusion_test.h"

using rgbdi::frontend::fitWindowPlane;
using rgbdi::frontend::FrontendOptions;
using rgbdi::frontend::straddlesOcclusion;

namespace {

/// Depth of the plane with inverse depth 1/z = a + b u + c v (any plane seen by a pinhole camera).
cv::Mat planeDepth(double a, double b, double c, int w = 80, int h = 60) {
  cv::Mat d(h, w, CV_32FC1);
  for (int v = 0; v < h; ++v)
    for (int u = 0; u < w; ++u) d.at<float>(v, u) = static_cast<float>(1.0 / (a + b * u + c * v));
  return d;
}

/// Foreground at z_near for u < edge_u, background at z_far from there on.
cv::Mat stepDepth(double z_near, double z_far, int edge_u, int w = 80, int h = 60) {
  cv::Mat d(h, w, CV_32FC1, cv::Scalar(static_cast<float>(z_far)));
  d(cv::Rect(0, 0, edge_u, h)).setTo(static_cast<float>(z_near));
  return d;
}

/// The RMS residual by an independent route: the full design matrix solved by QR.
double referenceRms(const cv::Mat& depth, int uc, int vc, int half, int step) {
  std::vector<Eigen::Vector3d> rows;
  std::vector<double> w;
  for (int j = -half / step; j <= half / step; ++j)
    for (int i = -half / step; i <= half / step; ++i) {
      const int u = uc + i * step, v = vc + j * step;
      if (u < 0 || v < 0 || u >= depth.cols || v >= depth.rows) continue;
      const float z = depth.at<float>(v, u);
      if (!(z > 0.0f)) continue;
      rows.emplace_back(i, j, 1.0);
      w.push_back(1.0 / z);
    }
  Eigen::MatrixXd A(static_cast<Eigen::Index>(rows.size()), 3);
  Eigen::VectorXd b(static_cast<Eigen::Index>(w.size()));
  for (size_t k = 0; k < rows.size(); ++k) {
    A.row(static_cast<Eigen::Index>(k)) = rows[k].transpose();
    b(static_cast<Eigen::Index>(k)) = w[k];
  }
  const Eigen::VectorXd x = A.colPivHouseholderQr().solve(b);
  return std::sqrt((A * x - b).squaredNorm() / static_cast<double>(w.size()));
}

}  // namespace

TEST(OcclusionTest, APlaneFitsExactlyHoweverSlanted) {
  // A floor seen at a grazing angle: depth changes by a factor of two across the window, which a
  // spread test would call an edge; in inverse depth it is one plane.
  const cv::Mat d = planeDepth(0.2, 0.004, 0.01);
  const auto fit = fitWindowPlane(d, {40.3, 29.6}, 10, 2);
  EXPECT_EQ(fit.samples, 121);
  EXPECT_EQ(fit.grid_samples, 121);
  EXPECT_LT(fit.rms_residual_inv_m, 1e-6);  // float rounding of the stored depths only
  EXPECT_FALSE(straddlesOcclusion(d, {40.3, 29.6}, FrontendOptions()));
}

TEST(OcclusionTest, StepResidualEqualsAnIndependentLeastSquaresSolution) {
  const cv::Mat d = stepDepth(1.0, 2.0, 43);
  for (int uc : {35, 40, 43, 47, 52}) {
    const auto fit = fitWindowPlane(d, {double(uc), 30.0}, 10, 2);
    EXPECT_NEAR(fit.rms_residual_inv_m, referenceRms(d, uc, 30, 10, 2), 1e-9) << "centre u " << uc;
  }
  // Fully on one side: no residual; the edge inside the window: a residual far above the noise.
  EXPECT_LT(fitWindowPlane(d, {20.0, 30.0}, 10, 2).rms_residual_inv_m, 1e-9);
  EXPECT_GT(fitWindowPlane(d, {45.0, 30.0}, 10, 2).rms_residual_inv_m, 0.1);
}

TEST(OcclusionTest, DecidesByTheWindowAndTheNoiseModel) {
  const FrontendOptions o;  // window 10 px, 5 sigmas of 0.004 / m: 0.02 / m
  const cv::Mat d = stepDepth(1.0, 2.0, 43);
  EXPECT_FALSE(straddlesOcclusion(d, {32.0, 30.0}, o));  // edge 11 px away: outside the window
  EXPECT_TRUE(straddlesOcclusion(d, {34.0, 30.0}, o));   // edge 9 px away: in the window
  EXPECT_TRUE(straddlesOcclusion(d, {52.0, 30.0}, o));   // background side
  EXPECT_FALSE(straddlesOcclusion(d, {54.0, 30.0}, o));
  FrontendOptions off = o;
  off.occlusion_window_px = 0;
  EXPECT_FALSE(straddlesOcclusion(d, {43.0, 30.0}, off));
  // A small step (3.0 m behind 2.9 m): inverse depths 0.345 / 0.333, residual ~0.006 / m, below
  // five sigmas: at that range the sensor cannot tell it from noise.
  EXPECT_FALSE(straddlesOcclusion(stepDepth(2.9, 3.0, 43), {43.0, 30.0}, o));
  // The same step nearer (0.9 / 1.0 m): 0.11 / m apart, clearly two surfaces.
  EXPECT_TRUE(straddlesOcclusion(stepDepth(0.9, 1.0, 43), {43.0, 30.0}, o));
}

TEST(OcclusionTest, SensorNoiseAloneIsNoBoundary) {
  // D435-like noise sigma_z = 0.004 z^2 on flat walls from 0.5 to 4 m, and mm quantisation.
  const FrontendOptions o;
  std::mt19937 rng(5);
  for (double z : {0.5, 1.0, 2.0, 3.0, 4.0}) {
    std::normal_distribution<double> noise(0.0, 0.004 * z * z);
    cv::Mat d(60, 80, CV_32FC1);
    for (int v = 0; v < d.rows; ++v)
      for (int u = 0; u < d.cols; ++u)
        d.at<float>(v, u) = static_cast<float>(std::round((z + noise(rng)) * 1000.0) / 1000.0);
    int flagged = 0;
    for (int v = 12; v < 48; v += 3)
      for (int u = 12; u < 68; u += 3)
        flagged += straddlesOcclusion(d, {double(u), double(v)}, o) ? 1 : 0;
    EXPECT_EQ(flagged, 0) << "at " << z << " m";
  }
}

TEST(OcclusionTest, TooFewDepthSamplesAreNotJudgedAndTheImageBorderIsHandled) {
  const FrontendOptions o;
  cv::Mat d = stepDepth(1.0, 2.0, 43);
  // Holes over 70 % of the window: the remaining samples are not enough to judge by.
  d(cv::Rect(30, 0, 14, 60)).setTo(0.0f);
  d(cv::Rect(46, 0, 10, 60)).setTo(0.0f);
  EXPECT_FALSE(straddlesOcclusion(d, {45.0, 30.0}, o));
  // At the image corner only the part of the window inside the image counts.
  const cv::Mat flat(60, 80, CV_32FC1, cv::Scalar(1.5f));
  const auto fit = fitWindowPlane(flat, {0.0, 0.0}, 10, 2);
  EXPECT_EQ(fit.grid_samples, 36);
  EXPECT_EQ(fit.samples, 36);
  EXPECT_FALSE(straddlesOcclusion(flat, {0.0, 0.0}, o));
  EXPECT_FALSE(straddlesOcclusion(flat, {-1e9, 5.0}, o));  // no sample at all
  EXPECT_THROW(fitWindowPlane(cv::Mat(10, 10, CV_16UC1), {5.0, 5.0}, 3, 1), std::invalid_argument);
}
