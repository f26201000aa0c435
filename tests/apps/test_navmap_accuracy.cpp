// Navigation maps of a real run against the simulator's truth (issue 35, doc/navigation-maps.md
// "Accuracy"): rgbdi-sim renders the navigation-map world ([sim] nav_features: a step, a hole
// and a table beside the path) at 15 Hz and writes its true maps, rgbdi-slam writes navmap.*,
// rgbdi-eval --navmap compares them on the observed area. The profiles whose bounds hold on
// seeds 1-3: wheeled_slopes (with its ramps), wheeled_circle and handheld (tracked_slopes does
// not: the hole beside its path, doc/navigation-maps.md "Accuracy table").
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "rgbdi/navmap/navmap_files.h"
#include "testing/fixtures.h"

namespace fs = std::filesystem;
using rgbdi::test::binDir;
using rgbdi::test::runCommand;

namespace {

/// Runs the profile's navigation world through rgbdi-slam and rgbdi-eval --navmap; returns
/// the "navmap" figures and checks the files and the summary on the way.
nlohmann::json navmapRun(const std::string& profile, int duration_s) {
  const std::string seq = rgbdi::test::cachedSimSequence(
      "--profile " + profile + " --duration " + std::to_string(duration_s) + " --fps 15 --config " +
      rgbdi::test::sourceDir() + "/tests/apps/navmap_world.ini");
  for (const char* f : {"truth_navmap.yaml", "truth_navmap.pgm", "truth_navmap_layers.yml.gz",
                        "truth_navmap.gridmap", "truth_navmap.png"})
    EXPECT_TRUE(fs::exists(seq + "/" + f)) << f;
  const std::string out = rgbdi::test::makeTempDir("navmap_accuracy_" + profile);
  std::string log;
  EXPECT_EQ(runCommand(binDir() + "/rgbdi-slam --input " + seq + "/sequence.rawlog --config " +
                           seq + "/config.ini --out " + out + " --quiet --no-save-map",
                       &log),
            0)
      << log;
  // Every navigation-map file, listed in summary.json with the map's figures.
  std::ifstream summary_file(out + "/summary.json");
  const nlohmann::json summary = nlohmann::json::parse(summary_file);
  for (const char* name : {"navmap_yaml", "navmap_pgm", "navmap_gridmap", "navmap_height_gridmap",
                           "navmap_layers", "navmap_png", "navmap_traversability_png"}) {
    EXPECT_TRUE(summary["outputs"].contains(name)) << name;
    if (summary["outputs"].contains(name)) {
      EXPECT_TRUE(fs::exists(summary["outputs"][name].get<std::string>())) << name;
    }
  }
  EXPECT_GT(summary["navmap"]["free_area_m2"].get<double>(), 5.0);
  // map_server's reading of navmap.yaml + navmap.pgm (trinary, negate, thresholds, origin;
  // readRosMap, tests/navmap/test_navmap_files.cpp) gives the run's grid back cell by cell.
  const rgbdi::navmap::RosMap ros = rgbdi::navmap::readRosMap(out + "/navmap.yaml");
  const rgbdi::navmap::NavMap layers = rgbdi::navmap::readLayers(out + "/navmap_layers.yml.gz");
  EXPECT_EQ(ros.grid.width, summary["navmap"]["width_cells"].get<int>());
  EXPECT_EQ(ros.grid.width, layers.grid.width);
  EXPECT_EQ(ros.grid.height, layers.grid.height);
  EXPECT_NEAR(ros.grid.origin_x_m, layers.grid.origin_x_m, 1e-9);
  EXPECT_NEAR(ros.grid.origin_y_m, layers.grid.origin_y_m, 1e-9);
  EXPECT_DOUBLE_EQ(ros.grid.cell_size_m, layers.grid.cell_size_m);
  std::size_t differ = 0;
  for (std::size_t i = 0; i < ros.occupancy.size() && i < layers.grid.cellCount(); ++i)
    differ += ros.occupancy[i] != layers.occupancy(i) ? 1 : 0;
  EXPECT_EQ(differ, 0u);

  std::string eval;
  EXPECT_EQ(
      runCommand(binDir() + "/rgbdi-eval " + seq + "/groundtruth.tum " + out +
                     "/trajectory.tum --align posyaw --json --navmap " + out +
                     "/navmap_layers.yml.gz --navmap-truth " + seq + "/truth_navmap_layers.yml.gz",
                 &eval),
      0)
      << eval;
  return nlohmann::json::parse(eval)["navmap"];
}

/// The issue's bounds: true free cells free, true obstacles occupied (both judged within one
/// cell at true boundaries: the truth's raster and the alignment's lattice shift make a face's
/// cell ambiguous by one, below any robot's obstacle inflation; doc/navigation-maps.md), every
/// cell driven over free, ground height within 2 cm RMS.
void expectIssueBounds(const nlohmann::json& nav) {
  EXPECT_GT(nav["observed_cells"].get<int>(), 3000);
  EXPECT_GE(nav["free_recall_tolerant"].get<double>(), 0.95);
  EXPECT_GE(nav["occupied_recall_tolerant"].get<double>(), 0.95);
  // The strict figures are reported beside them and can only be lower.
  EXPECT_LE(nav["free_recall"].get<double>(), nav["free_recall_tolerant"].get<double>());
  EXPECT_LE(nav["occupied_recall"].get<double>(), nav["occupied_recall_tolerant"].get<double>());
  EXPECT_EQ(nav["driven_free"].get<double>(), 1.0);
  EXPECT_LE(nav["height_rmse_m"].get<double>(), 0.02);
}

}  // namespace

TEST(NavMapAccuracy, WheeledSlopesNavigationWorldMatchesTheTruth) {
  const nlohmann::json nav = navmapRun("wheeled_slopes", 20);
  SCOPED_TRACE(nav.dump(1));
  expectIssueBounds(nav);
  // Ramps traversable.
  EXPECT_GT(nav["sloped_cells"].get<int>(), 100);
  EXPECT_GE(nav["sloped_free"].get<double>(), 0.95);
  // Obstacles were seen (boxes, walls; the hole and the step beside the path stay out of view of
  // the forward-looking camera on this path, doc/navigation-maps.md).
  EXPECT_GT(nav["true_occupied_cells"].get<int>(), 200);
}

TEST(NavMapAccuracy, WheeledCircleNavigationWorldMatchesTheTruth) {
  const nlohmann::json nav = navmapRun("wheeled_circle", 30);
  SCOPED_TRACE(nav.dump(1));
  expectIssueBounds(nav);
  EXPECT_GT(nav["true_occupied_cells"].get<int>(), 200);
  // The hole's rim and the step's edges beside this path were seen: occupied.
  EXPECT_GT(nav["edge_cells"].get<int>(), 10);
  EXPECT_GE(nav["edges_occupied"].get<double>(), 0.95);
}

TEST(NavMapAccuracy, HandHeldNavigationWorldMatchesTheTruth) {
  // A camera carried 1.3 m up looking down at the walls: its one-cell fringe in front of faces
  // is what the strict free recall (about 87 %) misses; within one cell it holds.
  const nlohmann::json nav = navmapRun("handheld", 20);
  SCOPED_TRACE(nav.dump(1));
  expectIssueBounds(nav);
  EXPECT_GT(nav["true_occupied_cells"].get<int>(), 200);
  EXPECT_GT(nav["free_tolerated_cells"].get<int>(), 100);
}
