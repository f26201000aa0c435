// [sim] twin_rooms: the wheeled_circle room split into two identical rooms. Every ray from a
// point and the same ray turned by 180 deg about the room's centre see the same surface at the
// same distance (furniture with the same material: the same texture); the path passes the
// partition through its doors; other profiles refuse the option.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>

#include "rgbdi/sim/profile_scene.h"
#include "rgbdi/sim/profiles.h"

namespace rgbdi::sim {
namespace {

MotionProfile worldOf(ProfileKind kind) {
  ProfileOptions o;
  o.kind = kind;
  return makeMotionProfile(o, Eigen::Isometry3d::Identity());
}

ProfileSceneOptions twin() {
  ProfileSceneOptions o;
  o.twin_rooms = true;
  return o;
}

}  // namespace

TEST(TwinRooms, EachRoomIsTheOtherTurnedByAHalfTurn) {
  const MotionProfile prof = worldOf(ProfileKind::WheeledCircle);
  const Scene scene = buildProfileScene(prof, 1, twin());
  // Room (6 slabs), partition (3 pieces beside and between the doors), furniture twice.
  ASSERT_GT(scene.primitiveCount(), 9u + 20u);
  EXPECT_EQ((scene.primitiveCount() - 9u) % 2u, 0u);
  const ProfileLayout& l = prof.layout;
  const Eigen::Vector2d c = 0.5 * (l.room_min + l.room_max).head<2>();
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> ux(l.room_min.x() + 0.3, l.room_max.x() - 0.3),
      uy(l.room_min.y() + 0.3, l.room_max.y() - 0.3), ua(-M_PI, M_PI), uz(0.1, 2.0);
  int furniture_hits = 0;
  for (int k = 0; k < 2000; ++k) {
    const Eigen::Vector3d p(ux(rng), uy(rng), uz(rng));
    const double a = ua(rng);
    const Eigen::Vector3d d(std::cos(a) * 0.9, std::sin(a) * 0.9,
                            std::sqrt(1.0 - 0.81) * (k % 2 ? 1 : -1));
    const Eigen::Vector3d p2(2 * c.x() - p.x(), 2 * c.y() - p.y(), p.z());
    const Eigen::Vector3d d2(-d.x(), -d.y(), d.z());
    Hit h1, h2;
    const bool hit1 = scene.raycast(p, d, 100.0, h1), hit2 = scene.raycast(p2, d2, 100.0, h2);
    ASSERT_EQ(hit1, hit2) << k;
    if (!hit1) continue;
    EXPECT_NEAR(h1.t, h2.t, 1e-9) << k;
    // Inside the room a point is nearer the furniture than the walls on some rays; those rays
    // hit the twin's furniture with the same material.
    if (h1.point.z() > l.room_min.z() + 1e-6 && h1.point.z() < l.room_max.z() - 1e-6 &&
        h1.material == h2.material && h1.primitive != h2.primitive)
      ++furniture_hits;
  }
  EXPECT_GT(furniture_hits, 100);
}

TEST(TwinRooms, ThePathGoesThroughTheDoors) {
  const MotionProfile prof = worldOf(ProfileKind::WheeledCircle);
  const Scene scene = buildProfileScene(prof, 1, twin());
  // Along the path at the camera's height nothing is within 0.3 m ahead.
  const auto& xy = prof.layout.path_xy;
  for (std::size_t i = 0; i + 1 < xy.size(); i += 5) {
    const Eigen::Vector2d dir = (xy[i + 1] - xy[i]).normalized();
    Hit h;
    EXPECT_FALSE(scene.raycast(Eigen::Vector3d(xy[i].x(), xy[i].y(), 0.3),
                               Eigen::Vector3d(dir.x(), dir.y(), 0.0), 0.3, h))
        << "path sample " << i;
  }
}

TEST(TwinRooms, OnlyTheCircleHasTwinRooms) {
  EXPECT_THROW(buildProfileScene(worldOf(ProfileKind::Handheld), 1, twin()), std::invalid_argument);
  IniReader ini = IniReader::fromText("[sim]\ntwin_rooms = true\n", "twin.ini");
  EXPECT_TRUE(ProfileSceneOptions::load(ini).twin_rooms);
}

}  // namespace rgbdi::sim
