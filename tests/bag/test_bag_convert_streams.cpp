// RgbdPairer (colour/depth pairing by stamp) and AccelGyroMerger (separate accelerometer and gyro
// streams onto the gyro stamps): known answers, dropped counts, bounded buffering.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "rgbdi/bag/accel_gyro_merger.h"
#include "rgbdi/bag/rgbd_pairer.h"

namespace rgbdi::bag {
namespace {

StampedImage img(double t) {
  StampedImage s;
  s.t = t;
  s.label = std::to_string(t);
  return s;
}

struct Result {
  std::vector<std::pair<double, double>> pairs;  ///< (colour t, depth t)
  std::vector<double> color_alone, depth_alone;
};

Result drain(RgbdPairer& p) {
  Result r;
  PairedImages x;
  while (p.pop(x)) {
    if (x.color && x.depth)
      r.pairs.emplace_back(x.color->t, x.depth->t);
    else if (x.color)
      r.color_alone.push_back(x.color->t);
    else
      r.depth_alone.push_back(x.depth->t);
  }
  return r;
}

TEST(RgbdPairer, IdenticalStampsPairOneToOne) {
  RgbdPairer p(0.02, 0.5);
  for (int k = 0; k < 10; ++k) {
    p.pushColor(img(100.0 + k / 30.0));
    p.pushDepth(img(100.0 + k / 30.0));
  }
  p.finish();
  const Result r = drain(p);
  ASSERT_EQ(r.pairs.size(), 10u);
  for (int k = 0; k < 10; ++k) {
    EXPECT_DOUBLE_EQ(r.pairs[static_cast<size_t>(k)].first, 100.0 + k / 30.0);
    EXPECT_DOUBLE_EQ(r.pairs[static_cast<size_t>(k)].second, 100.0 + k / 30.0);
  }
  EXPECT_EQ(p.stats().pairs, 10u);
  EXPECT_EQ(p.buffered(), 0u);
}

TEST(RgbdPairer, NearestMutualPartnersWithinTolerance) {
  RgbdPairer p(0.02, 0.5);
  // Colour at 30 Hz; depth offset by 7 ms, one depth missing (k = 3), an extra depth far away.
  for (int k = 0; k < 6; ++k) p.pushColor(img(10.0 + k * 0.0333));
  for (int k = 0; k < 6; ++k)
    if (k != 3) p.pushDepth(img(10.007 + k * 0.0333));
  p.pushDepth(img(10.5));
  p.finish();
  const Result r = drain(p);
  ASSERT_EQ(r.pairs.size(), 5u);
  for (const auto& [c, d] : r.pairs) EXPECT_NEAR(d - c, 0.007, 1e-9);
  ASSERT_EQ(r.color_alone.size(), 1u);
  EXPECT_NEAR(r.color_alone[0], 10.0 + 3 * 0.0333, 1e-9);
  ASSERT_EQ(r.depth_alone.size(), 1u);
  EXPECT_DOUBLE_EQ(r.depth_alone[0], 10.5);
}

TEST(RgbdPairer, CloserLaterImageWinsAndPairsNeverCross) {
  // c0 = 0, d0 = 0.012, c1 = 0.015: d0's nearest colour is c1 (0.003), so c0 stays alone even
  // though d0 is within its tolerance.
  RgbdPairer p(0.02, 0.5);
  p.pushColor(img(1.000));
  p.pushDepth(img(1.012));
  p.pushColor(img(1.015));
  p.finish();
  Result r = drain(p);
  ASSERT_EQ(r.pairs.size(), 1u);
  EXPECT_DOUBLE_EQ(r.pairs[0].first, 1.015);
  ASSERT_EQ(r.color_alone.size(), 1u);
  EXPECT_DOUBLE_EQ(r.color_alone[0], 1.000);

  // Ties go to the earlier image.
  RgbdPairer tie(0.02, 0.5);
  tie.pushColor(img(2.000));
  tie.pushDepth(img(2.010));
  tie.pushColor(img(2.020));
  tie.finish();
  r = drain(tie);
  ASSERT_EQ(r.pairs.size(), 1u);
  EXPECT_DOUBLE_EQ(r.pairs[0].first, 2.000);
}

TEST(RgbdPairer, DecidesWithoutFinishOnceTheOtherStreamHasPassed) {
  RgbdPairer p(0.02, 0.5);
  p.pushColor(img(5.0));
  EXPECT_TRUE(drain(p).pairs.empty());  // depth may still come
  p.pushDepth(img(5.001));
  EXPECT_TRUE(drain(p).pairs.empty());  // a closer colour image may still come
  p.pushColor(img(5.0334));
  EXPECT_TRUE(drain(p).pairs.empty());  // another depth image within 0.02 s of 5.0 may still come
  p.pushDepth(img(5.0344));             // depth has passed 5.0 + 0.02: decided
  const Result r = drain(p);
  ASSERT_EQ(r.pairs.size(), 1u);
  EXPECT_DOUBLE_EQ(r.pairs[0].first, 5.0);
  EXPECT_DOUBLE_EQ(r.pairs[0].second, 5.001);
  EXPECT_EQ(p.buffered(), 2u);
}

TEST(RgbdPairer, StalledStreamDoesNotGrowTheBuffer) {
  // Depth stops after 1 s: colour images are decided (alone) once 0.5 s of newer data exists.
  RgbdPairer p(0.02, 0.5);
  std::size_t max_buffered = 0, alone = 0;
  for (int k = 0; k < 300; ++k) {
    const double t = k / 30.0;
    p.pushColor(img(t));
    if (t < 1.0) p.pushDepth(img(t + 0.001));
    max_buffered = std::max(max_buffered, p.buffered());
    alone += drain(p).color_alone.size();
  }
  EXPECT_LE(max_buffered, 17u);  // 0.5 s of colour at 30 Hz, plus the newest
  EXPECT_GT(alone, 250u);
}

TEST(RgbdPairer, FrameFromPairTakesColourStampAndDepthUnitAndCountsDroppedDepth) {
  StampedImage c{10.0, cv::Mat(2, 2, CV_8UC3, cv::Scalar(1, 2, 3)), 0.0, "colour 7"};
  StampedImage d{10.004, cv::Mat(2, 2, CV_16UC1, cv::Scalar(1500)), 0.001, "depth 9"};
  std::size_t dropped = 0;
  const auto f = frameFromPair(PairedImages{c, d}, true, &dropped);
  ASSERT_TRUE(f.has_value());
  EXPECT_EQ(f->t, 10.0);
  EXPECT_EQ(f->depth_unit_m, 0.001);
  EXPECT_EQ(f->rgb.at<cv::Vec3b>(1, 1), cv::Vec3b(1, 2, 3));
  EXPECT_EQ(f->depth.at<std::uint16_t>(0, 1), 1500);
  EXPECT_EQ(f->source_label, "colour 7");
  // Colour alone never makes a frame; depth alone only when colour is not required.
  EXPECT_FALSE(frameFromPair(PairedImages{c, std::nullopt}, true, &dropped).has_value());
  EXPECT_EQ(dropped, 0u);
  EXPECT_FALSE(frameFromPair(PairedImages{std::nullopt, d}, true, &dropped).has_value());
  EXPECT_EQ(dropped, 1u);
  const auto depth_only = frameFromPair(PairedImages{std::nullopt, d}, false, &dropped);
  ASSERT_TRUE(depth_only.has_value());
  EXPECT_EQ(depth_only->t, 10.004);
  EXPECT_TRUE(depth_only->rgb.empty());
  EXPECT_EQ(depth_only->source_label, "depth 9");
  EXPECT_EQ(dropped, 1u);
}

TEST(AccelGyroMerger, InterpolatesLinearAccelerationOnGyroStamps) {
  // Acceleration linear in time is reproduced exactly; gyro at 200 Hz, accel at 63 Hz.
  const auto acc = [](double t) { return Eigen::Vector3d(1.0 + 2.0 * t, -3.0 * t, 9.81); };
  AccelGyroMerger m(0.05, 0.5);
  std::vector<ImuSample> out;
  const auto drainInto = [&]() {
    ImuSample s;
    while (m.pop(s)) out.push_back(s);
  };
  int ia = 0, ig = 0;
  while (ia < 64 || ig < 200) {
    const double ta = ia / 63.0, tg = 0.001 + ig / 200.0;
    if (ia < 64 && (ig >= 200 || ta <= tg)) {
      m.pushAccel(ta, acc(ta));
      ++ia;
    } else {
      m.pushGyro(tg, Eigen::Vector3d(0.1, 0.2, tg));
      ++ig;
    }
    drainInto();
  }
  m.finish();
  drainInto();
  ASSERT_EQ(out.size(), 200u);  // accelerometer spans 0 .. 1 s, every gyro stamp inside
  for (std::size_t i = 0; i < out.size(); ++i) {
    EXPECT_NEAR(out[i].t, 0.001 + static_cast<double>(i) / 200.0, 1e-12);
    EXPECT_LT((out[i].acc - acc(out[i].t)).norm(), 1e-12) << i;
    EXPECT_DOUBLE_EQ(out[i].gyr.z(), out[i].t);
  }
  EXPECT_EQ(m.stats().merged, 200u);
  EXPECT_EQ(m.stats().dropped(), 0u);
}

TEST(AccelGyroMerger, DropsOutsideTheAccelerometerSpanAndInGaps) {
  AccelGyroMerger m(0.05, 0.5);
  m.pushGyro(0.99, Eigen::Vector3d::Zero());  // before the first accelerometer sample
  m.pushAccel(1.00, Eigen::Vector3d(0, 0, 1));
  m.pushAccel(1.02, Eigen::Vector3d(0, 0, 3));
  m.pushGyro(1.01, Eigen::Vector3d::Zero());    // interpolated: z = 2
  m.pushAccel(1.20, Eigen::Vector3d(0, 0, 5));  // 0.18 s gap
  m.pushGyro(1.10, Eigen::Vector3d::Zero());    // inside the gap
  m.pushGyro(1.20, Eigen::Vector3d::Zero());    // exactly on a sample: z = 5
  m.pushGyro(1.25, Eigen::Vector3d::Zero());    // after the last accelerometer sample
  m.pushGyro(1.15, Eigen::Vector3d::Zero());    // older than an emitted gyro sample
  m.finish();
  std::vector<ImuSample> out;
  ImuSample s;
  while (m.pop(s)) out.push_back(s);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_DOUBLE_EQ(out[0].t, 1.01);
  EXPECT_NEAR(out[0].acc.z(), 2.0, 1e-12);
  EXPECT_DOUBLE_EQ(out[1].acc.z(), 5.0);
  EXPECT_EQ(m.stats().gyro_before_accel, 1u);
  EXPECT_EQ(m.stats().gyro_in_accel_gap, 1u);
  EXPECT_EQ(m.stats().gyro_after_accel, 1u);
  EXPECT_EQ(m.stats().out_of_order, 1u);
  EXPECT_EQ(m.stats().gyro_in, 6u);
  EXPECT_EQ(m.stats().accel_in, 3u);
}

}  // namespace
}  // namespace rgbdi::bag
