// MRPT <-> rgbdi conversions: frame conventions (checked against MRPT's own pose algebra and its
// documented unprojection formula), round trips, colour order, units, and the real OpenNI2 fixture.
#include <gtest/gtest.h>
#include <mrpt/img/CImage.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/poses/CPoint3D.h>
#include <mrpt/serialization/CArchive.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <opencv2/imgproc.hpp>
#include <random>
#include <string>
#include <utility>

#include "rgbdi/io/mrpt_conversions.h"
#include "testing/fixtures.h"

namespace rgbdi::io {
namespace {

constexpr double kDeg = M_PI / 180.0;

Eigen::Isometry3d makePose(double x, double y, double z, double rx, double ry, double rz) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = (Eigen::AngleAxisd(rz, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(ry, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(rx, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  T.translation() = Eigen::Vector3d(x, y, z);
  return T;
}

void expectIsoNear(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, double tol) {
  EXPECT_LT((a.matrix() - b.matrix()).cwiseAbs().maxCoeff(), tol) << "\n"
                                                                  << a.matrix() << "\nvs\n"
                                                                  << b.matrix();
}

PinholeCamera makeCam(int w, int h, double fx, double fy, double cx, double cy, double k1) {
  PinholeCamera c;
  c.width = w;
  c.height = h;
  c.fx = fx;
  c.fy = fy;
  c.cx = cx;
  c.cy = cy;
  c.dist = {k1, -0.01, 0.001, -0.002, 0.0005};
  return c;
}

RgbdFrame makeFrame(bool aligned) {
  std::mt19937_64 rng(42);
  std::uniform_int_distribution<int> px(0, 255), dd(0, 5000);
  RgbdFrame f;
  f.t = 1700000000.123456;
  f.rgb = cv::Mat(6, 8, CV_8UC3);
  f.rgb.forEach<cv::Vec3b>([&](cv::Vec3b& p, const int*) {
    p = cv::Vec3b(static_cast<uchar>(px(rng)), static_cast<uchar>(px(rng)),
                  static_cast<uchar>(px(rng)));
  });
  f.depth = cv::Mat(aligned ? 6 : 4, aligned ? 8 : 5, CV_16UC1);
  for (int r = 0; r < f.depth.rows; ++r)
    for (int c = 0; c < f.depth.cols; ++c)
      f.depth.at<std::uint16_t>(r, c) = static_cast<std::uint16_t>(dd(rng));
  f.depth_unit_m = 1e-3;
  f.cam_color = makeCam(8, 6, 7.5, 7.25, 3.9, 2.8, 0.05);
  f.cam_depth = aligned ? f.cam_color : makeCam(5, 4, 4.5, 4.25, 2.1, 1.6, -0.02);
  f.depth_aligned_to_color = aligned;
  f.T_color_depth = aligned ? Eigen::Isometry3d::Identity()
                            : makePose(0.025, -0.001, 0.002, 1.0 * kDeg, -0.5 * kDeg, 0.3 * kDeg);
  f.source_label = "test";
  return f;
}

TEST(MrptConversions, FixedRotationIsMrptsCoincidingCameraPose) {
  // MRPT's default relativePoseIntensityWRTDepth is the "cameras coincide" rotation.
  const mrpt::obs::CObservation3DRangeScan def;
  expectIsoNear(toIsometry(def.relativePoseIntensityWRTDepth), mrptDepthFromOptical(), 1e-15);
  // Optical z (forward) is MRPT +X, optical x (right) is MRPT -Y, optical y (down) is MRPT -Z.
  const Eigen::Isometry3d R = mrptDepthFromOptical();
  EXPECT_EQ(R * Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(1, 0, 0));
  EXPECT_EQ(R * Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, -1, 0));
  EXPECT_EQ(R * Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(0, 0, -1));
}

TEST(MrptConversions, PoseConversionMatchesMrptAlgebra) {
  const Eigen::Isometry3d A = makePose(0.3, -1.2, 2.0, 10 * kDeg, -40 * kDeg, 170 * kDeg);
  const Eigen::Isometry3d B = makePose(-0.5, 0.25, 0.1, -30 * kDeg, 5 * kDeg, 60 * kDeg);
  const mrpt::poses::CPose3D a = toCPose3D(A), b = toCPose3D(B);
  expectIsoNear(toIsometry(a + b), A * B, 1e-14);
  const mrpt::poses::CPoint3D p = a + mrpt::poses::CPoint3D(1.0, 2.0, 3.0);
  const Eigen::Vector3d q = A * Eigen::Vector3d(1.0, 2.0, 3.0);
  EXPECT_NEAR(p.x(), q.x(), 1e-14);
  EXPECT_NEAR(p.y(), q.y(), 1e-14);
  EXPECT_NEAR(p.z(), q.z(), 1e-14);
  expectIsoNear(toIsometry(toCPose3D(A)), A, 1e-15);
}

// A depth pixel unprojected with MRPT's documented formula (x forward = depth, y = (cx - c) x / fx,
// z = (cy - r) x / fy in the MRPT depth frame, then sensorPose) must land on the same body point as
// rgbdi's optical back-projection with the converted calibration.
TEST(MrptConversions, DepthPixelLandsOnSameBodyPointBothConventions) {
  for (const bool coincide : {true, false}) {
    mrpt::obs::CObservation3DRangeScan obs;
    obs.hasRangeImage = true;
    obs.rangeImage_setSize(4, 5);
    obs.rangeImage.fill(0);
    obs.rangeImage(3, 1) = 2500;
    obs.rangeUnits = 0.001f;
    PinholeCamera cam = makeCam(5, 4, 4.0, 3.5, 2.2, 1.4, 0.0);
    cam.dist = {0, 0, 0, 0, 0};
    obs.cameraParams = toMrpt(cam);
    obs.cameraParamsIntensity = toMrpt(cam);
    obs.sensorPose = mrpt::poses::CPose3D(0.2, -0.1, 0.5, 20 * kDeg, 3 * kDeg, -4 * kDeg);
    if (!coincide) {
      obs.relativePoseIntensityWRTDepth =
          mrpt::poses::CPose3D(0.01, -0.025, 0.003, -88 * kDeg, 1 * kDeg, -91 * kDeg);
    }
    const RgbdFrame f = fromMrpt(obs, "synthetic");
    EXPECT_EQ(f.depth_aligned_to_color, coincide);

    const double d = 2.5, r = 3, c = 1;
    const mrpt::poses::CPoint3D p_mrpt(d, (cam.cx - c) * d / cam.fx, (cam.cy - r) * d / cam.fy);
    const mrpt::poses::CPoint3D p_body_mrpt = obs.sensorPose + p_mrpt;

    const Eigen::Vector3d p_depth_opt =
        f.cam_depth.backProject(Eigen::Vector2d(c, r), f.depthAt(1, 3));
    const Eigen::Vector3d p_body = f.source_T_body_cam * (f.T_color_depth * p_depth_opt);
    EXPECT_NEAR(p_body.x(), p_body_mrpt.x(), 1e-12);
    EXPECT_NEAR(p_body.y(), p_body_mrpt.y(), 1e-12);
    EXPECT_NEAR(p_body.z(), p_body_mrpt.z(), 1e-12);

    // The colour camera optical frame in the body frame is sensorPose (+) relativePose in MRPT.
    const mrpt::poses::CPose3D color_in_body = obs.sensorPose + obs.relativePoseIntensityWRTDepth;
    expectIsoNear(f.source_T_body_cam, toIsometry(color_in_body), 1e-12);
    // The depth optical frame in the body frame is sensorPose (+) the fixed rotation.
    expectIsoNear(f.source_T_body_cam * f.T_color_depth,
                  toIsometry(obs.sensorPose) * mrptDepthFromOptical(), 1e-12);
  }
}

TEST(MrptConversions, RgbdRoundTripAlignedAndNotAligned) {
  for (const bool aligned : {true, false}) {
    const RgbdFrame f = makeFrame(aligned);
    const Eigen::Isometry3d T_body_cam =
        makePose(0.01, 0.015, -0.02, -90 * kDeg, 0.5 * kDeg, -90 * kDeg);
    const auto obs = toMrpt(f, T_body_cam, "RGBD");
    EXPECT_EQ(obs->sensorLabel, "RGBD");
    EXPECT_EQ(obs->doDepthAndIntensityCamerasCoincide(), aligned);
    EXPECT_EQ(obs->rangeUnits, 0.001f);
    EXPECT_EQ(obs->intensityImage.getChannelsOrder(), "BGR");

    const RgbdFrame g = fromMrpt(*obs, "roundtrip");
    EXPECT_EQ(g.source_label, "roundtrip");
    EXPECT_NEAR(g.t, f.t, 1e-6);
    EXPECT_EQ(g.depth_unit_m, 1e-3);
    EXPECT_EQ(g.depth_aligned_to_color, aligned);
    EXPECT_EQ(cv::norm(g.rgb, f.rgb, cv::NORM_INF), 0.0);
    ASSERT_EQ(g.depth.size(), f.depth.size());
    EXPECT_EQ(cv::norm(g.depth, f.depth, cv::NORM_INF), 0.0);
    for (const auto& [a, b] :
         {std::pair{g.cam_color, f.cam_color}, std::pair{g.cam_depth, f.cam_depth}}) {
      EXPECT_EQ(a.width, b.width);
      EXPECT_EQ(a.height, b.height);
      EXPECT_EQ(a.fx, b.fx);
      EXPECT_EQ(a.fy, b.fy);
      EXPECT_EQ(a.cx, b.cx);
      EXPECT_EQ(a.cy, b.cy);
      EXPECT_EQ(a.dist, b.dist);
    }
    expectIsoNear(g.T_color_depth, f.T_color_depth, 1e-12);
    ASSERT_TRUE(g.has_source_T_body_cam);
    expectIsoNear(g.source_T_body_cam, T_body_cam, 1e-12);
  }
}

// SlamSystem queues such frames without copying their images (RgbdFrame::images_exclusive):
// nothing else may hold or write the buffers, the observation's own images included.
TEST(MrptConversions, ConvertedImagesBelongToTheFrameAlone) {
  EXPECT_FALSE(RgbdFrame().images_exclusive);  // other sources copy unless they say so
  for (const bool aligned : {true, false}) {
    const RgbdFrame f = makeFrame(aligned);
    const auto obs = toMrpt(f, Eigen::Isometry3d::Identity(), "RGBD");
    const RgbdFrame g = fromMrpt(*obs, "own");
    EXPECT_TRUE(g.images_exclusive);
    for (const cv::Mat* m : {&g.rgb, &g.depth}) {
      ASSERT_NE(m->u, nullptr);
      EXPECT_EQ(m->u->refcount, 1);
    }
    EXPECT_NE(g.rgb.data, obs->intensityImage.asCvMatRef().data);
  }
}

TEST(MrptConversions, AlignedFlagWithNonIdentityExtrinsicIsRejected) {
  RgbdFrame f = makeFrame(true);
  f.T_color_depth.translation().x() = 0.02;
  f.source_label = "bad frame";
  try {
    toMrpt(f, Eigen::Isometry3d::Identity(), "RGBD");
    FAIL() << "expected ConversionError";
  } catch (const ConversionError& e) {
    EXPECT_STREQ(
        e.what(),
        "bad frame: depth is declared aligned to colour but T_color_depth is not the identity");
  }
}

TEST(MrptConversions, ColourIsConvertedFromBgrAndGreyIsReplicated) {
  mrpt::obs::CObservation3DRangeScan obs;
  obs.hasIntensityImage = true;
  cv::Mat bgr(2, 2, CV_8UC3, cv::Scalar(255, 20, 10));  // blue in OpenCV/MRPT order
  obs.intensityImage = mrpt::img::CImage(bgr, mrpt::img::DEEP_COPY);
  RgbdFrame f = fromMrpt(obs, "c");
  EXPECT_EQ(f.rgb.type(), CV_8UC3);
  EXPECT_EQ(f.rgb.at<cv::Vec3b>(1, 1), cv::Vec3b(10, 20, 255));
  EXPECT_FALSE(f.hasDepth());

  cv::Mat grey(3, 2, CV_8UC1, cv::Scalar(77));
  obs.intensityImage = mrpt::img::CImage(grey, mrpt::img::DEEP_COPY);
  f = fromMrpt(obs, "g");
  EXPECT_EQ(f.rgb.type(), CV_8UC3);
  EXPECT_EQ(f.rgb.at<cv::Vec3b>(2, 1), cv::Vec3b(77, 77, 77));
}

TEST(MrptConversions, EuclideanRangesAreConvertedToDepth) {
  mrpt::obs::CObservation3DRangeScan obs;
  obs.hasRangeImage = true;
  obs.range_is_depth = false;
  obs.rangeImage_setSize(3, 4);
  obs.rangeImage.fill(0);
  PinholeCamera cam = makeCam(4, 3, 2.0, 2.0, 1.0, 1.0, 0.0);
  cam.dist = {0, 0, 0, 0, 0};
  obs.cameraParams = toMrpt(cam);
  obs.rangeImage(1, 1) = 3000;  // principal point: range == depth
  obs.rangeImage(1, 3) = 3000;  // xn = (3 - 1) / 2 = 1: depth = range / sqrt(2)
  obs.rangeImage(0, 0) = 3000;  // xn = yn = -0.5: depth = range / sqrt(1.5)
  const RgbdFrame f = fromMrpt(obs, "ranges");
  EXPECT_EQ(f.depth.at<std::uint16_t>(1, 1), 3000);
  EXPECT_EQ(f.depth.at<std::uint16_t>(1, 3),
            static_cast<std::uint16_t>(std::lround(3000 / std::sqrt(2.0))));
  EXPECT_EQ(f.depth.at<std::uint16_t>(0, 0),
            static_cast<std::uint16_t>(std::lround(3000 / std::sqrt(1.5))));
  EXPECT_EQ(f.depth.at<std::uint16_t>(2, 2), 0);
}

TEST(MrptConversions, EmptyObservationAndExoticDistortionAreErrors) {
  mrpt::obs::CObservation3DRangeScan obs;
  EXPECT_THROW(
      {
        try {
          fromMrpt(obs, "f.rawlog record 3");
        } catch (const ConversionError& e) {
          EXPECT_STREQ(
              e.what(),
              "f.rawlog record 3: 3-D range scan has neither an intensity nor a range image");
          throw;
        }
      },
      ConversionError);
  mrpt::img::TCamera cam;
  cam.dist[6] = 0.1;
  EXPECT_THROW(fromMrpt(cam, "x"), ConversionError);
}

TEST(MrptConversions, ImuRoundTripAndMissingFields) {
  ImuSample s;
  s.t = 1462879443.617188;
  s.acc = Eigen::Vector3d(0.1, -0.2, 9.81);
  s.gyr = Eigen::Vector3d(0.01, 0.02, -0.03);
  const auto obs = toMrpt(s, "IMU");
  EXPECT_EQ(obs->sensorLabel, "IMU");
  EXPECT_EQ(obs->get(mrpt::obs::IMU_WZ), -0.03);
  EXPECT_EQ(obs->get(mrpt::obs::IMU_Y_ACC), -0.2);
  const ImuSample r = fromMrpt(*obs);
  EXPECT_NEAR(r.t, s.t, 1e-6);
  EXPECT_EQ(r.acc, s.acc);
  EXPECT_EQ(r.gyr, s.gyr);

  mrpt::obs::CObservationIMU only_acc;
  only_acc.sensorLabel = "XSENS";
  only_acc.timestamp = fromSeconds(12.5);
  only_acc.set(mrpt::obs::IMU_X_ACC, 1);
  only_acc.set(mrpt::obs::IMU_Y_ACC, 1);
  only_acc.set(mrpt::obs::IMU_Z_ACC, 1);
  only_acc.set(mrpt::obs::IMU_WZ, 1);
  try {
    fromMrpt(only_acc);
    FAIL() << "expected ConversionError";
  } catch (const ConversionError& e) {
    EXPECT_STREQ(e.what(),
                 "IMU observation 'XSENS' at t = 12.500000 s lacks accelerometer/gyroscope data: "
                 "IMU_WX IMU_WY");
  }
}

// MRPT deserialises a bool as the file's byte: a damaged rawlog can hold 54 in a flag. That is
// refused as damage, never read as a bool (undefined behaviour; UBSan found it in
// fuzz_replay_rawlog: "load of value 54, which is not a valid value for type 'bool'").
TEST(MrptConversions, StoredFlagsThatAreNoBoolAreRefusedAsDamage) {
  const unsigned char damaged = 54;
  ImuSample s;
  s.t = 12.5;
  s.acc = Eigen::Vector3d(0.1, -0.2, 9.81);
  const auto imu = toMrpt(s, "IMU");
  std::memcpy(&imu->dataIsPresent.at(mrpt::obs::IMU_WX), &damaged, 1);
  try {
    fromMrpt(*imu);
    FAIL() << "expected ConversionError";
  } catch (const ConversionError& e) {
    EXPECT_STREQ(e.what(),
                 "IMU observation 'IMU' at t = 12.500000 s: the presence flag of IMU_WX "
                 "is stored as 54, which is no bool (0 or 1): the record is damaged");
  }

  const auto obs = toMrpt(makeFrame(true), Eigen::Isometry3d::Identity(), "RGBD");
  const std::pair<bool*, std::string> flags[] = {{&obs->hasRangeImage, "hasRangeImage"},
                                                 {&obs->hasIntensityImage, "hasIntensityImage"},
                                                 {&obs->range_is_depth, "range_is_depth"}};
  for (const auto& [flag, name] : flags) {
    const bool saved = *flag;
    std::memcpy(flag, &damaged, 1);
    try {
      fromMrpt(*obs, "x");
      ADD_FAILURE() << name << ": expected ConversionError";
    } catch (const ConversionError& e) {
      EXPECT_EQ(
          std::string(e.what()),
          "x: " + name + " is stored as 54, which is no bool (0 or 1): the record is damaged");
    }
    *flag = saved;
  }
  EXPECT_NO_THROW(fromMrpt(*obs, "x"));  // the same observation with its flags intact
}

TEST(MrptConversions, TimestampsKeepMicroseconds) {
  for (const double t : {0.000001, 1.5, 1462879443.617188, 1700000000.999999}) {
    EXPECT_NEAR(toSeconds(fromSeconds(t)), t, 0.5e-6) << t;
  }
  EXPECT_NE(fromSeconds(1700000000.000001), fromSeconds(1700000000.000002));
}

TEST(MrptConversions, RealOpenNi2Observation) {
  const std::string path = rgbdi::test::fixturePath("real/openni2_single_rgbd.rawlog");
  RGBDI_REQUIRE_FIXTURE(path);
  mrpt::io::CFileGZInputStream in(path);
  auto ar = mrpt::serialization::archiveFrom(in);
  const auto obs = std::dynamic_pointer_cast<mrpt::obs::CObservation3DRangeScan>(ar.ReadObject());
  ASSERT_TRUE(obs);
  const RgbdFrame f = fromMrpt(*obs, "openni2 record 0");

  std::printf("openni2 t=%.6f depth %dx%d colour %dx%d aligned=%d\n", f.t, f.depth.cols,
              f.depth.rows, f.rgb.cols, f.rgb.rows, f.depth_aligned_to_color);
  for (const auto* c : {&f.cam_depth, &f.cam_color})
    std::printf("  %dx%d fx=%.17g fy=%.17g cx=%.17g cy=%.17g k1=%.17g k2=%.17g\n", c->width,
                c->height, c->fx, c->fy, c->cx, c->cy, c->dist[0], c->dist[1]);

  EXPECT_NEAR(f.t, 1462879443.617188, 1e-6);
  ASSERT_EQ(f.depth.cols, 640);
  ASSERT_EQ(f.depth.rows, 480);
  ASSERT_EQ(f.rgb.cols, 640);
  ASSERT_EQ(f.rgb.rows, 480);
  EXPECT_EQ(f.depth_unit_m, 1e-3);
  int n_valid = 0;
  double dmin = 1e9, dmax = 0;
  for (int v = 0; v < f.depth.rows; ++v)
    for (int u = 0; u < f.depth.cols; ++u) {
      const double d = f.depthAt(u, v);
      if (d == 0.0) continue;
      ++n_valid;
      dmin = std::min(dmin, d);
      dmax = std::max(dmax, d);
    }
  EXPECT_EQ(n_valid, 273225);
  EXPECT_DOUBLE_EQ(dmin, 1.624);
  EXPECT_DOUBLE_EQ(dmax, 2.560);

  EXPECT_EQ(f.cam_depth.width, 640);
  EXPECT_EQ(f.cam_depth.height, 480);
  EXPECT_DOUBLE_EQ(f.cam_depth.fx, 572.882768);
  EXPECT_DOUBLE_EQ(f.cam_depth.fy, 542.73998);
  EXPECT_DOUBLE_EQ(f.cam_depth.cx, 314.649173);
  EXPECT_DOUBLE_EQ(f.cam_depth.cy, 240.160459);
  EXPECT_DOUBLE_EQ(f.cam_depth.dist[0], -0.004747169);
  EXPECT_DOUBLE_EQ(f.cam_depth.dist[1], -0.004357976);
  EXPECT_DOUBLE_EQ(f.cam_color.fx, 521.179233);
  EXPECT_DOUBLE_EQ(f.cam_color.fy, 493.033034);
  EXPECT_DOUBLE_EQ(f.cam_color.cx, 322.515987);
  EXPECT_DOUBLE_EQ(f.cam_color.cy, 259.055966);
  EXPECT_DOUBLE_EQ(f.cam_color.dist[0], 0.05858325);
  EXPECT_DOUBLE_EQ(f.cam_color.dist[1], 0.03856792);
  EXPECT_EQ(f.cam_color.dist[2], 0.0);

  // The cameras do not coincide: the colour camera sits 1.46 mm behind and 0.61 mm above the
  // depth camera (MRPT frame), i.e. the depth camera is at (0, +0.61 mm, +1.46 mm) in the colour
  // optical frame (y down, z forward).
  EXPECT_FALSE(f.depth_aligned_to_color);
  EXPECT_NEAR(f.T_color_depth.translation().x(), 0.0, 1e-7);
  EXPECT_NEAR(f.T_color_depth.translation().y(), 0.000609, 1e-7);
  EXPECT_NEAR(f.T_color_depth.translation().z(), 0.001462, 1e-7);
  EXPECT_LT((f.T_color_depth.linear() - Eigen::Matrix3d::Identity()).norm(), 1e-6);
  // The rawlog's sensorPose is the identity: the colour optical frame sits in the body frame
  // with the fixed MRPT rotation (plus the small offset above).
  expectIsoNear(f.source_T_body_cam, toIsometry(obs->relativePoseIntensityWRTDepth), 1e-15);

  // Colour: MRPT keeps BGR, we deliver RGB.
  const cv::Vec3b bgr = obs->intensityImage.asCvMatRef().at<cv::Vec3b>(240, 320);
  EXPECT_EQ(f.rgb.at<cv::Vec3b>(240, 320), cv::Vec3b(bgr[2], bgr[1], bgr[0]));
  EXPECT_EQ(f.rgb.at<cv::Vec3b>(240, 320), cv::Vec3b(218, 167, 136));
}

}  // namespace
}  // namespace rgbdi::io
