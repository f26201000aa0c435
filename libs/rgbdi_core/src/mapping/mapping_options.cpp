#include "rgbdi/mapping/mapping_options.h"

#include <string>
#include <vector>

#include "rgbdi/common/option_keys.h"

namespace rgbdi::mapping {
namespace {

const char* const kSection = "mapping";

// One table of keys and ranges serves load() and validate(), so options built in code are held
// to the same limits as options read from a file. Accessors reach into the nested structs.
using IntKey = rgbdi::IntKey<MappingOptions>;
using DoubleKey = rgbdi::DoubleKey<MappingOptions>;

const std::vector<IntKey>& intKeys() {
  static const std::vector<IntKey> keys = {
      {"grid_step_px", [](MappingOptions& o) -> int& { return o.grid_step_px; }, 1, 1000},
      {"u_min_px", [](MappingOptions& o) -> int& { return o.u_min_px; }, 0, 100000},
      {"u_max_px", [](MappingOptions& o) -> int& { return o.u_max_px; }, 0, 100000},
      {"v_min_px", [](MappingOptions& o) -> int& { return o.v_min_px; }, 0, 100000},
      {"v_max_px", [](MappingOptions& o) -> int& { return o.v_max_px; }, 0, 100000},
      {"max_points_per_leaf", [](MappingOptions& o) -> int& { return o.max_points_per_leaf; }, 1,
       1000000},
      {"min_points_per_leaf_rebuild",
       [](MappingOptions& o) -> int& { return o.min_points_per_leaf_rebuild; }, 0, 1000000},
      {"occupancy_grid_stride", [](MappingOptions& o) -> int& { return o.occupancy_grid_stride; },
       1, 100},
      {"plot_panel_px", [](MappingOptions& o) -> int& { return o.plot.panel_px; }, 100, 4000},
  };
  return keys;
}

const std::vector<DoubleKey>& doubleKeys() {
  static const std::vector<DoubleKey> keys = {
      {"depth_min_m", [](MappingOptions& o) -> double& { return o.depth_min_m; }, 0.0, 100.0},
      {"depth_max_m", [](MappingOptions& o) -> double& { return o.depth_max_m; }, 0.01, 1000.0},
      {"octree_resolution_m", [](MappingOptions& o) -> double& { return o.octree_resolution_m; },
       0.001, 10.0},
      {"occupancy_resolution_m",
       [](MappingOptions& o) -> double& { return o.occupancy_resolution_m; }, 0.005, 10.0},
      {"occupancy_prob_hit", [](MappingOptions& o) -> double& { return o.occupancy_prob_hit; },
       0.51, 0.99},
      {"occupancy_prob_miss", [](MappingOptions& o) -> double& { return o.occupancy_prob_miss; },
       0.01, 0.49},
      {"view_update_distance_m",
       [](MappingOptions& o) -> double& { return o.view_update_distance_m; }, 0.0, 100.0},
      {"view_update_angle_deg",
       [](MappingOptions& o) -> double& { return o.view_update_angle_deg; }, 0.0, 180.0},
      {"correction_min_shift_m",
       [](MappingOptions& o) -> double& { return o.correction_min_shift_m; }, 0.0, 10.0},
      {"correction_min_rotation_deg",
       [](MappingOptions& o) -> double& { return o.correction_min_rotation_deg; }, 0.0, 180.0},
      {"plot_max_time_diff_s", [](MappingOptions& o) -> double& { return o.plot.max_time_diff_s; },
       0.0, 10.0},
      {"scene_keyframe_axis_m",
       [](MappingOptions& o) -> double& { return o.scene.keyframe_axis_m; }, 0.001, 100.0},
  };
  return keys;
}

[[noreturn]] void failKey(const std::string& key, const std::string& what) {
  throw ConfigError("MappingOptions [" + std::string(kSection) + "] " + key + ": " + what);
}

// Cross-key rules shared by load() (reported with the file name) and validate().
template <typename Fail>
void checkConsistency(const MappingOptions& o, Fail&& fail) {
  if (o.depth_min_m >= o.depth_max_m) fail("depth_min_m", "must be smaller than depth_max_m");
  if (o.u_min_px > o.u_max_px) fail("u_min_px", "must not exceed u_max_px");
  if (o.v_min_px > o.v_max_px) fail("v_min_px", "must not exceed v_max_px");
  // A threshold above the capacity would empty the whole map at the first rebuild.
  if (o.min_points_per_leaf_rebuild > o.max_points_per_leaf)
    fail("min_points_per_leaf_rebuild", "must not exceed max_points_per_leaf");
}

}  // namespace

void MappingOptions::validate() const {
  checkKeyRanges(*this, intKeys(), doubleKeys(), failKey);
  checkConsistency(*this,
                   [](const std::string& key, const std::string& what) { failKey(key, what); });
}

MappingOptions MappingOptions::load(IniReader& ini) {
  MappingOptions o;
  loadKeys(ini, kSection, o, intKeys(), doubleKeys());
  checkConsistency(o, [&ini](const std::string& key, const std::string& what) {
    ini.fail(kSection, key, what);
  });
  return o;
}

}  // namespace rgbdi::mapping
