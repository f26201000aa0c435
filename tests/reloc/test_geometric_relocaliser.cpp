// GeometricRelocaliser: the height offset from the floor, the ICP refinement (analytic known
// answers) and whole fits of a moved room (x, y, z, yaw recovered; twin rooms ambiguous).
#include <gtest/gtest.h>

#include <cmath>

#include "reloc_test_worlds.h"
#include "rgbdi/reloc/geometric_relocaliser.h"

using namespace rgbdi::reloc;
using namespace rgbdi::reloc::test;

namespace {
RelocOptions options() {
  RelocOptions o;
  o.grid.max_range_m = 10.0;
  o.search.yaw_step_deg = 5.0;
  o.search.pyramid_levels = 5;
  o.submap_min_occupied_cells = 50;
  o.min_floor_cells = 10;
  return o;
}
Eigen::Isometry3d yawPose(double yaw, const Eigen::Vector3d& t) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = t;
  return T;
}
RelocJob jobOf(const std::vector<DepthSample>& samples) {
  RelocJob j;
  j.number = 1;
  j.segment = 1;
  j.anchor_id = 7;
  j.T_anchor.translation() = samples.front().origin;
  j.samples = samples;
  return j;
}

/// Points on three walls and a floor patch: structure in x, y and z for the ICP tests.
std::vector<Eigen::Vector3d> threeWallsAndAFloor() {
  std::vector<Eigen::Vector3d> map_points;
  for (int i = 0; i < 60; ++i)
    for (int k = 0; k < 10; ++k) {
      map_points.emplace_back(0.013 * i, 0.0, 0.05 * k);
      map_points.emplace_back(0.0, 0.017 * i, 0.05 * k);
      map_points.emplace_back(0.8, 0.011 * i, 0.05 * k);
    }
  for (int i = 0; i < 30; ++i)
    for (int j = 0; j < 30; ++j) map_points.emplace_back(0.025 * i, 0.021 * j, 0.0);
  return map_points;
}

}  // namespace

TEST(GeometricRelocaliser, FloorOffsetIsTheMedianHeightDifference) {
  const Eigen::Vector3d cam(at(30), at(20), kCamZ);
  std::vector<DepthSample> map_s, local_s;
  addFloor(0, 0, 20, 20, 0.0, cam, &map_s);
  addFloor(0, 0, 20, 20, -0.4, cam + Eigen::Vector3d(0, 0, -0.4), &local_s);
  PlanGridOptions g;
  g.max_range_m = 10.0;
  const PlanGrid map = PlanGrid::build(map_s, g), local = PlanGrid::build(local_s, g);
  PlanAlignment a;  // identity: pivot = t
  double dz = 0.0;
  ASSERT_TRUE(GeometricRelocaliser::floorOffset(map, local, a, 10, &dz));
  EXPECT_NEAR(dz, 0.4, 1e-12);
  EXPECT_FALSE(GeometricRelocaliser::floorOffset(map, local, a, 1000, &dz));  // too few cells
}

TEST(GeometricRelocaliser, RefineRecoversASmallYawAndShift) {
  // Points on three walls and a floor patch (structure in x, y and z); the local copy is moved
  // by 2 deg and (4, -3, 2) cm, point-to-plane ICP from identity must undo it.
  const std::vector<Eigen::Vector3d> map_points = threeWallsAndAFloor();
  const Eigen::Isometry3d motion = yawPose(2.0 * M_PI / 180.0, Eigen::Vector3d(0.04, -0.03, 0.02));
  std::vector<Eigen::Vector3d> local;
  for (const Eigen::Vector3d& p : map_points) local.push_back(motion.inverse() * p);
  const PointIndex index(map_points, 1e-4, 0.15);  // no thinning: exact correspondences exist
  const GeometricRelocaliser::Refinement r =
      GeometricRelocaliser::refine(local, index, Eigen::Isometry3d::Identity(), 0.15, 50, 1e9);
  EXPECT_NEAR((r.T.translation() - motion.translation()).norm(), 0.0, 1e-6);
  EXPECT_NEAR(Eigen::AngleAxisd(r.T.linear().transpose() * motion.linear()).angle(), 0.0, 1e-6);
  EXPECT_GT(r.pairs, static_cast<int>(0.8 * local.size()));  // points with a surface normal
  EXPECT_LT(r.rms_m, 1e-6);
  EXPECT_GT(r.horizontal_constraint, 0.1);  // walls facing x and y
}

