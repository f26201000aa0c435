// Rendered images: depth agrees with projected scene points, the tile-culled renderer equals
// per-pixel ray casting, textures are deterministic, corner-rich and alias-free at a distance.
#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <random>

#include "rgbdi/common/sensor_options.h"
#include "rgbdi/sim/renderer.h"
#include "rgbdi/sim/scene_presets.h"

namespace rgbdi::sim {
namespace {

PinholeCamera d435() { return CameraOptions().camera; }

PinholeCamera distorted() {
  PinholeCamera c = d435();
  c.dist = {0.12, -0.08, 0.001, -0.0015, 0.01};
  return c;
}

// Optical frame (x right, y down, z forward) of a camera at `eye` looking horizontally along
// yaw, tilted down by pitch [rad].
Eigen::Isometry3d lookFrom(const Eigen::Vector3d& eye, double yaw, double pitch = 0.0) {
  Eigen::Matrix3d R_body_cam;
  R_body_cam << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()))
                   .toRotationMatrix() *
               R_body_cam;
  T.translation() = eye;
  return T;
}

cv::Mat grey(const cv::Mat& rgb) {
  cv::Mat g;
  cv::cvtColor(rgb, g, cv::COLOR_RGB2GRAY);
  return g;
}

TEST(RenderImage, FrontoParallelWallDepthEqualsCameraZOfItsPoints) {
  Scene scene(4);
  scene.addRoom({-3, -4, 0}, {5, 4, 3});
  scene.build();
  const Renderer renderer(scene, d435());
  // Camera 4 m in front of the wall x = 5, looking straight at it.
  const Eigen::Isometry3d T = lookFrom({1, 0.3, 1.4}, 0.0);
  cv::Mat rgb, depth;
  renderer.render(T, rgb, depth);
  int checked = 0;
  for (double y = -1.2; y <= 1.2; y += 0.3)
    for (double z = 0.5; z <= 2.3; z += 0.3) {
      const Eigen::Vector3d p_cam = T.inverse() * Eigen::Vector3d(5, y, z);
      Eigen::Vector2d uv;
      ASSERT_TRUE(d435().project(p_cam, uv));
      const int u = static_cast<int>(std::lround(uv.x())),
                v = static_cast<int>(std::lround(uv.y()));
      if (u < 0 || v < 0 || u >= 640 || v >= 480) continue;
      EXPECT_NEAR(depth.at<float>(v, u), p_cam.z(), 1e-6) << "point y=" << y << " z=" << z;
      ++checked;
    }
  EXPECT_GT(checked, 40);
}

// The first wall of the box [lo, hi] hit from inside along o + t d (analytic).
double exitDistance(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Eigen::Vector3d& lo,
                    const Eigen::Vector3d& hi) {
  double t = std::numeric_limits<double>::infinity();
  for (int a = 0; a < 3; ++a) {
    if (d[a] > 0) t = std::min(t, (hi[a] - o[a]) / d[a]);
    if (d[a] < 0) t = std::min(t, (lo[a] - o[a]) / d[a]);
  }
  return t;
}

TEST(RenderImage, ScenePointsProjectOntoThePixelWithTheirDepthWithDistortion) {
  const Eigen::Vector3d lo(-3, -4, 0), hi(5, 4, 3);
  Scene scene(4);
  scene.addRoom(lo, hi);
  scene.build();
  const PinholeCamera cam = distorted();
  const Renderer renderer(scene, cam);
  const Eigen::Isometry3d T = lookFrom({0.2, -0.5, 1.1}, 0.4, 0.2);
  cv::Mat rgb, depth;
  renderer.render(T, rgb, depth);
  // Scene points seen through pixel centres (analytic wall intersections): each projects back
  // onto its pixel, and that pixel's depth is the point's camera-frame z.
  int checked = 0;
  for (int v = 3; v < cam.height; v += 29)
    for (int u = 5; u < cam.width; u += 31) {
      const Eigen::Vector2d xn = cam.pixelToNormalized({double(u), double(v)});
      const Eigen::Vector3d d = (T.linear() * Eigen::Vector3d(xn.x(), xn.y(), 1.0)).normalized();
      const Eigen::Vector3d p_world =
          T.translation() + exitDistance(T.translation(), d, lo, hi) * d;
      const Eigen::Vector3d p_cam = T.inverse() * p_world;
      Eigen::Vector2d uv;
      ASSERT_TRUE(cam.project(p_cam, uv));
      EXPECT_NEAR(uv.x(), u, 1e-6);
      EXPECT_NEAR(uv.y(), v, 1e-6);
      EXPECT_NEAR(depth.at<float>(v, u), p_cam.z(), 1e-6) << "pixel " << u << "," << v;
      ++checked;
    }
  EXPECT_GT(checked, 300);
}

