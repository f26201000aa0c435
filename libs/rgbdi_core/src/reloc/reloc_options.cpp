#include "rgbdi/reloc/reloc_options.h"

#include <string>

namespace rgbdi::reloc {

RelocOptions RelocOptions::load(IniReader& ini) {
  RelocOptions o;
  const std::string s = "relocalise";
  o.enable = ini.getBool(s, "geometric", o.enable);
  PlanGridOptions& g = o.grid;
  g.resolution_m = ini.getDouble(s, "grid_resolution_m", g.resolution_m, 0.01, 1.0);
  g.band_min_m = ini.getDouble(s, "band_min_m", g.band_min_m, -10.0, 10.0);
  g.band_max_m = ini.getDouble(s, "band_max_m", g.band_max_m, -10.0, 10.0);
  if (g.band_max_m <= g.band_min_m)
    ini.fail(s, "band_max_m",
             std::to_string(g.band_max_m) + " must be above band_min_m (" +
                 std::to_string(g.band_min_m) + ")");
  g.max_range_m = ini.getDouble(s, "max_range_m", g.max_range_m, 0.1, 100.0);
  g.min_hits = ini.getInt(s, "min_hits", g.min_hits, 1, 1000);
  ScanSearchOptions& q = o.search;
  q.yaw_step_deg = ini.getDouble(s, "yaw_step_deg", q.yaw_step_deg, 0.05, 45.0);
  q.pyramid_levels = ini.getInt(s, "pyramid_levels", q.pyramid_levels, 0, 12);
  q.candidate_margin = ini.getDouble(s, "candidate_margin", q.candidate_margin, 0.0, 1.0);
  q.conflict_penalty = ini.getDouble(s, "conflict_penalty", q.conflict_penalty, 0.0, 100.0);
  q.hypothesis_margin = ini.getDouble(s, "hypothesis_margin", q.hypothesis_margin, 0.0, 1.0);
  q.place_separation_m = ini.getDouble(s, "place_separation_m", q.place_separation_m, 0.0, 1000.0);
  q.place_separation_deg =
      ini.getDouble(s, "place_separation_deg", q.place_separation_deg, 0.0, 180.0);
  q.min_overlap_fraction =
      ini.getDouble(s, "min_overlap_fraction", q.min_overlap_fraction, 0.0, 1.0);
  q.max_conflict_fraction =
      ini.getDouble(s, "max_conflict_fraction", q.max_conflict_fraction, 0.0, 1.0);
  q.max_hypotheses = ini.getInt(s, "max_hypotheses", q.max_hypotheses, 2, 1000);
  o.submap_path_m = ini.getDouble(s, "submap_path_m", o.submap_path_m, 0.0, 1000.0);
  o.submap_min_occupied_cells =
      ini.getInt(s, "submap_min_occupied_cells", o.submap_min_occupied_cells, 1, 1000000);
  o.submap_max_path_m = ini.getDouble(s, "submap_max_path_m", o.submap_max_path_m, 0.0, 1000.0);
  o.attempt_interval_m = ini.getDouble(s, "attempt_interval_m", o.attempt_interval_m, 0.0, 1000.0);
  o.result_lag_keyframes = ini.getInt(s, "result_lag_keyframes", o.result_lag_keyframes, 1, 1000);
  o.confirm_fits = ini.getInt(s, "confirm_fits", o.confirm_fits, 2, 100);
  o.confirm_distance_m = ini.getDouble(s, "confirm_distance_m", o.confirm_distance_m, 0.0, 1000.0);
  o.confirm_max_disagreement_m =
      ini.getDouble(s, "confirm_max_disagreement_m", o.confirm_max_disagreement_m, 0.0, 100.0);
  o.confirm_max_disagreement_deg =
      ini.getDouble(s, "confirm_max_disagreement_deg", o.confirm_max_disagreement_deg, 0.0, 180.0);
  o.confirm_join_mean = ini.getBool(s, "confirm_join_mean", o.confirm_join_mean);
  o.refine_max_distance_m =
      ini.getDouble(s, "refine_max_distance_m", o.refine_max_distance_m, 0.001, 10.0);
  o.refine_max_range_m = ini.getDouble(s, "refine_max_range_m", o.refine_max_range_m, 0.1, 100.0);
  o.refine_horizontal = ini.getBool(s, "refine_horizontal", o.refine_horizontal);
  o.refine_iterations = ini.getInt(s, "refine_iterations", o.refine_iterations, 0, 1000);
  o.refine_huber_m = ini.getDouble(s, "refine_huber_m", o.refine_huber_m, 0.0001, 1e12);
  o.refine_height_drift_sigma_per_m = ini.getDouble(s, "refine_height_drift_sigma_per_m",
                                                    o.refine_height_drift_sigma_per_m, 0.0, 1.0);
  o.refine_min_view_cos = ini.getDouble(s, "refine_min_view_cos", o.refine_min_view_cos, -1.0, 1.0);
  o.refine_tilt_sigma_deg =
      ini.getDouble(s, "refine_tilt_sigma_deg", o.refine_tilt_sigma_deg, 0.0, 90.0);
  o.refine_min_pair_fraction =
      ini.getDouble(s, "refine_min_pair_fraction", o.refine_min_pair_fraction, 0.0, 1.0);
  o.refine_max_rms_m = ini.getDouble(s, "refine_max_rms_m", o.refine_max_rms_m, 0.0, 10.0);
  o.refine_min_horizontal_constraint = ini.getDouble(s, "refine_min_horizontal_constraint",
                                                     o.refine_min_horizontal_constraint, 0.0, 0.5);
  o.min_floor_cells = ini.getInt(s, "min_floor_cells", o.min_floor_cells, 1, 1000000);
  o.join_keyframes = ini.getInt(s, "join_keyframes", o.join_keyframes, 1, 1000);
  o.join_max_distance_m =
      ini.getDouble(s, "join_max_distance_m", o.join_max_distance_m, 0.0, 100.0);
  o.track_interval_m = ini.getDouble(s, "track_interval_m", o.track_interval_m, 0.0, 1000.0);
  o.track_max_correction_m =
      ini.getDouble(s, "track_max_correction_m", o.track_max_correction_m, 0.0, 100.0);
  o.track_max_correction_deg =
      ini.getDouble(s, "track_max_correction_deg", o.track_max_correction_deg, 0.0, 180.0);
  o.track_keyframes = ini.getInt(s, "track_keyframes", o.track_keyframes, 1, 1000);
  o.track_sigma_pos_m = ini.getDouble(s, "track_sigma_pos_m", o.track_sigma_pos_m, 1e-6, 100.0);
  o.track_sigma_yaw_deg =
      ini.getDouble(s, "track_sigma_yaw_deg", o.track_sigma_yaw_deg, 1e-6, 180.0);
  return o;
}

}  // namespace rgbdi::reloc
