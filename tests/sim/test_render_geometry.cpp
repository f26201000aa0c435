// Ray-primitive intersections against analytic answers, the room helper, and BVH == brute force.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>

#include "rgbdi/sim/scene.h"

namespace rgbdi::sim {
namespace {

constexpr double kTol = 1e-12;

std::array<MaterialId, 6> mats6() { return {0, 1, 2, 3, 4, 5}; }

TEST(RenderGeometry, BoxFromOutsideHitsEntryFace) {
  const Box box(Eigen::Isometry3d::Identity(), {1, 2, 3}, mats6());
  PrimitiveHit h;
  ASSERT_TRUE(box.intersect({-5, 0.5, 0.5}, {1, 0, 0}, 100, h));
  EXPECT_NEAR(h.t, 4.0, kTol);
  EXPECT_EQ(h.face, 0);
  ASSERT_TRUE(box.intersect({0.2, 0.3, 10}, {0, 0, -1}, 100, h));
  EXPECT_NEAR(h.t, 7.0, kTol);
  EXPECT_EQ(h.face, 5);
  const SurfaceInfo s = box.surface({0.2, 0.3, 3}, 5);
  EXPECT_TRUE(s.normal.isApprox(Eigen::Vector3d::UnitZ()));
  EXPECT_NEAR(s.uv.x(), 1.2, kTol);  // measured from the face corner
  EXPECT_NEAR(s.uv.y(), 2.3, kTol);
  // Misses: beside the box, pointing away, and beyond t_max.
  EXPECT_FALSE(box.intersect({-5, 2.5, 0}, {1, 0, 0}, 100, h));
  EXPECT_FALSE(box.intersect({-5, 0, 0}, {-1, 0, 0}, 100, h));
  EXPECT_FALSE(box.intersect({-5, 0, 0}, {1, 0, 0}, 3.9, h));
}

TEST(RenderGeometry, BoxFromInsideHitsExitFace) {
  const Box box(Eigen::Isometry3d::Identity(), {1, 2, 3}, mats6());
  PrimitiveHit h;
  ASSERT_TRUE(box.intersect({0, 0, 0}, {0, 1, 0}, 100, h));
  EXPECT_NEAR(h.t, 2.0, kTol);
  EXPECT_EQ(h.face, 3);
  const Eigen::Vector3d d = Eigen::Vector3d(1, 1, 1).normalized();
  ASSERT_TRUE(box.intersect({0, 0, 0}, d, 100, h));
  EXPECT_NEAR(h.t, std::sqrt(3.0), kTol);  // leaves through x = 1 first
  EXPECT_EQ(h.face, 1);
}

TEST(RenderGeometry, OrientedBox) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = (Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  T.translation() = Eigen::Vector3d(2, 1, 0.5);
  const Eigen::Vector3d half(0.5, 1.0, 0.25);
  const Box box(T, half, mats6());
  // Along the box's own x axis, offset in y/z: enters through the -x face at local x = -0.5.
  const Eigen::Vector3d o = T * Eigen::Vector3d(-5, 0.3, 0.1);
  const Eigen::Vector3d d = T.linear() * Eigen::Vector3d::UnitX();
  PrimitiveHit h;
  ASSERT_TRUE(box.intersect(o, d, 100, h));
  EXPECT_NEAR(h.t, 4.5, 1e-12);
  EXPECT_EQ(h.face, 0);
  const Eigen::Vector3d p = o + h.t * d;
  EXPECT_LT((p - T * Eigen::Vector3d(-0.5, 0.3, 0.1)).norm(), 1e-12);
  const SurfaceInfo s = box.surface(p, h.face);
  EXPECT_LT((s.normal + T.linear().col(0)).norm(), 1e-12);
  EXPECT_NEAR(s.uv.x(), 1.3, 1e-12);
  EXPECT_NEAR(s.uv.y(), 0.35, 1e-12);
  // An oblique ray: its hit lies on the box surface and no earlier point is inside.
  const Eigen::Vector3d o2(-3, -2, 2), d2 = (T.translation() - o2).normalized();
  ASSERT_TRUE(box.intersect(o2, d2, 100, h));
  const Eigen::Vector3d local = T.inverse() * (o2 + h.t * d2);
  EXPECT_NEAR((local.cwiseAbs() - half).maxCoeff(), 0.0, 1e-12);
  const Eigen::Vector3d before = T.inverse() * (o2 + (h.t - 1e-6) * d2);
  EXPECT_GT((before.cwiseAbs() - half).maxCoeff(), 0.0);
  // Bounds contain all corners.
  const Eigen::AlignedBox3d b = box.bounds();
  for (int k = 0; k < 8; ++k) {
    const Eigen::Vector3d c(k & 1 ? 0.5 : -0.5, k & 2 ? 1.0 : -1.0, k & 4 ? 0.25 : -0.25);
    EXPECT_TRUE(b.contains(T * c));
  }
}

TEST(RenderGeometry, Cylinder) {
  const Cylinder cyl({1, 2}, 0.5, 0.0, 3.0, {7, 8, 9});
  PrimitiveHit h;
  ASSERT_TRUE(cyl.intersect({-3, 2, 1}, {1, 0, 0}, 100, h));
  EXPECT_NEAR(h.t, 3.5, kTol);
  EXPECT_EQ(h.face, 0);
  EXPECT_EQ(cyl.material(h.face), 7u);
  // Off-centre: x offset 0.3 -> hits at y = 2 - sqrt(0.25 - 0.09) = 1.6, normal (0.6, -0.8, 0).
  ASSERT_TRUE(cyl.intersect({1.3, -3, 1.5}, {0, 1, 0}, 100, h));
  EXPECT_NEAR(h.t, 4.6, 1e-12);
  SurfaceInfo s = cyl.surface(Eigen::Vector3d(1.3, 1.6, 1.5), h.face);
  EXPECT_LT((s.normal - Eigen::Vector3d(0.6, -0.8, 0)).norm(), 1e-12);
  EXPECT_NEAR(s.uv.y(), 1.5, kTol);
  // Top cap from above, bottom cap from below.
  ASSERT_TRUE(cyl.intersect({1.2, 2.1, 10}, {0, 0, -1}, 100, h));
  EXPECT_NEAR(h.t, 7.0, kTol);
  EXPECT_EQ(h.face, 2);
  ASSERT_TRUE(cyl.intersect({1.2, 2.1, -1}, {0, 0, 1}, 100, h));
  EXPECT_NEAR(h.t, 1.0, kTol);
  EXPECT_EQ(h.face, 1);
  // From inside: exits through the side.
  ASSERT_TRUE(cyl.intersect({1, 2, 1}, {1, 0, 0}, 100, h));
  EXPECT_NEAR(h.t, 0.5, kTol);
  EXPECT_EQ(h.face, 0);
  // Misses: above the top, beside, and a vertical ray outside the circle.
  EXPECT_FALSE(cyl.intersect({-3, 2, 3.5}, {1, 0, 0}, 100, h));
  EXPECT_FALSE(cyl.intersect({-3, 2.6, 1}, {1, 0, 0}, 100, h));
  EXPECT_FALSE(cyl.intersect({1.6, 2, 10}, {0, 0, -1}, 100, h));
  // A slanted ray entering through the top cap edge region: check against the analytic solid.
  const Eigen::Vector3d o(3, 4, 5), d = (Eigen::Vector3d(1.1, 2.1, 3.0) - o).normalized();
  ASSERT_TRUE(cyl.intersect(o, d, 100, h));
  const Eigen::Vector3d p = o + h.t * d;
  const double radial = std::hypot(p.x() - 1, p.y() - 2);
  EXPECT_TRUE(std::abs(p.z() - 3.0) < 1e-12 || std::abs(radial - 0.5) < 1e-12);
  EXPECT_LE(radial, 0.5 + 1e-12);
}

// Height of the first surface below (x, y) seen from z = 10, or NaN.
double surfaceHeight(const Scene& scene, double x, double y) {
  Hit hit;
  if (!scene.raycast({x, y, 10}, {0, 0, -1}, 100, hit)) return std::nan("");
  return hit.point.z();
}

TEST(RenderGeometry, RampSurfaceHeight) {
  Scene scene(3);
  scene.addRamp({0, 0}, {4, 0}, 0.0, 2.0, 1.0, TextureStyle::Tiles);
  // The same ramp rotated: from (1, 1) to (1, 4) on a base at z = 0.5.
  scene.addRamp({10, 1}, {10, 4}, 0.5, 1.0, 0.6, TextureStyle::Tiles);
  scene.addSymmetricRamp({0, 10}, {4, 10}, 0.0, 2.0, 1.0, TextureStyle::Planks);
  scene.build();
  EXPECT_NEAR(surfaceHeight(scene, 1.0, 0.3), 0.25, 1e-12);
  EXPECT_NEAR(surfaceHeight(scene, 3.9, -0.9), 0.975, 1e-12);
  EXPECT_TRUE(std::isnan(surfaceHeight(scene, 1.0, 1.1)));    // beside (width 2)
  EXPECT_TRUE(std::isnan(surfaceHeight(scene, 4.05, 0.0)));   // past the top edge
  EXPECT_TRUE(std::isnan(surfaceHeight(scene, -0.05, 0.0)));  // before the foot
  EXPECT_NEAR(surfaceHeight(scene, 10.2, 2.5), 0.5 + 0.3, 1e-12);
  EXPECT_NEAR(surfaceHeight(scene, 1.0, 10.0), 0.5, 1e-12);
  EXPECT_NEAR(surfaceHeight(scene, 2.0, 10.5), 1.0, 1e-12);
  EXPECT_NEAR(surfaceHeight(scene, 3.0, 9.5), 0.5, 1e-12);
  // Slope normal of the first ramp, and its vertical back face.
  Hit hit;
  ASSERT_TRUE(scene.raycast({1, 0, 10}, {0, 0, -1}, 100, hit));
  EXPECT_LT((hit.normal - Eigen::Vector3d(-1, 0, 4).normalized()).norm(), 1e-12);
  ASSERT_TRUE(scene.raycast({10, 0, 0.5}, {-1, 0, 0}, 100, hit));
  EXPECT_NEAR(hit.t, 6.0, 1e-12);
  EXPECT_LT((hit.normal - Eigen::Vector3d::UnitX()).norm(), 1e-12);
  // From inside the wedge the visible face is an exit face, normal facing the origin.
  ASSERT_TRUE(scene.raycast({1, 0, 0.1}, {0, 0, 1}, 100, hit));
  EXPECT_NEAR(hit.point.z(), 0.25, 1e-12);
  EXPECT_LT(hit.normal.dot(Eigen::Vector3d::UnitZ()), 0.0);
  // Texture coordinates on the slope run along it in metres.
  ASSERT_TRUE(scene.raycast({2, 0.25, 10}, {0, 0, -1}, 100, hit));
  EXPECT_NEAR(hit.uv.x(), std::hypot(2.0, 0.5), 1e-12);
  EXPECT_NEAR(hit.uv.y(), 1.25, 1e-12);
}

TEST(RenderGeometry, RoomIsClosedAndEverySurfaceHasItsOwnMaterial) {
  Scene scene(5);
  const auto ids = scene.addRoom({-2, -3, 0}, {4, 5, 2.5});
  scene.build();
  const Eigen::Vector3d c(1, 1, 1.2);
  struct Case {
    Eigen::Vector3d dir;
    double t;
    std::uint32_t prim;
  };
  const Case cases[] = {{{0, 0, -1}, 1.2, ids[0]}, {{0, 0, 1}, 1.3, ids[1]},
                        {{-1, 0, 0}, 3.0, ids[2]}, {{1, 0, 0}, 3.0, ids[3]},
                        {{0, -1, 0}, 4.0, ids[4]}, {{0, 1, 0}, 4.0, ids[5]}};
  std::set<MaterialId> seen;
  for (const Case& k : cases) {
    Hit hit;
    ASSERT_TRUE(scene.raycast(c, k.dir, 100, hit));
    EXPECT_NEAR(hit.t, k.t, 1e-12);
    EXPECT_EQ(hit.primitive, k.prim);
    EXPECT_LT((hit.normal + k.dir).norm(), 1e-12);  // interior faces look into the room
    seen.insert(hit.material);
  }
  EXPECT_EQ(seen.size(), 6u);
  // Closed: rays in random directions from inside always hit something within the room.
  std::mt19937_64 rng(11);
  std::normal_distribution<double> n01;
  for (int i = 0; i < 2000; ++i) {
    const Eigen::Vector3d d = Eigen::Vector3d(n01(rng), n01(rng), n01(rng)).normalized();
    Hit hit;
    ASSERT_TRUE(scene.raycast(c, d, 100, hit));
    EXPECT_LT(hit.t, 6.0);
  }
}

TEST(RenderGeometry, UnbuiltSceneAndBadPrimitivesAreRejected) {
  Scene scene(1);
  scene.addStep({0, 0}, {1, 1}, 0.0, 0.0, 0.2, TextureStyle::Tiles);
  Hit hit;
  EXPECT_THROW(scene.raycast({0, 0, 5}, {0, 0, -1}, 10, hit), std::logic_error);
  scene.build();
  EXPECT_TRUE(scene.raycast({0, 0, 5}, {0, 0, -1}, 10, hit));
  EXPECT_NEAR(hit.t, 4.8, 1e-12);
  scene.addCylinder({3, 0}, 0.2, 0, 1, TextureStyle::Speckle);
  EXPECT_THROW(scene.raycast({0, 0, 5}, {0, 0, -1}, 10, hit), std::logic_error);
  EXPECT_THROW(scene.addCylinder({0, 0}, -1, 0, 1, TextureStyle::Speckle), std::invalid_argument);
  EXPECT_THROW(scene.addBox(Eigen::Isometry3d::Identity(), {1, 0, 1}, TextureStyle::Posters),
               std::invalid_argument);
  EXPECT_THROW(scene.addRamp({0, 0}, {0, 0}, 0, 1, 1, TextureStyle::Tiles), std::invalid_argument);
  EXPECT_THROW(scene.addRoom({0, 0, 0}, {1, -1, 1}), std::invalid_argument);
  EXPECT_THROW(scene.material(9999), std::out_of_range);
}

// A cluttered scene with every primitive kind, overlapping and touching objects.
Scene randomScene(std::uint64_t seed, int objects) {
  Scene scene(seed);
  scene.addRoom({-6, -5, 0}, {6, 5, 3});
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> ux(-5.5, 5.5), uy(-4.5, 4.5), us(0.1, 0.8),
      ua(-M_PI, M_PI);
  for (int i = 0; i < objects; ++i) {
    switch (i % 4) {
      case 0: {
        Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
        T.linear() = (Eigen::AngleAxisd(ua(rng), Eigen::Vector3d::UnitZ()) *
                      Eigen::AngleAxisd(0.3 * ua(rng), Eigen::Vector3d::UnitX()))
                         .toRotationMatrix();
        T.translation() = Eigen::Vector3d(ux(rng), uy(rng), 3 * us(rng));
        scene.addBox(T, {us(rng), us(rng), us(rng)}, TextureStyle::Posters);
        break;
      }
      case 1:
        scene.addCylinder({ux(rng), uy(rng)}, 0.5 * us(rng), 0.0, 3 * us(rng),
                          TextureStyle::Speckle);
        break;
      case 2: {
        const Eigen::Vector2d a(ux(rng), uy(rng));
        const Eigen::Vector2d b = a + Eigen::Vector2d(us(rng) * 2, us(rng) - 0.45);
        if (i % 8 == 2)
          scene.addRamp(a, b, 0.0, us(rng) * 2, us(rng), TextureStyle::Tiles);
        else
          scene.addSymmetricRamp(a, b, 0.0, us(rng) * 2, us(rng), TextureStyle::Planks);
        break;
      }
      default:
        scene.addStep({ux(rng), uy(rng)}, {us(rng), us(rng)}, ua(rng), 0.0, us(rng),
                      TextureStyle::Bricks);
    }
  }
  scene.build();
  return scene;
}

TEST(RenderGeometry, BvhRaycastEqualsBruteForce) {
  const Scene scene = randomScene(21, 200);
  EXPECT_EQ(scene.primitiveCount(), 206u);
  EXPECT_LT(scene.bvh().depth(), 30);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> ux(-8, 8), uy(-7, 7), uz(-1, 4), ur(0.5, 30);
  std::normal_distribution<double> n01;
  int hits = 0, tested = 0;
  for (int i = 0; i < 20000; ++i) {
    // Mostly from inside the room; some from outside the whole scene.
    const Eigen::Vector3d o(ux(rng), uy(rng), uz(rng));
    const Eigen::Vector3d d = Eigen::Vector3d(n01(rng), n01(rng), n01(rng)).normalized();
    const double range = ur(rng);
    Hit a, b;
    const bool ha = scene.raycast(o, d, range, a);
    const bool hb = scene.raycastBruteForce(o, d, range, b);
    ++tested;
    ASSERT_EQ(ha, hb) << "ray " << i;
    if (!ha) continue;
    ++hits;
    ASSERT_EQ(a.t, b.t) << "ray " << i;
    ASSERT_EQ(a.primitive, b.primitive) << "ray " << i;
    ASSERT_EQ(a.face, b.face);
    ASSERT_EQ(a.material, b.material);
    ASSERT_LE(a.t, range);
  }
  EXPECT_GT(hits, tested / 2);
}

TEST(RenderGeometry, BvhOfIdenticalBoundsStaysShallow) {
  Scene scene(2);
  for (int i = 0; i < 300; ++i) scene.addStep({0, 0}, {1, 1}, 0.0, 0.0, 1.0, TextureStyle::Tiles);
  scene.build();
  EXPECT_LE(scene.bvh().depth(), 12);
  Hit a, b;
  ASSERT_TRUE(scene.raycast({5, 0.1, 0.5}, {-1, 0, 0}, 100, a));
  ASSERT_TRUE(scene.raycastBruteForce({5, 0.1, 0.5}, {-1, 0, 0}, 100, b));
  EXPECT_EQ(a.t, b.t);
  EXPECT_EQ(a.primitive, b.primitive);
}

}  // namespace
}  // namespace rgbdi::sim
