// Options of the keyframe features and place recognition: defaults equal share/config.ini, and
// bad values name file, section and key.
#include <gtest/gtest.h>

#include <string>

#include "rgbdi/loop/loop_features.h"
#include "rgbdi/loop/loop_options.h"
#include "rgbdi/loop/place_recognizer.h"
#include "testing/fixtures.h"
#include "testing/options_load_error.h"

using rgbdi::ConfigError;
using rgbdi::IniReader;
using rgbdi::loop::LoopFeatureOptions;
using rgbdi::loop::PlaceRecognitionOptions;

namespace {

template <typename Options>
std::string loadError(const std::string& text) {
  return rgbdi::test::optionsLoadError<Options>(text);
}

}  // namespace

TEST(LoopPlaceOptions, DefaultsEqualTheShippedConfig) {
  IniReader ini = IniReader::fromFile(rgbdi::test::sourceDir() + "/share/config.ini");
  const LoopFeatureOptions f = LoopFeatureOptions::load(ini);
  const LoopFeatureOptions fd;
  EXPECT_EQ(f.max_keypoints, fd.max_keypoints);
  EXPECT_EQ(f.detect_candidates, fd.detect_candidates);
  EXPECT_EQ(f.fast_threshold, fd.fast_threshold);
  EXPECT_EQ(f.pyramid_levels, fd.pyramid_levels);
  EXPECT_EQ(f.pyramid_scale, fd.pyramid_scale);
  EXPECT_EQ(f.border_px, fd.border_px);
  EXPECT_EQ(f.grid_cols, fd.grid_cols);
  EXPECT_EQ(f.grid_rows, fd.grid_rows);
  EXPECT_EQ(f.depth_min_m, fd.depth_min_m);
  EXPECT_EQ(f.depth_max_m, fd.depth_max_m);
  EXPECT_EQ(f.depth_window_px, fd.depth_window_px);
  EXPECT_EQ(f.depth_max_relative_spread, fd.depth_max_relative_spread);
  EXPECT_EQ(f.depth_noise_coeff, fd.depth_noise_coeff);
  EXPECT_EQ(f.depth_max_noise_sigmas, fd.depth_max_noise_sigmas);

  const PlaceRecognitionOptions p = PlaceRecognitionOptions::load(ini);
  const PlaceRecognitionOptions pd;
  EXPECT_EQ(p.index.tables, pd.index.tables);
  EXPECT_EQ(p.index.key_bits, pd.index.key_bits);
  EXPECT_EQ(p.index.seed, pd.index.seed);
  EXPECT_EQ(p.index.max_key_keyframes, pd.index.max_key_keyframes);
  EXPECT_EQ(p.top_k, pd.top_k);
  EXPECT_EQ(p.exclude_recent_s, pd.exclude_recent_s);
  EXPECT_EQ(p.exclude_recent_m, pd.exclude_recent_m);
  EXPECT_EQ(p.exclude_recent_count, pd.exclude_recent_count);
  EXPECT_EQ(p.min_normalised_score, pd.min_normalised_score);
  EXPECT_EQ(p.min_reference_ratio, pd.min_reference_ratio);
  EXPECT_EQ(p.consistency_keyframes, pd.consistency_keyframes);
  EXPECT_EQ(p.consistency_window_s, pd.consistency_window_s);
  EXPECT_EQ(p.proximity_radius_m, pd.proximity_radius_m);
  EXPECT_EQ(p.proximity_max_candidates, pd.proximity_max_candidates);
  // The numbers: 300-500 keypoints, 2-3 consistent keyframes.
  EXPECT_GE(fd.max_keypoints, 300);
  EXPECT_LE(fd.max_keypoints, 500);
  EXPECT_GE(pd.consistency_keyframes, 2);
  EXPECT_LE(pd.consistency_keyframes, 3);
  // Every feature_ and place_ key of the file was read by these two loaders.
  IniReader only = IniReader::fromFile(rgbdi::test::sourceDir() + "/share/config.ini");
  LoopFeatureOptions::load(only);
  PlaceRecognitionOptions::load(only);
  only.getBool("loop", "enable", true);
  only.acceptConfigSectionsExcept({"loop"});
  try {
    only.checkNoUnknownKeys();
  } catch (const ConfigError& e) {
    // Keys of the other loop modules (verification, pose graph) may follow; ours must not be
    // among the unknown ones.
    const std::string what = e.what();
    EXPECT_EQ(what.find("feature_"), std::string::npos) << what;
    EXPECT_EQ(what.find("place_"), std::string::npos) << what;
  }
}

