#include "rgbdi/io/stream_options.h"

#include <algorithm>

namespace rgbdi::io {

StreamOptions StreamOptions::load(IniReader& ini) {
  StreamOptions o;
  const std::string s = "stream";
  o.imu_reorder_window_s =
      ini.getDouble(s, "imu_reorder_window_s", o.imu_reorder_window_s, 0.0, 10.0);
  o.image_reorder_window_s =
      ini.getDouble(s, "image_reorder_window_s", o.image_reorder_window_s, 0.0, 10.0);
  o.imu_gap_factor = ini.getDouble(s, "imu_gap_factor", o.imu_gap_factor, 1.0, 1000.0);
  o.image_gap_factor = ini.getDouble(s, "image_gap_factor", o.image_gap_factor, 1.0, 1000.0);
  o.imu_rate_tolerance = ini.getDouble(s, "imu_rate_tolerance", o.imu_rate_tolerance, 0.0, 10.0);
  o.g_units_min_m_s2 = ini.getDouble(s, "g_units_min_m_s2", o.g_units_min_m_s2, 0.0, 9.0);
  o.g_units_max_m_s2 = ini.getDouble(s, "g_units_max_m_s2", o.g_units_max_m_s2, 0.0, 9.0);
  if (o.g_units_max_m_s2 < o.g_units_min_m_s2)
    ini.fail(s, "g_units_max_m_s2", "must not be smaller than g_units_min_m_s2");
  o.acc_magnitude_tolerance =
      ini.getDouble(s, "acc_magnitude_tolerance", o.acc_magnitude_tolerance, 0.0, 10.0);
  o.depth_median_min_m = ini.getDouble(s, "depth_median_min_m", o.depth_median_min_m, 0.0, 1000.0);
  o.depth_median_max_m = ini.getDouble(s, "depth_median_max_m", o.depth_median_max_m, 0.0, 1e6);
  if (o.depth_median_max_m <= o.depth_median_min_m)
    ini.fail(s, "depth_median_max_m", "must be larger than depth_median_min_m");
  o.depth_check_step_px = ini.getInt(s, "depth_check_step_px", o.depth_check_step_px, 1, 64);
  o.max_listed_issues = ini.getInt(s, "max_listed_issues", o.max_listed_issues, 0, 100000);
  o.accel_scale = ini.getDouble(s, "accel_scale", o.accel_scale, 1e-3, 1e3);
  o.accel_check_samples = ini.getInt(s, "accel_check_samples", o.accel_check_samples, 1, 100000);
  o.accel_check_max_s = ini.getDouble(s, "accel_check_max_s", o.accel_check_max_s, 0.0, 1000.0);
  o.time_jump_back_s = ini.getDouble(s, "time_jump_back_s", o.time_jump_back_s, 0.0, 1e6);
  if (o.time_jump_back_s <= std::max(o.imu_reorder_window_s, o.image_reorder_window_s))
    ini.fail(s, "time_jump_back_s",
             "must be larger than imu_reorder_window_s and image_reorder_window_s");
  o.constant_image_max_range =
      ini.getInt(s, "constant_image_max_range", o.constant_image_max_range, 0, 255);
  o.image_check_step_px = ini.getInt(s, "image_check_step_px", o.image_check_step_px, 1, 64);
  o.image_rate_limit_hz =
      ini.getDouble(s, "image_rate_limit_hz", o.image_rate_limit_hz, 0.0, 1000.0);
  o.wheel_gap_factor = ini.getDouble(s, "wheel_gap_factor", o.wheel_gap_factor, 1.0, 1000.0);
  o.wheel_rest_window_s =
      ini.getDouble(s, "wheel_rest_window_s", o.wheel_rest_window_s, 0.05, 100.0);
  o.wheel_rest_gyr_rad_s =
      ini.getDouble(s, "wheel_rest_gyr_rad_s", o.wheel_rest_gyr_rad_s, 0.0, 10.0);
  o.wheel_rest_acc_std_m_s2 =
      ini.getDouble(s, "wheel_rest_acc_std_m_s2", o.wheel_rest_acc_std_m_s2, 0.0, 100.0);
  o.wheel_rest_speed_m_s =
      ini.getDouble(s, "wheel_rest_speed_m_s", o.wheel_rest_speed_m_s, 0.0, 100.0);
  o.wheel_rest_yaw_rate_rad_s =
      ini.getDouble(s, "wheel_rest_yaw_rate_rad_s", o.wheel_rest_yaw_rate_rad_s, 0.0, 100.0);
  o.wheel_still_gyr_rad_s =
      ini.getDouble(s, "wheel_still_gyr_rad_s", o.wheel_still_gyr_rad_s, 0.0, 10.0);
  o.wheel_still_acc_m_s2 =
      ini.getDouble(s, "wheel_still_acc_m_s2", o.wheel_still_acc_m_s2, 0.0, 100.0);
  o.wheel_still_block_s = ini.getDouble(s, "wheel_still_block_s", o.wheel_still_block_s, 0.001,
                                        o.wheel_rest_window_s / 2);
  return o;
}

StreamConfig StreamConfig::load(IniReader& ini) {
  StreamConfig c;
  c.stream = StreamOptions::load(ini);
  c.imu = ImuOptions::load(ini);
  c.extrinsic = ExtrinsicOptions::load(ini);
  return c;
}

}  // namespace rgbdi::io
