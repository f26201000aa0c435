// Images prepared ahead of tracking (ImagePreparer): the corner response equals the one from the
// KLT pyramid's derivatives, the candidates are exactly the response's local maxima, and a
// tracker given prepared images produces the same features, bit for bit, as one preparing them
// itself (the SLAM system prepares on the feeding thread only when threaded).
#include <gtest/gtest.h>

#include <algorithm>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

#include "rgbdi/frontend/feature_tracker.h"
#include "rgbdi/frontend/prepared_image.h"
#include "synthetic_scene.h"

using rgbdi::PinholeCamera;
using rgbdi::RgbdFrame;
using namespace rgbdi::frontend;
using namespace rgbdi::test;

namespace {

constexpr double kDt = 1.0 / 30.0;

/// Frames of a texture drifting and zooming out, so tracks leave the image and new corners are
/// detected in most frames.
std::vector<RgbdFrame> driftingFrames(int n, const PinholeCamera& cam, bool grey_frames) {
  const cv::Mat texture = randomRectangleTexture(1000, 800, 5);
  std::vector<RgbdFrame> frames;
  for (int k = 0; k < n; ++k) {
    const double s = 1.0 - 0.02 * k;
    cv::Mat H = (cv::Mat_<double>(2, 3) << s, 0.0, -180.0 + 3.3 * k, 0.0, s, -160.0 + 1.7 * k);
    cv::Mat warped;
    cv::warpAffine(texture, warped, H, cv::Size(640, 480), cv::INTER_LINEAR, cv::BORDER_REFLECT);
    RgbdFrame f = colourFrame(toGrey8(warped), k * kDt, static_cast<std::uint64_t>(k), cam);
    if (grey_frames) f.rgb = toGrey8(warped);
    frames.push_back(f);
  }
  return frames;
}

void expectSameFeatures(const FeatureFrame& a, const FeatureFrame& b, int k) {
  ASSERT_EQ(a.features.size(), b.features.size()) << "frame " << k;
  EXPECT_EQ(a.n_tracked, b.n_tracked) << "frame " << k;
  EXPECT_EQ(a.n_new, b.n_new) << "frame " << k;
  for (std::size_t i = 0; i < a.features.size(); ++i) {
    EXPECT_EQ(a.features[i].id, b.features[i].id) << "frame " << k;
    EXPECT_EQ(a.features[i].uv, b.features[i].uv) << "frame " << k;  // bit-identical
    EXPECT_EQ(a.features[i].track_length, b.features[i].track_length) << "frame " << k;
  }
}

}  // namespace

TEST(PreparedImage, ScharrDerivativesAreThoseOfTheKltPyramid) {
  // The preparer takes cv::Scharr's derivatives where the tracker takes the pyramid's: the
  // response is only the same if these are, value for value (borders included).
  const cv::Mat grey = toGrey8(randomRectangleTexture(640, 480, 11));
  std::vector<cv::Mat> pyramid;
  cv::buildOpticalFlowPyramid(grey, pyramid, cv::Size(21, 21), 3, true);
  cv::Mat planes[2];
  cv::split(pyramid[1], planes);
  cv::Mat dx, dy;
  cv::Scharr(grey, dx, CV_16S, 1, 0);
  cv::Scharr(grey, dy, CV_16S, 0, 1);
  EXPECT_EQ(cv::countNonZero(planes[0] != dx), 0);
  EXPECT_EQ(cv::countNonZero(planes[1] != dy), 0);
}

TEST(PreparedImage, ResponseIsTheSmallerStructureTensorEigenvalue) {
  const cv::Mat grey = toGrey8(randomRectangleTexture(160, 120, 12));
  FrontendOptions options;
  options.shi_tomasi_block_size = 3;
  ImagePreparer preparer(options);
  const PreparedImage p = preparer.prepare(colourFrame(grey, 0.0, 0, simpleCamera()));
  ASSERT_EQ(p.corner_response.type(), CV_32FC1);
  ASSERT_EQ(p.corner_response.size(), grey.size());
  cv::Mat dx, dy;
  cv::Scharr(grey, dx, CV_64F, 1, 0);
  cv::Scharr(grey, dy, CV_64F, 0, 1);
  double strongest = 0.0;
  for (int v = 0; v < grey.rows; ++v)
    for (int u = 0; u < grey.cols; ++u) {
      const float r = p.corner_response.at<float>(v, u);
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
      strongest = std::max(strongest, double(r));
    }
  EXPECT_EQ(p.strongest_response, static_cast<float>(strongest));
  EXPECT_EQ(p.t, 0.0);
  EXPECT_EQ(p.frame_index, 0u);
  EXPECT_GT(p.strongest_response, 0.0f);
}

