// RawlogOutput: re-ordering within the window, drops beyond it, acceleration-only IMU records,
// ground truth sorted with repeated stamps dropped, all read back (RawlogSource, MRPT, TUM); the
// progress line; output naming.
#include <gtest/gtest.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/serialization/CArchive.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "rgbdi/common/atomic_file.h"
#include "rgbdi/convert/progress_meter.h"
#include "rgbdi/convert/rawlog_output.h"
#include "rgbdi/io/rawlog_source.h"
#include "testing/fixtures.h"

namespace rgbdi::convert {
namespace {

RgbdFrame frameAt(double t) {
  RgbdFrame f;
  f.t = t;
  f.rgb = cv::Mat(8, 8, CV_8UC3, cv::Scalar(1, 2, 3));
  f.depth = cv::Mat(8, 8, CV_16UC1, cv::Scalar(1500));
  f.cam_color.width = f.cam_color.height = 8;
  f.cam_color.fx = f.cam_color.fy = 8;
  f.cam_color.cx = f.cam_color.cy = 4;
  f.cam_depth = f.cam_color;
  f.source_label = "frame " + std::to_string(t);
  return f;
}

ImuSample imuAt(double t) {
  ImuSample s;
  s.t = t;
  s.acc = Eigen::Vector3d(0, 0, 9.81);
  s.gyr = Eigen::Vector3d(0.1, 0, t - 10.0);
  return s;
}

TEST(RawlogOutput, NamesFollowTheOutputStem) {
  EXPECT_EQ(outputStem("/d/seq.rawlog"), "/d/seq");
  EXPECT_EQ(outputStem("/d/seq.rawlog.gz"), "/d/seq");
  EXPECT_EQ(outputStem("seq.v2.rawlog"), "seq.v2");
}

TEST(RawlogOutput, ReordersWithinTheWindowAndDropsBeyond) {
  const std::string dir = test::makeTempDir("rawlog_output");
  bag::ConversionReport report;
  RawlogOutputOptions o;
  o.path = dir + "/out.rawlog.gz";
  o.reorder_window_s = 0.1;
  RawlogOutput out(o, report);
  // IMU at 100 Hz; frames arrive 50 ms late (inside the window); one IMU sample 0.3 s late.
  for (int k = 0; k <= 100; ++k) {
    out.imu(imuAt(10.0 + 0.01 * k));
    if (k % 10 == 5) out.frame(frameAt(10.0 + 0.01 * (k - 5) + 0.001));
    if (k == 60) out.imu(imuAt(10.0 + 0.3 + 0.0005));
  }
  out.accelerometer(11.5, Eigen::Vector3d(0.1, -9.7, 0.2));
  StampedPose p;
  for (double t : {10.2, 10.1, 10.2, 10.3}) {
    p.t = t;
    p.p = Eigen::Vector3d(t, 0, 0);
    out.groundTruth(p);
  }
  out.finish();
  EXPECT_EQ(report.dropped_by_ordering, 1u);
  EXPECT_EQ(report.imu_written, 102u);  // 101 combined + 1 accelerometer-only
  EXPECT_EQ(report.frames_written, 10u);
  EXPECT_EQ(report.groundtruth_written, 3u);
  EXPECT_NEAR(out.imuRateHz(), 100.0, 1e-9);
  EXPECT_NE(report.text().find("arrived after data up to"), std::string::npos) << report.text();

  // Read back: time-ordered; the accelerometer-only record is not usable by rgbdi (no gyro).
  io::RawlogSource src(o.path);
  src.logging_enable_console_output = false;
  io::Measurement m;
  double last = 0.0;
  std::size_t n = 0;
  while (src.next(m)) {
    EXPECT_GE(io::measurementTime(m), last);
    last = io::measurementTime(m);
    ++n;
  }
  EXPECT_EQ(n, 111u);
  EXPECT_EQ(src.diagnostics().unusable, 1u);
  EXPECT_EQ(src.diagnostics().records, 112u);

  // MRPT sees the acceleration-only record with only the accelerometer fields present.
  mrpt::io::CFileGZInputStream f(o.path);
  auto arch = mrpt::serialization::archiveFrom(f);
  mrpt::serialization::CSerializable::Ptr obj;
  mrpt::obs::CObservationIMU::Ptr accel_only;
  while (true) {
    try {
      obj = arch.ReadObject();
    } catch (...) {
      break;
    }
    if (auto imu = std::dynamic_pointer_cast<mrpt::obs::CObservationIMU>(obj))
      if (!imu->has(mrpt::obs::IMU_WZ)) accel_only = imu;
  }
  ASSERT_TRUE(accel_only);
  EXPECT_DOUBLE_EQ(accel_only->get(mrpt::obs::IMU_Y_ACC), -9.7);

  std::ifstream gt(dir + "/out_groundtruth.tum");
  std::string frame_and_clock, header, line;
  std::getline(gt, frame_and_clock);
  std::getline(gt, header);
  std::getline(gt, line);
  EXPECT_EQ(frame_and_clock.rfind("# ground truth as recorded in the input", 0), 0u)
      << frame_and_clock;
  EXPECT_EQ(header, "# timestamp tx ty tz qx qy qz qw");
  EXPECT_EQ(line.rfind("10.100000000 10.1 0 0 0 0 0 1", 0), 0u) << line;
}

TEST(RawlogOutput, CreatesTheOutputDirectory) {
  // 'rawlog-convert BAG -o /tmp/ds/ds.rawlog' on a machine where /tmp/ds does not exist yet.
  const std::string dir = test::makeTempDir("rawlog_output_dir") + "/new/sub";
  bag::ConversionReport report;
  RawlogOutputOptions o;
  o.path = dir + "/out.rawlog";
  RawlogOutput out(o, report);
  out.imu(imuAt(10.0));
  out.frame(frameAt(10.001));
  StampedPose p;
  p.t = 10.0;
  out.groundTruth(p);
  out.finish();
  EXPECT_EQ(report.frames_written, 1u);
  EXPECT_TRUE(std::filesystem::is_regular_file(dir + "/out.rawlog"));
  EXPECT_TRUE(std::filesystem::is_regular_file(dir + "/out_groundtruth.tum"));
}

TEST(RawlogOutput, UncreatableDirectoryIsAnErrorNamingIt) {
  const std::string file = test::makeTempDir("rawlog_output_file") + "/plain_file";
  std::ofstream(file) << "x";
  bag::ConversionReport report;
  RawlogOutputOptions o;
  o.path = file + "/out.rawlog";
  try {
    RawlogOutput out(o, report);
    FAIL() << "expected an IoError";
  } catch (const IoError& e) {
    EXPECT_NE(std::string(e.what()).find(file + ": cannot create the rawlog's directory"),
              std::string::npos)
        << e.what();
  }
}

TEST(ProgressMeter, LineShowsFractionMegabytesRateAndEta) {
  EXPECT_EQ(ProgressMeter::line("rawlog-convert", 0.25, 200000000, 10.0),
            "rawlog-convert: [#####---------------]  25.0 %  50.0/200.0 MB  5.0 MB/s  ETA 30 s");
  EXPECT_EQ(ProgressMeter::line("x", 1.0, 1000000, 2.0),
            "x: [####################] 100.0 %  1.0/1.0 MB  0.5 MB/s  2.0 s");
  std::ostringstream os;
  ProgressMeter meter(&os, true, 3600.0, 1000000);
  meter.update(0.5);  // a terminal, within the interval: nothing printed
  EXPECT_TRUE(os.str().empty());
  meter.update(1.0);
  meter.finish();
  EXPECT_EQ(os.str().rfind("\r", 0), 0u) << os.str();  // redrawn in place
  EXPECT_NE(os.str().find("100.0 %"), std::string::npos) << os.str();
}

TEST(ProgressMeter, LogGetsOneLinePerTenthWhateverTheInterval) {
  // stderr redirected to a file: a line per tenth of the input, however short the interval
  // (one line per interval filled logs of long conversions); no copy of the last line.
  std::ostringstream os;
  ProgressMeter meter(&os, false, 0.05, 1000000);
  for (int i = 0; i <= 1000; ++i) meter.update(i / 1000.0);
  meter.finish();
  const std::string log = os.str();
  EXPECT_EQ(std::count(log.begin(), log.end(), '\n'), 10) << log;
  EXPECT_EQ(log.find('\r'), std::string::npos) << log;
  EXPECT_EQ(log.rfind("rawlog-convert: [##------------------]  10.0 %", 0), 0u) << log;
  EXPECT_NE(log.find(" 100.0 %"), std::string::npos) << log;
}

}  // namespace
}  // namespace rgbdi::convert
