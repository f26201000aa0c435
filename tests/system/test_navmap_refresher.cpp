// NavMapRefresher (live runs): the navigation maps are rewritten after a loop correction and at
// the refresh interval, not otherwise; a failure is reported, not thrown.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <thread>

#include "mapping/synthetic_frames.h"
#include "rgbdi/mapping/mapper.h"
#include "rgbdi/navmap/navmap_files.h"
#include "rgbdi/system/navmap_refresher.h"
#include "rgbdi/system/slam_navmap.h"
#include "testing/fixtures.h"

using namespace rgbdi;
namespace fs = std::filesystem;

namespace {

/// A mapper holding one keyframe 1 m above a floor, looking straight down at it.
std::unique_ptr<mapping::Mapper> floorMapper() {
  auto m = std::make_unique<mapping::Mapper>(mapping::MappingOptions{}, false);
  mapping::Keyframe k;
  k.T_world_cam.linear() = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix();
  k.T_world_cam.translation() = Eigen::Vector3d(0.0, 0.0, 1.0);
  m->addKeyframe(k, mapping::test::planeFrame(1000));
  return m;
}

}  // namespace

TEST(NavMapRefresher, RewritesTheMapsAfterACorrectionAndOnlyThenWithoutAnInterval) {
  const auto mapper = floorMapper();
  const std::string dir = test::makeTempDir("navmap_refresher");
  navmap::NavMapOptions o;
  o.refresh_interval_s = 0.0;
  system::NavMapRefresher r(dir, o);
  r.update(*mapper, false);
  EXPECT_EQ(r.refreshes(), 0u);
  EXPECT_FALSE(fs::exists(dir + "/navmap.yaml"));
  r.update(*mapper, true);
  EXPECT_EQ(r.refreshes(), 1u);
  EXPECT_EQ(r.lastError(), "");
  const navmap::NavMap m = navmap::readLayers(dir + "/navmap_layers.yml.gz");
  int ix = 0, iy = 0;
  ASSERT_TRUE(m.grid.cellOf(0.3, 0.2, &ix, &iy));
  EXPECT_EQ(m.state[m.grid.index(ix, iy)], navmap::CellState::kFree);
  EXPECT_NEAR(m.ground_z_m[m.grid.index(ix, iy)], 0.0, 0.01);
  EXPECT_TRUE(fs::exists(dir + "/navmap.yaml"));
  EXPECT_TRUE(fs::exists(dir + "/navmap.gridmap"));
}

TEST(NavMapRefresher, RewritesTheMapsAtTheIntervalAndNeverWhenDisabled) {
  const auto mapper = floorMapper();
  const std::string dir = test::makeTempDir("navmap_refresher_interval");
  navmap::NavMapOptions o;
  o.refresh_interval_s = 0.3;
  system::NavMapRefresher r(dir, o);
  r.update(*mapper, false);  // not due yet
  EXPECT_EQ(r.refreshes(), 0u);
  std::this_thread::sleep_for(std::chrono::milliseconds(350));
  r.update(*mapper, false);
  EXPECT_EQ(r.refreshes(), 1u);
  r.update(*mapper, false);  // at once again: the period counts from the end of the refresh
  EXPECT_EQ(r.refreshes(), 1u);
  o.enable = false;
  system::NavMapRefresher off(dir, o);
  std::this_thread::sleep_for(std::chrono::milliseconds(350));
  off.update(*mapper, true);
  EXPECT_EQ(off.refreshes(), 0u);
}

TEST(NavMapRefresher, AFailedWriteIsReportedAndTheRunGoesOn) {
  const auto mapper = floorMapper();
  navmap::NavMapOptions o;
  system::NavMapRefresher r("/nonexistent/rgbdi_navmap_dir", o);
  EXPECT_NO_THROW(r.update(*mapper, true));
  EXPECT_EQ(r.refreshes(), 0u);
  EXPECT_NE(r.lastError().find("/nonexistent/rgbdi_navmap_dir/navmap"), std::string::npos)
      << r.lastError();
}

TEST(NavMapRefresher, KeepsTheMapIncrementallyAndRebuildsItWhenPosesMove) {
  auto mapper = std::make_unique<mapping::Mapper>(mapping::MappingOptions{}, false);
  navmap::NavMapOptions o;
  o.refresh_interval_s = 0.0;
  const std::string dir = test::makeTempDir("navmap_refresher_incremental");
  system::NavMapRefresher r(dir, o);
  // Three keyframes looking down at the floor from 1 m, 0.6 m apart along x.
  for (int k = 0; k < 3; ++k) {
    mapping::Keyframe kf;
    kf.id = static_cast<std::uint64_t>(k);
    kf.T_world_cam.linear() = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix();
    kf.T_world_cam.translation() = Eigen::Vector3d(0.6 * k, 0.0, 1.0);
    mapper->addKeyframe(kf, mapping::test::planeFrame(1000));
    r.update(*mapper, false);
  }
  EXPECT_EQ(r.refreshes(), 0u);
  EXPECT_EQ(r.fullRebuilds(), 1u);  // the first fill only: later keyframes were added
  auto fullBuild = [&]() {
    std::vector<Eigen::Vector3d> path;
    for (const mapping::Keyframe& kf : mapper->store().keyframes())
      path.push_back(kf.T_world_cam.translation());
    const navmap::NavMap m = navmap::buildNavMap(system::navMapPoints(mapper->store(), o), path, o);
    const std::string full_dir = test::makeTempDir("navmap_refresher_full");
    navmap::writeNavMapFiles(m, full_dir, &path);
    return full_dir;
  };
  auto bytes = [](const std::string& f) {
    std::ifstream in(f, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  r.update(*mapper, true);  // a correction that moved nothing: still incremental
  EXPECT_EQ(r.refreshes(), 1u);
  EXPECT_EQ(r.fullRebuilds(), 1u);
  std::string full = fullBuild();
  for (const char* f : {"/navmap.pgm", "/navmap_layers.yml.gz", "/navmap.gridmap"})
    EXPECT_EQ(bytes(dir + f), bytes(full + f)) << f;
  // A loop correction moves a keyframe 0.3 m: every point is added again.
  Eigen::Isometry3d moved = mapper->store().at(2).T_world_cam;
  moved.translation().y() += 0.3;
  mapper->correct({{2, moved}});
  r.update(*mapper, true);
  EXPECT_EQ(r.refreshes(), 2u);
  EXPECT_EQ(r.fullRebuilds(), 2u);
  full = fullBuild();
  for (const char* f : {"/navmap.pgm", "/navmap_layers.yml.gz", "/navmap.gridmap"})
    EXPECT_EQ(bytes(dir + f), bytes(full + f)) << f;
}
