// RawlogSource on rawlogs written by the test: both layouts, plain and gzip, external images,
// ordering problems, unit and size checks, skipped types, truncated and corrupt files.
#include <gtest/gtest.h>
#include <mrpt/img/CImage.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationBatteryState.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>

#include "rgbdi/io/mrpt_conversions.h"
#include "rgbdi/io/rawlog_source.h"
#include "rgbdi/io/rawlog_writer.h"
#include "testing/fixtures.h"

namespace rgbdi::io {
namespace {

namespace fs = std::filesystem;
using Layout = RawlogWriterOptions::Layout;

constexpr double kT0 = 1700000000.0;
constexpr double kImuDt = 0.005;  // 200 Hz
constexpr double kFrameDt = 0.1;  // 10 Hz

std::string fmt6(double t) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6f", t);
  return buf;
}

ImuSample imuAt(double t, double acc_z = 9.805) {
  ImuSample s;
  s.t = t;
  s.acc = Eigen::Vector3d(0.01, -0.02, acc_z);
  s.gyr = Eigen::Vector3d(0.001, 0.002, -0.003);
  return s;
}

PinholeCamera smallCam(int w, int h) {
  PinholeCamera c;
  c.width = w;
  c.height = h;
  c.fx = c.fy = 30.0;
  c.cx = w / 2.0;
  c.cy = h / 2.0;
  return c;
}

RgbdFrame frameAt(double t, std::uint16_t depth_raw = 1500, double unit = 1e-3) {
  RgbdFrame f;
  f.t = t;
  f.rgb = cv::Mat(24, 32, CV_8UC3, cv::Scalar(10, 200, 30));
  f.rgb.at<cv::Vec3b>(0, 0) = cv::Vec3b(90, 20, 130);  // not a flat image (constant-image check)
  f.depth = cv::Mat(24, 32, CV_16UC1, cv::Scalar(depth_raw));
  f.depth.at<std::uint16_t>(0, 0) = 0;
  f.depth.at<std::uint16_t>(5, 7) = static_cast<std::uint16_t>(depth_raw + 1);
  f.depth_unit_m = unit;
  f.cam_color = f.cam_depth = smallCam(32, 24);
  f.depth_aligned_to_color = true;
  return f;
}

/// 1 s of data: IMU at 200 Hz (201 samples) and frames at 10 Hz (10 frames, t0 + 0.05 + k 0.1),
/// written in time order.
std::vector<Measurement> normalSequence() {
  std::vector<Measurement> seq;
  int next_frame = 0;
  for (int i = 0; i <= 200; ++i) {
    const double t = kT0 + i * kImuDt;
    while (next_frame < 10 && kT0 + 0.05 + next_frame * kFrameDt <= t) {
      seq.emplace_back(frameAt(kT0 + 0.05 + next_frame * kFrameDt));
      ++next_frame;
    }
    seq.emplace_back(imuAt(t));
  }
  return seq;
}

StreamConfig testConfig() {
  StreamConfig c;  // defaults = share/config.ini
  return c;
}

RawlogWriterOptions writerOptions(Layout layout = Layout::Observations, bool gzip = false,
                                  bool external = false) {
  RawlogWriterOptions o;
  o.layout = layout;
  o.gzip = gzip;
  o.external_images = external;
  o.T_body_cam = StreamConfig().extrinsic.T_body_cam;  // agrees with the configuration
  return o;
}

void writeAll(const std::string& path, const RawlogWriterOptions& o,
              const std::vector<Measurement>& seq) {
  RawlogWriter w(path, o);
  for (const auto& m : seq) {
    if (const auto* s = std::get_if<ImuSample>(&m)) {
      w.write(*s);
    } else {
      w.write(std::get<RgbdFrame>(m));
    }
  }
  w.close();
}

std::vector<Measurement> readAll(RawlogSource& src) {
  src.logging_enable_console_output = false;
  std::vector<Measurement> out;
  Measurement m;
  while (src.next(m)) out.push_back(m);
  return out;
}

size_t countImu(const std::vector<Measurement>& v) {
  return static_cast<size_t>(
      std::count_if(v.begin(), v.end(), [](const Measurement& m) { return isImu(m); }));
}

std::string joined(const std::vector<std::string>& w) {
  std::string s;
  for (const auto& x : w) s += x + "\n";
  return s;
}

void expectTimeOrdered(const std::vector<Measurement>& v) {
  for (size_t i = 1; i < v.size(); ++i)
    ASSERT_LE(measurementTime(v[i - 1]), measurementTime(v[i])) << "at " << i;
}

/// Removes the temporary directories a test created.
class TempDirs {
 protected:
  std::string tempDir(const std::string& prefix) {
    dirs_.push_back(rgbdi::test::makeTempDir(prefix));
    return dirs_.back();
  }
  ~TempDirs() {
    std::error_code ec;
    for (const auto& d : dirs_) fs::remove_all(d, ec);
  }

