// A blackout on the ramps, carried by the gyroscope and the wheels (doc/wheels.md "Blind frames"):
// 5 s of black frames from the top of wheeled_slopes' first ramp down to the flat. With the wheels
// the run goes on without a reset and its odometry ATE stays within 1 cm of the clean run's
// (issue 34's bound); the factor over the blind interval taken as planar in the wheel frame where
// the blackout began ([wheel] direction_from_gyro = never) misses it, as main did before.
#include <gtest/gtest.h>

#include <fstream>
#include <future>
#include <nlohmann/json.hpp>
#include <string>

#include "testing/fixtures.h"

using rgbdi::test::binDir;
using rgbdi::test::makeTempDir;
using rgbdi::test::runCommand;

namespace {

/// wheeled_slopes with encoders, 16 s at 15 Hz (the first ramp rises from 7.5 s to its top at
/// 9.5 s and ends at 12 s), with the rgbdi-sim flags `extra`.
std::string slopes(const std::string& extra) {
  const std::string dir = makeTempDir("rgbdi_wheel_blackout_cfg");
  const std::string cfg = dir + "/wheels.ini";
  std::ofstream(cfg) << "[sim]\nwheel_encoders = on\n";
  return rgbdi::test::cachedSimSequence(
      "--profile wheeled_slopes --duration 16 --fps 15 --config " + cfg + " " + extra);
}

/// rgbdi-slam (no loop closing) on `seq` with the wheels fused and the [wheel] lines `wheel`, the
/// ground plane off: it holds the height after the ramp by itself (the planar factor then grows by
/// 0.9 mm only), and this test is about the factor over the blind interval.
nlohmann::json slam(const std::string& seq, const std::string& wheel = "") {
  const std::string out = makeTempDir("rgbdi_wheel_blackout_run");
  const std::string config = out + "_config.ini";
  {
    std::ifstream in(seq + "/config.ini");
    std::ofstream o(config);
    o << in.rdbuf() << "\n[wheel]\nenable = true\nground_plane_sigma_m = 0\n" << wheel;
  }
  std::string log;
  const int rc = runCommand(binDir() + "/rgbdi-slam --input " + seq + "/sequence.rawlog --config " +
                                config + " --gt " + seq + "/groundtruth.tum --out " + out +
                                " --quiet --no-loop --no-save-map",
                            &log);
  EXPECT_EQ(rc, 0) << log;
  std::ifstream f(out + "/summary.json");
  return nlohmann::json::parse(f);
}

double odometryAte(const nlohmann::json& s) {
  return s["evaluation_odometry"]["ate_rmse"].get<double>();
}

}  // namespace

TEST(WheelBlackout, FiveSecondsBlackOverARampStayWithinOneCentimetreOfTheCleanRun) {
  auto clean_seq = std::async(std::launch::async, [] { return slopes(""); });
  auto black_seq = std::async(std::launch::async, [] { return slopes("--blackout 10:5"); });
  const nlohmann::json clean = slam(clean_seq.get());
  const std::string black = black_seq.get();
  const nlohmann::json carried = slam(black);
  const nlohmann::json planar = slam(black, "direction_from_gyro = never\n");
  EXPECT_EQ(carried["resets"].get<int>(), 0);
  EXPECT_EQ(carried["wheel"]["intervals_left_out"]["stream_gap"].get<int>(), 0);
  const double growth = odometryAte(carried) - odometryAte(clean);
  // Measured: clean 6.4 mm, 3-D 8.8 mm (+2.4), planar 17.8 mm (+11.4).
  EXPECT_LT(growth, 0.010) << "clean " << odometryAte(clean) << " m, blackout "
                           << odometryAte(carried) << " m";
  EXPECT_GT(odometryAte(planar) - odometryAte(clean), 0.010)
      << "the planar factor over the ramp's end is expected to miss the bound";
}