TEST(GeometricRelocaliser, ALoneWallDoesNotPinTheHorizontalPosition) {
  // One wall (normal along y) and a floor: nothing holds the fit along x.
  std::vector<Eigen::Vector3d> map_points;
  for (int i = 0; i < 60; ++i)
    for (int k = 0; k < 10; ++k) map_points.emplace_back(0.013 * i, 0.0, 0.05 * k);
  for (int i = 0; i < 30; ++i)
    for (int j = 0; j < 10; ++j) map_points.emplace_back(0.025 * i, 0.021 * j + 0.05, 0.0);
  const PointIndex index(map_points, 1e-4, 0.15);
  const GeometricRelocaliser::Refinement r =
      GeometricRelocaliser::refine(map_points, index, Eigen::Isometry3d::Identity(), 0.15, 5, 1e9);
  EXPECT_LT(r.rms_m, 1e-9);
  EXPECT_LT(r.horizontal_constraint, 1e-3);  // every normal is along y or z
  RelocOptions o;
  EXPECT_LT(r.horizontal_constraint, o.refine_min_horizontal_constraint);
}

TEST(GeometricRelocaliser, FitsAMovedRoomInXYZAndYaw) {
  const Eigen::Vector3d cam(at(30), at(20), kCamZ);
  const std::vector<DepthSample> world = asymmetricRoom(cam);
  const GeometricRelocaliser reloc(world, options());
  // The part's frame: the room turned by 90 deg, moved by whole cells and 0.25 m down.
  const Eigen::Isometry3d T_part_map =
      yawPose(M_PI / 2, Eigen::Vector3d(-7 * kCell, 12 * kCell, -0.25));
  const RelocFit f = reloc.fit(jobOf(moved(world, M_PI / 2, T_part_map.translation())));
  ASSERT_EQ(f.outcome, FitOutcome::kFit) << toString(f.outcome);
  const Eigen::Isometry3d expected = T_part_map.inverse();
  EXPECT_NEAR((f.T_map_part.translation() - expected.translation()).norm(), 0.0, 1e-6);
  EXPECT_NEAR(Eigen::AngleAxisd(f.T_map_part.linear().transpose() * expected.linear()).angle(), 0.0,
              1e-6);
  EXPECT_EQ(f.places, 1);
  EXPECT_DOUBLE_EQ(f.overlap, 1.0);
  EXPECT_GT(f.refine_pairs, 100);
}

TEST(GeometricRelocaliser, TwinRoomsAreAmbiguous) {
  const Eigen::Vector3d cam_a(at(30), at(20), kCamZ), cam_b(at(110), at(20), kCamZ);
  std::vector<DepthSample> world = asymmetricRoom(cam_a);
  const std::vector<DepthSample> twin = asymmetricRoom(cam_b, 80, 0);
  world.insert(world.end(), twin.begin(), twin.end());
  const GeometricRelocaliser reloc(world, options());
  const RelocFit f = reloc.fit(jobOf(moved(asymmetricRoom(cam_a), 1.0, Eigen::Vector3d(1, 2, 0))));
  EXPECT_EQ(f.outcome, FitOutcome::kAmbiguous);
  EXPECT_EQ(f.places, 2);
}

TEST(GeometricRelocaliser, TooLittleStructureIsNotSearched) {
  const Eigen::Vector3d cam(at(30), at(20), kCamZ);
  const GeometricRelocaliser reloc(asymmetricRoom(cam), options());
  const RelocFit f = reloc.fit(jobOf(scan({cells(0, 0, 3, 3)}, Eigen::Vector3d(0.1, 0.1, kCamZ))));
  EXPECT_EQ(f.outcome, FitOutcome::kTooLittle);
  EXPECT_EQ(f.local_obstacles, 12);
}