TEST(PreparedImage, AReusedResponseImageIsOverwrittenBorderIncluded) {
  // Prepared images are reused from frame to frame: only the border of the response is zeroed
  // explicitly, every other pixel must be written. Odd and even blocks (even ones have one
  // border row and column fewer at the top and left).
  const cv::Mat grey = toGrey8(randomRectangleTexture(160, 120, 13));
  const RgbdFrame frame = colourFrame(grey, 0.0, 0, simpleCamera());
  for (int block : {3, 4, 5}) {
    FrontendOptions options;
    options.shi_tomasi_block_size = block;
    ImagePreparer preparer(options);
    const PreparedImage fresh = preparer.prepare(frame);
    PreparedImage reused;
    reused.corner_response = cv::Mat(grey.size(), CV_32FC1, cv::Scalar(7.0f));
    preparer.prepare(frame, reused);
    EXPECT_EQ(cv::countNonZero(reused.corner_response != fresh.corner_response), 0)
        << "block " << block;
    // Pixels with a complete window: rows block-1-half .. h-1-half, columns half .. w-1-half.
    const int half = block / 2;
    for (int v = 0; v < grey.rows; ++v)
      for (int u = 0; u < grey.cols; ++u) {
        const bool inside = v >= block - 1 - half && v <= grey.rows - 1 - half && u >= half &&
                            u <= grey.cols - 1 - half;
        if (!inside)
          ASSERT_EQ(reused.corner_response.at<float>(v, u), 0.0f)
              << "block " << block << " border pixel " << u << "," << v;
      }
  }
}

TEST(PreparedImage, CandidatesAreEveryLocalMaximumStrongestFirst) {
  const cv::Mat grey = toGrey8(randomRectangleTexture(320, 240, 13));
  FrontendOptions options;  // texture floor 2 grey levels per pixel
  ImagePreparer preparer(options);
  const PreparedImage p = preparer.prepare(colourFrame(grey, 0.0, 0, simpleCamera()));
  const cv::Mat& r = p.corner_response;
  const float floor = static_cast<float>(32.0 * 32.0 * 9 * options.min_gradient_grey_per_px *
                                         options.min_gradient_grey_per_px);
  EXPECT_EQ(p.candidate_min_response, floor);
  std::vector<CornerCandidate> expected;
  for (int v = 1; v + 1 < r.rows; ++v)
    for (int u = 1; u + 1 < r.cols; ++u) {
      const float x = r.at<float>(v, u);
      bool local_max = x >= floor;
      for (int j = -1; j <= 1 && local_max; ++j)
        for (int i = -1; i <= 1; ++i)
          if (x < r.at<float>(v + j, u + i)) local_max = false;
      if (local_max) expected.push_back({x, u, v});
    }
  ASSERT_GT(expected.size(), 50u);
  ASSERT_EQ(p.corner_candidates.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(p.corner_candidates[i].response, expected[i].response) << i;
    EXPECT_EQ(p.corner_candidates[i].u, expected[i].u) << i;
    EXPECT_EQ(p.corner_candidates[i].v, expected[i].v) << i;
  }
}

TEST(PreparedImage, TrackingPreparedImagesGivesTheSameFeatures) {
  const PinholeCamera cam = simpleCamera();
  for (const bool grey_frames : {false, true})
    for (const double clahe : {0.0, 3.0})
      for (const double min_gradient : {2.0, 0.0}) {
        SCOPED_TRACE(std::string(grey_frames ? "grey" : "colour") + " frames, CLAHE " +
                     std::to_string(clahe) + ", texture floor " + std::to_string(min_gradient));
        FrontendOptions options;
        options.clahe_clip_limit = clahe;
        options.min_gradient_grey_per_px = min_gradient;
        FeatureTracker itself(options, cam), given(options, cam);
        ImagePreparer preparer(options);
        int detected = 0;
        const std::vector<RgbdFrame> frames = driftingFrames(8, cam, grey_frames);
        for (std::size_t k = 0; k < frames.size(); ++k) {
          const PreparedImage prepared = preparer.prepare(frames[k]);
          const FeatureFrame a = itself.track(frames[k]);
          const FeatureFrame b = given.track(frames[k], std::nullopt, &prepared);
          expectSameFeatures(a, b, static_cast<int>(k));
          if (k > 0) detected += a.n_new;
        }
        EXPECT_GT(detected, 20);  // the detector ran on the prepared candidates
      }
}

TEST(PreparedImage, AnImagePreparedFromAnotherFrameOrWithOtherOptionsIsRefused) {
  const PinholeCamera cam = simpleCamera();
  const std::vector<RgbdFrame> frames = driftingFrames(2, cam, false);
  FrontendOptions options;
  FeatureTracker tracker(options, cam);
  ImagePreparer preparer(options);
  const PreparedImage first = preparer.prepare(frames[0]);
  try {
    tracker.track(frames[1], std::nullopt, &first);
    FAIL() << "an image of frame 0 was accepted for frame 1";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("synthetic frame 1"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("another frame"), std::string::npos) << e.what();
  }
  FrontendOptions other = options;
  other.shi_tomasi_block_size = 5;
  ImagePreparer other_preparer(other);
  const PreparedImage wrong_recipe = other_preparer.prepare(frames[0]);
  EXPECT_THROW(tracker.track(frames[0], std::nullopt, &wrong_recipe), std::invalid_argument);
  // The tracker is still usable with the right image.
  EXPECT_GT(tracker.track(frames[0], std::nullopt, &first).features.size(), 100u);
}

TEST(PreparedImage, FramesWithoutAColourImageAreLeftToTheTracker) {
  RgbdFrame depth_only;
  depth_only.index = 3;
  EXPECT_FALSE(ImagePreparer::accepts(depth_only));
  RgbdFrame wrong_type = depth_only;
  wrong_type.rgb = cv::Mat(480, 640, CV_16UC1, cv::Scalar(0));
  EXPECT_FALSE(ImagePreparer::accepts(wrong_type));
  ImagePreparer preparer{FrontendOptions()};
  EXPECT_THROW(preparer.prepare(wrong_type), std::invalid_argument);
}
