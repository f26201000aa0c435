#include "rgbdi/loop/loop_options.h"

namespace rgbdi::loop {

LoopOptions LoopOptions::load(IniReader& ini) {
  LoopOptions o;
  const std::string s = "loop";
  o.enable = ini.getBool(s, "enable", o.enable);
  o.offline_lag_keyframes = ini.getInt(s, "offline_lag_keyframes", o.offline_lag_keyframes, 0, 100);
  o.max_verified_candidates =
      ini.getInt(s, "max_verified_candidates", o.max_verified_candidates, 1, 50);
  o.max_loops_per_keyframe =
      ini.getInt(s, "max_loops_per_keyframe", o.max_loops_per_keyframe, 1, 50);
  o.min_keyframe_distance_m =
      ini.getDouble(s, "min_keyframe_distance_m", o.min_keyframe_distance_m, 0.0, 100.0);
  o.min_keyframe_angle_deg =
      ini.getDouble(s, "min_keyframe_angle_deg", o.min_keyframe_angle_deg, 0.0, 180.0);
  o.solve_interval_keyframes =
      ini.getInt(s, "solve_interval_keyframes", o.solve_interval_keyframes, 1, 10000);
  o.features = LoopFeatureOptions::load(ini);
  o.place = PlaceRecognitionOptions::load(ini);
  o.verify = LoopVerificationOptions::load(ini);
  o.graph = PoseGraphOptions::load(ini);
  return o;
}

}  // namespace rgbdi::loop