 private:
  std::vector<std::string> dirs_;
};

class RawlogSourceTest : public ::testing::Test, public TempDirs {};

struct LayoutCase {
  Layout layout;
  bool gzip;
};

class RawlogLayouts : public ::testing::TestWithParam<LayoutCase>, public TempDirs {};

TEST_P(RawlogLayouts, ReadsEverythingInOrderWithoutWarnings) {
  const auto [layout, gzip] = GetParam();
  const std::string dir = tempDir("rgbdi_io_layout");
  const std::string path = dir + (gzip ? "/seq.rawlog.gz" : "/seq.rawlog");
  writeAll(path, writerOptions(layout, gzip), normalSequence());
  // gzip output really is compressed (magic 1f 8b), plain output is not.
  std::ifstream raw(path, std::ios::binary);
  const int b0 = raw.get(), b1 = raw.get();
  EXPECT_EQ(b0 == 0x1f && b1 == 0x8b, gzip);

  RawlogSource src(path, testConfig());
  const auto out = readAll(src);
  ASSERT_EQ(out.size(), 211u);
  EXPECT_EQ(countImu(out), 201u);
  expectTimeOrdered(out);
  std::uint64_t expected_index = 0;
  for (const auto& m : out) {
    if (const auto* f = std::get_if<RgbdFrame>(&m)) {
      EXPECT_EQ(f->index, expected_index++);
      ASSERT_EQ(f->depth.size(), cv::Size(32, 24));
      EXPECT_EQ(f->depth.at<std::uint16_t>(5, 7), 1501);
      EXPECT_EQ(f->depth.at<std::uint16_t>(0, 0), 0);
      // Embedded colour is JPEG-compressed by MRPT: a flat image survives within 2 levels.
      const cv::Vec3b p = f->rgb.at<cv::Vec3b>(12, 16);
      EXPECT_NEAR(p[0], 10, 2);
      EXPECT_NEAR(p[1], 200, 2);
      EXPECT_NEAR(p[2], 30, 2);
      EXPECT_TRUE(f->depth_aligned_to_color);
      EXPECT_EQ(f->source_label.rfind(path + " record ", 0), 0u) << f->source_label;
    }
  }
  const auto& d = src.diagnostics();
  EXPECT_TRUE(d.warnings.empty()) << joined(d.warnings);
  EXPECT_TRUE(d.ok());
  const size_t per_obs = layout == Layout::Observations ? 1 : 2;
  EXPECT_EQ(d.records, 211 * per_obs);
  EXPECT_EQ(d.actions, layout == Layout::Observations ? 0u : 211u);
  EXPECT_EQ(d.observations, 211u);
  EXPECT_EQ(d.imu.delivered, 201u);
  EXPECT_NEAR(d.imu.duration_s, 1.0, 1e-6);
  EXPECT_NEAR(d.imu.rate_hz, 200.0, 1e-3);
  EXPECT_EQ(d.imu.gaps, 0u);
  EXPECT_NEAR(d.imu.max_gap_s, 0.005, 1e-6);
  EXPECT_NEAR(d.mean_acc_norm_m_s2, std::sqrt(0.01 * 0.01 + 0.02 * 0.02 + 9.805 * 9.805), 1e-9);
  EXPECT_EQ(d.images.delivered, 10u);
  EXPECT_NEAR(d.images.rate_hz, 10.0, 1e-4);
  EXPECT_NEAR(d.images.median_period_s, 0.1, 1e-6);
  EXPECT_NEAR(d.images.gap_limit_s, 0.25, 1e-5);
  EXPECT_EQ(d.frames_with_color, 10u);
  EXPECT_EQ(d.frames_with_depth, 10u);
  EXPECT_EQ(d.frames_aligned, 10u);
  EXPECT_DOUBLE_EQ(d.median_depth_m, 1.5);
  EXPECT_EQ(d.depth_unit_m, 1e-3);
  EXPECT_FALSE(d.extrinsic_mismatch);
  EXPECT_EQ(d.imu.non_monotonic + d.imu.reordered + d.imu.duplicates + d.imu.dropped_late, 0u);
}

INSTANTIATE_TEST_SUITE_P(AllLayouts, RawlogLayouts,
                         ::testing::Values(LayoutCase{Layout::Observations, false},
                                           LayoutCase{Layout::Observations, true},
                                           LayoutCase{Layout::SensoryFrames, false},
                                           LayoutCase{Layout::SensoryFrames, true}));

TEST_F(RawlogSourceTest, FrameLabelsNameFileAndRecord) {
  const std::string dir = tempDir("rgbdi_io_label");
  const std::string path = dir + "/l.rawlog";
  writeAll(path, writerOptions(Layout::SensoryFrames),
           {imuAt(kT0), Measurement(frameAt(kT0 + 0.01)), imuAt(kT0 + 0.02)});
  RawlogSource src(path);
  const auto out = readAll(src);
  ASSERT_EQ(out.size(), 3u);
  // Records: 0 action, 1 IMU, 2 action, 3 sensory frame with the RGB-D observation, ...
  EXPECT_EQ(std::get<RgbdFrame>(out[1]).source_label, path + " record 3");
}

TEST_F(RawlogSourceTest, ExternalImagesAreLoadedFromTheImagesDirectory) {
  const std::string dir = tempDir("rgbdi_io_ext");
  const std::string path = dir + "/ext.rawlog";
  std::vector<Measurement> seq;
  for (int k = 0; k < 3; ++k) {
    RgbdFrame f = frameAt(kT0 + k * kFrameDt);
    f.rgb.at<cv::Vec3b>(3, 4) = cv::Vec3b(static_cast<uchar>(k), 99, 250);  // lossless check
    seq.emplace_back(f);
  }
  writeAll(path, writerOptions(Layout::Observations, false, true), seq);
  ASSERT_TRUE(fs::exists(dir + "/ext_Images/RGBD_0_color.png"));
  ASSERT_TRUE(fs::exists(dir + "/ext_Images/RGBD_2_depth.bin"));

  // Whatever the process-wide path was, the source points MRPT at this rawlog's directory.
  mrpt::img::CImage::setImagesPathBase("/nonexistent");
  RawlogSource src(path);
  EXPECT_EQ(src.imagesDirectory(), dir + "/ext_Images");
  const auto out = readAll(src);
  ASSERT_EQ(out.size(), 3u);
  for (int k = 0; k < 3; ++k) {
    const auto& f = std::get<RgbdFrame>(out[static_cast<size_t>(k)]);
    EXPECT_EQ(f.rgb.at<cv::Vec3b>(3, 4), cv::Vec3b(static_cast<uchar>(k), 99, 250));
    EXPECT_EQ(f.rgb.at<cv::Vec3b>(10, 10), cv::Vec3b(10, 200, 30));
    EXPECT_EQ(f.depth.at<std::uint16_t>(5, 7), 1501);
    EXPECT_EQ(f.cam_depth.width, 32);
    EXPECT_EQ(f.cam_depth.height, 24);
  }
  EXPECT_TRUE(src.diagnostics().warnings.size() == 1u)
      << joined(src.diagnostics().warnings);  // no IMU
  EXPECT_EQ(src.diagnostics().images_directory, dir + "/ext_Images");
}

TEST_F(RawlogSourceTest, MissingExternalImageIsReportedAndSkipped) {
  const std::string dir = tempDir("rgbdi_io_extmiss");
  const std::string path = dir + "/m.rawlog";
  writeAll(path, writerOptions(Layout::Observations, false, true),
           {Measurement(frameAt(kT0)), Measurement(frameAt(kT0 + 0.1))});
  fs::remove(dir + "/m_Images/RGBD_1_depth.bin");
  RawlogSource src(path);
  const auto out = readAll(src);
  ASSERT_EQ(out.size(), 1u);
  const auto& d = src.diagnostics();
  EXPECT_EQ(d.unusable, 1u);
  ASSERT_FALSE(d.warnings.empty());
  EXPECT_EQ(d.warnings[0], path + " record 1: cannot load the observation's images: range image " +
                               dir +
                               "/m_Images/RGBD_1_depth.bin does not exist (external images "
                               "folder " +
                               dir + "/m_Images); skipped")
      << d.warnings[0];
  EXPECT_NE(d.warnings[0].find("; skipped"), std::string::npos);
}

TEST_F(RawlogSourceTest, OutOfOrderDuplicatedAndLateImuSamples) {
  const std::string dir = tempDir("rgbdi_io_order");
  const std::string path = dir + "/o.rawlog";
  const auto t = [](int i) { return kT0 + i * kImuDt; };
  std::vector<Measurement> seq;
  for (int i = 0; i <= 200; ++i) {
    if (i == 50) continue;  // written after 51
    seq.emplace_back(imuAt(t(i)));
    if (i == 51) seq.emplace_back(imuAt(t(50)));             // record 51: reordered
    if (i == 80) seq.emplace_back(imuAt(t(80)));             // record 81: duplicate
    if (i == 119) seq.emplace_back(imuAt(t(100) + 0.0025));  // record 121: 0.0925 s late
  }
  writeAll(path, writerOptions(), seq);
  RawlogSource src(path);
  const auto out = readAll(src);
  EXPECT_EQ(out.size(), 201u);
  expectTimeOrdered(out);
  const auto& d = src.diagnostics();
  EXPECT_EQ(d.imu.delivered, 201u);
  EXPECT_EQ(d.imu.non_monotonic, 2u);
  EXPECT_EQ(d.imu.reordered, 1u);
  EXPECT_EQ(d.imu.duplicates, 1u);
  EXPECT_EQ(d.imu.dropped_late, 1u);
  EXPECT_EQ(d.imu.gaps, 0u);
  const std::vector<std::string> expected = {
      path + " record 51: IMU stamp t = " + fmt6(t(50)) + " s is older than the newest IMU stamp " +
          fmt6(t(51)) +
          " s read before it (non-monotonic); reordered (within imu_reorder_window_s = 0.05 s)",
      path + " record 81: IMU stamp t = " + fmt6(t(80)) +
          " s duplicates an earlier IMU stamp; dropped",
      path + " record 121: IMU stamp t = " + fmt6(t(100) + 0.0025) +
          " s is 0.092500 s older than the newest IMU stamp " + fmt6(t(119)) +
          " s, beyond imu_reorder_window_s = 0.05 s; dropped",
      path + " records 0-202: no RGB-D frames (CObservation3DRangeScan)",
  };
  EXPECT_EQ(d.warnings, expected) << joined(d.warnings);
}

TEST_F(RawlogSourceTest, FrameArrivingTooLateAfterImuIsDropped) {
  const std::string dir = tempDir("rgbdi_io_late");
  const std::string path = dir + "/late.rawlog";
  std::vector<Measurement> seq;
  for (int i = 0; i <= 100; ++i) {
    seq.emplace_back(imuAt(kT0 + i * kImuDt));
    if (i == 40) seq.emplace_back(frameAt(kT0 + 0.18));  // 0.02 s early: fine
    if (i == 50) {                                       // two frames swapped: reordered
      seq.emplace_back(frameAt(kT0 + 0.26));
      seq.emplace_back(frameAt(kT0 + 0.22));
    }
    if (i == 90) seq.emplace_back(frameAt(kT0 + 0.25));  // 0.2 s late: behind the output
  }
  writeAll(path, writerOptions(), seq);
  RawlogSource src(path);
  const auto out = readAll(src);
  EXPECT_EQ(out.size(), 104u);
  expectTimeOrdered(out);
  std::vector<std::uint64_t> indices;
  for (const auto& m : out)
    if (const auto* f = std::get_if<RgbdFrame>(&m)) indices.push_back(f->index);
  EXPECT_EQ(indices, (std::vector<std::uint64_t>{0, 1, 2}));  // numbered in delivery order
  const auto& d = src.diagnostics();
  EXPECT_EQ(d.images.delivered, 3u);
  EXPECT_EQ(d.images.non_monotonic, 1u);  // 0.25 is newer than the arrival before it (0.22)
  EXPECT_EQ(d.images.reordered, 1u);
  EXPECT_EQ(d.images.dropped_late, 1u);
  const std::vector<std::string> expected = {
      path + " record 53: RGB-D stamp t = " + fmt6(kT0 + 0.22) +
          " s is older than the newest RGB-D stamp " + fmt6(kT0 + 0.26) +
          " s read before it (non-monotonic); reordered (within image_reorder_window_s = 0.1 s)",
      path + " record 94: RGB-D stamp t = " + fmt6(kT0 + 0.25) +
          " s is older than measurements already delivered (it arrived more than 0.1 s after newer "
          "data of another sensor); dropped",
  };
  EXPECT_EQ(d.warnings, expected) << joined(d.warnings);
}

TEST_F(RawlogSourceTest, ImuInGUnitsGapsAndRate) {
  const std::string dir = tempDir("rgbdi_io_g");
  const std::string path = dir + "/g.rawlog";
  std::vector<Measurement> seq;
  for (int i = 0; i <= 100; ++i) {
    if (i > 20 && i < 31) continue;  // 0.055 s gap between samples 20 and 31
    seq.emplace_back(imuAt(kT0 + i * kImuDt, 1.0));
  }
  for (int k = 0; k < 6; ++k) {
    if (k == 3 || k == 4) continue;  // frames at 0, 0.1, 0.2, 0.5: one 0.3 s gap
    seq.emplace_back(frameAt(kT0 + 1.0 + k * kFrameDt));
  }
  writeAll(path, writerOptions(), seq);
  StreamConfig inspect;
  inspect.report_only = true;  // as rawlog-convert --info: reported, not refused
  RawlogSource src(path, inspect);
  readAll(src);
  const auto& d = src.diagnostics();
  EXPECT_TRUE(d.acc_looks_like_g_units);
  EXPECT_EQ(d.imu.gaps, 1u);
  EXPECT_EQ(d.images.gaps, 1u);
  const double mean = std::sqrt(0.01 * 0.01 + 0.02 * 0.02 + 1.0);
  char mean_txt[32];
  std::snprintf(mean_txt, sizeof mean_txt, "%.3f", mean);
  const std::vector<std::string> expected = {
      path + " record 21: IMU gap of 0.0550 s between t = " + fmt6(kT0 + 20 * kImuDt) +
          " s and t = " + fmt6(kT0 + 31 * kImuDt) +
          " s (limit 0.0150 s = imu_gap_factor 3 / [imu] rate_hz 200 Hz)",
      path + " records 0-90: mean IMU acceleration magnitude " + mean_txt +
          " m/s^2 over 91 samples looks like g units (expected about 9.805 m/s^2): the "
          "accelerometer must be given in m/s^2 (set [stream] accel_scale = 9.80665 to read one "
          "recorded in g)",
      path + " record 94: image gap of 0.3000 s between t = " + fmt6(kT0 + 1.2) + " s and t = " +
          fmt6(kT0 + 1.5) + " s (limit 0.2500 s = image_gap_factor 2.5 x median period 0.1000 s)",
  };
  EXPECT_EQ(d.warnings, expected) << joined(d.warnings);
}

/// 1 s at 200 Hz with the accelerometer in g (|acc| about 1) and 10 frames.
std::vector<Measurement> gUnitsSequence() {
  std::vector<Measurement> seq;
  for (int i = 0; i <= 200; ++i) {
    if (i % 20 == 10) seq.emplace_back(frameAt(kT0 + i * kImuDt));
    seq.emplace_back(imuAt(kT0 + i * kImuDt, 1.0));
  }
  return seq;
}

TEST_F(RawlogSourceTest, AccelerometerInGIsRefusedBeforeAnythingIsDelivered) {
  const std::string dir = tempDir("rgbdi_io_grefuse");
  const std::string path = dir + "/g.rawlog";
  writeAll(path, writerOptions(), gUnitsSequence());
  RawlogSource src(path);
  src.logging_enable_console_output = false;
  Measurement m;
  try {
    src.next(m);
    FAIL() << "expected RawlogError";
  } catch (const RawlogError& e) {
    // 100 IMU samples arrive in records 0-104 (5 frames among them).
    const std::string expected =
        path +
        " records 0-104: mean IMU acceleration magnitude 1.00025 m/s^2 over the first 100 "
        "samples looks like g units (expected about 9.805 m/s^2); the stream is refused: set "
        "[stream] accel_scale = 9.80665 to read an accelerometer recorded in g";
    EXPECT_EQ(std::string(e.what()), expected);
    EXPECT_EQ(src.diagnostics().error, expected);
  }
  EXPECT_TRUE(src.diagnostics().refused);
  EXPECT_EQ(src.diagnostics().imu.delivered, 0u);
  EXPECT_EQ(src.diagnostics().images.delivered, 0u);
  EXPECT_FALSE(src.next(m));
}

TEST_F(RawlogSourceTest, AccelScaleReadsAnAccelerometerRecordedInG) {
  const std::string dir = tempDir("rgbdi_io_gscale");
  const std::string path = dir + "/g.rawlog";
  writeAll(path, writerOptions(), gUnitsSequence());
  StreamConfig cfg;
  cfg.stream.accel_scale = 9.80665;
  RawlogSource src(path, cfg);
  const auto out = readAll(src);
  ASSERT_EQ(countImu(out), 201u);
  EXPECT_EQ(out.size(), 211u);
  for (const auto& x : out)
    if (const auto* s = std::get_if<ImuSample>(&x)) {
      EXPECT_DOUBLE_EQ(s->acc.z(), 9.80665);
      EXPECT_DOUBLE_EQ(s->acc.x(), 0.01 * 9.80665);
      EXPECT_DOUBLE_EQ(s->gyr.z(), -0.003);  // the gyroscope is not scaled
    }
  EXPECT_FALSE(src.diagnostics().acc_looks_like_g_units);
  EXPECT_TRUE(src.diagnostics().ok());
}

TEST_F(RawlogSourceTest, ShortStreamInGIsRefusedAtItsEnd) {
  const std::string dir = tempDir("rgbdi_io_gshort");
  const std::string path = dir + "/g.rawlog";
  std::vector<Measurement> seq;
  for (int i = 0; i < 20; ++i) seq.emplace_back(imuAt(kT0 + i * kImuDt, 1.0));
  writeAll(path, writerOptions(), seq);
  RawlogSource src(path);
  EXPECT_THROW(readAll(src), RawlogError);
  EXPECT_NE(src.diagnostics().error.find("records 0-19: mean IMU acceleration magnitude"),
            std::string::npos)
      << src.diagnostics().error;
}

TEST_F(RawlogSourceTest, TimeJumpingBackStopsTheStreamAfterDeliveringWhatCameBefore) {
  const std::string dir = tempDir("rgbdi_io_jump");
  const std::string path = dir + "/j.rawlog";
  std::vector<Measurement> seq;
  for (int i = 0; i <= 200; ++i) seq.emplace_back(imuAt(kT0 + i * kImuDt));  // records 0-200
  for (int i = 0; i <= 200; ++i) seq.emplace_back(imuAt(kT0 + i * kImuDt - 0.0025));  // 1 s back
  writeAll(path, writerOptions(), seq);
  RawlogSource src(path);
  src.logging_enable_console_output = false;
  std::vector<Measurement> out;
  Measurement m;
  try {
    while (src.next(m)) out.push_back(m);
    FAIL() << "expected RawlogError";
  } catch (const RawlogError& e) {
    const std::string expected =
        path + " record 201: IMU stamp t = " + fmt6(kT0 - 0.0025) +
        " s is 1.002500 s older than "
        "the newest one read before it (" +
        fmt6(kT0 + 1.0) +
        " s): time goes backwards (clock "
        "reset or recordings joined?); reading stops at this record, the data before it is used "
        "(limit [stream] time_jump_back_s = 0.5 s; split the rawlog here to use the rest)";
    EXPECT_EQ(std::string(e.what()), expected);
  }
  EXPECT_EQ(out.size(), 201u);
  expectTimeOrdered(out);
  EXPECT_EQ(measurementTime(out.back()), kT0 + 1.0);
  EXPECT_FALSE(src.diagnostics().refused);  // damage: what came before was delivered
}

TEST_F(RawlogSourceTest, SmallBackwardStepsBelowTheJumpLimitAreStillOnlyDropped) {
  const std::string dir = tempDir("rgbdi_io_nojump");
  const std::string path = dir + "/n.rawlog";
  std::vector<Measurement> seq;
  for (int i = 0; i <= 100; ++i) seq.emplace_back(imuAt(kT0 + i * kImuDt));
  seq.emplace_back(imuAt(kT0 + 0.3 + 0.0025));  // 0.1975 s back: too late, dropped
  for (int i = 101; i <= 200; ++i) seq.emplace_back(imuAt(kT0 + i * kImuDt));
  writeAll(path, writerOptions(), seq);
  RawlogSource src(path);
  const auto out = readAll(src);
  EXPECT_EQ(out.size(), 201u);
  EXPECT_EQ(src.diagnostics().imu.dropped_late, 1u);
  EXPECT_TRUE(src.diagnostics().ok());
}

TEST_F(RawlogSourceTest, NonFiniteImuValuesAreReportedCountedAndSkipped) {
  const std::string dir = tempDir("rgbdi_io_nan");
  const std::string path = dir + "/nan.rawlog";
  std::vector<Measurement> seq;
  for (int i = 0; i <= 200; ++i) {
    ImuSample s = imuAt(kT0 + i * kImuDt);
    if (i == 7) s.acc.y() = std::numeric_limits<double>::quiet_NaN();
    if (i == 9) s.gyr.x() = std::numeric_limits<double>::infinity();
    seq.emplace_back(s);
  }
  writeAll(path, writerOptions(), seq);
  RawlogSource src(path);
  const auto out = readAll(src);
  EXPECT_EQ(out.size(), 199u);
  const auto& d = src.diagnostics();
  EXPECT_EQ(d.non_finite_imu, 2u);
  EXPECT_EQ(d.unusable, 2u);
  ASSERT_GE(d.warnings.size(), 2u);
  EXPECT_EQ(d.warnings[0], path + " record 7: IMU sample at t = " + fmt6(kT0 + 7 * kImuDt) +
                               " s has a non-finite value (acc = [0.01 nan 9.805], gyr = [0.001 "
                               "0.002 -0.003]); skipped");
  EXPECT_EQ(d.warnings[1], path + " record 9: IMU sample at t = " + fmt6(kT0 + 9 * kImuDt) +
                               " s has a non-finite value (acc = [0.01 -0.02 9.805], gyr = [inf "
                               "0.002 -0.003]); skipped");
  EXPECT_NE(d.report().find("non-finite IMU samples 2"), std::string::npos) << d.report();
}

TEST_F(RawlogSourceTest, RunsOfBlackOrFlatColourImagesAreReportedWithTheirDuration) {
  const std::string dir = tempDir("rgbdi_io_black");
  const std::string path = dir + "/b.rawlog";
  std::vector<Measurement> seq;
  for (int i = 0; i <= 400; ++i) {
    const double t = kT0 + i * kImuDt;
    if (i % 20 == 0) {
      RgbdFrame f = frameAt(t);
      const int k = i / 20;                                    // frames 0..20 at 10 Hz
      if (k >= 3 && k <= 7) f.rgb.setTo(cv::Scalar(0, 1, 0));  // black, 0.4 s
      if (k == 12) f.rgb.setTo(cv::Scalar(90, 90, 90));        // one flat grey frame
      seq.emplace_back(f);
    }
    seq.emplace_back(imuAt(t));
  }
  writeAll(path, writerOptions(), seq);
  RawlogSource src(path);
  readAll(src);
  const auto& d = src.diagnostics();
  EXPECT_EQ(d.constant_color_frames, 6u);
  EXPECT_NEAR(d.constant_color_s, 0.4, 1e-6);
  // Frame k is record 21 k (20 IMU records and the frame before each frame).
  const std::vector<std::string> expected = {
      path +
          " records 63-147: 5 colour images are black (sampled values 0-1, "
          "constant_image_max_range 2) for 0.400 s from t = " +
          fmt6(kT0 + 0.3) + " s to t = " + fmt6(kT0 + 0.7) + " s: no visual tracking there",
      path +
          " record 252: 1 colour image is one flat colour (sampled values 90-90, "
          "constant_image_max_range 2) for 0.000 s from t = " +
          fmt6(kT0 + 1.2) + " s to t = " + fmt6(kT0 + 1.2) + " s: no visual tracking there",
  };
  EXPECT_EQ(d.warnings, expected) << joined(d.warnings);
}

TEST_F(RawlogSourceTest, ProblemLinesListEachWarningOnceThenTheError) {
  StreamDiagnostics d;
  d.warnings = {"f record 1: a", "f record 2: b", "f record 1: a"};
  d.error = "f record 9: truncated";
  EXPECT_EQ(streamProblemLines(d), (std::vector<std::string>{"f record 1: a", "f record 2: b",
                                                             "error: f record 9: truncated"}));
  EXPECT_TRUE(streamProblemLines(StreamDiagnostics()).empty());
}

TEST_F(RawlogSourceTest, ImuRateDifferentFromConfiguration) {
  const std::string dir = tempDir("rgbdi_io_rate");
  const std::string path = dir + "/r.rawlog";
  std::vector<Measurement> seq;
  for (int i = 0; i <= 100; ++i) seq.emplace_back(imuAt(kT0 + i * 0.01));  // 100 Hz
  seq.emplace_back(frameAt(kT0 + 1.0));
  writeAll(path, writerOptions(), seq);
  StreamConfig cfg = testConfig();
  cfg.stream.max_listed_issues = 3;
  RawlogSource src(path, cfg);
  readAll(src);
  const auto& d = src.diagnostics();
  EXPECT_NEAR(d.imu.rate_hz, 100.0, 1e-3);
  EXPECT_EQ(d.imu.gaps, 0u);  // 0.01 s < 3 / 200 Hz
  const std::vector<std::string> expected = {
      path +
          " records 0-100: measured IMU rate 100.0 Hz differs from [imu] rate_hz = 200 Hz by "
          "more than 20% (imu_rate_tolerance); the IMU gap limit is based on [imu] rate_hz",
  };
  EXPECT_EQ(d.warnings, expected) << joined(d.warnings);
}

TEST_F(RawlogSourceTest, DepthInWrongUnitsIsReportedAndSummarised) {
  const std::string dir = tempDir("rgbdi_io_units");
  for (const bool metres_as_mm : {true, false}) {
    const std::string path = dir + (metres_as_mm ? "/m.rawlog" : "/mm.rawlog");
    std::vector<Measurement> seq;
    seq.emplace_back(imuAt(kT0));
    for (int k = 0; k < 10; ++k) {
      // 2 "units" of 1 mm (really metres), or 1500 "units" of 1 m (really millimetres).
      seq.emplace_back(metres_as_mm ? frameAt(kT0 + 0.01 + k * kFrameDt, 2, 1e-3)
                                    : frameAt(kT0 + 0.01 + k * kFrameDt, 1500, 1.0));
    }
    seq.emplace_back(imuAt(kT0 + 1.0));
    writeAll(path, writerOptions(), seq);
    StreamConfig cfg = testConfig();
    cfg.stream.max_listed_issues = 2;
    RawlogSource src(path, cfg);
    readAll(src);
    const auto& d = src.diagnostics();
    EXPECT_EQ(d.depth_unit_suspects, 10u);
    const std::string what = metres_as_mm
                                 ? "median valid depth 0.002 m is below depth_median_min_m = 0.05 "
                                   "m (depth unit 0.001 m): metres stored as millimetres?"
                                 : "median valid depth 1500 m is above depth_median_max_m = 20 m "
                                   "(depth unit 1 m): millimetres stored as metres?";
    ASSERT_GE(d.warnings.size(), 3u) << joined(d.warnings);
    EXPECT_EQ(d.warnings[0], path + " record 1: " + what);
    EXPECT_EQ(d.warnings[1], path + " record 2: " + what);
    EXPECT_EQ(
        d.warnings.back(),
        path + " records 3-10: 8 more 'depth units' messages not listed (max_listed_issues = 2)");
  }
}

TEST_F(RawlogSourceTest, SizeMismatchAndMissingIntrinsics) {
  const std::string dir = tempDir("rgbdi_io_size");
  const std::string path = dir + "/s.rawlog";
  RgbdFrame small_depth = frameAt(kT0 + 0.1);
  small_depth.depth = cv::Mat(12, 16, CV_16UC1, cv::Scalar(1000));
  small_depth.cam_depth = smallCam(16, 12);
  RgbdFrame no_intrinsics = frameAt(kT0 + 0.2);
  no_intrinsics.cam_color.fx = 0.0;
  RgbdFrame wrong_intrinsics = frameAt(kT0 + 0.3);
  wrong_intrinsics.depth_aligned_to_color = false;
  wrong_intrinsics.cam_color = smallCam(64, 48);
  wrong_intrinsics.T_color_depth.translation().x() = 0.025;
  writeAll(path, writerOptions(),
           {imuAt(kT0), Measurement(small_depth), Measurement(no_intrinsics),
            Measurement(wrong_intrinsics), imuAt(kT0 + 0.4)});
  RawlogSource src(path);
  readAll(src);
  const auto& d = src.diagnostics();
  EXPECT_EQ(d.size_mismatches, 2u);
  EXPECT_EQ(d.missing_intrinsics, 1u);
  EXPECT_EQ(d.frames_aligned, 2u);
  // (A depth image that does not match its intrinsics cannot be written: MRPT's deserialiser
  // resizes cameraParams to the range image.)
  const std::vector<std::string> expected = {
      path +
          " record 1: colour image 32x24 and depth image 16x12 differ in size although depth is "
          "declared aligned to colour",
      path + " record 2: colour camera intrinsics missing (fx = 0)",
      path + " record 3: colour image 32x24 does not match its intrinsics 64x48",
  };
  // The IMU gap is found when the last sample is delivered, after the frames.
  ASSERT_GE(d.warnings.size(), 4u) << joined(d.warnings);
  for (size_t i = 0; i < 3; ++i) EXPECT_EQ(d.warnings[i], expected[i]);
  EXPECT_EQ(d.warnings[3], path + " record 4: IMU gap of 0.4000 s between t = " + fmt6(kT0) +
                               " s and t = " + fmt6(kT0 + 0.4) +
                               " s (limit 0.0150 s = imu_gap_factor 3 / [imu] rate_hz 200 Hz)");
}

TEST_F(RawlogSourceTest, SensorPoseDisagreeingWithExtrinsicIsWarnedOnce) {
  const std::string dir = tempDir("rgbdi_io_extr");
  const std::string path = dir + "/e.rawlog";
  RawlogWriterOptions o = writerOptions();
  o.T_body_cam.translation() += Eigen::Vector3d(0.03, 0.0, -0.04);  // 5 cm off
  std::vector<Measurement> seq;
  for (int k = 0; k < 5; ++k) {
    seq.emplace_back(imuAt(kT0 + k * kImuDt));
    seq.emplace_back(frameAt(kT0 + k * kImuDt + 0.001));
  }
  writeAll(path, o, seq);
  StreamConfig cfg = testConfig();
  RawlogSource src(path, cfg);
  readAll(src);
  const auto& d = src.diagnostics();
  EXPECT_TRUE(d.extrinsic_mismatch);
  std::vector<std::string> extr;
  for (const auto& w : d.warnings)
    if (w.find("sensorPose") != std::string::npos) extr.push_back(w);
  ASSERT_EQ(extr.size(), 1u) << joined(d.warnings);
  EXPECT_EQ(extr[0].rfind(path + " record 1: the rawlog's sensorPose places the colour camera at t "
                                 "= [0.030013 0.0149225 -0.0396832] m, R = [",
                          0),
            0u)
      << extr[0];
  EXPECT_NE(extr[0].find(" in the body frame, but [extrinsic] T_body_cam is t = [1.30441e-05 "
                         "0.0149225 0.000316835] m, R = [0.000874"),
            std::string::npos)
      << extr[0];
  EXPECT_NE(extr[0].find("; they differ by 0.0500 m and 0.00 deg (tolerances 0.01 m, 1 deg); "
                         "[extrinsic] is the one used"),
            std::string::npos)
      << extr[0];
}

TEST_F(RawlogSourceTest, OtherTypesAreSkippedAndCountedAndBadImuIsReported) {
  const std::string dir = tempDir("rgbdi_io_skip");
  const std::string path = dir + "/k.rawlog";
  {
    RawlogWriter w(path, writerOptions(Layout::SensoryFrames));
    w.write(imuAt(kT0));
    for (int i = 0; i < 3; ++i) {
      auto battery = mrpt::obs::CObservationBatteryState::Create();
      battery->timestamp = fromSeconds(kT0 + 0.001 * i);
      w.writeObservation(battery);
    }
    auto scan = mrpt::obs::CObservation2DRangeScan::Create();
    w.writeObservation(scan);
    auto bad = mrpt::obs::CObservationIMU::Create();
    bad->sensorLabel = "IMU";
    bad->timestamp = fromSeconds(kT0 + 0.004);
    bad->set(mrpt::obs::IMU_X_ACC, 0.0);
    bad->set(mrpt::obs::IMU_Y_ACC, 0.0);
    bad->set(mrpt::obs::IMU_Z_ACC, 9.8);
    w.writeObservation(bad);
    w.write(imuAt(kT0 + 0.005));
    w.close();
    EXPECT_EQ(w.records(), 14u);
  }
  RawlogSource src(path);
  const auto out = readAll(src);
  EXPECT_EQ(out.size(), 2u);
  const auto& d = src.diagnostics();
  EXPECT_EQ(d.records, 14u);
  EXPECT_EQ(d.actions, 7u);
  EXPECT_EQ(d.observations, 7u);
  EXPECT_EQ(d.unusable, 1u);
  const std::map<std::string, std::size_t> skipped = {{"mrpt::obs::CObservation2DRangeScan", 1},
                                                      {"mrpt::obs::CObservationBatteryState", 3}};
  EXPECT_EQ(d.skipped, skipped);
  ASSERT_FALSE(d.warnings.empty());
  EXPECT_EQ(d.warnings[0],
            path + " record 11: IMU observation 'IMU' at t = " + fmt6(kT0 + 0.004) +
                " s lacks accelerometer/gyroscope data: IMU_WX IMU_WY IMU_WZ; skipped");
}

/// Byte size of one serialised IMU record (all IMU records have the same size).
size_t imuRecordSize(const std::string& dir) {
  const std::string p = dir + "/one.rawlog";
  writeAll(p, writerOptions(), {imuAt(kT0)});
  return static_cast<size_t>(fs::file_size(p));
}

TEST_F(RawlogSourceTest, TruncatedFileDeliversEverythingBeforeTheBadRecord) {
  const std::string dir = tempDir("rgbdi_io_trunc");
  const std::string path = dir + "/t.rawlog";
  std::vector<Measurement> seq;
  for (int i = 0; i < 50; ++i) seq.emplace_back(imuAt(kT0 + i * kImuDt));
  writeAll(path, writerOptions(), seq);
  const size_t rec = imuRecordSize(dir);
  ASSERT_EQ(fs::file_size(path), 50 * rec);
  fs::resize_file(path, 50 * rec - 10);

  RawlogSource src(path);
  src.logging_enable_console_output = false;
  Measurement m;
  size_t n = 0;
  const std::string expected = path + " record 49: truncated: the file ends inside this record (" +
                               std::to_string(rec - 10) + " bytes of it read)";
  try {
    while (src.next(m)) ++n;
    FAIL() << "expected RawlogError";
  } catch (const RawlogError& e) {
    EXPECT_EQ(std::string(e.what()), expected);
  }
  EXPECT_EQ(n, 49u);
  EXPECT_EQ(src.diagnostics().error, expected);
  EXPECT_EQ(src.diagnostics().imu.delivered, 49u);
  EXPECT_FALSE(src.next(m));  // the error is raised once, then the stream is over
}

struct CountingSink : MeasurementSink {
  std::vector<double> stamps;
  int ends = 0;
  std::function<void()> after_each;
  void feedImu(const ImuSample& s) override {
    stamps.push_back(s.t);
    if (after_each) after_each();
  }
  void feedRgbd(const RgbdFrame& f) override {
    stamps.push_back(f.t);
    if (after_each) after_each();
  }
  void endOfStream() override { ++ends; }
};

TEST_F(RawlogSourceTest, PumpDeliversThenEndsAndRethrowsOnTruncatedGzip) {
  const std::string dir = tempDir("rgbdi_io_pumpgz");
  const std::string path = dir + "/t.rawlog.gz";
  writeAll(path, writerOptions(Layout::Observations, true), normalSequence());
  fs::resize_file(path, fs::file_size(path) - 200);
  RawlogSource src(path);
  src.logging_enable_console_output = false;
  CountingSink sink;
  try {
    src.pump(sink);
    FAIL() << "expected RawlogError";
  } catch (const RawlogError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind(path + " record ", 0), 0u) << what;
    EXPECT_NE(what.find(": truncated: the file ends inside this record ("), std::string::npos)
        << what;
    // Every complete record before the bad one has been delivered.
    const size_t bad_record = std::stoul(what.substr(path.size() + 8));
    EXPECT_EQ(sink.stamps.size(), bad_record);
    EXPECT_GT(bad_record, 100u);
  }
  EXPECT_EQ(sink.ends, 1);
  for (size_t i = 1; i < sink.stamps.size(); ++i) EXPECT_LE(sink.stamps[i - 1], sink.stamps[i]);
}