TEST(LoopPlaceOptions, ReadsValuesFromTheFile) {
  IniReader ini = IniReader::fromText(
      "[loop]\nfeature_max_keypoints = 300\nfeature_pyramid_scale = 1.5\n"
      "place_index_tables = 6\nplace_index_seed = 77\nplace_consistency_keyframes = 3\n"
      "place_proximity_radius_m = 0\n",
      "test.ini");
  const LoopFeatureOptions f = LoopFeatureOptions::load(ini);
  const PlaceRecognitionOptions p = PlaceRecognitionOptions::load(ini);
  EXPECT_EQ(f.max_keypoints, 300);
  EXPECT_EQ(f.pyramid_scale, 1.5);
  EXPECT_EQ(p.index.tables, 6);
  EXPECT_EQ(p.index.seed, 77u);
  EXPECT_EQ(p.consistency_keyframes, 3);
  EXPECT_EQ(p.proximity_radius_m, 0.0);
}

TEST(LoopPlaceOptions, BadValuesNameFileSectionAndKey) {
  const std::string e1 = loadError<LoopFeatureOptions>("[loop]\nfeature_max_keypoints = 0\n");
  EXPECT_NE(e1.find("test.ini"), std::string::npos) << e1;
  EXPECT_NE(e1.find("feature_max_keypoints"), std::string::npos) << e1;
  const std::string e2 = loadError<LoopFeatureOptions>("[loop]\nfeature_depth_min_m = 7\n");
  EXPECT_NE(e2.find("feature_depth_min_m"), std::string::npos) << e2;
  const std::string e3 = loadError<LoopFeatureOptions>("[loop]\nfeature_detect_candidates = 100\n");
  EXPECT_NE(e3.find("feature_detect_candidates"), std::string::npos) << e3;
  const std::string e4 = loadError<PlaceRecognitionOptions>("[loop]\nplace_index_key_bits = 32\n");
  EXPECT_NE(e4.find("place_index_key_bits"), std::string::npos) << e4;
  const std::string e5 =
      loadError<PlaceRecognitionOptions>("[loop]\nplace_consistency_keyframes = banana\n");
  EXPECT_NE(e5.find("place_consistency_keyframes"), std::string::npos) << e5;
  const std::string e6 =
      loadError<PlaceRecognitionOptions>("[loop]\nplace_min_normalised_score = -1\n");
  EXPECT_NE(e6.find("place_min_normalised_score"), std::string::npos) << e6;
}

TEST(LoopPlaceOptions, OptionsBuiltInCodeAreValidated) {
  LoopFeatureOptions f;
  EXPECT_NO_THROW(f.validate());
  f.grid_cols = 0;
  EXPECT_THROW(rgbdi::loop::LoopFeatureExtractor{f}, ConfigError);
  PlaceRecognitionOptions p;
  EXPECT_NO_THROW(p.validate());
  p.exclude_recent_s = std::nan("");
  EXPECT_THROW(rgbdi::loop::PlaceRecognizer{p}, ConfigError);
  p = PlaceRecognitionOptions();
  p.index.key_bits = 4;
  try {
    rgbdi::loop::PlaceRecognizer{p};
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("[loop] place_index_key_bits"), std::string::npos)
        << e.what();
  }
}

TEST(LoopJoinCheckOptions, DefaultsEqualTheShippedConfigAndBadValuesAreNamed) {
  IniReader ini = IniReader::fromFile(rgbdi::test::sourceDir() + "/share/config.ini");
  const rgbdi::loop::LoopOptions shipped = rgbdi::loop::LoopOptions::load(ini);
  const rgbdi::loop::LoopOptions code;
  EXPECT_EQ(shipped.relocalize_check_keyframes, code.relocalize_check_keyframes);
  EXPECT_EQ(shipped.relocalize_check_radius_m, code.relocalize_check_radius_m);
  EXPECT_EQ(shipped.relocalize_check_max_conflict_fraction,
            code.relocalize_check_max_conflict_fraction);
  EXPECT_EQ(shipped.relocalize_check_max_conflict_fraction_geometric,
            code.relocalize_check_max_conflict_fraction_geometric);
  IniReader off = IniReader::fromText("[loop]\nrelocalize_check_keyframes = 0\n", "off.ini");
  EXPECT_EQ(rgbdi::loop::LoopOptions::load(off).relocalize_check_keyframes, 0);
  const std::string e1 =
      loadError<rgbdi::loop::LoopOptions>("[loop]\nrelocalize_check_keyframes = -1\n");
  EXPECT_NE(e1.find("relocalize_check_keyframes"), std::string::npos) << e1;
  const std::string e2 =
      loadError<rgbdi::loop::LoopOptions>("[loop]\nrelocalize_check_radius_m = -2\n");
  EXPECT_NE(e2.find("relocalize_check_radius_m"), std::string::npos) << e2;
  const std::string e3 =
      loadError<rgbdi::loop::LoopOptions>("[loop]\nrelocalize_check_max_conflict_fraction = 1.5\n");
  EXPECT_NE(e3.find("relocalize_check_max_conflict_fraction"), std::string::npos) << e3;
  const std::string e4 = loadError<rgbdi::loop::LoopOptions>(
      "[loop]\nrelocalize_check_max_conflict_fraction_geometric = -0.1\n");
  EXPECT_NE(e4.find("relocalize_check_max_conflict_fraction_geometric"), std::string::npos) << e4;
}