TEST(GeometricRelocaliser, HuberKeepsASurfaceTheMapSawElsewhereFromDraggingTheFit) {
  // The three walls and floor of the test above, the local copy exact, plus a patch (320
  // points, 0.1-0.45 m high) 6 cm in front of the x = 0 wall that the map does not have (the back
  // of a shelf, a surface seen with a few centimetres of height drift): paired with that wall, it
  // pulls the fit along x.
  const std::vector<Eigen::Vector3d> map_points = threeWallsAndAFloor();
  std::vector<Eigen::Vector3d> local = map_points;
  for (int i = 0; i < 40; ++i)
    for (int k = 2; k < 10; ++k) local.emplace_back(0.06, 0.3 + 0.017 * i, 0.05 * k);
  const PointIndex index(map_points, 1e-4, 0.15);
  const auto moved_x = [&](double huber_m) {
    return GeometricRelocaliser::refine(local, index, Eigen::Isometry3d::Identity(), 0.15, 50,
                                        huber_m)
        .T.translation()
        .x();
  };
  // Least squares follows the patch by millimetres (the floor and the y walls hold the rest);
  // Huber at 1 cm weighs each patch pair 1/6 and moves less than a quarter of that.
  const double plain = moved_x(1e9), huber = moved_x(0.01);
  EXPECT_LT(plain, -2e-3);
  EXPECT_LT(std::abs(huber), 0.25 * std::abs(plain));
}

TEST(GeometricRelocaliser, ThinStructureGrowsTheSubmapToOlderKeyframes) {
  // Four keyframes, newest first, 0 / 2 / 4 / 7 m of path back from the anchor, each adding 40
  // obstacle cells in a row of its own (samples at their own origin: a hit, no ray).
  RelocJob job;
  for (int kf = 0; kf < 4; ++kf) {
    for (int i = 0; i < 40; ++i) {
      const Eigen::Vector3d p(at(i), at(3 * kf), kCamZ);
      job.samples.push_back({p, p});
    }
    job.spans.push_back({std::vector<double>{0.0, 2.0, 4.0, 7.0}[kf], job.samples.size()});
  }
  RelocOptions o;  // submap_path_m 3, submap_max_path_m 6
  o.submap_min_occupied_cells = 100;
  PlanGrid plan;
  double path = -1.0;
  // 3 m hold 80 cells: the keyframe 4 m back is added (120), the one 7 m back is not needed.
  EXPECT_EQ(GeometricRelocaliser::chooseSubmap(job, o, &plan, &path), 120u);
  EXPECT_EQ(plan.count(CellState::kOccupied), 120u);
  EXPECT_DOUBLE_EQ(path, 4.0);
  // Enough structure within 3 m: nothing older.
  o.submap_min_occupied_cells = 80;
  EXPECT_EQ(GeometricRelocaliser::chooseSubmap(job, o, &plan, &path), 80u);
  EXPECT_DOUBLE_EQ(path, 2.0);
  // Never beyond submap_max_path_m, even when still short of cells.
  o.submap_min_occupied_cells = 1000;
  EXPECT_EQ(GeometricRelocaliser::chooseSubmap(job, o, &plan, &path), 120u);
  EXPECT_DOUBLE_EQ(path, 4.0);
  // submap_max_path_m at or below submap_path_m: no growth.
  o.submap_max_path_m = 3.0;
  EXPECT_EQ(GeometricRelocaliser::chooseSubmap(job, o, &plan, &path), 80u);
  EXPECT_EQ(plan.count(CellState::kOccupied), 80u);
}