TEST_F(RawlogSourceTest, CorruptRecordIsAnErrorNamingTheRecord) {
  const std::string dir = tempDir("rgbdi_io_corrupt");
  const std::string path = dir + "/c.rawlog";
  std::vector<Measurement> seq;
  for (int i = 0; i < 40; ++i) seq.emplace_back(imuAt(kT0 + i * kImuDt));
  writeAll(path, writerOptions(), seq);
  const size_t rec = imuRecordSize(dir);
  {
    std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(static_cast<std::streamoff>(20 * rec));
    const char junk[8] = {'\x55', '\x55', '\x55', '\x55', '\x55', '\x55', '\x55', '\x55'};
    f.write(junk, sizeof junk);
  }
  RawlogSource src(path);
  src.logging_enable_console_output = false;
  CountingSink sink;
  EXPECT_THROW(src.pump(sink), RawlogError);
  EXPECT_EQ(sink.stamps.size(), 20u);
  EXPECT_EQ(sink.ends, 1);
  const std::string& err = src.diagnostics().error;
  EXPECT_EQ(err.rfind(path + " record 20: corrupt record (", 0), 0u) << err;
  EXPECT_EQ(err.find('\n'), std::string::npos) << err;
}

TEST_F(RawlogSourceTest, StopFlagEndsTheStreamCleanly) {
  const std::string dir = tempDir("rgbdi_io_stop");
  const std::string path = dir + "/s.rawlog";
  writeAll(path, writerOptions(), normalSequence());
  StreamConfig cfg;
  cfg.stream.accel_check_samples = 1;  // deliveries start at once (they wait for the unit check)
  RawlogSource src(path, cfg);
  src.logging_enable_console_output = false;
  std::atomic<bool> stop{false};
  CountingSink sink;
  sink.after_each = [&] {
    if (sink.stamps.size() == 10) stop = true;
  };
  src.pump(sink, &stop);
  EXPECT_EQ(sink.ends, 1);
  // Reading stopped at the 10th delivery; what was buffered (at most 0.1 s of data) still came.
  EXPECT_GE(sink.stamps.size(), 10u);
  EXPECT_LT(sink.stamps.size(), 40u);
  EXPECT_LE(sink.stamps.back() - sink.stamps.front(), 0.2);
  for (size_t i = 1; i < sink.stamps.size(); ++i) EXPECT_LE(sink.stamps[i - 1], sink.stamps[i]);
}

