#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>

#include "rgbdi/loop/loop_verifier.h"
#include "testing/fixtures.h"
#include "testing/options_load_error.h"

using rgbdi::ConfigError;
using rgbdi::IniReader;
using rgbdi::loop::LoopVerificationOptions;

namespace {

std::string loadError(const std::string& text) {
  return rgbdi::test::optionsLoadError<LoopVerificationOptions>(text);
}

}  // namespace

TEST(LoopVerificationOptions, DefaultsEqualTheShippedConfig) {
  const std::string path = rgbdi::test::sourceDir() + "/share/config.ini";
  IniReader ini = IniReader::fromFile(path);
  const LoopVerificationOptions f = LoopVerificationOptions::load(ini);
  const LoopVerificationOptions d;
  EXPECT_EQ(f.match_ratio, d.match_ratio);
  EXPECT_EQ(f.max_hamming_bits, d.max_hamming_bits);
  EXPECT_EQ(f.cross_check, d.cross_check);
  EXPECT_EQ(f.min_matches, d.min_matches);
  EXPECT_EQ(f.pnp_threshold_px, d.pnp_threshold_px);
  EXPECT_EQ(f.pnp_iterations, d.pnp_iterations);
  EXPECT_EQ(f.pnp_confidence, d.pnp_confidence);
  EXPECT_EQ(f.min_pnp_inliers, d.min_pnp_inliers);
  EXPECT_EQ(f.depth_tolerance_m, d.depth_tolerance_m);
  EXPECT_EQ(f.depth_noise_coeff, d.depth_noise_coeff);
  EXPECT_EQ(f.depth_tolerance_sigmas, d.depth_tolerance_sigmas);
  EXPECT_EQ(f.min_depth_inliers, d.min_depth_inliers);
  EXPECT_EQ(f.min_depth_inlier_fraction, d.min_depth_inlier_fraction);
  EXPECT_EQ(f.refine_rounds, d.refine_rounds);
  EXPECT_DOUBLE_EQ(f.keypoint_sigma_px, d.keypoint_sigma_px);
  EXPECT_EQ(f.max_gravity_deg, d.max_gravity_deg);
  EXPECT_EQ(f.max_yaw_deg, d.max_yaw_deg);
  EXPECT_EQ(f.max_translation_m, d.max_translation_m);
  EXPECT_EQ(f.drift_base_m, d.drift_base_m);
  EXPECT_EQ(f.drift_fraction, d.drift_fraction);
  EXPECT_EQ(f.drift_base_deg, d.drift_base_deg);
  EXPECT_EQ(f.drift_deg_per_m, d.drift_deg_per_m);
  EXPECT_EQ(f.freespace_margin_m, d.freespace_margin_m);
  EXPECT_EQ(f.freespace_margin_sigmas, d.freespace_margin_sigmas);
  EXPECT_EQ(f.freespace_max_conflict_fraction, d.freespace_max_conflict_fraction);
  EXPECT_EQ(f.freespace_min_samples, d.freespace_min_samples);
  EXPECT_EQ(f.freespace_for_loops, d.freespace_for_loops);
  // The reference's gates (SPEC: PnP >= 25 inliers, yaw < 30 deg).
  EXPECT_EQ(d.min_pnp_inliers, 25);
  EXPECT_EQ(d.max_yaw_deg, 30.0);
  // Every verify_* key of the file was read (other [loop] keys belong to other modules), and
  // the file has exactly the 27 keys compared above.
  ini.acceptConfigSectionsExcept({"loop"});
  try {
    ini.checkNoUnknownKeys();
  } catch (const ConfigError& e) {
    EXPECT_EQ(std::string(e.what()).find("verify_"), std::string::npos) << e.what();
  }
  std::ifstream in(path);
  std::string line, section;
  int verify_keys = 0;
  while (std::getline(in, line)) {
    if (!line.empty() && line[0] == '[') section = line;
    if (section == "[loop]" && line.rfind("verify_", 0) == 0) ++verify_keys;
  }
  EXPECT_EQ(verify_keys, 27);
}

TEST(LoopVerificationOptions, ReadsValuesFromTheFile) {
  IniReader ini = IniReader::fromText(
      "[loop]\nverify_match_ratio = 0.7\nverify_cross_check = false\nverify_min_matches = 40\n"
      "verify_max_yaw_deg = 45\nverify_drift_fraction = 0.1\n",
      "test.ini");
  const LoopVerificationOptions o = LoopVerificationOptions::load(ini);
  EXPECT_EQ(o.match_ratio, 0.7);
  EXPECT_FALSE(o.cross_check);
  EXPECT_EQ(o.min_matches, 40);
  EXPECT_EQ(o.max_yaw_deg, 45.0);
  EXPECT_EQ(o.drift_fraction, 0.1);
}

TEST(LoopVerificationOptions, OutOfRangeValuesNameFileSectionAndKey) {
  const std::string e1 = loadError("[loop]\nverify_match_ratio = 1.5\n");
  EXPECT_NE(e1.find("test.ini"), std::string::npos) << e1;
  EXPECT_NE(e1.find("verify_match_ratio"), std::string::npos) << e1;
  EXPECT_NE(loadError("[loop]\nverify_min_pnp_inliers = 3\n").find("verify_min_pnp_inliers"),
            std::string::npos);
  EXPECT_NE(loadError("[loop]\nverify_cross_check = banana\n").find("verify_cross_check"),
            std::string::npos);
  EXPECT_NE(loadError("[loop]\nverify_max_gravity_deg = -1\n").find("verify_max_gravity_deg"),
            std::string::npos);
}

TEST(LoopVerificationOptions, GatesThatCouldNeverPassAreRejected) {
  EXPECT_NE(loadError("[loop]\nverify_min_pnp_inliers = 31\n").find("verify_min_pnp_inliers"),
            std::string::npos);
  EXPECT_NE(loadError("[loop]\nverify_min_depth_inliers = 26\n").find("verify_min_depth_inliers"),
            std::string::npos);
  EXPECT_EQ(loadError("[loop]\nverify_min_depth_inliers = 25\n"), "");
  LoopVerificationOptions o;
  EXPECT_NO_THROW(o.validate());
  o.depth_noise_coeff = std::nan("");
  try {
    o.validate();
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("[loop] verify_depth_noise_coeff"), std::string::npos)
        << e.what();
  }
}
