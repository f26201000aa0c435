// Images prepared ahead of tracking (ImagePreparer): a tracker given prepared images produces the
// same features, bit for bit, as one preparing them itself (the SLAM system prepares on the
// feeding thread only when threaded).
#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

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

TEST(PreparedImage, GreyImageIsTheTrackersOwn) {
  const PinholeCamera cam = simpleCamera();
  for (const double clahe : {0.0, 3.0}) {
    FrontendOptions options;
    options.clahe_clip_limit = clahe;
    ImagePreparer preparer(options), own(options);
    const RgbdFrame frame = driftingFrames(1, cam, false)[0];
    const PreparedImage p = preparer.prepare(frame);
    EXPECT_EQ(p.t, frame.t);
    EXPECT_EQ(p.frame_index, frame.index);
    ASSERT_EQ(p.grey.type(), CV_8UC1);
    EXPECT_EQ(cv::countNonZero(p.grey != own.grey(frame)), 0) << "CLAHE " << clahe;
    EXPECT_TRUE(p.matches(frame, PreparationRecipe::of(options)));
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
        EXPECT_GT(detected, 20);  // the detector ran
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
  other.clahe_clip_limit = 2.0;
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