TEST_F(RawlogSourceTest, OpenErrorsNameThePath) {
  const std::string dir = tempDir("rgbdi_io_open");
  try {
    RawlogSource src(dir + "/missing.rawlog");
    FAIL();
  } catch (const RawlogError& e) {
    EXPECT_EQ(std::string(e.what()), dir + "/missing.rawlog: rawlog file does not exist");
  }
  try {
    RawlogSource src(dir);
    FAIL();
  } catch (const RawlogError& e) {
    EXPECT_EQ(std::string(e.what()), dir + ": is a directory, not a rawlog file");
  }
}

TEST_F(RawlogSourceTest, RealOpenNi2Rawlog) {
  const std::string path = rgbdi::test::fixturePath("real/openni2_single_rgbd.rawlog");
  RGBDI_REQUIRE_FIXTURE(path);
  RawlogSource src(path);
  const auto out = readAll(src);
  ASSERT_EQ(out.size(), 1u);
  const auto& f = std::get<RgbdFrame>(out[0]);
  EXPECT_EQ(f.depth.size(), cv::Size(640, 480));
  EXPECT_EQ(f.source_label, path + " record 0");
  const auto& d = src.diagnostics();
  EXPECT_EQ(d.records, 1u);
  EXPECT_EQ(d.images.delivered, 1u);
  EXPECT_EQ(d.size_mismatches, 0u);
  EXPECT_EQ(d.depth_unit_suspects, 0u);
  EXPECT_DOUBLE_EQ(d.median_depth_m, 2.04);  // every 4th pixel
  // Identity sensorPose vs the D435i extrinsic of the configuration, and no IMU.
  EXPECT_TRUE(d.extrinsic_mismatch);
  ASSERT_EQ(d.warnings.size(), 2u) << joined(d.warnings);
  EXPECT_EQ(d.warnings[0].rfind(
                path + " record 0: the rawlog's sensorPose places the colour camera at", 0),
            0u);
  EXPECT_EQ(d.warnings[1],
            path + " record 0: no IMU samples (CObservationIMU with accelerometer and gyroscope)");
}

}  // namespace

