// ScanSearch: a known rotation and shift of a room is found exactly at grid resolution from
// anywhere (a global search); symmetric rooms and twin rooms give several places.
#include <gtest/gtest.h>

#include <cmath>

#include "reloc_test_worlds.h"
#include "rgbdi/reloc/scan_search.h"

using namespace rgbdi::reloc;
using namespace rgbdi::reloc::test;

namespace {
PlanGridOptions gridOptions() {
  PlanGridOptions o;
  o.resolution_m = kCell;
  o.max_range_m = 10.0;
  return o;
}
ScanSearchOptions searchOptions() {
  ScanSearchOptions o;
  o.yaw_step_deg = 5.0;  // 90 deg is a multiple: the tests' rotations are on the search lattice
  o.pyramid_levels = 5;
  return o;
}
}  // namespace

TEST(ScanSearch, FindsARotatedAndShiftedRoomExactly) {
  const Eigen::Vector3d cam(at(30), at(20), kCamZ);
  const std::vector<DepthSample> world = asymmetricRoom(cam);
  const ScanSearch search(PlanGrid::build(world, gridOptions()), searchOptions());
  // The local frame: the world turned by +90 deg and shifted by whole cells (odometry frame).
  const double yaw = M_PI / 2;
  const Eigen::Vector3d shift(-7 * kCell, 12 * kCell, 0.0);
  const std::vector<DepthSample> local_samples = moved(world, yaw, shift);
  const PlanGrid local = PlanGrid::build(local_samples, gridOptions());
  const Eigen::Vector2d pivot = local_samples.front().origin.head<2>();  // the camera
  const ScanSearchResult r = search.search(local, pivot);
  ASSERT_EQ(r.places.size(), 1u);
  const PlanHypothesis& h = r.places.front();
  EXPECT_NEAR(h.alignment.yaw, -M_PI / 2, 1e-12);  // local -> map undoes the turn
  EXPECT_NEAR(h.alignment.t.x(), cam.x(), 1e-9);   // the pivot lands on the camera
  EXPECT_NEAR(h.alignment.t.y(), cam.y(), 1e-9);
  EXPECT_DOUBLE_EQ(h.overlap, 1.0);
  EXPECT_EQ(h.conflicts, 0);
  EXPECT_GT(h.compared, 1000);
  EXPECT_FALSE(r.truncated);
  EXPECT_GT(r.nodes_scored, 0u);
}

TEST(ScanSearch, APartOfTheRoomSeenFromElsewhereIsFoundToo) {
  // The local plan holds only the walls near the crate corner (what a short drive sees).
  const Eigen::Vector3d cam(at(20), at(25), kCamZ);
  const std::vector<DepthSample> world = asymmetricRoom(cam);
  const ScanSearch search(PlanGrid::build(world, gridOptions()), searchOptions());
  std::vector<DepthSample> part;
  for (const DepthSample& d : world)
    if (d.point.x() < at(25) && d.point.y() > at(15)) part.push_back(d);
  const std::vector<DepthSample> local_samples = moved(part, M_PI, Eigen::Vector3d(3.0, -1.0, 0.0));
  const PlanGrid local = PlanGrid::build(local_samples, gridOptions());
  const ScanSearchResult r = search.search(local, local_samples.front().origin.head<2>());
  ASSERT_EQ(r.places.size(), 1u);
  EXPECT_NEAR(std::abs(r.places.front().alignment.yaw), M_PI, 1e-12);
  EXPECT_NEAR(r.places.front().alignment.t.x(), cam.x(), 1e-9);
  EXPECT_NEAR(r.places.front().alignment.t.y(), cam.y(), 1e-9);
}

TEST(ScanSearch, APointSymmetricRoomIsTwoPlaces) {
  // A bare rectangle seen from its centre: turned by 180 deg it is the same room.
  const Eigen::Vector3d cam(at(30), at(20), kCamZ);
  const std::vector<DepthSample> world = scan({cells(0, 0, 60, 40)}, cam);
  const ScanSearch search(PlanGrid::build(world, gridOptions()), searchOptions());
  const std::vector<DepthSample> local_samples = moved(world, 0.0, Eigen::Vector3d(1.0, 1.0, 0.0));
  const ScanSearchResult r = search.search(PlanGrid::build(local_samples, gridOptions()),
                                           local_samples.front().origin.head<2>());
  ASSERT_EQ(r.places.size(), 2u);
  EXPECT_EQ(r.places[0].score, r.places[1].score);
  EXPECT_NEAR(std::abs(r.places[0].alignment.yaw - r.places[1].alignment.yaw), M_PI, 1e-12);
}

