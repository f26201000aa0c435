#include <gtest/gtest.h>

#include <string>

#include "rgbdi/mapping/mapping_options.h"
#include "rgbdi/mapping/occupancy_map.h"
#include "rgbdi/mapping/point_map.h"
#include "testing/fixtures.h"
#include "testing/options_load_error.h"

using rgbdi::ConfigError;
using rgbdi::IniReader;
using rgbdi::mapping::MappingOptions;

namespace {

std::string loadError(const std::string& text) {
  return rgbdi::test::optionsLoadError<MappingOptions>(text);
}

}  // namespace

TEST(MappingOptions, DefaultsEqualTheShippedConfig) {
  IniReader ini = IniReader::fromFile(rgbdi::test::sourceDir() + "/share/config.ini");
  const MappingOptions f = MappingOptions::load(ini);
  const MappingOptions d;
  EXPECT_EQ(f.grid_step_px, d.grid_step_px);
  EXPECT_EQ(f.u_min_px, d.u_min_px);
  EXPECT_EQ(f.u_max_px, d.u_max_px);
  EXPECT_EQ(f.v_min_px, d.v_min_px);
  EXPECT_EQ(f.v_max_px, d.v_max_px);
  EXPECT_EQ(f.depth_min_m, d.depth_min_m);
  EXPECT_EQ(f.depth_max_m, d.depth_max_m);
  EXPECT_EQ(f.octree_resolution_m, d.octree_resolution_m);
  EXPECT_EQ(f.max_points_per_leaf, d.max_points_per_leaf);
  EXPECT_EQ(f.view_update_distance_m, d.view_update_distance_m);
  EXPECT_EQ(f.view_update_angle_deg, d.view_update_angle_deg);
  EXPECT_EQ(f.min_points_per_leaf_rebuild, d.min_points_per_leaf_rebuild);
  EXPECT_EQ(f.correction_min_shift_m, d.correction_min_shift_m);
  EXPECT_EQ(f.correction_min_rotation_deg, d.correction_min_rotation_deg);
  EXPECT_EQ(f.occupancy_resolution_m, d.occupancy_resolution_m);
  EXPECT_EQ(f.occupancy_grid_stride, d.occupancy_grid_stride);
  EXPECT_EQ(f.occupancy_prob_hit, d.occupancy_prob_hit);
  EXPECT_EQ(f.occupancy_prob_miss, d.occupancy_prob_miss);
  EXPECT_EQ(f.plot.panel_px, d.plot.panel_px);
  EXPECT_EQ(f.plot.max_time_diff_s, d.plot.max_time_diff_s);
  EXPECT_EQ(f.scene.keyframe_axis_m, d.scene.keyframe_axis_m);
  // The paper's values (section 4.5 / SPEC section 2).
  EXPECT_EQ(d.grid_step_px, 10);
  EXPECT_EQ(d.u_min_px, 40);
  EXPECT_EQ(d.u_max_px, 590);
  EXPECT_EQ(d.v_min_px, 10);
  EXPECT_EQ(d.v_max_px, 460);
  EXPECT_EQ(d.depth_min_m, 0.3);
  EXPECT_EQ(d.depth_max_m, 6.0);
  EXPECT_EQ(d.octree_resolution_m, 0.02);
  EXPECT_EQ(d.max_points_per_leaf, 5);
  EXPECT_EQ(d.min_points_per_leaf_rebuild, 3);
  // Every [mapping] key of the file was read (no typo, nothing unused).
  ini.acceptConfigSectionsExcept({"mapping"});
  EXPECT_NO_THROW(ini.checkNoUnknownKeys());
}

TEST(MappingOptions, ReadsValuesFromTheFile) {
  IniReader ini = IniReader::fromText(
      "[mapping]\ngrid_step_px = 4\noctree_resolution_m = 0.05\nmax_points_per_leaf = 1\n"
      "min_points_per_leaf_rebuild = 0\nplot_panel_px = 300\n",
      "test.ini");
  const MappingOptions o = MappingOptions::load(ini);
  EXPECT_EQ(o.grid_step_px, 4);
  EXPECT_EQ(o.octree_resolution_m, 0.05);
  EXPECT_EQ(o.max_points_per_leaf, 1);
  EXPECT_EQ(o.min_points_per_leaf_rebuild, 0);
  EXPECT_EQ(o.plot.panel_px, 300);
}

TEST(MappingOptions, OutOfRangeValuesNameFileSectionAndKey) {
  const std::string e1 = loadError("[mapping]\ngrid_step_px = 0\n");
  EXPECT_NE(e1.find("test.ini"), std::string::npos) << e1;
  EXPECT_NE(e1.find("grid_step_px"), std::string::npos) << e1;
  const std::string e2 = loadError("[mapping]\noctree_resolution_m = -1\n");
  EXPECT_NE(e2.find("octree_resolution_m"), std::string::npos) << e2;
  const std::string e3 = loadError("[mapping]\noccupancy_prob_hit = 0.3\n");
  EXPECT_NE(e3.find("occupancy_prob_hit"), std::string::npos) << e3;
  const std::string e4 = loadError("[mapping]\nmax_points_per_leaf = five\n");
  EXPECT_NE(e4.find("max_points_per_leaf"), std::string::npos) << e4;
}

TEST(MappingOptions, InconsistentValuesAreRejected) {
  EXPECT_NE(loadError("[mapping]\ndepth_min_m = 7\n").find("depth_min_m"), std::string::npos);
  EXPECT_NE(loadError("[mapping]\nu_min_px = 600\n").find("u_min_px"), std::string::npos);
  EXPECT_NE(loadError("[mapping]\nv_max_px = 5\n").find("v_min_px"), std::string::npos);
  EXPECT_NE(
      loadError("[mapping]\nmin_points_per_leaf_rebuild = 6\n").find("min_points_per_leaf_rebuild"),
      std::string::npos);
  EXPECT_EQ(loadError("[mapping]\nmin_points_per_leaf_rebuild = 5\n"), "");
}

TEST(MappingOptions, OptionsBuiltInCodeAreValidatedByTheMaps) {
  MappingOptions o;
  EXPECT_NO_THROW(o.validate());
  o.max_points_per_leaf = 0;
  EXPECT_THROW(rgbdi::mapping::PointMap{o}, ConfigError);
  o = MappingOptions{};
  o.octree_resolution_m = std::nan("");
  EXPECT_THROW(rgbdi::mapping::PointMap{o}, ConfigError);
  o = MappingOptions{};
  o.occupancy_grid_stride = 0;
  EXPECT_THROW(rgbdi::mapping::OccupancyMap{o}, ConfigError);
  o = MappingOptions{};
  o.depth_min_m = o.depth_max_m;
  try {
    o.validate();
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("[mapping] depth_min_m"), std::string::npos) << e.what();
  }
}