TEST_F(RawlogSourceTest, DamagedExternalImagesAreReportedWithTheirFileAndSkipped) {
  // The decoders of image_decode.h name the damaged file (MRPT's own reader returned a
  // truncated range file as zeros); the frame is skipped, the others load.
  const std::string dir = tempDir("rgbdi_io_extbad");
  const std::string path = dir + "/d.rawlog";
  writeAll(path, writerOptions(Layout::Observations, false, true),
           {Measurement(frameAt(kT0)), Measurement(frameAt(kT0 + 0.1)),
            Measurement(frameAt(kT0 + 0.2))});
  const auto truncate = [](const std::string& file) {
    fs::resize_file(file, fs::file_size(file) / 2);
  };
  truncate(dir + "/d_Images/RGBD_1_color.png");
  truncate(dir + "/d_Images/RGBD_2_depth.bin");
  RawlogSource src(path);
  const auto out = readAll(src);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(std::get<RgbdFrame>(out[0]).depth.at<std::uint16_t>(5, 7), 1501);
  const auto& d = src.diagnostics();
  EXPECT_EQ(d.unusable, 2u);
  ASSERT_GE(d.warnings.size(), 2u);
  EXPECT_EQ(d.warnings[0], path + " record 1: intensity image " + dir +
                               "/d_Images/RGBD_1_color.png: PNG truncated inside a chunk; skipped");
  // (which of its checks catches the cut depends on the bytes that end up last)
  const std::string range_error = path +
                                  " record 2: cannot load the observation's images: range file " +
                                  dir + "/d_Images/RGBD_2_depth.bin is damaged: ";
  EXPECT_EQ(d.warnings[1].rfind(range_error, 0), 0u) << d.warnings[1];
  const std::string tail = "(truncated or corrupt); skipped";
  EXPECT_EQ(d.warnings[1].substr(d.warnings[1].size() - tail.size()), tail) << d.warnings[1];
}