TEST(ScanSearch, TwinRoomsAreTwoPlaces) {
  // Two identical asymmetric rooms side by side (their own cameras), the run sees one of them.
  const Eigen::Vector3d cam_a(at(30), at(20), kCamZ), cam_b(at(30 + 80), at(20), kCamZ);
  std::vector<DepthSample> world = asymmetricRoom(cam_a);
  const std::vector<DepthSample> twin = asymmetricRoom(cam_b, 80, 0);
  world.insert(world.end(), twin.begin(), twin.end());
  const ScanSearch search(PlanGrid::build(world, gridOptions()), searchOptions());
  const std::vector<DepthSample> local_samples =
      moved(asymmetricRoom(cam_a), 0.3, Eigen::Vector3d(0.5, 2, 0));
  const ScanSearchResult r = search.search(PlanGrid::build(local_samples, gridOptions()),
                                           local_samples.front().origin.head<2>());
  // Turned by 0.3 rad (off the 5 deg lattice) the two rooms score a little differently, both
  // within the margin; the places are the two rooms, 4 m apart (to a cell).
  ASSERT_EQ(r.places.size(), 2u);
  EXPECT_GE(r.places[1].score, (1.0 - searchOptions().hypothesis_margin) * r.places[0].score);
  EXPECT_NEAR(std::abs(r.places[0].alignment.t.x() - r.places[1].alignment.t.x()), 80 * kCell,
              kCell + 1e-9);
  EXPECT_NEAR(r.places[0].alignment.t.y(), r.places[1].alignment.t.y(), kCell + 1e-9);
}

TEST(ScanSearch, AnOtherWorldFitsNowhere) {
  const Eigen::Vector3d cam(at(30), at(20), kCamZ);
  const ScanSearch search(PlanGrid::build(asymmetricRoom(cam), gridOptions()), searchOptions());
  // A long corridor of 8 x 1 m: nowhere in the 3 x 2 m room.
  const std::vector<DepthSample> corridor =
      scan({cells(0, 0, 160, 20)}, Eigen::Vector3d(at(80), at(10), kCamZ));
  const ScanSearchResult r =
      search.search(PlanGrid::build(corridor, gridOptions()), Eigen::Vector2d(at(80), at(10)));
  EXPECT_TRUE(r.places.empty());
}

TEST(ScanSearch, ObstaclesInTheMapsFreeSpaceRefuseAPlace) {
  // The map room is empty inside; the local plan has the same walls plus a box in the middle
  // (seen from the same camera): the walls fit, but the box stands where the map saw through.
  const Eigen::Vector3d cam(at(30), at(20), kCamZ);
  const std::vector<DepthSample> map_samples =
      scan({cells(0, 0, 59, 39), cells(5, 28, 14, 34)}, cam);
  const std::vector<DepthSample> local_samples =  // a 0.75 x 0.95 m box the map never had
      scan({cells(0, 0, 59, 39), cells(5, 28, 14, 34), cells(36, 12, 50, 30)}, cam);
  // The box's faces are about 1 % of the compared cells: the test's limit is 0.5 %.
  ScanSearchOptions o = searchOptions();
  o.min_overlap_fraction = 0.3;
  o.max_conflict_fraction = 0.005;
  const ScanSearch search(PlanGrid::build(map_samples, gridOptions()), o);
  const PlanGrid local = PlanGrid::build(local_samples, gridOptions());
  const ScanSearchResult r = search.search(local, cam.head<2>());
  ASSERT_GE(r.candidates.size(), 1u);
  EXPECT_NEAR(r.candidates.front().alignment.yaw, 0.0, 1e-12);
  EXPECT_GT(r.candidates.front().conflict_fraction, o.max_conflict_fraction);
  EXPECT_TRUE(r.places.empty());
}

TEST(ScanSearch, AgreementIsTheScoreLessThePenaltyPerConflict) {
  // The box-in-free-space case at the true alignment: score and conflicts as counted, the
  // agreement exactly score - conflict_penalty x conflicts.
  const Eigen::Vector3d cam(at(30), at(20), kCamZ);
  const std::vector<DepthSample> map_samples =
      scan({cells(0, 0, 59, 39), cells(5, 28, 14, 34)}, cam);
  const PlanGrid local = PlanGrid::build(
      scan({cells(0, 0, 59, 39), cells(5, 28, 14, 34), cells(36, 12, 50, 30)}, cam), gridOptions());
  PlanAlignment a;
  a.pivot = a.t = cam.head<2>();
  for (double penalty : {0.0, 1.0, 2.5}) {
    ScanSearchOptions o = searchOptions();
    o.conflict_penalty = penalty;
    const PlanHypothesis h =
        ScanSearch(PlanGrid::build(map_samples, gridOptions()), o).evaluate(local, a);
    ASSERT_GT(h.conflicts, 0);
    EXPECT_DOUBLE_EQ(h.agreement, h.score - penalty * h.conflicts);
  }
}
