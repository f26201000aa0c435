#include "rgbdi/bag/convert_options.h"

namespace rgbdi::bag {

ConvertOptions ConvertOptions::load(IniReader& ini) {
  ConvertOptions o;
  const std::string s = "convert";
  o.pair_tolerance_s = ini.getDouble(s, "pair_tolerance_s", o.pair_tolerance_s, 0.0, 1.0);
  o.max_wait_s = ini.getDouble(s, "max_wait_s", o.max_wait_s, 0.01, 60.0);
  if (o.max_wait_s < o.pair_tolerance_s)
    ini.fail(s, "max_wait_s", "must not be smaller than pair_tolerance_s");
  o.reorder_window_s = ini.getDouble(s, "reorder_window_s", o.reorder_window_s, 0.0, 60.0);
  o.max_accel_gap_s = ini.getDouble(s, "max_accel_gap_s", o.max_accel_gap_s, 1e-4, 10.0);
  o.integer_depth_unit_m =
      ini.getDouble(s, "integer_depth_unit_m", o.integer_depth_unit_m, 1e-6, 1.0);
  o.float_depth_unit_m = ini.getDouble(s, "float_depth_unit_m", o.float_depth_unit_m, 1e-6, 1.0);
  o.tum_depth_factor = ini.getDouble(s, "tum_depth_factor", o.tum_depth_factor, 1.0, 1e6);
  o.require_colour = ini.getBool(s, "require_colour", o.require_colour);
  o.max_listed_issues = ini.getInt(s, "max_listed_issues", o.max_listed_issues, 0, 100000);
  o.progress_interval_s =
      ini.getDouble(s, "progress_interval_s", o.progress_interval_s, 0.05, 3600.0);
  return o;
}

}  // namespace rgbdi::bag