TEST(RenderImage, TileCulledRendererEqualsPerPixelRaycast) {
  const Scene scene = makeFurnishedRoom(9);
  for (const PinholeCamera& cam : {d435(), distorted()}) {
    const Renderer renderer(scene, cam);
    for (int k = 0; k < 3; ++k) {
      const Eigen::Isometry3d T =
          lookFrom({0.5 * k - 0.5, 0.3 * k, 0.35 + 0.3 * k}, 2.1 * k, 0.15 * (k - 1));
      cv::Mat rgb, depth;
      renderer.render(T, rgb, depth);
      int mismatches = 0, hits = 0;
      for (int v = 0; v < cam.height; v += 3)
        for (int u = 0; u < cam.width; u += 3) {
          const Eigen::Vector2d xn = cam.pixelToNormalized({double(u), double(v)});
          const Eigen::Vector3d rc = Eigen::Vector3d(xn.x(), xn.y(), 1.0).normalized();
          Hit hit;
          const bool h =
              scene.raycast(T.translation(), T.linear() * rc, renderer.options().max_range_m, hit);
          const float expected = h ? static_cast<float>(hit.t * rc.z()) : 0.0f;
          if (depth.at<float>(v, u) != expected) ++mismatches;
          hits += h;
        }
      EXPECT_EQ(mismatches, 0) << "pose " << k;
      EXPECT_GT(hits, 30000);
    }
  }
}

// The same geometry with textures from the scene seed.
Scene fixedLayout(std::uint64_t seed) {
  Scene scene(seed);
  scene.addRoom({-3, -3, 0}, {4, 3, 2.8});
  scene.addCylinder({2, 0.5}, 0.25, 0, 2.8, TextureStyle::Speckle);
  scene.addStep({2.5, -1}, {0.6, 0.8}, 0.3, 0.0, 0.9, TextureStyle::Shelves);
  scene.addRamp({1, 1.5}, {2.5, 1.8}, 0.0, 0.8, 0.3, TextureStyle::Planks);
  scene.build();
  return scene;
}

TEST(RenderImage, SameSeedSameBytesOtherSeedOtherTextures) {
  const Eigen::Isometry3d T = lookFrom({0.0, 0.1, 0.6}, 0.1, 0.1);
  auto renderWith = [&](std::uint64_t seed, cv::Mat& rgb, cv::Mat& depth) {
    const Scene scene = fixedLayout(seed);
    const Renderer r(scene, d435());
    r.render(T, rgb, depth);
  };
  cv::Mat a, da, b, db, c, dc;
  renderWith(5, a, da);
  renderWith(5, b, db);
  renderWith(6, c, dc);
  ASSERT_EQ(a.total(), b.total());
  EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(da, db, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(da, dc, cv::NORM_INF), 0.0);  // same geometry
  cv::Mat diff;
  cv::absdiff(grey(a), grey(c), diff);
  EXPECT_GT(cv::countNonZero(diff > 10), static_cast<int>(0.3 * diff.total()));
}

TEST(RenderImage, GeneratedTexturesAreDeterministicPerSeed) {
  for (int s = 0; s < kTextureStyleCount; ++s) {
    const TextureStyle style = static_cast<TextureStyle>(s);
    const cv::Mat a = generateTexture(style, 256, 0.004, 77);
    const cv::Mat b = generateTexture(style, 256, 0.004, 77);
    const cv::Mat c = generateTexture(style, 256, 0.004, 78);
    EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0.0) << toString(style);
    EXPECT_GT(cv::norm(a, c, cv::NORM_L1) / a.total(), 10.0) << toString(style);
  }
}

// Reference bilinear of an RGB image at texel coordinates (u, v), wrapping (texel centres at
// integer + 0.5).
Eigen::Vector3f referenceBilinear(const cv::Mat& img, double u, double v) {
  const int n = img.cols;
  const double x = u - 0.5, y = v - 0.5;
  const int x0 = static_cast<int>(std::floor(x)), y0 = static_cast<int>(std::floor(y));
  const double ax = x - x0, ay = y - y0;
  auto texel = [&](int xi, int yi) {
    const cv::Vec3b c = img.at<cv::Vec3b>(((yi % n) + n) % n, ((xi % n) + n) % n);
    return Eigen::Vector3d(c[0], c[1], c[2]);
  };
  const Eigen::Vector3d top = (1 - ax) * texel(x0, y0) + ax * texel(x0 + 1, y0);
  const Eigen::Vector3d bottom = (1 - ax) * texel(x0, y0 + 1) + ax * texel(x0 + 1, y0 + 1);
  return ((1 - ay) * top + ay * bottom).cast<float>();
}

