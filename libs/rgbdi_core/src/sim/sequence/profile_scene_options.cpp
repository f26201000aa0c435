#include <climits>
#include <stdexcept>
#include <string>

#include "rgbdi/sim/profile_scene.h"

namespace rgbdi::sim {
namespace {

constexpr double kMaxRoomMarginM = 10.0;
constexpr double kMinFurnitureLateralM = 0.05;  // the lower end of the lateral draw
constexpr double kMaxFurnitureLateralM = 6.0;

}  // namespace

ProfileSceneOptions ProfileSceneOptions::load(IniReader& ini) {
  ProfileSceneOptions o;
  const std::string s = "sim";
  o.aliased_walls = ini.getBool(s, "aliased_walls", o.aliased_walls);
  o.world_seed = static_cast<std::uint64_t>(
      ini.getInt(s, "world_seed", static_cast<int>(o.world_seed), 0, INT_MAX));
  o.room_margin_m = ini.getDouble(s, "room_margin_m", o.room_margin_m, 0.0, kMaxRoomMarginM);
  o.furniture_density = ini.getDouble(s, "furniture_density", o.furniture_density, 0.0, 1.0);
  o.furniture_lateral_max_m = ini.getDouble(s, "furniture_lateral_max_m", o.furniture_lateral_max_m,
                                            kMinFurnitureLateralM, kMaxFurnitureLateralM);
  o.texture_contrast = ini.getDouble(s, "texture_contrast", o.texture_contrast, 0.0, 1.0);
  o.twin_rooms = ini.getBool(s, "twin_rooms", o.twin_rooms);
  o.nav_features = ini.getBool(s, "nav_features", o.nav_features);
  if (!(o.texture_contrast > 0.0))
    ini.fail(s, "texture_contrast", "must be greater than 0 (at most 1)");
  return o;
}

void ProfileSceneOptions::validate() const {
  if (!(room_margin_m >= 0.0 && room_margin_m <= kMaxRoomMarginM))
    throw std::invalid_argument("ProfileSceneOptions: room_margin_m must be in [0, 10] m");
  if (!(furniture_density >= 0.0 && furniture_density <= 1.0))
    throw std::invalid_argument("ProfileSceneOptions: furniture_density must be in [0, 1]");
  if (!(furniture_lateral_max_m >= kMinFurnitureLateralM &&
        furniture_lateral_max_m <= kMaxFurnitureLateralM))
    throw std::invalid_argument(
        "ProfileSceneOptions: furniture_lateral_max_m must be in [0.05, 6] m");
  if (!(texture_contrast > 0.0 && texture_contrast <= 1.0))
    throw std::invalid_argument("ProfileSceneOptions: texture_contrast must be in (0, 1]");
}

}  // namespace rgbdi::sim
