// [relocalise] options: defaults equal share/config.ini; bad values name the key.
#include <gtest/gtest.h>

#include <string>

#include "rgbdi/reloc/reloc_options.h"
#include "testing/fixtures.h"
#include "testing/options_load_error.h"

using rgbdi::ConfigError;
using rgbdi::IniReader;
using rgbdi::reloc::RelocOptions;

namespace {
std::string loadError(const std::string& text) {
  return rgbdi::test::optionsLoadError<RelocOptions>(text);
}
}  // namespace

TEST(RelocOptions, DefaultsEqualTheShippedConfig) {
  IniReader ini = IniReader::fromFile(rgbdi::test::sourceDir() + "/share/config.ini");
  const RelocOptions o = RelocOptions::load(ini);
  const RelocOptions d;
  EXPECT_EQ(o.enable, d.enable);
  EXPECT_EQ(o.grid.resolution_m, d.grid.resolution_m);
  EXPECT_EQ(o.grid.band_min_m, d.grid.band_min_m);
  EXPECT_EQ(o.grid.band_max_m, d.grid.band_max_m);
  EXPECT_EQ(o.grid.max_range_m, d.grid.max_range_m);
  EXPECT_EQ(o.grid.min_hits, d.grid.min_hits);
  EXPECT_EQ(o.search.yaw_step_deg, d.search.yaw_step_deg);
  EXPECT_EQ(o.search.pyramid_levels, d.search.pyramid_levels);
  EXPECT_EQ(o.search.hypothesis_margin, d.search.hypothesis_margin);
  EXPECT_EQ(o.search.place_separation_m, d.search.place_separation_m);
  EXPECT_EQ(o.search.place_separation_deg, d.search.place_separation_deg);
  EXPECT_EQ(o.search.min_overlap_fraction, d.search.min_overlap_fraction);
  EXPECT_EQ(o.search.max_conflict_fraction, d.search.max_conflict_fraction);
  EXPECT_EQ(o.search.max_hypotheses, d.search.max_hypotheses);
  EXPECT_EQ(o.search.candidate_margin, d.search.candidate_margin);
  EXPECT_EQ(o.search.conflict_penalty, d.search.conflict_penalty);
  EXPECT_EQ(o.refine_huber_m, d.refine_huber_m);
  EXPECT_EQ(o.refine_height_drift_sigma_per_m, d.refine_height_drift_sigma_per_m);
  EXPECT_EQ(o.refine_max_range_m, d.refine_max_range_m);
  EXPECT_EQ(o.refine_horizontal, d.refine_horizontal);
  EXPECT_EQ(o.submap_path_m, d.submap_path_m);
  EXPECT_EQ(o.submap_min_occupied_cells, d.submap_min_occupied_cells);
  EXPECT_EQ(o.submap_max_path_m, d.submap_max_path_m);
  EXPECT_EQ(o.attempt_interval_m, d.attempt_interval_m);
  EXPECT_EQ(o.result_lag_keyframes, d.result_lag_keyframes);
  EXPECT_EQ(o.confirm_fits, d.confirm_fits);
  EXPECT_EQ(o.confirm_distance_m, d.confirm_distance_m);
  EXPECT_EQ(o.confirm_max_disagreement_m, d.confirm_max_disagreement_m);
  EXPECT_EQ(o.confirm_max_disagreement_deg, d.confirm_max_disagreement_deg);
  EXPECT_EQ(o.refine_max_distance_m, d.refine_max_distance_m);
  EXPECT_EQ(o.refine_iterations, d.refine_iterations);
  EXPECT_EQ(o.refine_min_pair_fraction, d.refine_min_pair_fraction);
  EXPECT_EQ(o.refine_min_view_cos, d.refine_min_view_cos);
  EXPECT_EQ(o.refine_tilt_sigma_deg, d.refine_tilt_sigma_deg);
  EXPECT_EQ(o.refine_max_rms_m, d.refine_max_rms_m);
  EXPECT_EQ(o.refine_min_horizontal_constraint, d.refine_min_horizontal_constraint);
  EXPECT_EQ(o.min_floor_cells, d.min_floor_cells);
  EXPECT_EQ(o.join_keyframes, d.join_keyframes);
  EXPECT_EQ(o.join_max_distance_m, d.join_max_distance_m);
  EXPECT_EQ(o.track_interval_m, d.track_interval_m);
  EXPECT_EQ(o.track_max_correction_m, d.track_max_correction_m);
  EXPECT_EQ(o.track_max_correction_deg, d.track_max_correction_deg);
  EXPECT_EQ(o.track_keyframes, d.track_keyframes);
  EXPECT_EQ(o.track_sigma_pos_m, d.track_sigma_pos_m);
  EXPECT_EQ(o.track_sigma_yaw_deg, d.track_sigma_yaw_deg);
}

TEST(RelocOptions, BadValuesNameTheKey) {
  EXPECT_NE(loadError("[relocalise]\ngrid_resolution_m = 0\n").find("grid_resolution_m"),
            std::string::npos);
  EXPECT_NE(loadError("[relocalise]\nband_min_m = 0.5\nband_max_m = 0.2\n").find("band_max_m"),
            std::string::npos);
  EXPECT_NE(loadError("[relocalise]\nhypothesis_margin = 1.5\n").find("hypothesis_margin"),
            std::string::npos);
  EXPECT_NE(loadError("[relocalise]\nresult_lag_keyframes = 0\n").find("result_lag_keyframes"),
            std::string::npos);
  EXPECT_NE(loadError("[relocalise]\nconfirm_fits = 1\n").find("confirm_fits"), std::string::npos);
  EXPECT_NE(loadError("[relocalise]\nsubmap_max_path_m = -1\n").find("submap_max_path_m"),
            std::string::npos);
  EXPECT_NE(loadError("[relocalise]\nrefine_min_view_cos = 1.5\n").find("refine_min_view_cos"),
            std::string::npos);
  EXPECT_NE(loadError("[relocalise]\nrefine_tilt_sigma_deg = -1\n").find("refine_tilt_sigma_deg"),
            std::string::npos);
  EXPECT_NE(loadError("[relocalise]\ntrack_sigma_pos_m = 0\n").find("track_sigma_pos_m"),
            std::string::npos);
  EXPECT_NE(loadError("[relocalise]\ntrack_keyframes = 0\n").find("track_keyframes"),
            std::string::npos);
  EXPECT_EQ(loadError("[relocalise]\ngeometric = false\n"), "");
}