TEST(RenderImage, MipTextureSamplingIsTrilinearOverBoxFilteredLevels) {
  const cv::Mat level0 = generateTexture(TextureStyle::Tiles, 64, 0.004, 5);
  // Level 1 by hand: rounded 2x2 averages.
  cv::Mat level1(32, 32, CV_8UC3);
  for (int r = 0; r < 32; ++r)
    for (int c = 0; c < 32; ++c)
      for (int k = 0; k < 3; ++k) {
        const int sum = level0.at<cv::Vec3b>(2 * r, 2 * c)[k] +
                        level0.at<cv::Vec3b>(2 * r, 2 * c + 1)[k] +
                        level0.at<cv::Vec3b>(2 * r + 1, 2 * c)[k] +
                        level0.at<cv::Vec3b>(2 * r + 1, 2 * c + 1)[k];
        level1.at<cv::Vec3b>(r, c)[k] = static_cast<std::uint8_t>((sum + 2) / 4);
      }
  const MipTexture tex(level0);
  EXPECT_EQ(tex.levels(), 7);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> coord(-200.0, 200.0), frac(0.0, 1.0);
  for (int i = 0; i < 500; ++i) {
    const double u = coord(rng), v = coord(rng);
    const Eigen::Vector3f c0 = referenceBilinear(level0, u, v);
    const Eigen::Vector3f c1 = referenceBilinear(level1, u / 2, v / 2);
    EXPECT_LT((tex.sample(u, v, 0.0f) - c0).cwiseAbs().maxCoeff(), 1e-3);
    EXPECT_LT((tex.sample(u, v, -3.0f) - c0).cwiseAbs().maxCoeff(), 1e-3);  // magnified
    EXPECT_LT((tex.sample(u, v, 1.0f) - c1).cwiseAbs().maxCoeff(), 1e-3);
    const float f = static_cast<float>(frac(rng));
    EXPECT_LT((tex.sample(u, v, f) - (c0 + f * (c1 - c0))).cwiseAbs().maxCoeff(), 1e-3);
  }
  // The coarsest level is the mean colour (up to one rounding of at most 0.5 per level).
  const cv::Scalar mean = cv::mean(level0);
  EXPECT_LT((tex.sample(3.3, 7.1, 50.0f) - Eigen::Vector3f(mean[0], mean[1], mean[2]))
                .cwiseAbs()
                .maxCoeff(),
            3.0);
  EXPECT_THROW(MipTexture(cv::Mat(48, 48, CV_8UC3)), std::invalid_argument);
}

// Texture must not repeat at short scales (KLT would lock onto the wrong period): along each
// axis, the autocorrelation for shifts of 1 texel .. 1 m never climbs back by more than 0.3 above
// its lowest value at smaller shifts (a periodic pattern would climb back to ~1 at its period).
TEST(RenderImage, TexturesHaveNoShortScalePeriod) {
  for (int s = 0; s < kTextureStyleCount; ++s) {
    const TextureStyle style = static_cast<TextureStyle>(s);
    cv::Mat g;
    cv::cvtColor(generateTexture(style, 1024, 0.004, 11), g, cv::COLOR_RGB2GRAY);
    g.convertTo(g, CV_32F);
    cv::Scalar mean, stdev;
    cv::meanStdDev(g, mean, stdev);
    EXPECT_GT(stdev[0], 25.0) << toString(style) << ": contrast too low";
    g -= mean[0];
    // Circular autocorrelation (the texture is periodic) through the power spectrum.
    cv::Mat spectrum, power, acorr;
    cv::dft(g, spectrum, cv::DFT_COMPLEX_OUTPUT);
    cv::mulSpectrums(spectrum, spectrum, power, 0, true);
    cv::idft(power, acorr, cv::DFT_REAL_OUTPUT | cv::DFT_SCALE);
    acorr /= acorr.at<float>(0, 0);
    for (int axis = 0; axis < 2; ++axis) {
      double lowest = 1.0, rebound = 0.0;
      for (int d = 1; d <= 250; ++d) {
        const double c = axis == 0 ? acorr.at<float>(0, d) : acorr.at<float>(d, 0);
        lowest = std::min(lowest, c);
        rebound = std::max(rebound, c - lowest);
      }
      EXPECT_LT(rebound, 0.3) << toString(style) << " axis " << axis;
    }
  }
}

