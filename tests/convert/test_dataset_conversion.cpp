// convertDataset / loadConversionSettings: the calibration precedence (--config, --camera-yaml),
// the files written, stopping early (a valid, shorter rawlog), usage errors; the [convert]
// keys documented in doc/rawlog-convert.md load to the defaults of ConvertOptions.
#include <gtest/gtest.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "rgbdi/bag/bag_writer.h"
#include "rgbdi/common/atomic_file.h"
#include "rgbdi/common/ini_reader.h"
#include "rgbdi/convert/dataset_conversion.h"
#include "rgbdi/io/rawlog_source.h"
#include "testing/fixtures.h"
#include "testing/tiny_frame.h"

namespace rgbdi::convert {
namespace {

namespace fs = std::filesystem;

/// 1 s of a 32x24 camera at 10 Hz with IMU at 100 Hz and ground truth.
std::string writeBag(const std::string& dir) {
  const std::string path = dir + "/in.bag";
  bag::BagWriter w(path, bag::Compression::Lz4);
  for (int k = 0; k <= 100; ++k) {
    ImuSample s;
    s.t = 50.0 + 0.01 * k;
    s.acc = Eigen::Vector3d(0, 0, 9.8);
    w.writeImu(s);
    w.writePose(s.t, Eigen::Isometry3d::Identity());
    if (k % 10 == 0) w.writeRgbd(test::tinyFrame(s.t, k));
  }
  w.close();
  return path;
}

const char* const kConfig =
    "[camera]\nwidth = 32\nheight = 24\nfx = 30\nfy = 30\ncx = 16\ncy = 12\n"
    "[extrinsic]\nt_body_cam_m = 0.1 0 0\n[convert]\npair_tolerance_s = 0.005\n"
    "[frontend]\nmax_features = 100\n";

TEST(DatasetConversion, ConfigCalibrationAndFilesWritten) {
  const std::string dir = test::makeTempDir("dataset_conversion");
  std::ofstream(dir + "/c.ini") << kConfig;
  ConversionRequest q;
  q.input = writeBag(dir);
  q.output = dir + "/out.rawlog";
  q.settings = loadConversionSettings(dir + "/c.ini", "");
  EXPECT_TRUE(q.settings.calibration.intrinsics_from_user);
  EXPECT_TRUE(q.settings.calibration.extrinsic_from_user);
  EXPECT_DOUBLE_EQ(q.settings.options.pair_tolerance_s, 0.005);
  std::ostringstream progress;
  q.progress = &progress;
  const bag::ConversionReport r = convertDataset(q);
  ASSERT_TRUE(r.ok()) << r.error;
  EXPECT_EQ(r.frames_written, 11u);
  EXPECT_EQ(r.imu_written, 101u);
  EXPECT_EQ(r.groundtruth_written, 101u);
  EXPECT_TRUE(fs::exists(dir + "/out_groundtruth.tum"));
  EXPECT_FALSE(fs::exists(dir + "/out.ini"));  // no --camera-yaml
  EXPECT_NE(progress.str().find("100.0 %"), std::string::npos) << progress.str();
  EXPECT_NE(r.text().find("(" + dir + "/c.ini [camera])"), std::string::npos) << r.text();

  io::RawlogSource src(q.output);
  src.logging_enable_console_output = false;
  io::Measurement m;
  std::size_t frames = 0;
  while (src.next(m)) {
    if (const auto* f = std::get_if<RgbdFrame>(&m)) {
      EXPECT_DOUBLE_EQ(f->cam_color.fx, 30.0);
      EXPECT_NEAR(f->source_T_body_cam.translation().x(), 0.1,
                  1e-12);  // sensorPose from [extrinsic]
      ++frames;
    }
  }
  EXPECT_EQ(frames, 11u);
}

TEST(DatasetConversion, CameraYamlWritesTheIniAndStopLeavesAValidRawlog) {
  const std::string dir = test::makeTempDir("dataset_conversion");
  std::ofstream(dir + "/c.yaml")
      << "%YAML:1.0\nimage_width: 32\nimage_height: 24\n"
         "projection_parameters:\n   fx: 31.0\n   fy: 31.0\n   cx: 16.0\n   cy: 12.0\n"
         "acc_n: 0.1\ngyr_n: 0.01\nacc_w: 0.0002\ngyr_w: 2.0e-5\ng_norm: 9.81\n";
  ConversionRequest q;
  q.input = writeBag(dir);
  q.output = dir + "/y.rawlog.gz";
  q.settings = loadConversionSettings("", dir + "/c.yaml");
  EXPECT_FALSE(q.settings.calibration.extrinsic_from_user);  // the yaml has no extrinsic
  std::atomic<bool> stop{true};
  q.stop = &stop;
  const bag::ConversionReport r = convertDataset(q);
  EXPECT_TRUE(r.ok()) << r.error;
  EXPECT_NE(r.text().find("interrupted"), std::string::npos) << r.text();
  EXPECT_EQ(r.frames_written, 0u);
  ASSERT_TRUE(fs::exists(q.output));  // a valid, empty rawlog
  io::RawlogSource src(q.output);
  io::Measurement m;
  EXPECT_FALSE(src.next(m));
  // No IMU data converted: the INI assumes the dataset's 200 Hz and says so.
  IniReader ini = IniReader::fromFile(dir + "/y.ini");
  EXPECT_DOUBLE_EQ(ImuOptions::load(ini).rate_hz, 200.0);
  EXPECT_DOUBLE_EQ(CameraOptions::load(ini).camera.fx, 31.0);
  std::ifstream in(dir + "/y.ini");
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  EXPECT_NE(text.find("no IMU data in the input; the VINS-RGBD dataset's 200 Hz assumed"),
            std::string::npos);

  stop = false;
  q.output = dir + "/full.rawlog";
  EXPECT_EQ(convertDataset(q).imu_written, 101u);
  IniReader full = IniReader::fromFile(dir + "/full.ini");
  EXPECT_DOUBLE_EQ(ImuOptions::load(full).rate_hz, 100.0);  // measured in the bag
}

TEST(DatasetConversion, UsageErrors) {
  const std::string dir = test::makeTempDir("dataset_conversion");
  ConversionRequest q;
  q.input = writeBag(dir);
  q.output = dir + "/out.bag";
  EXPECT_THROW(convertDataset(q), UsageError);
  q.output = q.input;
  EXPECT_THROW(convertDataset(q), UsageError);
  q.output = dir + "/o.rawlog";
  q.input = dir + "/none.bag";
  EXPECT_THROW(convertDataset(q), IoError);
  std::ofstream(dir + "/bad.ini") << "[camera]\nfx = -3\n";
  EXPECT_THROW(loadConversionSettings(dir + "/bad.ini", ""), ConfigError);
  std::ofstream(dir + "/typo.ini") << "[convert]\npair_tolerence_s = 0.01\n";
  EXPECT_THROW(loadConversionSettings(dir + "/typo.ini", ""), ConfigError);
}

TEST(DatasetConversion, DocumentedConvertSectionIsTheDefault) {
  std::ifstream in(test::sourceDir() + "/doc/rawlog-convert.md");
  const std::string doc((std::istreambuf_iterator<char>(in)), {});
  const auto begin = doc.find("[convert]\n");
  ASSERT_NE(begin, std::string::npos);
  const std::string section = doc.substr(begin, doc.find("```", begin) - begin);
  IniReader ini = IniReader::fromText(section, "doc/rawlog-convert.md [convert]");
  const bag::ConvertOptions o = bag::ConvertOptions::load(ini);
  ini.checkNoUnknownKeys();
  const bag::ConvertOptions d;
  EXPECT_DOUBLE_EQ(o.pair_tolerance_s, d.pair_tolerance_s);
  EXPECT_DOUBLE_EQ(o.max_wait_s, d.max_wait_s);
  EXPECT_DOUBLE_EQ(o.reorder_window_s, d.reorder_window_s);
  EXPECT_DOUBLE_EQ(o.max_accel_gap_s, d.max_accel_gap_s);
  EXPECT_DOUBLE_EQ(o.integer_depth_unit_m, d.integer_depth_unit_m);
  EXPECT_DOUBLE_EQ(o.float_depth_unit_m, d.float_depth_unit_m);
  EXPECT_DOUBLE_EQ(o.tum_depth_factor, d.tum_depth_factor);
  EXPECT_EQ(o.require_colour, d.require_colour);
  EXPECT_EQ(o.max_listed_issues, d.max_listed_issues);
  EXPECT_DOUBLE_EQ(o.progress_interval_s, d.progress_interval_s);
  for (const char* key : {"pair_tolerance_s", "max_wait_s", "reorder_window_s", "max_accel_gap_s",
                          "integer_depth_unit_m", "float_depth_unit_m", "tum_depth_factor",
                          "require_colour", "max_listed_issues", "progress_interval_s"})
    EXPECT_TRUE(ini.hasKey("convert", key)) << key;
}

}  // namespace
}  // namespace rgbdi::convert
