// End-to-end: wheel odometry through a ROS1 bag (doc/wheels.md, doc/rawlog-convert.md).
// rgbdi-sim --bag writes its encoders' odometry as /odom (nav_msgs/Odometry) and the wheel frame
// on /tf_static; rawlog-convert turns them back into the simulator's CObservationOdometry
// readings (same count, stamps, poses, velocities; the bag has no encoder ticks) and the
// extrinsic into OUT.ini [wheel]; --info reports the wheel stream, --odom-topic chooses or
// leaves it out; rgbdi-slam fuses the converted wheels.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "rgbdi/common/ini_reader.h"
#include "rgbdi/io/rawlog_source.h"
#include "testing/fixtures.h"

namespace {

namespace fs = std::filesystem;
using rgbdi::test::runCommand;

std::string app(const std::string& name) { return rgbdi::test::binDir() + "/" + name; }

std::vector<rgbdi::io::Measurement> readAll(const std::string& rawlog) {
  rgbdi::io::RawlogSource src(rawlog);
  src.logging_enable_console_output = false;
  std::vector<rgbdi::io::Measurement> all;
  rgbdi::io::Measurement m;
  while (src.next(m)) all.push_back(m);
  return all;
}

TEST(RawlogConvertOdometry, SimulatorWheelsSurviveTheBagAndAreFused) {
  const std::string dir = rgbdi::test::makeTempDir("rgbdi_convert_odometry");
  std::ofstream(dir + "/wheels.ini") << "[sim]\nwheel_encoders = on\n";
  std::string out;
  ASSERT_EQ(runCommand(app("rgbdi-sim") +
                           " --profile wheeled_circle --duration 10 --fps 15 --bag --config " +
                           dir + "/wheels.ini --out " + dir + "/seq",
                       &out),
            0)
      << out;
  const std::string seq = dir + "/seq", converted = dir + "/converted.rawlog";
  ASSERT_EQ(runCommand(app("rawlog-convert") + " " + seq + "/sequence.bag -o " + converted +
                           " --camera-yaml " + seq + "/vins_config.yaml --external-images --quiet",
                       &out),
            0)
      << out;
  EXPECT_NE(out.find("wheel odometry: /odom (nav_msgs/Odometry, 501 messages)"), std::string::npos)
      << out;
  EXPECT_NE(out.find("501 wheel odometry observations"), std::string::npos) << out;

  // The same measurements in the same order; the readings equal but for the ticks.
  const auto a = readAll(converted), b = readAll(seq + "/sequence.rawlog");
  ASSERT_EQ(a.size(), b.size());
  std::size_t wheels = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a[i].index(), b[i].index()) << i;
    const auto* wa = std::get_if<rgbdi::WheelOdometrySample>(&a[i]);
    if (!wa) continue;
    const auto& wb = std::get<rgbdi::WheelOdometrySample>(b[i]);
    EXPECT_NEAR(wa->t, wb.t, 1e-6) << i;  // ROS nanoseconds, MRPT 100 ns ticks
    EXPECT_EQ(wa->x_m, wb.x_m) << i;
    EXPECT_EQ(wa->y_m, wb.y_m) << i;
    EXPECT_NEAR(wa->yaw_rad, wb.yaw_rad, 1e-14) << i;
    ASSERT_TRUE(wb.has_velocities);
    EXPECT_TRUE(wa->has_velocities);
    EXPECT_EQ(wa->v_forward_m_s, wb.v_forward_m_s) << i;
    EXPECT_EQ(wa->v_lateral_m_s, wb.v_lateral_m_s) << i;
    EXPECT_EQ(wa->yaw_rate_rad_s, wb.yaw_rate_rad_s) << i;
    EXPECT_TRUE(wb.has_encoders);
    EXPECT_FALSE(wa->has_encoders);  // nav_msgs/Odometry carries no ticks
    ++wheels;
  }
  EXPECT_EQ(wheels, 501u);  // 10 s at 50 Hz

  // The simulator's wheel frame is its body frame: /tf_static says so, OUT.ini keeps it.
  rgbdi::IniReader ini = rgbdi::IniReader::fromFile(dir + "/converted.ini");
  const Eigen::VectorXd R = ini.getVector("wheel", "R_body_wheel", Eigen::VectorXd::Zero(9));
  const Eigen::VectorXd t = ini.getVector("wheel", "t_body_wheel_m", Eigen::VectorXd::Ones(3));
  EXPECT_EQ(R, (Eigen::VectorXd(9) << 1, 0, 0, 0, 1, 0, 0, 0, 1).finished());
  EXPECT_EQ(t, Eigen::VectorXd::Zero(3));

  // --info on the bag: the wheel stream and its verdicts (a clean drive: no finding).
  ASSERT_EQ(runCommand(app("rawlog-convert") + " --info " + seq + "/sequence.bag", &out), 0) << out;
  EXPECT_NE(out.find("  odometry      /odom\n"), std::string::npos) << out;
  EXPECT_NE(out.find("Wheel odometry /odom checked against the IMU /camera/imu:\nWheel: 501 "
                     "readings, 10.000 s, 50.00 Hz\n"),
            std::string::npos)
      << out;
  EXPECT_NE(out.find("moving while the IMU is at rest: 0 times (0.000 s); standing while the IMU "
                     "moves: 0 times (0.000 s)"),
            std::string::npos)
      << out;
  EXPECT_NE(out.find("Wheel warnings: 0\n"), std::string::npos) << out;

  // --odom-topic none: no readings and no wheel extrinsic (no OUT.ini without --camera-yaml).
  ASSERT_EQ(runCommand(app("rawlog-convert") + " " + seq + "/sequence.bag -o " + dir +
                           "/nowheels.rawlog --odom-topic none --external-images --quiet",
                       &out),
            0)
      << out;
  EXPECT_EQ(out.find("wheel odometry"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(dir + "/nowheels.ini"));
  // A topic that is not odometry: the error names it and its type.
  EXPECT_EQ(runCommand(app("rawlog-convert") + " " + seq + "/sequence.bag -o " + dir +
                           "/bad.rawlog --odom-topic /camera/imu --quiet",
                       &out),
            1);
  EXPECT_NE(out.find("odometry topic '/camera/imu' has type sensor_msgs/Imu, expected "
                     "nav_msgs/Odometry"),
            std::string::npos)
      << out;

  // rgbdi-slam on the converted bag with the configuration written, wheels on.
  {
    std::ifstream in(dir + "/converted.ini");
    std::ofstream o(dir + "/slam.ini");
    o << in.rdbuf() << "\n[wheel]\nenable = true\n";
  }
  ASSERT_EQ(runCommand(app("rgbdi-slam") + " --input " + converted + " --config " + dir +
                           "/slam.ini --gt " + dir + "/converted_groundtruth.tum --out " + dir +
                           "/slam --quiet --no-loop",
                       &out),
            0)
      << out;
  std::ifstream f(dir + "/slam/summary.json");
  const nlohmann::json s = nlohmann::json::parse(f);
  ASSERT_TRUE(s.contains("wheel")) << s.dump();
  const auto& w = s["wheel"];
  // Measured: 34 intervals used, 1415 factors solved, none left out; ATE 3.78 mm (the same run
  // on the simulator's own rawlog: the same numbers).
  EXPECT_GT(w["intervals_used"].get<int>(), 20) << w.dump();
  EXPECT_GT(w["factors_solved"].get<int>(), 0) << w.dump();
  EXPECT_EQ(w["intervals_left_out"]["stream_gap"].get<int>(), 0) << w.dump();
  EXPECT_LT(s["evaluation"]["ate_rmse"].get<double>(), 0.02);

  std::error_code ec;
  fs::remove_all(dir, ec);
}

}  // namespace