TEST(RenderImage, WallAtTwoMetresHasManyCorners) {
  for (int s = 0; s < kTextureStyleCount; ++s) {
    const TextureStyle style = static_cast<TextureStyle>(s);
    Scene scene(13);
    RoomStyles styles;
    styles.walls[1] = style;  // the +x wall
    scene.addRoom({-4, -3, 0}, {2, 3, 3}, styles);
    scene.build();
    const Renderer renderer(scene, d435());
    cv::Mat rgb, depth;
    renderer.render(lookFrom({0, 0.2, 1.5}, 0.0), rgb, depth);
    // The whole image is that wall, 2 m away.
    double lo, hi;
    cv::minMaxLoc(depth, &lo, &hi);
    ASSERT_NEAR(lo, 2.0, 1e-6);
    ASSERT_NEAR(hi, 2.0, 1e-6);
    std::vector<cv::Point2f> corners;
    cv::goodFeaturesToTrack(grey(rgb), corners, 2000, 0.01, 15);
    EXPECT_GE(corners.size(), 150u) << toString(style);
  }
}

// Mip-mapping: a distant wall shifted by a quarter pixel changes little, whereas point-sampling
// the finest level (lod_bias -20) aliases and the image changes a lot.
TEST(RenderImage, DistantSurfacesDoNotAlias) {
  Scene scene(8);
  RoomStyles styles;
  styles.walls[1] = TextureStyle::Posters;
  scene.addRoom({-2, -4, 0}, {14, 4, 3}, styles);
  scene.build();
  const PinholeCamera cam = d435();
  const double z = 14.0;
  const Eigen::Isometry3d T0 = lookFrom({0, 0, 1.5}, 0.0);
  Eigen::Isometry3d T1 = T0;
  T1.translation().y() -= 0.25 * z / cam.fx;  // a quarter pixel to the right on the far wall
  auto meanChange = [&](double lod_bias) {
    RenderOptions o;
    o.lod_bias = lod_bias;
    o.optics_blur_sigma_px = 0.0;
    const Renderer r(scene, cam, o);
    cv::Mat a, b, da, db, diff;
    r.render(T0, a, da);
    r.render(T1, b, db);
    cv::absdiff(grey(a), grey(b), diff);
    return cv::mean(diff(cv::Rect(200, 200, 240, 80)))[0];  // centre: the far wall only
  };
  const double filtered = meanChange(0.0), aliased = meanChange(-20.0);
  EXPECT_LT(filtered, 0.35 * aliased) << "filtered " << filtered << " aliased " << aliased;
}

TEST(RenderImage, EmptyViewAndBadArguments) {
  Scene scene(1);
  scene.addStep({0, 0}, {1, 1}, 0.0, 0.0, 1.0, TextureStyle::Tiles);
  RenderOptions o;
  o.background = {10, 20, 30};
  EXPECT_THROW((Renderer{scene, d435(), o}), std::invalid_argument);  // not built
  scene.build();
  PinholeCamera bad = d435();
  bad.fx = 0;
  EXPECT_THROW((Renderer{scene, bad, o}), std::invalid_argument);
  const Renderer r(scene, d435(), o);
  cv::Mat rgb, depth;
  r.render(lookFrom({5, 0, 0.5}, 0.0), rgb, depth);  // looking away from the only object
  EXPECT_EQ(cv::countNonZero(depth), 0);
  EXPECT_EQ(rgb.at<cv::Vec3b>(100, 100), cv::Vec3b(10, 20, 30));
  r.render(lookFrom({5, 0, 0.5}, M_PI), rgb, depth);  // facing it: the box face at 4.5 m
  EXPECT_NEAR(depth.at<float>(240, 324), 4.5, 1e-6);
  Eigen::Isometry3d bad_pose = lookFrom({5, 0, 0.5}, M_PI);
  bad_pose.linear() *= 1.01;
  EXPECT_THROW(r.render(bad_pose, rgb, depth), std::invalid_argument);
  bad_pose = lookFrom({std::nan(""), 0, 0.5}, M_PI);
  EXPECT_THROW(r.render(bad_pose, rgb, depth), std::invalid_argument);
}

}  // namespace
}  // namespace rgbdi::sim
