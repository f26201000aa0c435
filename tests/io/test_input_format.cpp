// Format detection and inspectRawlog (the library side of `rawlog-convert --info`).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "rgbdi/common/atomic_file.h"
#include "rgbdi/io/input_format.h"
#include "rgbdi/io/rawlog_source.h"
#include "rgbdi/io/rawlog_writer.h"
#include "testing/fixtures.h"

namespace rgbdi::io {
namespace {

namespace fs = std::filesystem;

class InputFormatTest : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = rgbdi::test::makeTempDir("rgbdi_io_fmt"); }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  std::string writeImuRawlog(const std::string& name, bool gzip, int n) {
    RawlogWriterOptions o;
    o.gzip = gzip;
    RawlogWriter w(dir_ + "/" + name, o);
    for (int i = 0; i < n; ++i) {
      ImuSample s;
      s.t = 100.0 + 0.005 * i;
      s.acc = Eigen::Vector3d(0, 0, 9.805);
      w.write(s);
    }
    w.close();
    return dir_ + "/" + name;
  }
  std::string dir_;
};

TEST_F(InputFormatTest, DetectsFormats) {
  EXPECT_EQ(detectInputFormat(writeImuRawlog("a.rawlog", false, 2)), InputFormat::Rawlog);
  EXPECT_EQ(detectInputFormat(writeImuRawlog("b.rawlog.gz", true, 2)), InputFormat::Rawlog);
  { std::ofstream(dir_ + "/x.txt") << "hello"; }
  EXPECT_EQ(detectInputFormat(dir_ + "/x.txt"), InputFormat::Unknown);
  fs::create_directory(dir_ + "/tum");
  EXPECT_EQ(detectInputFormat(dir_ + "/tum"), InputFormat::Unknown);
  std::ofstream(dir_ + "/tum/rgb.txt") << "# rgb\n";
  std::ofstream(dir_ + "/tum/depth.txt") << "# depth\n";
  EXPECT_EQ(detectInputFormat(dir_ + "/tum"), InputFormat::TumRgbd);
  try {
    detectInputFormat(dir_ + "/none.rawlog");
    FAIL();
  } catch (const IoError& e) {
    EXPECT_EQ(std::string(e.what()), dir_ + "/none.rawlog: no such file or directory");
  }
  EXPECT_EQ(formatName(InputFormat::Ros1Bag), "ROS1 bag");
}

TEST_F(InputFormatTest, RealBagIsRecognisedByItsHeader) {
  const std::string bag =
      rgbdi::test::fixturePath("real/realsense_d435_single_depth_color_640x480.bag");
  RGBDI_REQUIRE_FIXTURE(bag);
  EXPECT_EQ(detectInputFormat(bag), InputFormat::Ros1Bag);
}

TEST_F(InputFormatTest, InspectRawlogReportsCorruptionInsteadOfThrowing) {
  const std::string p = writeImuRawlog("t.rawlog", false, 30);
  fs::resize_file(p, fs::file_size(p) - 3);
  const StreamDiagnostics d = inspectRawlog(p, StreamConfig());
  EXPECT_FALSE(d.ok());
  EXPECT_EQ(d.imu.delivered, 29u);
  EXPECT_EQ(d.error.rfind(p + " record 29: truncated: the file ends inside this record (", 0), 0u)
      << d.error;
  EXPECT_NE(d.report().find("ERROR: " + d.error), std::string::npos);
  EXPECT_NE(d.toJson().find("\"ok\": false"), std::string::npos);
  EXPECT_THROW(inspectRawlog(dir_ + "/missing.rawlog", StreamConfig()), RawlogError);
}

}  // namespace
}  // namespace rgbdi::io
