// PoseGraphOptions: the graph_* keys of [loop] in share/config.ini equal the defaults, every one
// is documented with a unit, and bad values name file, section and key.
#include <gtest/gtest.h>

#include <fstream>
#include <set>
#include <string>

#include "rgbdi/loop/pose_graph.h"
#include "rgbdi/loop/pose_graph_options.h"
#include "testing/fixtures.h"
#include "testing/options_load_error.h"

using rgbdi::ConfigError;
using rgbdi::IniReader;
using rgbdi::loop::PoseGraphOptions;
using rgbdi::loop::RobustLoss;

namespace {

std::string loadError(const std::string& text) {
  return rgbdi::test::optionsLoadError<PoseGraphOptions>(text);
}

const std::set<std::string> kKeys = {"graph_sequential_edges",
                                     "graph_odom_pos_sigma_floor_m",
                                     "graph_odom_pos_sigma_per_sqrt_m",
                                     "graph_odom_yaw_sigma_floor_deg",
                                     "graph_odom_yaw_sigma_per_sqrt_m_deg",
                                     "graph_odom_yaw_sigma_per_sqrt_rad_deg",
                                     "graph_odom_bridge_pos_sigma_m",
                                     "graph_odom_bridge_yaw_sigma_deg",
                                     "graph_loop_sigma_pos_m",
                                     "graph_loop_sigma_yaw_deg",
                                     "graph_loss",
                                     "graph_loss_scale_sigma",
                                     "graph_max_iterations",
                                     "graph_function_tolerance",
                                     "graph_gradient_tolerance",
                                     "graph_parameter_tolerance",
                                     "graph_rollback_gate_sigma",
                                     "graph_max_rollbacks"};

}  // namespace

TEST(PoseGraphOptions, DefaultsEqualTheShippedConfig) {
  const std::string path = rgbdi::test::sourceDir() + "/share/config.ini";
  IniReader ini = IniReader::fromFile(path);
  const PoseGraphOptions f = PoseGraphOptions::load(ini);
  const PoseGraphOptions d;
  EXPECT_EQ(f.sequential_edges, d.sequential_edges);
  EXPECT_EQ(f.odom_pos_sigma_floor_m, d.odom_pos_sigma_floor_m);
  EXPECT_EQ(f.odom_pos_sigma_per_sqrt_m, d.odom_pos_sigma_per_sqrt_m);
  EXPECT_EQ(f.odom_yaw_sigma_floor_deg, d.odom_yaw_sigma_floor_deg);
  EXPECT_EQ(f.odom_yaw_sigma_per_sqrt_m_deg, d.odom_yaw_sigma_per_sqrt_m_deg);
  EXPECT_EQ(f.odom_yaw_sigma_per_sqrt_rad_deg, d.odom_yaw_sigma_per_sqrt_rad_deg);
  EXPECT_EQ(f.odom_bridge_pos_sigma_m, d.odom_bridge_pos_sigma_m);
  EXPECT_EQ(f.odom_bridge_yaw_sigma_deg, d.odom_bridge_yaw_sigma_deg);
  EXPECT_EQ(f.loop_sigma_pos_m, d.loop_sigma_pos_m);
  EXPECT_EQ(f.loop_sigma_yaw_deg, d.loop_sigma_yaw_deg);
  EXPECT_EQ(f.loss, d.loss);
  EXPECT_EQ(f.loss_scale_sigma, d.loss_scale_sigma);
  EXPECT_EQ(f.max_iterations, d.max_iterations);
  EXPECT_EQ(f.function_tolerance, d.function_tolerance);
  EXPECT_EQ(f.gradient_tolerance, d.gradient_tolerance);
  EXPECT_EQ(f.parameter_tolerance, d.parameter_tolerance);
  EXPECT_EQ(f.rollback_gate_sigma, d.rollback_gate_sigma);
  EXPECT_EQ(f.max_rollbacks_per_solve, d.max_rollbacks_per_solve);
  // The brief's values: 4 predecessors, a 3-sigma rollback gate.
  EXPECT_EQ(d.sequential_edges, 4);
  EXPECT_EQ(d.rollback_gate_sigma, 3.0);

  // Every graph_* line of [loop] is a key the options read (no typo, nothing unused), each is
  // present, and each carries its unit in brackets.
  std::ifstream in(path);
  std::string line, section;
  std::set<std::string> seen;
  while (std::getline(in, line)) {
    if (!line.empty() && line[0] == '[') section = line.substr(1, line.find(']') - 1);
    if (section != "loop" || line.rfind("graph_", 0) != 0) continue;
    const std::string key = line.substr(0, line.find_first_of(" =\t"));
    EXPECT_TRUE(kKeys.count(key)) << "unknown key in share/config.ini: " << key;
    EXPECT_NE(line.find("; ["), std::string::npos) << "no unit: " << line;
    seen.insert(key);
  }
  EXPECT_EQ(seen, kKeys);
}

TEST(PoseGraphOptions, ReadsValuesFromTheFile) {
  IniReader ini = IniReader::fromText(
      "[loop]\ngraph_sequential_edges = 2\ngraph_loss = cauchy\ngraph_loop_sigma_pos_m = 0.2\n"
      "graph_rollback_gate_sigma = 5\ngraph_max_rollbacks = 0\n",
      "test.ini");
  const PoseGraphOptions o = PoseGraphOptions::load(ini);
  EXPECT_EQ(o.sequential_edges, 2);
  EXPECT_EQ(o.loss, RobustLoss::kCauchy);
  EXPECT_EQ(o.loop_sigma_pos_m, 0.2);
  EXPECT_EQ(o.rollback_gate_sigma, 5.0);
  EXPECT_EQ(o.max_rollbacks_per_solve, 0);
}

TEST(PoseGraphOptions, BadValuesNameFileSectionAndKey) {
  for (const char* text :
       {"[loop]\ngraph_sequential_edges = 0\n", "[loop]\ngraph_loss = tukey\n",
        "[loop]\ngraph_loop_sigma_yaw_deg = -1\n", "[loop]\ngraph_max_iterations = many\n",
        "[loop]\ngraph_rollback_gate_sigma = 0\n", "[loop]\ngraph_odom_pos_sigma_per_sqrt_m = -1\n",
        "[loop]\ngraph_odom_yaw_sigma_floor_deg = 0\n"}) {
    const std::string e = loadError(text);
    const std::string t(text);
    const std::string key = t.substr(7, t.find(' ', 7) - 7);
    EXPECT_NE(e.find("test.ini"), std::string::npos) << e;
    EXPECT_NE(e.find("[loop]"), std::string::npos) << e;
    EXPECT_NE(e.find(key), std::string::npos) << e;
  }
}

TEST(PoseGraphOptions, OptionsBuiltInCodeAreValidatedByTheGraph) {
  PoseGraphOptions o;
  EXPECT_NO_THROW(o.validate());
  o.odom_pos_sigma_floor_m = 0.0;  // a zero-length edge would have no uncertainty
  EXPECT_THROW(rgbdi::loop::PoseGraph4Dof{o}, ConfigError);
  o = PoseGraphOptions{};
  o.odom_yaw_sigma_per_sqrt_rad_deg = -0.1;
  EXPECT_THROW(rgbdi::loop::PoseGraph4Dof{o}, ConfigError);
  o = PoseGraphOptions{};
  o.loss_scale_sigma = std::nan("");
  try {
    o.validate();
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("[loop] graph_loss_scale_sigma"), std::string::npos)
        << e.what();
  }
}
