// Recording readers: known values of the EuRoC fixture's first rows, the dataset's own folder
// layout, and errors naming the file, the line and the fault.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "rgbdi/sim/recording.h"
#include "testing/fixtures.h"

namespace rgbdi::sim {
namespace {

namespace fs = std::filesystem;

const char* const kImuHeader =
    "#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1],w_RS_S_z [rad s^-1],"
    "a_RS_S_x [m s^-2],a_RS_S_y [m s^-2],a_RS_S_z [m s^-2]\n";
const char* const kImuRows =
    "1000000000,0.1,0.2,0.3,1,2,9.81\n"
    "1005000000,0.1,0.2,0.3,1,2,9.81\n"
    "1010000000,0.1,0.2,0.3,1,2,9.81\n";
const char* const kGtRows =
    "1000000000,1,2,3,1,0,0,0\n"
    "1005000000,1,2,3,1,0,0,0\n";

void writeFile(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  std::ofstream(path) << text;
}

/// A flat recording folder with the given file contents.
std::string flatRecording(const std::string& imu, const std::string& gt) {
  const std::string dir = test::makeTempDir("recording");
  writeFile(fs::path(dir) / "imu0.csv", imu);
  writeFile(fs::path(dir) / "groundtruth.csv", gt);
  return dir;
}

/// The RecordingError message of reading `dir` (empty when it reads).
std::string errorOf(const std::string& dir) {
  try {
    readEurocRecording(dir);
  } catch (const RecordingError& e) {
    return e.what();
  }
  return {};
}

TEST(RecordingEuroc, FixtureFirstRowsAndCounts) {
  const std::string dir = test::fixturePath("euroc_v102");
  RGBDI_REQUIRE_FIXTURE(dir + "/imu0.csv");
  const Recording r = readRecording(dir, "euroc");
  EXPECT_EQ(r.format, "euroc");
  ASSERT_EQ(r.imu.size(), 7999u);
  ASSERT_EQ(r.ground_truth.size(), 3340u);
  // 1403715523912140000,-0.0006981317,0.0195476876,0.0767944871,9.218251,0.3023717083,-3.1544724167
  EXPECT_EQ(r.imu[0].t, nanosecondsToSeconds(1403715523912140000LL));
  EXPECT_EQ(r.imu[0].gyr, Eigen::Vector3d(-0.0006981317, 0.0195476876, 0.0767944871));
  EXPECT_EQ(r.imu[0].acc, Eigen::Vector3d(9.218251, 0.3023717083, -3.1544724167));
  EXPECT_NEAR(r.imu[1].t - r.imu[0].t, 0.005, 1e-6);
  // 1403715524922140000,0.515292,1.996597,0.971028,0.161869,0.790012,-0.205215,0.554587,
  // -0.006748,-0.01478,-0.00455,-0.002153,0.020744,0.075806,-0.013337,0.103464,0.093086
  const RecordedPose& g = r.ground_truth[0];
  EXPECT_EQ(g.t, nanosecondsToSeconds(1403715524922140000LL));
  EXPECT_EQ(g.p_world, Eigen::Vector3d(0.515292, 1.996597, 0.971028));
  const Eigen::Quaterniond q = Eigen::Quaterniond(0.161869, 0.790012, -0.205215, 0.554587);
  EXPECT_NEAR(g.q_world_body.angularDistance(q.normalized()), 0.0, 1e-12);
  EXPECT_NEAR(g.q_world_body.norm(), 1.0, 1e-15);
  ASSERT_TRUE(g.has_velocity);
  EXPECT_EQ(g.v_world, Eigen::Vector3d(-0.006748, -0.01478, -0.00455));
  ASSERT_TRUE(g.has_bias);
  EXPECT_EQ(g.bias.gyr, Eigen::Vector3d(-0.002153, 0.020744, 0.075806));
  EXPECT_EQ(g.bias.acc, Eigen::Vector3d(-0.013337, 0.103464, 0.093086));
  // The sensor and camera of the dataset.
  EXPECT_EQ(r.sensor.rate_hz, 200.0);
  EXPECT_EQ(r.sensor.gyr_noise_density, 1.6968e-4);
  EXPECT_EQ(r.sensor.gyr_random_walk, 1.9393e-5);
  EXPECT_EQ(r.sensor.acc_noise_density, 2.0e-3);
  EXPECT_EQ(r.sensor.acc_random_walk, 3.0e-3);
  EXPECT_NEAR(r.T_body_cam.translation().x(), -0.0216401454975, 1e-12);
  EXPECT_NEAR(r.T_body_cam(1, 0), 0.999557249008, 1e-6);
  EXPECT_NEAR(
      (r.T_body_cam.rotation().transpose() * r.T_body_cam.rotation() - Eigen::Matrix3d::Identity())
          .norm(),
      0.0, 1e-14);
}

TEST(RecordingEuroc, NanosecondsToSecondsKeepsTheFraction) {
  EXPECT_EQ(nanosecondsToSeconds(1000000000LL), 1.0);
  EXPECT_EQ(nanosecondsToSeconds(1500000000LL), 1.5);
  EXPECT_EQ(nanosecondsToSeconds(5000000LL), 0.005);
  // Whole seconds and fraction rounded separately: within half an ulp of the true value.
  EXPECT_NEAR(nanosecondsToSeconds(1403715523912140000LL), 1403715523.91214, 2.4e-7);
}

TEST(RecordingEuroc, ReadsTheDatasetsOwnLayoutAndCrLf) {
  const std::string dir = test::makeTempDir("recording_asl");
  writeFile(fs::path(dir) / "mav0" / "imu0" / "data.csv",
            std::string(kImuHeader) + "1000000000,0.1,0.2,0.3,1,2,9.81\r\n" +
                "1005000000, -0.1, -0.2, -0.3, -1, -2, 9.8\r\n");
  writeFile(fs::path(dir) / "mav0" / "state_groundtruth_estimate0" / "data.csv",
            "1000000000,1,2,3,1,0,0,0,0.5,0,0\n1005000000,1,2,3,0,1,0,0,0.5,0,0\n");
  const Recording r = readEurocRecording(dir);
  ASSERT_EQ(r.imu.size(), 2u);
  EXPECT_EQ(r.imu[1].t, 1.005);
  EXPECT_EQ(r.imu[1].gyr, Eigen::Vector3d(-0.1, -0.2, -0.3));
  EXPECT_EQ(r.imu[1].acc, Eigen::Vector3d(-1, -2, 9.8));
  ASSERT_EQ(r.ground_truth.size(), 2u);
  EXPECT_TRUE(r.ground_truth[0].has_velocity);
  EXPECT_FALSE(r.ground_truth[0].has_bias);
  EXPECT_EQ(r.ground_truth[0].v_world, Eigen::Vector3d(0.5, 0, 0));
  EXPECT_EQ(r.ground_truth[1].q_world_body.coeffs(), Eigen::Vector4d(1, 0, 0, 0));  // x y z w
}

TEST(RecordingEuroc, ErrorsNameTheFileTheLineAndTheFault) {
  const std::string imu_ok = std::string(kImuHeader) + kImuRows;
  struct Case {
    std::string imu, gt, file, expected;
  };
  const std::vector<Case> cases = {
      {std::string(kImuHeader) + "1000000000,0.1,0.2,0.3,1,2\n", kGtRows, "imu0.csv",
       "imu0.csv line 2: expected 7 comma-separated values (t [ns], w xyz, a xyz), got 6"},
      {std::string(kImuHeader) + kImuRows + "1020000000,0.1,abc,0.3,1,2,9.81\n", kGtRows,
       "imu0.csv", "imu0.csv line 5: angular rate 'abc' is not a finite number"},
      {std::string(kImuHeader) + kImuRows + "1010000000,0.1,0.2,0.3,1,2,9.81\n", kGtRows,
       "imu0.csv", "imu0.csv line 5: timestamp 1010000000 does not increase (previous 1010000000)"},
      {std::string(kImuHeader) + "1.5e9,0.1,0.2,0.3,1,2,9.81\n", kGtRows, "imu0.csv",
       "imu0.csv line 2: timestamp '1.5e9' is not a non-negative integer of nanoseconds"},
      {std::string(kImuHeader) + "1000000000,0.1,0.2,0.3,1,2,nan\n", kGtRows, "imu0.csv",
       "imu0.csv line 2: acceleration 'nan' is not a finite number"},
      {std::string(kImuHeader) + "1000000000,0.1,0.2,0.3,1,2,9.81\n", kGtRows, "imu0.csv",
       "imu0.csv: fewer than 2 IMU samples"},
      {imu_ok, "1000000000,1,2,3,1,0,0\n", "groundtruth.csv",
       "groundtruth.csv line 1: expected 8 (t, p xyz, q wxyz), 11 (+ v xyz) or 17 (+ bg, ba) "
       "values, got 7"},
      {imu_ok, "1000000000,1,2,3,0.5,0,0,0\n", "groundtruth.csv",
       "groundtruth.csv line 1: quaternion (w x y z) has norm 0.500000, not 1"},
      {imu_ok, "# header\n1000000000,1,2,3,1,0,0,0\n999999999,1,2,3,1,0,0,0\n", "groundtruth.csv",
       "groundtruth.csv line 3: timestamp 999999999 does not increase (previous 1000000000)"},
  };
  for (const Case& c : cases) {
    const std::string dir = flatRecording(c.imu, c.gt);
    const std::string message = errorOf(dir);
    EXPECT_EQ(message, (fs::path(dir) / c.file).string() + c.expected.substr(c.file.size()))
        << c.expected;
  }
}

TEST(RecordingEuroc, MissingFilesAndUnknownFormat) {
  const std::string dir = test::makeTempDir("recording_empty");
  const std::string message = errorOf(dir);
  EXPECT_NE(message.find(dir + ": no EuRoC IMU file (looked for "), std::string::npos) << message;
  EXPECT_NE(message.find("imu0.csv"), std::string::npos) << message;
  EXPECT_NE(errorOf(dir + "/absent").find("not a directory"), std::string::npos);
  writeFile(fs::path(dir) / "imu0.csv", std::string(kImuHeader) + kImuRows);
  EXPECT_NE(errorOf(dir).find("no EuRoC ground-truth file"), std::string::npos);
  EXPECT_THROW(readRecording(dir, "kitti"), std::invalid_argument);
}

}  // namespace
}  // namespace rgbdi::sim
