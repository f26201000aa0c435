// [stream] options: defaults equal share/config.ini, ranges are enforced.
#include <gtest/gtest.h>

#include "rgbdi/io/stream_options.h"
#include "testing/fixtures.h"

namespace rgbdi::io {
namespace {

/// The ConfigError StreamOptions::load() raises for the INI `text` (named `file`), or "no error".
std::string loadError(const std::string& text, const std::string& file) {
  IniReader ini = IniReader::fromText(text, file);
  try {
    StreamOptions::load(ini);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "no error";
}

TEST(StreamOptions, DefaultsEqualTheShippedConfig) {
  IniReader ini = IniReader::fromFile(rgbdi::test::sourceDir() + "/share/config.ini");
  const StreamOptions o = StreamOptions::load(ini);
  const StreamOptions d;
  EXPECT_EQ(o.imu_reorder_window_s, d.imu_reorder_window_s);
  EXPECT_EQ(o.image_reorder_window_s, d.image_reorder_window_s);
  EXPECT_EQ(o.imu_gap_factor, d.imu_gap_factor);
  EXPECT_EQ(o.image_gap_factor, d.image_gap_factor);
  EXPECT_EQ(o.imu_rate_tolerance, d.imu_rate_tolerance);
  EXPECT_EQ(o.g_units_min_m_s2, d.g_units_min_m_s2);
  EXPECT_EQ(o.g_units_max_m_s2, d.g_units_max_m_s2);
  EXPECT_EQ(o.acc_magnitude_tolerance, d.acc_magnitude_tolerance);
  EXPECT_EQ(o.depth_median_min_m, d.depth_median_min_m);
  EXPECT_EQ(o.depth_median_max_m, d.depth_median_max_m);
  EXPECT_EQ(o.depth_check_step_px, d.depth_check_step_px);
  EXPECT_EQ(o.max_listed_issues, d.max_listed_issues);
  EXPECT_EQ(o.accel_scale, d.accel_scale);
  EXPECT_EQ(o.accel_check_samples, d.accel_check_samples);
  EXPECT_EQ(o.accel_check_max_s, d.accel_check_max_s);
  EXPECT_EQ(o.time_jump_back_s, d.time_jump_back_s);
  EXPECT_EQ(o.constant_image_max_range, d.constant_image_max_range);
  EXPECT_EQ(o.image_check_step_px, d.image_check_step_px);
  EXPECT_EQ(o.image_rate_limit_hz, d.image_rate_limit_hz);
  EXPECT_EQ(o.wheel_gap_factor, d.wheel_gap_factor);
  EXPECT_EQ(o.wheel_rest_window_s, d.wheel_rest_window_s);
  EXPECT_EQ(o.wheel_rest_gyr_rad_s, d.wheel_rest_gyr_rad_s);
  EXPECT_EQ(o.wheel_rest_acc_std_m_s2, d.wheel_rest_acc_std_m_s2);
  EXPECT_EQ(o.wheel_rest_speed_m_s, d.wheel_rest_speed_m_s);
  EXPECT_EQ(o.wheel_rest_yaw_rate_rad_s, d.wheel_rest_yaw_rate_rad_s);
  // Every key of [stream] is one that StreamOptions reads.
  ini.acceptConfigSectionsExcept({"stream"});
  EXPECT_NO_THROW(ini.checkNoUnknownKeys());
}

TEST(StreamOptions, AccelScaleAndTimeJumpAreValidated) {
  IniReader ini =
      IniReader::fromText("[stream]\naccel_scale = 9.80665\ntime_jump_back_s = 2\n", "a.ini");
  const StreamOptions o = StreamOptions::load(ini);
  EXPECT_EQ(o.accel_scale, 9.80665);
  EXPECT_EQ(o.time_jump_back_s, 2.0);
  EXPECT_EQ(loadError("[stream]\naccel_scale = 0\n", "z.ini"),
            "z.ini [stream] accel_scale: value 0 is out of the accepted range [0.001, 1000]");
  EXPECT_EQ(loadError("[stream]\ntime_jump_back_s = 0.08\n", "j.ini"),
            "j.ini [stream] time_jump_back_s: must be larger than imu_reorder_window_s and "
            "image_reorder_window_s");
}

TEST(StreamOptions, LoadsValuesAndRejectsBadOnes) {
  IniReader ini = IniReader::fromText(
      "[stream]\nimu_reorder_window_s = 0.02\nmax_listed_issues = 0\n", "t.ini");
  const StreamOptions o = StreamOptions::load(ini);
  EXPECT_EQ(o.imu_reorder_window_s, 0.02);
  EXPECT_EQ(o.max_listed_issues, 0);

  EXPECT_EQ(loadError("[stream]\nimage_gap_factor = 0.5\n", "bad.ini"),
            "bad.ini [stream] image_gap_factor: value 0.5 is out of the accepted range [1, 1000]");
  IniReader limited = IniReader::fromText("[stream]\nimage_rate_limit_hz = 15\n", "l.ini");
  EXPECT_EQ(StreamOptions::load(limited).image_rate_limit_hz, 15.0);
  EXPECT_EQ(loadError("[stream]\nimage_rate_limit_hz = -1\n", "n.ini"),
            "n.ini [stream] image_rate_limit_hz: value -1 is out of the accepted range [0, "
            "1000]");
  EXPECT_EQ(loadError("[stream]\ndepth_median_min_m = 30\n", "inv.ini"),
            "inv.ini [stream] depth_median_max_m: must be larger than depth_median_min_m");
}

TEST(StreamConfig, LoadsStreamImuAndExtrinsic) {
  IniReader ini = IniReader::fromText(
      "[imu]\nrate_hz = 400\n[extrinsic]\nsensor_pose_tolerance_m = 0.05\n", "c.ini");
  const StreamConfig c = StreamConfig::load(ini);
  EXPECT_EQ(c.imu.rate_hz, 400.0);
  EXPECT_EQ(c.extrinsic.sensor_pose_tolerance_m, 0.05);
  EXPECT_EQ(c.stream.imu_gap_factor, 3.0);
}

}  // namespace
}  // namespace rgbdi::io
