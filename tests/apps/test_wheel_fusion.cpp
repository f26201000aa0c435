// Wheel odometry end to end (doc/wheels.md): rgbdi-sim writes encoder odometry, rgbdi-slam fuses
// it behind [wheel] enable. A wrong wheel radius is learnt and the odometry is no worse than
// without wheels; encoder faults (stuck wheel, robot lifted) are left out and counted; on a
// sequence without odometry the switch changes no trajectory.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "testing/fixtures.h"

using rgbdi::test::binDir;
using rgbdi::test::makeTempDir;
using rgbdi::test::runCommand;

namespace {

/// A generated wheeled_circle sequence (20 s, 15 Hz) with the [sim] text `sim` (in a file whose
/// content keys the sequence cache).
std::string sequenceWith(const std::string& name, const std::string& sim) {
  const std::string dir = makeTempDir("rgbdi_wheel_sim_cfg");
  const std::string cfg = dir + "/" + name + ".ini";
  std::ofstream(cfg) << "[sim]\n" << sim;
  return rgbdi::test::cachedSimSequence(
      "--profile wheeled_circle --duration 20 --fps 15 --config " + cfg);
}

struct SlamRun {
  nlohmann::json summary;
  std::string out;
};

/// rgbdi-slam on `seq` with its config.ini plus `extra`; fails the test on a non-zero status.
SlamRun slam(const std::string& seq, const std::string& extra, const std::string& flags = "") {
  SlamRun r;
  r.out = makeTempDir("rgbdi_wheel_run");
  const std::string config = r.out + "_config.ini";
  {
    std::ifstream in(seq + "/config.ini");
    std::ofstream o(config);
    o << in.rdbuf() << "\n" << extra;
  }
  std::string log;
  const int rc = runCommand(binDir() + "/rgbdi-slam --input " + seq + "/sequence.rawlog --config " +
                                config + " --gt " + seq + "/groundtruth.tum --out " + r.out +
                                " --quiet --no-loop " + flags,
                            &log);
  EXPECT_EQ(rc, 0) << log;
  std::ifstream f(r.out + "/summary.json");
  r.summary = nlohmann::json::parse(f);
  return r;
}

std::string fileText(const std::string& path) {
  std::ifstream f(path);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

double ate(const SlamRun& r) { return r.summary["evaluation"]["ate_rmse"].get<double>(); }

const char* const kWheelsOn = "[wheel]\nenable = true\n";

}  // namespace

TEST(WheelFusion, AWrongRadiusIsLearntAndTheOdometryIsNoWorse) {
  // Both wheels 3 % larger than the robot assumes: it reports 3 % too little distance and turn.
  const std::string seq = sequenceWith(
      "radius",
      "wheel_encoders = on\nwheel_radius_error_left = 0.03\nwheel_radius_error_right = "
      "0.03\n");
  const SlamRun without = slam(seq, kWheelsOn, "--no-wheels");
  const SlamRun with = slam(seq, kWheelsOn);
  EXPECT_FALSE(without.summary.contains("wheel"));
  const auto& w = with.summary["wheel"];
  // Measured: 1.0294 after 20 s (0.06 % off).
  EXPECT_NEAR(w["scale_forward"].get<double>(), 1.03, 0.003 * 1.03) << w.dump();
  EXPECT_GT(w["intervals_used"].get<int>(), 80) << w.dump();
  EXPECT_EQ(w["intervals_left_out"]["stream_gap"].get<int>(), 0) << w.dump();
  EXPECT_EQ(w["intervals_left_out"]["slip"].get<int>() +
                w["intervals_left_out"]["stuck"].get<int>() +
                w["intervals_left_out"]["lifted"].get<int>(),
            0)
      << w.dump();
  // Measured: 4.28 mm without wheels, 4.23 mm with.
  EXPECT_LE(ate(with), ate(without) + 2e-4) << ate(with) << " vs " << ate(without);
}

TEST(WheelFusion, EncoderFaultsAreLeftOutAndCounted) {
  // A blocked left wheel for 1.5 s from 6 s, a spinning one for 1.5 s from 13 s.
  const std::string seq =
      sequenceWith("faults", "wheel_encoders = on\nwheel_events = stuck:6:1.5,spin:13:1.5\n");
  const SlamRun without = slam(seq, kWheelsOn, "--no-wheels");
  const SlamRun with = slam(seq, kWheelsOn);
  const auto& w = with.summary["wheel"];
  EXPECT_GT(w["intervals_left_out"]["stuck"].get<int>(), 0) << w.dump();
  EXPECT_GT(w["intervals_left_out"]["slip"].get<int>(), 0) << w.dump();
  // Each event is found: a left-out episode of its kind overlaps it; none starts elsewhere.
  const auto found = [&](const std::string& kind, double start, double end) {
    for (const auto& e : w["left_out_episodes"])
      if (e["kind"] == kind && e["start_s"].get<double>() < end && e["end_s"].get<double>() > start)
        return true;
    return false;
  };
  EXPECT_TRUE(found("stuck", 6.0, 7.5)) << w.dump();
  EXPECT_TRUE(found("slip", 13.0, 14.5)) << w.dump();
  for (const auto& e : w["left_out_episodes"]) {
    const double t = e["start_s"].get<double>();
    EXPECT_TRUE((t > 5.0 && t < 8.0) || (t > 12.0 && t < 15.0)) << e.dump();
  }
  EXPECT_LE(ate(with), 1.1 * ate(without)) << ate(with) << " vs " << ate(without);
}

TEST(WheelFusion, WithoutOdometryTheSwitchChangesNoTrajectory) {
  const std::string seq = sequenceWith("none", "wheel_encoders = off\n");
  const SlamRun off = slam(seq, "");
  const SlamRun on = slam(seq, kWheelsOn);
  for (const char* f : {"trajectory.tum", "trajectory_odometry.tum", "keyframes.tum"})
    EXPECT_EQ(fileText(on.out + "/" + f), fileText(off.out + "/" + f)) << f;
  EXPECT_EQ(on.summary["wheel"]["intervals_used"].get<int>(), 0);
  EXPECT_GT(on.summary["wheel"]["intervals_left_out"]["stream_gap"].get<int>(), 0);
}
