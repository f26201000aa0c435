#include "rgbdi/sim/scene_presets.h"

#include <cmath>
#include <stdexcept>

#include "sim/render/det_random.h"

namespace rgbdi::sim {

Scene makeFurnishedRoom(std::uint64_t seed, const FurnishedRoomOptions& options) {
  const Eigen::Vector3d half = 0.5 * options.size;
  if (!(options.size.array() > 1.0).all() || options.objects < 0 || options.free_radius < 0.0 ||
      options.free_radius > 0.5 * std::min(options.size.x(), options.size.y()) - 0.5)
    throw std::invalid_argument(
        "makeFurnishedRoom: need a room larger than 1 m, objects >= 0 and a free radius leaving "
        "at least 0.5 m to the walls");
  Scene scene(seed);
  scene.addRoom({-half.x(), -half.y(), 0.0}, {half.x(), half.y(), options.size.z()});
  detail::DetRandom r(detail::mixSeed(seed, 0x726f6f6dULL));
  const TextureStyle styles[] = {TextureStyle::Posters, TextureStyle::Bricks,
                                 TextureStyle::Tiles,   TextureStyle::Shelves,
                                 TextureStyle::Speckle, TextureStyle::Planks};
  auto anyStyle = [&]() { return styles[r.integer(0, kTextureStyleCount - 1)]; };
  // A position outside the free disc and inside the walls by `margin`.
  auto place = [&](double margin) {
    for (;;) {
      const Eigen::Vector2d p(r.uniform(-half.x() + margin, half.x() - margin),
                              r.uniform(-half.y() + margin, half.y() - margin));
      if (p.norm() > options.free_radius + margin) return p;
    }
  };
  for (int i = 0; i < options.objects; ++i) {
    const int kind = i % 8;
    if (kind <= 2) {
      // Cabinet/shelf against a wall, facing the room.
      const int wall = r.integer(0, 3);
      const double depth = r.uniform(0.3, 0.6), width = r.uniform(0.5, 1.6);
      const double height = r.uniform(0.5, std::min(2.4, options.size.z() - 0.1));
      const double along = (wall < 2) ? r.uniform(-half.y() + 0.5 * width, half.y() - 0.5 * width)
                                      : r.uniform(-half.x() + 0.5 * width, half.x() - 0.5 * width);
      Eigen::Vector2d c;
      double yaw;
      switch (wall) {
        case 0:
          c = {-half.x() + 0.5 * depth, along};
          yaw = 0.0;
          break;
        case 1:
          c = {half.x() - 0.5 * depth, along};
          yaw = M_PI;
          break;
        case 2:
          c = {along, -half.y() + 0.5 * depth};
          yaw = 0.5 * M_PI;
          break;
        default:
          c = {along, half.y() - 0.5 * depth};
          yaw = -0.5 * M_PI;
          break;
      }
      if (c.norm() < options.free_radius + 0.5 * width) continue;
      scene.addStep(c, {depth, width}, yaw, 0.0, height,
                    r.chance(0.6) ? TextureStyle::Shelves : anyStyle());
    } else if (kind == 3) {
      scene.addCylinder(place(0.5), r.uniform(0.1, 0.3), 0.0, options.size.z(), anyStyle());
    } else if (kind <= 5) {
      // Crates and boxes, some stacked or standing on others' tops.
      const Eigen::Vector2d c = place(0.6);
      const double s = r.uniform(0.2, 0.7);
      const double base = r.chance(0.3) ? r.uniform(0.2, 0.8) : 0.0;
      scene.addStep(c, {s, s * r.uniform(0.6, 1.4)}, r.uniform(-M_PI, M_PI), base,
                    r.uniform(0.2, 0.9), anyStyle());
    } else if (kind == 6) {
      scene.addStep(place(0.8), {r.uniform(0.6, 1.5), r.uniform(0.3, 0.8)}, r.uniform(-M_PI, M_PI),
                    0.0, r.uniform(0.05, 0.2), TextureStyle::Tiles);  // low step
    } else {
      const Eigen::Vector2d a = place(1.6);
      const double heading = r.uniform(-M_PI, M_PI), length = r.uniform(0.8, 1.5);
      const Eigen::Vector2d b = a + length * Eigen::Vector2d(std::cos(heading), std::sin(heading));
      if (b.norm() < options.free_radius + 0.6) continue;
      if (r.chance(0.5))
        scene.addRamp(a, b, 0.0, r.uniform(0.6, 1.2), r.uniform(0.1, 0.3), anyStyle());
      else
        scene.addSymmetricRamp(a, b, 0.0, r.uniform(0.6, 1.2), r.uniform(0.1, 0.3), anyStyle());
    }
  }
  scene.build();
  return scene;
}

}  // namespace rgbdi::sim
