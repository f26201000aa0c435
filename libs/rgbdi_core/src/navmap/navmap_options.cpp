#include "rgbdi/navmap/navmap_options.h"

#include <string>
#include <vector>

#include "rgbdi/common/option_keys.h"

namespace rgbdi::navmap {
namespace {

const char* const kSection = "navmap";

// One table of keys and ranges serves load() and validate(), so options built in code are held
// to the same limits as options read from a file.
using IntKey = rgbdi::IntKey<NavMapOptions>;
using DoubleKey = rgbdi::DoubleKey<NavMapOptions>;

const std::vector<IntKey>& intKeys() {
  static const std::vector<IntKey> keys = {
      {"min_points_per_cell", [](NavMapOptions& o) -> int& { return o.min_points_per_cell; }, 1,
       100000},
      {"min_obstacle_points", [](NavMapOptions& o) -> int& { return o.min_obstacle_points; }, 1,
       100000},
  };
  return keys;
}

const std::vector<DoubleKey>& doubleKeys() {
  static const std::vector<DoubleKey> keys = {
      {"cell_size_m", [](NavMapOptions& o) -> double& { return o.cell_size_m; }, 0.005, 5.0},
      {"range_m", [](NavMapOptions& o) -> double& { return o.range_m; }, 0.1, 100.0},
      {"ground_band_m", [](NavMapOptions& o) -> double& { return o.ground_band_m; }, 0.001, 1.0},
      {"footprint_radius_m", [](NavMapOptions& o) -> double& { return o.footprint_radius_m; }, 0.0,
       10.0},
      {"max_slope_deg", [](NavMapOptions& o) -> double& { return o.max_slope_deg; }, 0.1, 89.0},
      {"max_step_m", [](NavMapOptions& o) -> double& { return o.max_step_m; }, 0.001, 5.0},
      {"clearance_height_m", [](NavMapOptions& o) -> double& { return o.clearance_height_m; }, 0.01,
       20.0},
      {"max_roughness_m", [](NavMapOptions& o) -> double& { return o.max_roughness_m; }, 0.001,
       5.0},
      {"path_ground_radius_m", [](NavMapOptions& o) -> double& { return o.path_ground_radius_m; },
       0.0, 100.0},
      {"path_ground_min_fraction",
       [](NavMapOptions& o) -> double& { return o.path_ground_min_fraction; }, 0.0, 1.0},
      {"max_depth_m", [](NavMapOptions& o) -> double& { return o.max_depth_m; }, 0.1, 100.0},
      {"refresh_interval_s", [](NavMapOptions& o) -> double& { return o.refresh_interval_s; }, 0.0,
       86400.0},
      {"drop_face_min_rise_m", [](NavMapOptions& o) -> double& { return o.drop_face_min_rise_m; },
       0.0, 5.0},
      {"drop_face_min_depth_m", [](NavMapOptions& o) -> double& { return o.drop_face_min_depth_m; },
       0.0, 5.0},
  };
  return keys;
}

[[noreturn]] void failKey(const std::string& key, const std::string& what) {
  throw ConfigError("NavMapOptions [" + std::string(kSection) + "] " + key + ": " + what);
}

// Cross-key rules shared by load() (reported with the file name) and validate().
template <typename Fail>
void checkConsistency(const NavMapOptions& o, Fail&& fail) {
  // The obstacle band (max_step_m, clearance_height_m] must not be empty.
  if (o.clearance_height_m <= o.max_step_m)
    fail("clearance_height_m",
         "must be larger than max_step_m (the band between is the obstacle band)");
  if (o.range_m < o.cell_size_m) fail("range_m", "must be at least cell_size_m");
  // The rise is measured within max_step_m of the lowest surface (higher points are obstacles).
  if (o.drop_face_min_rise_m > o.max_step_m)
    fail("drop_face_min_rise_m", "must be at most max_step_m (0 = off)");
}

}  // namespace

void NavMapOptions::validate() const {
  checkKeyRanges(*this, intKeys(), doubleKeys(), failKey);
  checkConsistency(*this,
                   [](const std::string& key, const std::string& what) { failKey(key, what); });
}

NavMapOptions NavMapOptions::load(IniReader& ini) {
  NavMapOptions o;
  o.enable = ini.getBool(kSection, "enable", o.enable);
  loadKeys(ini, kSection, o, intKeys(), doubleKeys());
  checkConsistency(o, [&ini](const std::string& key, const std::string& what) {
    ini.fail(kSection, key, what);
  });
  return o;
}

}  // namespace rgbdi::navmap
