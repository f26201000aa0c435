// FrontendOptions: defaults equal share/config.ini, ranges and cross-checks are enforced.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "rgbdi/frontend/frontend_options.h"
#include "testing/fixtures.h"

using rgbdi::ConfigError;
using rgbdi::IniReader;
using rgbdi::frontend::FrontendOptions;

TEST(FrontendOptions, DefaultsEqualTheShippedConfig) {
  IniReader ini = IniReader::fromFile(rgbdi::test::sourceDir() + "/share/config.ini");
  const FrontendOptions f = FrontendOptions::load(ini);
  const FrontendOptions d;
  EXPECT_EQ(f.max_features, d.max_features);
  EXPECT_EQ(f.max_features, 150);
  EXPECT_EQ(f.detect_min_missing, d.detect_min_missing);
  EXPECT_DOUBLE_EQ(f.min_distance_px, d.min_distance_px);
  EXPECT_DOUBLE_EQ(f.shi_tomasi_quality, d.shi_tomasi_quality);
  EXPECT_EQ(f.shi_tomasi_block_size, d.shi_tomasi_block_size);
  EXPECT_EQ(f.border_px, d.border_px);
  EXPECT_DOUBLE_EQ(f.clahe_clip_limit, d.clahe_clip_limit);
  EXPECT_EQ(f.klt_window_px, d.klt_window_px);
  EXPECT_EQ(f.klt_window_px, 15);
  EXPECT_EQ(f.klt_pyramid_levels, d.klt_pyramid_levels);
  EXPECT_EQ(f.klt_pyramid_levels, 3);
  EXPECT_EQ(f.klt_max_iterations, d.klt_max_iterations);
  EXPECT_DOUBLE_EQ(f.klt_epsilon_px, d.klt_epsilon_px);
  EXPECT_DOUBLE_EQ(f.klt_max_forward_backward_px, d.klt_max_forward_backward_px);
  EXPECT_DOUBLE_EQ(f.ransac_threshold_px, d.ransac_threshold_px);
  EXPECT_DOUBLE_EQ(f.ransac_confidence, d.ransac_confidence);
  EXPECT_DOUBLE_EQ(f.depth_min_m, d.depth_min_m);
  EXPECT_DOUBLE_EQ(f.depth_max_m, d.depth_max_m);
  EXPECT_EQ(f.depth_neighbourhood_px, d.depth_neighbourhood_px);
  EXPECT_DOUBLE_EQ(f.depth_max_relative_spread, d.depth_max_relative_spread);
  EXPECT_DOUBLE_EQ(f.registration_fill_max_relative_diff, d.registration_fill_max_relative_diff);
  EXPECT_EQ(f.occlusion_window_px, d.occlusion_window_px);
  EXPECT_EQ(f.occlusion_sample_step_px, d.occlusion_sample_step_px);
  EXPECT_DOUBLE_EQ(f.occlusion_max_residual_sigmas, d.occlusion_max_residual_sigmas);
  EXPECT_DOUBLE_EQ(f.occlusion_min_valid_fraction, d.occlusion_min_valid_fraction);
  EXPECT_EQ(f.opencv_threads, d.opencv_threads);
  EXPECT_EQ(f.opencv_threads, 1);
}

TEST(FrontendOptions, EveryFrontendKeyOfTheShippedConfigIsRead) {
  // Only the [frontend] section of the shipped file: other sections belong to other modules.
  std::ifstream in(rgbdi::test::sourceDir() + "/share/config.ini");
  ASSERT_TRUE(in.good());
  std::string line, section, frontend_text;
  int keys = 0;
  while (std::getline(in, line)) {
    if (!line.empty() && line[0] == '[') section = line.substr(0, line.find(']') + 1);
    if (section == "[frontend]") {
      frontend_text += line + "\n";
      if (line.find('=') != std::string::npos && line[0] != ';') ++keys;
    }
  }
  EXPECT_GE(keys, 9);
  IniReader ini = IniReader::fromText(frontend_text, "config.ini [frontend]");
  FrontendOptions::load(ini);
  EXPECT_NO_THROW(ini.checkNoUnknownKeys());
}

TEST(FrontendOptions, ValuesAreReadAndOutOfRangeNamesTheKey) {
  IniReader ok =
      IniReader::fromText("[frontend]\nmax_features = 200\nklt_pyramid_levels = 4\n", "f.ini");
  const FrontendOptions o = FrontendOptions::load(ok);
  EXPECT_EQ(o.max_features, 200);
  EXPECT_EQ(o.klt_pyramid_levels, 4);
  EXPECT_DOUBLE_EQ(o.min_distance_px, 15.0);

  IniReader bad = IniReader::fromText("[frontend]\nransac_threshold_px = -1\n", "bad.ini");
  try {
    FrontendOptions::load(bad);
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("bad.ini"), std::string::npos) << msg;
    EXPECT_NE(msg.find("ransac_threshold_px"), std::string::npos) << msg;
  }
}

TEST(FrontendOptions, DepthRangeMustBeOrdered) {
  IniReader bad = IniReader::fromText("[frontend]\ndepth_min_m = 4\ndepth_max_m = 3\n", "r.ini");
  EXPECT_THROW(FrontendOptions::load(bad), ConfigError);
  FrontendOptions o;
  o.depth_min_m = o.depth_max_m + 1.0;
  EXPECT_THROW(o.validate(), ConfigError);
}

TEST(FrontendOptions, TheOcclusionTestNeedsADepthNoiseScale) {
  // The test's threshold is sigmas x depth_noise_coeff: with no noise scale every window would be
  // a boundary.
  IniReader bad = IniReader::fromText("[frontend]\ndepth_noise_coeff = 0\n", "n.ini");
  try {
    FrontendOptions::load(bad);
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("occlusion_window_px"), std::string::npos) << e.what();
  }
  IniReader off =
      IniReader::fromText("[frontend]\ndepth_noise_coeff = 0\nocclusion_window_px = 0\n", "o.ini");
  EXPECT_NO_THROW(FrontendOptions::load(off));
  FrontendOptions o;
  o.depth_noise_coeff = 0.0;
  EXPECT_THROW(o.validate(), ConfigError);
  o.occlusion_window_px = 0;
  EXPECT_NO_THROW(o.validate());
}

TEST(FrontendOptions, ValidateRejectsCodeBuiltNonsense) {
  EXPECT_NO_THROW(FrontendOptions().validate());
  FrontendOptions o;
  o.max_features = 0;
  try {
    o.validate();
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("max_features"), std::string::npos) << e.what();
  }
  FrontendOptions n;
  n.klt_epsilon_px = std::nan("");
  EXPECT_THROW(n.validate(), ConfigError);
  FrontendOptions m;
  m.detect_min_missing = 0;
  EXPECT_THROW(m.validate(), ConfigError);
  m.detect_min_missing = m.max_features;
  EXPECT_NO_THROW(m.validate());
  m.detect_min_missing = m.max_features + 1;
  try {
    m.validate();
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("detect_min_missing"), std::string::npos) << e.what();
  }
}
