// Sensor noise: depth statistics, quantisation, range gate, hole blobs; colour noise; options.
#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <set>

#include "rgbdi/sim/sensor_noise.h"
#include "testing/fixtures.h"

namespace rgbdi::sim {
namespace {

TEST(RenderNoise, DepthSigmaAtTwoMetresQuantisedToMillimetres) {
  const cv::Mat ideal(480, 640, CV_32FC1, cv::Scalar(2.0f));
  std::mt19937_64 rng(42);
  const DepthNoiseOptions o;  // coeff 0.004 1/m -> sigma 0.016 m at 2 m
  const cv::Mat d = applyDepthNoise(ideal, o, rng);
  ASSERT_EQ(d.type(), CV_16UC1);
  double sum = 0, sum2 = 0;
  long n = 0, zeros = 0;
  std::set<int> values;
  for (int v = 0; v < d.rows; ++v)
    for (int u = 0; u < d.cols; ++u) {
      const int mm = d.at<std::uint16_t>(v, u);
      if (mm == 0) {
        ++zeros;
        continue;
      }
      values.insert(mm);
      const double e = mm * 1e-3 - 2.0;
      sum += e;
      sum2 += e * e;
      ++n;
    }
  const double mean = sum / n, sd = std::sqrt(sum2 / n - mean * mean);
  EXPECT_NEAR(sd, 0.016, 0.1 * 0.016);
  EXPECT_NEAR(mean, 0.0, 0.0005);
  // Whole millimetres, every one of them within +-2.5 sigma (40 mm) of 2 m occurring.
  for (int mm = 1960; mm <= 2040; ++mm) EXPECT_EQ(values.count(mm), 1u) << mm;
  // Holes: exactly the requested fraction (no depth was out of range).
  const double hole_fraction = static_cast<double>(zeros) / d.total();
  EXPECT_GE(hole_fraction, 0.01);
  EXPECT_LE(hole_fraction, 0.02);
  EXPECT_EQ(zeros, std::llround(o.hole_fraction * d.total()));
}

TEST(RenderNoise, HolesAreBlobsNotSinglePixels) {
  std::mt19937_64 rng(3);
  const DepthNoiseOptions o;
  const cv::Mat mask = makeDepthHoleMask({640, 480}, o, rng);
  long holes = 0, isolated = 0;
  for (int v = 1; v < mask.rows - 1; ++v)
    for (int u = 1; u < mask.cols - 1; ++u) {
      if (!mask.at<std::uint8_t>(v, u)) continue;
      ++holes;
      const int nb = (mask.at<std::uint8_t>(v - 1, u) > 0) + (mask.at<std::uint8_t>(v + 1, u) > 0) +
                     (mask.at<std::uint8_t>(v, u - 1) > 0) + (mask.at<std::uint8_t>(v, u + 1) > 0);
      if (nb == 0) ++isolated;
    }
  EXPECT_GT(holes, 4000);
  EXPECT_LT(isolated, holes / 20);
  // Blobs: far fewer connected components than hole pixels, typical blob of several pixels.
  cv::Mat labels;
  const int components = cv::connectedComponents(mask, labels, 8) - 1;
  EXPECT_LT(components, holes / 5);
  EXPECT_GT(components, 50);
}

TEST(RenderNoise, ZeroOutsideRange) {
  // Columns of ideal depths around and beyond the gates.
  const float depths[] = {0.0f, 0.05f, 0.15f, 0.3f, 1.0f, 5.0f, 9.0f, 13.0f, 20.0f, 50.0f};
  cv::Mat ideal(200, 10, CV_32FC1);
  for (int v = 0; v < ideal.rows; ++v)
    for (int u = 0; u < ideal.cols; ++u) ideal.at<float>(v, u) = depths[u];
  std::mt19937_64 rng(8);
  DepthNoiseOptions o;
  o.hole_fraction = 0.0;
  const cv::Mat d = applyDepthNoise(ideal, o, rng);
  for (int v = 0; v < d.rows; ++v)
    for (int u = 0; u < d.cols; ++u) {
      const int mm = d.at<std::uint16_t>(v, u);
      if (mm != 0) {
        EXPECT_GE(mm, 200);
        EXPECT_LE(mm, 10000);
      }
      // Far beyond the gates (> 5 sigma) the sensor returns nothing; well inside, always a value.
      if (u <= 2 || u >= 7) {
        EXPECT_EQ(mm, 0) << "ideal " << depths[u];
      } else {
        EXPECT_NE(mm, 0) << "ideal " << depths[u];
      }
    }
  // Without noise the gate is exact at whole millimetres.
  o.sigma_coeff = 0.0;
  const float edge[] = {0.1994f, 0.2f, 9.9996f, 10.0004f, 10.0006f};
  cv::Mat e(1, 5, CV_32FC1);
  for (int u = 0; u < 5; ++u) e.at<float>(0, u) = edge[u];
  const cv::Mat de = applyDepthNoise(e, o, rng);
  EXPECT_EQ(de.at<std::uint16_t>(0, 0), 0);
  EXPECT_EQ(de.at<std::uint16_t>(0, 1), 200);
  EXPECT_EQ(de.at<std::uint16_t>(0, 2), 10000);
  EXPECT_EQ(de.at<std::uint16_t>(0, 3), 10000);
  EXPECT_EQ(de.at<std::uint16_t>(0, 4), 0);
}

TEST(RenderNoise, DeterministicPerSeed) {
  cv::Mat ideal(120, 160, CV_32FC1);
  cv::randu(ideal, 0.5, 6.0);
  std::mt19937_64 a(1), b(1), c(2);
  const DepthNoiseOptions o;
  const cv::Mat da = applyDepthNoise(ideal, o, a), db = applyDepthNoise(ideal, o, b),
                dc = applyDepthNoise(ideal, o, c);
  EXPECT_EQ(cv::norm(da, db, cv::NORM_INF), 0.0);
  EXPECT_GT(cv::norm(da, dc, cv::NORM_L1), 0.0);
  cv::Mat ra(50, 50, CV_8UC3, cv::Scalar::all(100)), rb = ra.clone();
  std::mt19937_64 ca(4), cb(4);
  applyColorNoise(ra, ColorNoiseOptions{}, ca);
  applyColorNoise(rb, ColorNoiseOptions{}, cb);
  EXPECT_EQ(cv::norm(ra, rb, cv::NORM_INF), 0.0);
}

TEST(RenderNoise, ColourNoiseSigmaAndSaturation) {
  std::mt19937_64 rng(9);
  ColorNoiseOptions o;
  o.sigma = 2.0;
  cv::Mat img(480, 640, CV_8UC3, cv::Scalar::all(128));
  applyColorNoise(img, o, rng);
  cv::Scalar mean, sd;
  cv::meanStdDev(img.reshape(1), mean, sd);
  EXPECT_NEAR(mean[0], 128.0, 0.05);
  // Rounding to integers adds 1/12 grey level^2 of variance.
  EXPECT_NEAR(sd[0], std::sqrt(4.0 + 1.0 / 12.0), 0.05);
  cv::Mat black(100, 100, CV_8UC3, cv::Scalar::all(0)),
      white(100, 100, CV_8UC3, cv::Scalar::all(255));
  applyColorNoise(black, o, rng);
  applyColorNoise(white, o, rng);
  double lo, hi;
  cv::minMaxLoc(black.reshape(1), &lo, &hi);
  EXPECT_EQ(lo, 0.0);
  EXPECT_LE(hi, 15.0);  // no wrap-around to bright values
  cv::minMaxLoc(white.reshape(1), &lo, &hi);
  EXPECT_EQ(hi, 255.0);
  EXPECT_GE(lo, 240.0);
}

TEST(RenderNoise, OptionsDefaultsMatchConfigAndRangesAreChecked) {
  IniReader ini = IniReader::fromFile(test::sourceDir() + "/share/config.ini");
  const DepthNoiseOptions d = DepthNoiseOptions::load(ini);
  const DepthNoiseOptions def;
  EXPECT_EQ(d.sigma_coeff, def.sigma_coeff);
  EXPECT_EQ(d.min_m, def.min_m);
  EXPECT_EQ(d.max_m, def.max_m);
  EXPECT_EQ(d.hole_fraction, def.hole_fraction);
  EXPECT_EQ(ColorNoiseOptions::load(ini).sigma, ColorNoiseOptions{}.sigma);

  IniReader custom = IniReader::fromText(
      "[sim]\ndepth_sigma_coeff = 0.002\ndepth_min_m = 0.3\ndepth_max_m = 6\n"
      "depth_hole_fraction = 0.01\nphotometric_noise_sigma = 3.5\n");
  const DepthNoiseOptions c = DepthNoiseOptions::load(custom);
  EXPECT_EQ(c.sigma_coeff, 0.002);
  EXPECT_EQ(c.min_m, 0.3);
  EXPECT_EQ(c.max_m, 6.0);
  EXPECT_EQ(c.hole_fraction, 0.01);
  EXPECT_EQ(ColorNoiseOptions::load(custom).sigma, 3.5);

  for (const char* bad :
       {"[sim]\ndepth_sigma_coeff = -1\n", "[sim]\ndepth_hole_fraction = 0.9\n",
        "[sim]\ndepth_min_m = 3\ndepth_max_m = 2\n", "[sim]\ndepth_max_m = abc\n"}) {
    IniReader r = IniReader::fromText(bad, "bad.ini");
    try {
      DepthNoiseOptions::load(r);
      ADD_FAILURE() << "accepted: " << bad;
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find("bad.ini"), std::string::npos) << e.what();
    }
  }
  IniReader r = IniReader::fromText("[sim]\nphotometric_noise_sigma = -2\n");
  EXPECT_THROW(ColorNoiseOptions::load(r), ConfigError);
}

TEST(RenderNoise, BadInputsAreRejected) {
  std::mt19937_64 rng(1);
  EXPECT_THROW(applyDepthNoise(cv::Mat(4, 4, CV_16UC1), DepthNoiseOptions{}, rng),
               std::invalid_argument);
  EXPECT_THROW(applyDepthNoise(cv::Mat(), DepthNoiseOptions{}, rng), std::invalid_argument);
  DepthNoiseOptions o;
  o.max_m = 0.1;
  EXPECT_THROW(applyDepthNoise(cv::Mat(4, 4, CV_32FC1, cv::Scalar(1.0f)), o, rng),
               std::invalid_argument);
  cv::Mat grey(4, 4, CV_8UC1);
  EXPECT_THROW(applyColorNoise(grey, ColorNoiseOptions{}, rng), std::invalid_argument);
}

}  // namespace
}  // namespace rgbdi::sim
