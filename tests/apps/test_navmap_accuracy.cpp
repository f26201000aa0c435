// Navigation maps of a real run against the simulator's truth (issue 35, doc/navigation-maps.md
// "Accuracy"): rgbdi-sim renders the navigation-map world ([sim] nav_features: a step, a hole
// and a table beside the wheeled_slopes path with its ramps) and writes its true maps,
// rgbdi-slam writes navmap.*, rgbdi-eval --navmap compares them on the observed area.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "rgbdi/navmap/navmap_files.h"
#include "testing/fixtures.h"

namespace fs = std::filesystem;
using rgbdi::test::binDir;
using rgbdi::test::runCommand;

TEST(NavMapAccuracy, WheeledSlopesNavigationWorldMatchesTheTruth) {
  const std::string seq =
      rgbdi::test::cachedSimSequence("--profile wheeled_slopes --duration 20 --config " +
                                     rgbdi::test::sourceDir() + "/tests/apps/navmap_world.ini");
  for (const char* f : {"truth_navmap.yaml", "truth_navmap.pgm", "truth_navmap_layers.yml.gz",
                        "truth_navmap.gridmap", "truth_navmap.png"})
    EXPECT_TRUE(fs::exists(seq + "/" + f)) << f;
  const std::string out = rgbdi::test::makeTempDir("navmap_accuracy");
  std::string log;
  ASSERT_EQ(runCommand(binDir() + "/rgbdi-slam --input " + seq + "/sequence.rawlog --config " +
                           seq + "/config.ini --out " + out + " --quiet --no-save-map",
                       &log),
            0)
      << log;
  // Every navigation-map file, listed in summary.json with the map's figures.
  std::ifstream summary_file(out + "/summary.json");
  const nlohmann::json summary = nlohmann::json::parse(summary_file);
  for (const char* name : {"navmap_yaml", "navmap_pgm", "navmap_gridmap", "navmap_height_gridmap",
                           "navmap_layers", "navmap_png", "navmap_traversability_png"}) {
    ASSERT_TRUE(summary["outputs"].contains(name)) << name;
    EXPECT_TRUE(fs::exists(summary["outputs"][name].get<std::string>())) << name;
  }
  EXPECT_GT(summary["navmap"]["free_area_m2"].get<double>(), 5.0);
  // map_server reads the grid (trinary) as written.
  const rgbdi::navmap::RosMap ros = rgbdi::navmap::readRosMap(out + "/navmap.yaml");
  EXPECT_EQ(ros.grid.width, summary["navmap"]["width_cells"].get<int>());

  std::string eval;
  ASSERT_EQ(
      runCommand(binDir() + "/rgbdi-eval " + seq + "/groundtruth.tum " + out +
                     "/trajectory.tum --align posyaw --json --navmap " + out +
                     "/navmap_layers.yml.gz --navmap-truth " + seq + "/truth_navmap_layers.yml.gz",
                 &eval),
      0)
      << eval;
  const nlohmann::json nav = nlohmann::json::parse(eval)["navmap"];
  SCOPED_TRACE(nav.dump(1));
  EXPECT_GT(nav["observed_cells"].get<int>(), 3000);
  // The bounds: true free cells free, true obstacles occupied, every cell driven over
  // free, ramps traversable, ground height within 2 cm RMS.
  EXPECT_GE(nav["free_recall"].get<double>(), 0.95);
  EXPECT_GE(nav["occupied_recall"].get<double>(), 0.95);
  EXPECT_EQ(nav["driven_free"].get<double>(), 1.0);
  EXPECT_GT(nav["sloped_cells"].get<int>(), 100);
  EXPECT_GE(nav["sloped_free"].get<double>(), 0.95);
  EXPECT_LE(nav["height_rmse_m"].get<double>(), 0.02);
  // Obstacles were seen (boxes, walls; the hole and the step beside the path stay out of view of
  // the forward-looking camera on this path, doc/navigation-maps.md).
  EXPECT_GT(nav["true_occupied_cells"].get<int>(), 200);
}
