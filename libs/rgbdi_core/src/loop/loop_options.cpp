#include "rgbdi/loop/loop_options.h"

#include <string>

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
  o.relocalize_min_inliers =
      ini.getInt(s, "relocalize_min_inliers", o.relocalize_min_inliers, 1, 10000);
  o.relocalize_consistent_keyframes =
      ini.getInt(s, "relocalize_consistent_keyframes", o.relocalize_consistent_keyframes, 1, 50);
  o.relocalize_max_disagreement_m = ini.getDouble(s, "relocalize_max_disagreement_m",
                                                  o.relocalize_max_disagreement_m, 0.0, 100.0);
  o.relocalize_max_disagreement_deg = ini.getDouble(s, "relocalize_max_disagreement_deg",
                                                    o.relocalize_max_disagreement_deg, 0.0, 180.0);
  o.relocalize_window_keyframes =
      ini.getInt(s, "relocalize_window_keyframes", o.relocalize_window_keyframes, 1, 1000);
  o.relocalize_from_window = ini.getBool(s, "relocalize_from_window", o.relocalize_from_window);
  o.relocalize_check_keyframes =
      ini.getInt(s, "relocalize_check_keyframes", o.relocalize_check_keyframes, 0, 1000);
  o.relocalize_check_radius_m =
      ini.getDouble(s, "relocalize_check_radius_m", o.relocalize_check_radius_m, 0.0, 100.0);
  o.relocalize_check_max_conflict_fraction =
      ini.getDouble(s, "relocalize_check_max_conflict_fraction",
                    o.relocalize_check_max_conflict_fraction, 0.0, 1.0);
  o.relocalize_check_max_conflict_fraction_geometric =
      ini.getDouble(s, "relocalize_check_max_conflict_fraction_geometric",
                    o.relocalize_check_max_conflict_fraction_geometric, 0.0, 1.0);
  if (o.relocalize_window_keyframes < o.relocalize_consistent_keyframes)
    ini.fail(s, "relocalize_window_keyframes",
             std::to_string(o.relocalize_window_keyframes) +
                 " must be at least relocalize_consistent_keyframes (" +
                 std::to_string(o.relocalize_consistent_keyframes) + ")");
  o.correction.gate_sigma =
      ini.getDouble(s, "correction_gate_sigma", o.correction.gate_sigma, 0.0, 1000.0);
  o.correction.sigma_floor_m =
      ini.getDouble(s, "correction_sigma_floor_m", o.correction.sigma_floor_m, 1e-6, 10.0);
  o.correction.yaw_sigma_deg_per_m = ini.getDouble(s, "correction_yaw_sigma_deg_per_m",
                                                   o.correction.yaw_sigma_deg_per_m, 1e-3, 1e4);
  o.features = LoopFeatureOptions::load(ini);
  o.place = PlaceRecognitionOptions::load(ini);
  o.verify = LoopVerificationOptions::load(ini);
  o.graph = PoseGraphOptions::load(ini);
  return o;
}

}  // namespace rgbdi::loop
