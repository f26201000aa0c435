// The whole configuration: the shipped file loads, the [loop] and [pipeline] keys are validated
// like every other section (a bad value or an unknown key is an error naming it), and their
// defaults equal the shipped file.
#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

#include "rgbdi/system/system_config.h"
#include "testing/fixtures.h"
#include "testing/options_load_error.h"

using namespace rgbdi;

namespace {
std::string loadError(const std::string& text) {
  return rgbdi::test::optionsLoadError<system::SystemConfig>(text);
}
}  // namespace

TEST(SystemConfig, LoopDefaultsEqualTheShippedConfig) {
  const system::SystemConfig shipped =
      system::SystemConfig::load(test::sourceDir() + "/share/config.ini");
  const loop::LoopOptions d;
  const loop::LoopOptions& f = shipped.loop;
  EXPECT_EQ(f.enable, d.enable);
  EXPECT_TRUE(f.enable);  // on by default
  EXPECT_EQ(f.offline_lag_keyframes, d.offline_lag_keyframes);
  EXPECT_EQ(f.max_verified_candidates, d.max_verified_candidates);
  EXPECT_EQ(f.max_loops_per_keyframe, d.max_loops_per_keyframe);
  EXPECT_EQ(f.min_keyframe_distance_m, d.min_keyframe_distance_m);
  EXPECT_EQ(f.min_keyframe_angle_deg, d.min_keyframe_angle_deg);
  EXPECT_EQ(f.solve_interval_keyframes, d.solve_interval_keyframes);
  EXPECT_EQ(f.correction.gate_sigma, d.correction.gate_sigma);
  EXPECT_EQ(f.correction.sigma_floor_m, d.correction.sigma_floor_m);
  EXPECT_EQ(f.correction.yaw_sigma_deg_per_m, d.correction.yaw_sigma_deg_per_m);
}

TEST(SystemConfig, LoopKeysAreValidatedLikeEveryOtherSection) {
  const std::string bad_bool = loadError("[loop]\nenable = banana\n");
  EXPECT_NE(bad_bool.find("test.ini"), std::string::npos) << bad_bool;
  EXPECT_NE(bad_bool.find("[loop] enable"), std::string::npos) << bad_bool;
  const std::string unknown = loadError("[loop]\nno_such_key = 1\n");
  EXPECT_NE(unknown.find("no_such_key"), std::string::npos) << unknown;
  const std::string range = loadError("[loop]\nsolve_interval_keyframes = 0\n");
  EXPECT_NE(range.find("solve_interval_keyframes"), std::string::npos) << range;
  const std::string gate = loadError("[loop]\ncorrection_gate_sigma = -1\n");
  EXPECT_NE(gate.find("[loop] correction_gate_sigma"), std::string::npos) << gate;
  const std::string floor = loadError("[loop]\ncorrection_sigma_floor_m = 0\n");
  EXPECT_NE(floor.find("correction_sigma_floor_m"), std::string::npos) << floor;
  EXPECT_EQ(loadError("[loop]\nenable = false\n"), "");
  EXPECT_EQ(loadError("[loop]\ncorrection_gate_sigma = 0\n"), "");
}

TEST(SystemConfig, PipelineDefaultsEqualTheShippedConfigAndAreValidated) {
  const system::SystemConfig shipped =
      system::SystemConfig::load(test::sourceDir() + "/share/config.ini");
  const system::PipelineOptions d;
  EXPECT_EQ(shipped.pipeline.queue_capacity_packets, d.queue_capacity_packets);
  EXPECT_EQ(shipped.pipeline.images_prepared_ahead, d.images_prepared_ahead);
  IniReader custom = IniReader::fromText(
      "[pipeline]\nqueue_capacity_packets = 8\nimages_prepared_ahead = 0\n", "test.ini");
  const system::SystemConfig c = system::SystemConfig::load(custom);
  EXPECT_EQ(c.pipeline.queue_capacity_packets, 8);
  EXPECT_EQ(c.pipeline.images_prepared_ahead, 0);
  const std::string zero_queue = loadError("[pipeline]\nqueue_capacity_packets = 0\n");
  EXPECT_NE(zero_queue.find("[pipeline] queue_capacity_packets"), std::string::npos) << zero_queue;
  const std::string negative = loadError("[pipeline]\nimages_prepared_ahead = -1\n");
  EXPECT_NE(negative.find("images_prepared_ahead"), std::string::npos) << negative;
  EXPECT_NE(loadError("[pipeline]\nthreads = 2\n").find("threads"), std::string::npos);
}

TEST(SystemConfig, EverySectionOfTheShippedFileIsAConfigSection) {
  // Tools that read part of a full configuration accept the other sections by this list
  // (IniReader::acceptConfigSectionsExcept): a section added to the file must be added to it.
  std::ifstream in(test::sourceDir() + "/share/config.ini");
  std::vector<std::string> sections;
  for (std::string line; std::getline(in, line);)
    if (line.size() > 2 && line.front() == '[')
      sections.push_back(line.substr(1, line.find(']') - 1));
  EXPECT_EQ(sections, kConfigSections);
}