TEST(GeometricRelocaliser, RefineSolvesTheSubmapsHeightDrift) {
  // The three walls and floor plus a ramp (z = 0.15 x on y in [0.7, 1.0]); the local copy's
  // points lie s = 0.5 + 3 x metres of path before the anchor, and its odometry's height drifted
  // by -2 cm per metre of path (s = 0.5 .. 2.9 m: 1 to 6 cm low, as on the slopes profiles).
  std::vector<Eigen::Vector3d> map_points = threeWallsAndAFloor();
  for (int i = 0; i < 60; ++i)
    for (int j = 0; j < 15; ++j)
      map_points.emplace_back(0.013 * i, 0.7 + 0.02 * j, 0.15 * 0.013 * i);
  const double drift = 0.02;
  std::vector<Eigen::Vector3d> local;
  std::vector<double> path;
  for (const Eigen::Vector3d& p : map_points) {
    path.push_back(0.5 + 3.0 * p.x());
    local.push_back(p - Eigen::Vector3d(0.0, 0.0, drift * path.back()));
  }
  const PointIndex index(map_points, 1e-4, 0.15);
  // A weak prior (1 m per m) leaves the exact answer; the default 0.02 pulls it by a hair.
  const GeometricRelocaliser::Refinement with = GeometricRelocaliser::refine(
      local, index, Eigen::Isometry3d::Identity(), 0.15, 50, 0.01, path, 1.0);
  EXPECT_NEAR(with.height_drift_per_m, drift, 1e-7);
  EXPECT_NEAR(with.T.translation().norm(), 0.0, 1e-7);
  EXPECT_LT(with.rms_m, 1e-7);
  const GeometricRelocaliser::Refinement prior = GeometricRelocaliser::refine(
      local, index, Eigen::Isometry3d::Identity(), 0.15, 50, 0.01, path, 0.02);
  EXPECT_NEAR(prior.height_drift_per_m, drift, 1e-4);
  EXPECT_NEAR(prior.T.translation().norm(), 0.0, 1e-4);
  // Without the drift term the fit cannot explain it: a residual of centimetres remains.
  const GeometricRelocaliser::Refinement without =
      GeometricRelocaliser::refine(local, index, Eigen::Isometry3d::Identity(), 0.15, 50, 0.01);
  EXPECT_EQ(without.height_drift_per_m, 0.0);
  EXPECT_GT(without.rms_m, 5e-3);
}

TEST(GeometricRelocaliser, RefineCanKeepTheSearchsYawAndPosition) {
  // The local copy 3 cm and 1 deg off horizontally and 2 cm low: with horizontal refinement off
  // only the height moves (exactly), yaw, x and y stay as given.
  const std::vector<Eigen::Vector3d> map_points = threeWallsAndAFloor();
  const Eigen::Isometry3d motion = yawPose(M_PI / 180.0, Eigen::Vector3d(0.03, 0.0, 0.02));
  std::vector<Eigen::Vector3d> local;
  for (const Eigen::Vector3d& p : map_points) local.push_back(motion.inverse() * p);
  const PointIndex index(map_points, 1e-4, 0.15);
  const GeometricRelocaliser::Refinement r = GeometricRelocaliser::refine(
      local, index, Eigen::Isometry3d::Identity(), 0.15, 50, 0.01, {}, 0.0, false);
  EXPECT_TRUE(r.T.linear().isIdentity(0.0));
  EXPECT_EQ(r.T.translation().x(), 0.0);
  EXPECT_EQ(r.T.translation().y(), 0.0);
  // The floor patch pins z; Huber keeps the walls' sideways residuals from pulling it.
  EXPECT_NEAR(r.T.translation().z(), 0.02, 1e-3);
}

TEST(GeometricRelocaliser, ThinningAveragesAValuePerVoxel) {
  const std::vector<Eigen::Vector3d> pts{{0.01, 0.01, 0.01}, {0.03, 0.02, 0.01}, {0.2, 0, 0}};
  std::vector<double> values;
  const std::vector<Eigen::Vector3d> thin = PointIndex::thin(pts, {1.0, 3.0, 5.0}, 0.05, &values);
  ASSERT_EQ(thin.size(), 2u);
  ASSERT_EQ(values.size(), 2u);
  EXPECT_DOUBLE_EQ(values[0], 2.0);
  EXPECT_DOUBLE_EQ(values[1], 5.0);
  EXPECT_TRUE(thin[0].isApprox(Eigen::Vector3d(0.02, 0.015, 0.01)));
}

// Tracking after a join: the part's samples are already in the map's frame by its present poses,
// which are off by a small known offset; the ICP from the identity must return its inverse.
namespace {
RelocJob trackJobOf(const std::vector<DepthSample>& samples, std::uint64_t anchor_id) {
  RelocJob j = jobOf(samples);
  j.track = true;
  j.anchor_id = anchor_id;
  j.part_poses = {{anchor_id, j.T_anchor}};
  return j;
}
}  // namespace

