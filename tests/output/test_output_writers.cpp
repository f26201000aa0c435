// TUM trajectory and summary.json writers (each written file is re-read with its reader), and the
// [output] options.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "rgbdi/common/so3.h"
#include "rgbdi/eval/tum_reader.h"
#include "rgbdi/output/output_options.h"
#include "rgbdi/output/summary_json.h"
#include "rgbdi/output/tum_writer.h"
#include "testing/fixtures.h"

namespace rgbdi::output {
namespace {

std::string readAll(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

Trajectory sampleTrajectory() {
  Trajectory t;
  for (int k = 0; k < 20; ++k) {
    StampedPose s;
    s.t = 1403715529.262140036 + k / 30.0;
    s.p = Eigen::Vector3d(0.1 * k + 1.0 / 3.0, -2.0e-7 * k, 123.456789012345 + std::sqrt(2.0) * k);
    s.q = expQuat(Eigen::Vector3d(0.01 * k, -0.3, 0.7 + 0.05 * k));
    t.push_back(s);
  }
  return t;
}

TEST(TumWriter, RoundTripsThroughReadTumExactly) {
  const std::string path = test::makeTempDir("out_tum") + "/traj.tum";
  const Trajectory in = sampleTrajectory();
  writeTum(path, in);
  const std::string text = readAll(path);
  EXPECT_EQ(text.rfind("# timestamp tx ty tz qx qy qz qw\n", 0), 0u);
  // 9 decimals on the stamp.
  EXPECT_NE(text.find("\n1403715529.262140036 "), std::string::npos) << text.substr(0, 200);

  const Trajectory out = eval::readTum(path);
  ASSERT_EQ(out.size(), in.size());
  for (std::size_t k = 0; k < in.size(); ++k) {
    EXPECT_NEAR(out[k].t, in[k].t, 1e-9);
    EXPECT_EQ(out[k].p, in[k].p) << k;  // shortest round-trip text: bit-exact
    EXPECT_NEAR(std::abs(out[k].q.dot(in[k].q)), 1.0, 1e-15);
  }
  // No temporary left next to the result.
  for (const auto& entry :
       std::filesystem::directory_iterator(std::filesystem::path(path).parent_path())) {
    EXPECT_EQ(entry.path().filename(), "traj.tum");
  }
}

TEST(TumWriter, EmptyTrajectoryIsHeaderOnly) {
  const std::string path = test::makeTempDir("out_tum") + "/empty.tum";
  writeTum(path, {});
  EXPECT_EQ(readAll(path), "# timestamp tx ty tz qx qy qz qw\n");
}

TEST(TumWriter, RejectsUnreadableContentAndKeepsOldFile) {
  const std::string path = test::makeTempDir("out_tum") + "/traj.tum";
  writeTum(path, sampleTrajectory());
  const std::string before = readAll(path);

  Trajectory nan = sampleTrajectory();
  nan[3].p.y() = std::numeric_limits<double>::quiet_NaN();
  try {
    writeTum(path, nan);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(path + ": pose 3"), std::string::npos) << e.what();
  }
  Trajectory unsorted = sampleTrajectory();
  unsorted[5].t = unsorted[4].t;
  try {
    writeTum(path, unsorted);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("pose 5"), std::string::npos) << e.what();
  }
  EXPECT_EQ(readAll(path), before);
  EXPECT_THROW(writeTum("/nonexistent/dir/traj.tum", sampleTrajectory()), IoError);
}

TEST(SummaryJson, PrettyAtomicAndReparses) {
  const std::string path = test::makeTempDir("out_json") + "/summary.json";
  nlohmann::json j;
  j["frames"] = 1234;
  j["ate_rmse"] = 0.0134734678;
  j["name"] = "fr1/xyz";
  j["bad"] = std::numeric_limits<double>::quiet_NaN();
  j["nested"] = {{"a", {1, 2, 3}}};
  writeSummaryJson(path, j);
  const std::string text = readAll(path);
  EXPECT_NE(text.find("\n  \"ate_rmse\": 0.0134734678"), std::string::npos) << text;
  EXPECT_EQ(text.back(), '\n');
  const nlohmann::json back = nlohmann::json::parse(text);
  EXPECT_EQ(back["frames"], 1234);
  EXPECT_EQ(back["ate_rmse"].get<double>(), 0.0134734678);
  EXPECT_EQ(back["name"], "fr1/xyz");
  EXPECT_TRUE(back["bad"].is_null());
  EXPECT_EQ(back["nested"]["a"][2], 3);
  EXPECT_THROW(writeSummaryJson("/nonexistent/dir/summary.json", j), IoError);
}

TEST(OutputOptions, DefaultsEqualShareConfigAndRangesAreChecked) {
  IniReader shipped = IniReader::fromFile(test::sourceDir() + "/share/config.ini");
  const OutputOptions from_file = OutputOptions::load(shipped);
  const OutputOptions defaults;
  EXPECT_EQ(from_file.write_ply, defaults.write_ply);
  EXPECT_EQ(from_file.write_octomap, defaults.write_octomap);
  EXPECT_EQ(from_file.write_scene, defaults.write_scene);
  EXPECT_EQ(from_file.write_plot, defaults.write_plot);
  EXPECT_EQ(from_file.progress_interval_s, defaults.progress_interval_s);

  IniReader custom =
      IniReader::fromText("[output]\nwrite_ply = false\nprogress_interval_s = 0.5\n");
  const OutputOptions o = OutputOptions::load(custom);
  EXPECT_FALSE(o.write_ply);
  EXPECT_TRUE(o.write_scene);
  EXPECT_EQ(o.progress_interval_s, 0.5);
  IniReader bad = IniReader::fromText("[output]\nprogress_interval_s = 0\n");
  EXPECT_THROW(OutputOptions::load(bad), ConfigError);
}

}  // namespace
}  // namespace rgbdi::output

TEST(TumWriter, FrameAndClockLinesComeBeforeTheColumnHeader) {
  const std::string dir = rgbdi::test::makeTempDir("rgbdi_tum_hdr");
  const std::string path = dir + "/t.tum";
  rgbdi::Trajectory t(1);
  t[0].t = 1.5;
  rgbdi::output::writeTum(path, t, "body (IMU) frame in the world frame\nIMU clock");
  std::ifstream f(path);
  std::string l1, l2, l3;
  std::getline(f, l1);
  std::getline(f, l2);
  std::getline(f, l3);
  EXPECT_EQ(l1, "# body (IMU) frame in the world frame");
  EXPECT_EQ(l2, "# IMU clock");
  EXPECT_EQ(l3, "# timestamp tx ty tz qx qy qz qw");
  EXPECT_EQ(rgbdi::eval::readTum(path).size(), 1u);  // comments are skipped by readers
}
