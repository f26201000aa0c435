// Online calibration of the wheel odometry end to end (doc/wheels.md "Online calibration"): on
// a generated wheeled_circle (20 s, 15 Hz, both wheels 3 % large), a wheel extrinsic configured
// 10 deg wrong in yaw is learnt with [wheel] estimate_extrinsic_yaw, together with the radius,
// and the summary reports it.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "testing/fixtures.h"

using rgbdi::test::binDir;
using rgbdi::test::makeTempDir;
using rgbdi::test::runCommand;

namespace {

/// The sequence of test_wheel_fusion's radius test (same [sim] text: the same cached sequence).
std::string radiusSequence() {
  const std::string dir = makeTempDir("rgbdi_wheel_calib_cfg");
  const std::string cfg = dir + "/radius.ini";
  std::ofstream(cfg) << "[sim]\nwheel_encoders = on\nwheel_radius_error_left = 0.03\n"
                        "wheel_radius_error_right = 0.03\n";
  return rgbdi::test::cachedSimSequence(
      "--profile wheeled_circle --duration 20 --fps 15 --config " + cfg);
}

/// rgbdi-slam (no loop closing) with the wheels fused and the [wheel] lines `wheel`.
nlohmann::json slam(const std::string& seq, const std::string& wheel) {
  const std::string out = makeTempDir("rgbdi_wheel_calib_run");
  const std::string config = out + "_config.ini";
  {
    std::ifstream in(seq + "/config.ini");
    std::ofstream o(config);
    o << in.rdbuf() << "\n[wheel]\nenable = true\n" << wheel;
  }
  std::string log;
  const int rc =
      runCommand(binDir() + "/rgbdi-slam --input " + seq + "/sequence.rawlog --config " + config +
                     " --gt " + seq + "/groundtruth.tum --out " + out + " --quiet --no-loop",
                 &log);
  EXPECT_EQ(rc, 0) << log;
  std::ifstream f(out + "/summary.json");
  return nlohmann::json::parse(f);
}

double ate(const nlohmann::json& s) { return s["evaluation"]["ate_rmse"].get<double>(); }

}  // namespace

TEST(WheelCalibration, ATenDegreeWrongExtrinsicYawIsLearnt) {
  const std::string seq = radiusSequence();
  // The simulated wheel frame is the body frame; configured: turned by +10 deg about z, so the
  // correction to learn is -10 deg.
  const double a = 10.0 * M_PI / 180.0;
  const std::string wrong = "R_body_wheel = " + std::to_string(std::cos(a)) + " " +
                            std::to_string(-std::sin(a)) + " 0 " + std::to_string(std::sin(a)) +
                            " " + std::to_string(std::cos(a)) + " 0 0 0 1\n";
  const nlohmann::json right = slam(seq, "");
  const nlohmann::json learnt = slam(seq, wrong + "estimate_extrinsic_yaw = true\n");
  const auto& w = learnt["wheel"];
  EXPECT_TRUE(w["extrinsic_yaw_estimated"].get<bool>());
  EXPECT_FALSE(w["time_offset_estimated"].get<bool>());
  // Measured: -9.99 deg after 20 s; the radius as without the yaw error (1.0294).
  EXPECT_NEAR(w["extrinsic_yaw_correction_rad"].get<double>(), -a, 0.5 * M_PI / 180.0) << w.dump();
  EXPECT_NEAR(w["scale_forward"].get<double>(), 1.03, 0.003 * 1.03) << w.dump();
  EXPECT_EQ(w["time_offset_s"].get<double>(), 0.0);
  EXPECT_EQ(right["wheel"]["extrinsic_yaw_correction_rad"].get<double>(), 0.0);
  // Measured: 4.19 mm, with the right extrinsic 4.20 mm.
  EXPECT_LE(ate(learnt), ate(right) + 2e-4) << ate(learnt) << " vs " << ate(right);
}
