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

/// An ASL-layout recording (the dataset's own folders) with the given sensor files ("" = none).
std::string aslRecording(const std::string& imu_yaml, const std::string& cam_yaml) {
  const std::string dir = test::makeTempDir("recording_yaml");
  const fs::path mav = fs::path(dir) / "mav0";
  writeFile(mav / "imu0" / "data.csv", std::string(kImuHeader) + kImuRows);
  writeFile(mav / "state_groundtruth_estimate0" / "data.csv", kGtRows);
  if (!imu_yaml.empty()) writeFile(mav / "imu0" / "sensor.yaml", imu_yaml);
  if (!cam_yaml.empty()) writeFile(mav / "cam0" / "sensor.yaml", cam_yaml);
  return dir;
}

// The EuRoC dataset's own imu0/sensor.yaml and cam0/sensor.yaml, abridged (T_BS as written there,
// its data list over several lines; the camera's intrinsics are a list that is not read).
const char* const kImuYaml =
    "#Default imu sensor yaml file\n"
    "sensor_type: imu\n"
    "comment: VI-Sensor IMU (ADIS16448)\n"
    "\n"
    "# Sensor extrinsics wrt. the body-frame.\n"
    "T_BS:\n"
    "  cols: 4\n"
    "  rows: 4\n"
    "  data: [1.0, 0.0, 0.0, 0.0,\n"
    "         0.0, 1.0, 0.0, 0.0,\n"
    "         0.0, 0.0, 1.0, 0.0,\n"
    "         0.0, 0.0, 0.0, 1.0]\n"
    "rate_hz: 285.5\n"
    "\n"
    "# inertial sensor noise model parameters (static)\n"
    "gyroscope_noise_density: 1.5e-04     # [ rad / s / sqrt(Hz) ]   ( gyro \"white noise\" )\n"
    "gyroscope_random_walk: 2.5e-05       # [ rad / s^2 / sqrt(Hz) ] ( gyro bias diffusion )\n"
    "accelerometer_noise_density: 3.5e-03  # [ m / s^2 / sqrt(Hz) ]   ( accel \"white noise\" )\n"
    "accelerometer_random_walk: 4.5e-03    # [ m / s^3 / sqrt(Hz) ].  ( accel bias diffusion )\n";
const char* const kCamYaml =
    "sensor_type: camera\n"
    "T_BS:\n"
    "  cols: 4\n"
    "  rows: 4\n"
    "  data: [0.0, 0.0, 1.0, 0.1, -1.0, 0.0, 0.0, 0.2, 0.0, -1.0, 0.0, 0.3, 0.0, 0.0, 0.0, 1.0]\n"
    "rate_hz: 20\n"
    "resolution: [752, 480]\n"
    "camera_model: pinhole\n"
    "intrinsics: [458.654, 457.296, 367.215, 248.375] #fu, fv, cu, cv\n";

TEST(RecordingEuroc, SensorFilesOfTheAslLayoutGiveTheNoiseAndTheCamera) {
  const Recording r = readEurocRecording(aslRecording(kImuYaml, kCamYaml));
  EXPECT_NE(r.sensor.name.find("VI-Sensor IMU (ADIS16448) ("), std::string::npos) << r.sensor.name;
  EXPECT_EQ(r.sensor.rate_hz, 285.5);
  EXPECT_EQ(r.sensor.gyr_noise_density, 1.5e-4);
  EXPECT_EQ(r.sensor.gyr_random_walk, 2.5e-5);
  EXPECT_EQ(r.sensor.acc_noise_density, 3.5e-3);
  EXPECT_EQ(r.sensor.acc_random_walk, 4.5e-3);
  Eigen::Matrix4d expected;
  expected << 0, 0, 1, 0.1, -1, 0, 0, 0.2, 0, -1, 0, 0.3, 0, 0, 0, 1;
  EXPECT_EQ(r.T_body_cam.matrix(), expected);

  // Without them (or in the flat layout): the EuRoC MAV's sensor and camera.
  const Recording plain = readEurocRecording(aslRecording("", ""));
  const Recording flat =
      readEurocRecording(flatRecording(std::string(kImuHeader) + kImuRows, kGtRows));
  for (const Recording* x : {&plain, &flat}) {
    EXPECT_EQ(x->sensor.name, "ADIS16448 (EuRoC MAV imu0/sensor.yaml)");
    EXPECT_EQ(x->sensor.gyr_noise_density, 1.6968e-4);
    EXPECT_NEAR(x->T_body_cam.translation().x(), -0.0216401454975, 1e-12);
  }
}

TEST(RecordingEuroc, SensorFileErrorsNameTheFileAndTheFault) {
  struct Case {
    std::string imu, cam, file, expected;
  };
  const std::string imu_ok = kImuYaml;
  auto without = [](std::string text, const std::string& line_start) {
    const auto a = text.find(line_start);
    return text.erase(a, text.find('\n', a) - a + 1);
  };
  const std::vector<Case> cases = {
      {without(imu_ok, "gyroscope_random_walk"), "", "imu0/sensor.yaml",
       ": no 'gyroscope_random_walk'"},
      {imu_ok + "rate_hz_x: 1\n", "", "imu0/sensor.yaml", ""},
      {without(imu_ok, "rate_hz") + "rate_hz: fast\n", "", "imu0/sensor.yaml",
       ": 'rate_hz' value 'fast' is not a finite number"},
      {without(imu_ok, "accelerometer_noise_density") + "accelerometer_noise_density: 0\n", "",
       "imu0/sensor.yaml", ": rate and noise values must be positive"},
      {"sensor_type: imu\nT_BS:\n  data: [1, 0, 0, 0.5, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]\n" +
           without(without(imu_ok, "sensor_type"), "T_BS"),
       "", "imu0/sensor.yaml",
       ": T_BS is not the identity; the ground truth must be of the IMU's own frame (body = IMU)"},
      {imu_ok, "T_BS:\n  data: [1, 0, 0, 0,\n  0, 1, 0, 0\n", "cam0/sensor.yaml",
       " line 2: T_BS data list not closed with ']'"},
      {imu_ok, "T_BS:\n  data: [1, 0, 0, 0, 0, 1, 0, 0]\n", "cam0/sensor.yaml",
       " line 2: T_BS data has 8 values, expected 16"},
      {imu_ok, "T_BS:\n  data: [2, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]\n",
       "cam0/sensor.yaml", " line 2: T_BS's rotation is not a rotation (R R^T != I or det < 0)"},
      {imu_ok, "T_BS:\n  data: [1, 0, 0, x, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]\n",
       "cam0/sensor.yaml", " line 2: T_BS value 'x' is not a finite number"},
      {imu_ok, "sensor_type: camera\n", "cam0/sensor.yaml", ": no T_BS"},
      {imu_ok, "just words\n", "cam0/sensor.yaml", " line 1: expected 'key: value'"},
  };
  for (const Case& c : cases) {
    const std::string dir = aslRecording(c.imu, c.cam);
    const std::string message = errorOf(dir);
    if (c.expected.empty()) {
      EXPECT_EQ(message, "") << "an unknown key is ignored";
      continue;
    }
    EXPECT_EQ(message, (fs::path(dir) / "mav0" / c.file).string() + c.expected);
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