TEST_F(RawlogSourceTest, RateLimitSkipsFramesBeforeDecodingThem) {
  // 20 Hz frames under a 10 Hz limit: every second frame is used. The skipped frames' image
  // files are damaged: they are never read, so nothing is reported about them.
  const std::string dir = tempDir("rgbdi_io_ratelimit");
  const std::string path = dir + "/r.rawlog";
  std::vector<Measurement> seq;
  for (int i = 0; i <= 100; ++i) {  // 0.5 s of IMU
    const double t = kT0 + i * kImuDt;
    if (i % 10 == 5) seq.emplace_back(frameAt(t));  // frames at t0 + 0.025 + k 0.05
    seq.emplace_back(imuAt(t));
  }
  writeAll(path, writerOptions(Layout::Observations, false, true), seq);
  for (int k : {1, 3, 5, 7, 9}) {
    const std::string stem = dir + "/r_Images/RGBD_" + std::to_string(k);
    fs::resize_file(stem + "_color.png", fs::file_size(stem + "_color.png") / 2);
    fs::remove(stem + "_depth.bin");
  }
  StreamConfig cfg = testConfig();
  cfg.stream.image_rate_limit_hz = 10.0;
  RawlogSource src(path, cfg);
  const auto out = readAll(src);
  std::vector<double> stamps;
  for (const auto& m : out)
    if (const auto* f = std::get_if<RgbdFrame>(&m)) {
      stamps.push_back(f->t);
      EXPECT_EQ(f->index, stamps.size() - 1);  // delivered frames are numbered without gaps
    }
  ASSERT_EQ(stamps.size(), 5u);
  for (std::size_t k = 0; k < stamps.size(); ++k)
    EXPECT_NEAR(stamps[k], kT0 + 0.025 + 0.1 * static_cast<double>(k), 1e-6) << k;
  EXPECT_EQ(countImu(out), 101u);
  const auto& d = src.diagnostics();
  EXPECT_EQ(d.frames_rate_limited, 5u);
  EXPECT_EQ(d.images.delivered, 5u);
  EXPECT_EQ(d.unusable, 0u);
  EXPECT_TRUE(d.warnings.empty()) << joined(d.warnings);
  EXPECT_NE(d.report().find("skipped by [stream] image_rate_limit_hz (not decoded): 5"),
            std::string::npos)
      << d.report();
  EXPECT_NE(d.toJson().find("\"frames_rate_limited\": 5"), std::string::npos);

  // Inspection (rawlog-convert --info) reads every frame: the damaged ones are reported.
  StreamConfig inspect = cfg;
  inspect.report_only = true;
  RawlogSource all(path, inspect);
  const auto every = readAll(all);
  EXPECT_EQ(all.diagnostics().frames_rate_limited, 0u);
  EXPECT_EQ(all.diagnostics().unusable, 5u);
  EXPECT_EQ(all.diagnostics().images.delivered, 5u);
}

}  // namespace rgbdi::io