TEST(GeometricRelocaliser, TrackingCorrectsAKnownOffsetOfThePresentPose) {
  const Eigen::Vector3d cam(at(30), at(20), kCamZ);
  const std::vector<DepthSample> world = asymmetricRoom(cam);
  const GeometricRelocaliser reloc(world, options());
  // The present pose is off by 1 deg about the camera and (3, -2, 1) cm.
  const double yaw = 1.0 * M_PI / 180.0;
  const Eigen::Vector3d shift(0.03, -0.02, 0.01);
  const Eigen::Isometry3d off = yawPose(0.0, cam + shift) * yawPose(yaw, Eigen::Vector3d::Zero()) *
                                yawPose(0.0, -cam);  // samples -> where the present pose puts them
  std::vector<DepthSample> local;
  for (const DepthSample& d : world) local.push_back({off * d.origin, off * d.point});
  const RelocFit f = reloc.track(trackJobOf(local, 42));
  ASSERT_EQ(f.outcome, FitOutcome::kFit) << toString(f.outcome);
  EXPECT_TRUE(f.track);
  const Eigen::Isometry3d expected = off.inverse();
  EXPECT_NEAR((f.T_map_part * local.front().origin - world.front().origin).norm(), 0.0, 2e-3);
  EXPECT_NEAR(Eigen::AngleAxisd(f.T_map_part.linear().transpose() * expected.linear()).angle(), 0.0,
              1e-3);
  EXPECT_NEAR(f.correction_m, shift.norm(), 2e-3);  // the anchor's move: the shift undone
  EXPECT_NEAR(f.correction_rad, yaw, 1e-3);
  ASSERT_EQ(f.part_poses.size(), 1u);
  EXPECT_EQ(f.part_poses.front().first, 42u);
}

TEST(GeometricRelocaliser, TrackingRefusesAFitFarFromThePresentPose) {
  const Eigen::Vector3d cam(at(30), at(20), kCamZ);
  const std::vector<DepthSample> world = asymmetricRoom(cam);
  RelocOptions o = options();
  const GeometricRelocaliser reloc(world, o);
  // 12 cm off along x: the ICP finds it (neighbours within 15 cm), the bound (10 cm) refuses it.
  const RelocFit far = reloc.track(trackJobOf(moved(world, 0.0, Eigen::Vector3d(0.12, 0, 0)), 1));
  EXPECT_EQ(far.outcome, FitOutcome::kTooFar) << toString(far.outcome);
  EXPECT_NEAR(far.correction_m, 0.12, 2e-3);
  // The same with a bound of 15 cm is a fit.
  o.track_max_correction_m = 0.15;
  const GeometricRelocaliser loose(world, o);
  const RelocFit near = loose.track(trackJobOf(moved(world, 0.0, Eigen::Vector3d(0.12, 0, 0)), 1));
  EXPECT_EQ(near.outcome, FitOutcome::kFit) << toString(near.outcome);
  // 3 deg about the camera: beyond track_max_correction_deg (2).
  const Eigen::Isometry3d turn =
      yawPose(0.0, cam) * yawPose(3.0 * M_PI / 180.0, Eigen::Vector3d::Zero()) * yawPose(0.0, -cam);
  std::vector<DepthSample> turned;
  for (const DepthSample& d : world) turned.push_back({turn * d.origin, turn * d.point});
  const RelocFit t = reloc.track(trackJobOf(turned, 1));
  EXPECT_EQ(t.outcome, FitOutcome::kTooFar) << toString(t.outcome);
  EXPECT_NEAR(t.correction_rad, 3.0 * M_PI / 180.0, 1e-3);
  EXPECT_LT(t.correction_m, 2e-3);  // turned about the anchor: it does not move
}

TEST(GeometricRelocaliser, TrackingOfAPoseThatIsRightChangesNothing) {
  const Eigen::Vector3d cam(at(30), at(20), kCamZ);
  const std::vector<DepthSample> world = asymmetricRoom(cam);
  const GeometricRelocaliser reloc(world, options());
  const RelocFit f = reloc.track(trackJobOf(world, 1));
  ASSERT_EQ(f.outcome, FitOutcome::kFit);
  EXPECT_LT(f.correction_m, 1e-6);
  EXPECT_LT(f.correction_rad, 1e-6);
}
