// End-to-end: the rgbdi-eval binary on the TUM fr1/xyz golden fixtures (--json numbers and text
// report) and its error behaviour (exit codes, one-line messages naming file and line).
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "testing/fixtures.h"

namespace {

using rgbdi::test::binDir;
using rgbdi::test::fixturePath;
using rgbdi::test::runCommand;

std::string evalCommand(const std::string& args) { return binDir() + "/rgbdi-eval " + args; }

std::string goldenArgs() {
  return fixturePath("eval/freiburg1_xyz-groundtruth.txt") + " " +
         fixturePath("eval/freiburg1_xyz-rgbdslam.txt");
}

void expectRel(const nlohmann::json& j, const char* key, double expected) {
  ASSERT_TRUE(j.contains(key)) << key;
  EXPECT_NEAR(j[key].get<double>(), expected, 1e-6 * std::abs(expected)) << key;
}

std::string writeFile(const std::string& name, const std::string& text) {
  const std::string path = rgbdi::test::makeTempDir("app_eval") + "/" + name;
  std::ofstream(path) << text;
  return path;
}

std::size_t lineCount(const std::string& s) {
  std::size_t n = 0;
  for (char c : s) n += c == '\n';
  return n;
}

TEST(RgbdiEvalApp, JsonMatchesGoldenValues) {
  RGBDI_REQUIRE_FIXTURE(fixturePath("eval/freiburg1_xyz-groundtruth.txt"));
  std::string out;
  ASSERT_EQ(runCommand(evalCommand(goldenArgs() + " --json"), &out), 0) << out;
  EXPECT_EQ(lineCount(out), 1u) << out;  // exactly one JSON object, nothing else
  const nlohmann::json j = nlohmann::json::parse(out);
  EXPECT_EQ(j["pairs"].get<int>(), 786);
  expectRel(j, "ate_rmse", 0.0134734678);
  expectRel(j, "ate_mean", 0.0120294764);
  expectRel(j, "ate_median", 0.0111757511);
  expectRel(j, "ate_max", 0.0347272017);
  EXPECT_EQ(j["scale"].get<double>(), 1.0);
  EXPECT_EQ(j["rpe_pairs"].get<int>(), 753);
  expectRel(j, "rpe_trans_rmse", 0.0212174441);
  expectRel(j, "rpe_rot_rmse_deg", 0.9344804594);
  EXPECT_EQ(j["align"], "se3");
  EXPECT_EQ(j["max_dt"].get<double>(), 0.02);
  EXPECT_EQ(j["rpe_delta"].get<double>(), 1.0);
  // The estimate starts 3.5 s after the ground truth: coverage is clearly below 1.
  EXPECT_GT(j["coverage"].get<double>(), 0.8);
  EXPECT_LT(j["coverage"].get<double>(), 0.9);
}

TEST(RgbdiEvalApp, OptionsChangeTheEvaluation) {
  RGBDI_REQUIRE_FIXTURE(fixturePath("eval/freiburg1_xyz-groundtruth.txt"));
  std::string out;
  ASSERT_EQ(
      runCommand(evalCommand(goldenArgs() + " --align sim3 --json --rpe-delta 0.5 --max-dt=0.02"),
                 &out),
      0)
      << out;
  const nlohmann::json j = nlohmann::json::parse(out);
  expectRel(j, "ate_rmse", 0.0133940549);
  expectRel(j, "scale", 1.00792367);
  EXPECT_EQ(j["align"], "sim3");
  EXPECT_EQ(j["rpe_delta"].get<double>(), 0.5);
  EXPECT_GT(j["rpe_pairs"].get<int>(), 753);  // shorter step: more pairs fit

  ASSERT_EQ(runCommand(evalCommand(goldenArgs()), &out), 0) << out;
  EXPECT_NE(out.find("pairs      786"), std::string::npos) << out;
  EXPECT_NE(out.find("rmse 0.0134735"), std::string::npos) << out;
  EXPECT_NE(out.find("753 pairs"), std::string::npos) << out;
}

TEST(RgbdiEvalApp, MissingFileIsADataError) {
  RGBDI_REQUIRE_FIXTURE(fixturePath("eval/freiburg1_xyz-groundtruth.txt"));
  std::string out;
  const std::string missing = "/nonexistent/est.tum";
  EXPECT_EQ(
      runCommand(evalCommand(fixturePath("eval/freiburg1_xyz-groundtruth.txt") + " " + missing),
                 &out),
      1);
  EXPECT_EQ(lineCount(out), 1u) << out;
  EXPECT_NE(out.find(missing + ": cannot open"), std::string::npos) << out;
}

TEST(RgbdiEvalApp, AMissingOrBrokenNavigationMapIsADataErrorNamingTheFile) {
  RGBDI_REQUIRE_FIXTURE(fixturePath("eval/freiburg1_xyz-groundtruth.txt"));
  std::string out;
  const std::string missing = "/nonexistent/navmap_layers.yml.gz";
  const std::string broken = writeFile("broken_layers.yml", "%YAML:1.0\n---\nwidth: 3\n");
  for (const std::string& bad : {missing, broken}) {
    EXPECT_EQ(
        runCommand(evalCommand(goldenArgs() + " --navmap " + bad + " --navmap-truth " + bad), &out),
        1);
    EXPECT_EQ(lineCount(out), 1u) << out;
    EXPECT_NE(out.find(bad + ": "), std::string::npos) << out;
  }
  EXPECT_EQ(runCommand(evalCommand(goldenArgs() + " --navmap " + broken), &out), 2);
  EXPECT_NE(out.find("--navmap and --navmap-truth go together"), std::string::npos) << out;
  EXPECT_EQ(runCommand(evalCommand(goldenArgs() + " --navmap-diff x.png"), &out), 2);
}

TEST(RgbdiEvalApp, NanLineIsADataErrorNamingFileAndLine) {
  RGBDI_REQUIRE_FIXTURE(fixturePath("eval/freiburg1_xyz-groundtruth.txt"));
  const std::string est =
      writeFile("nan.tum",
                "# estimate\n1305031102.160407 1.34 0.62 1.66 0.658 0.611 -0.294 -0.326\n"
                "1305031102.194330 nan 0.62 1.65 0.657 0.613 -0.295 -0.323\n");
  std::string out;
  EXPECT_EQ(runCommand(evalCommand(fixturePath("eval/freiburg1_xyz-groundtruth.txt") + " " + est +
                                   " --json"),
                       &out),
            1);
  EXPECT_EQ(lineCount(out), 1u) << out;
  EXPECT_NE(out.find(est + ":3:"), std::string::npos) << out;
  EXPECT_NE(out.find("not finite"), std::string::npos) << out;
}

TEST(RgbdiEvalApp, UnsortedFileIsADataErrorNamingTheLine) {
  RGBDI_REQUIRE_FIXTURE(fixturePath("eval/freiburg1_xyz-groundtruth.txt"));
  const std::string est = writeFile("unsorted.tum",
                                    "1305031102.2 1 0 0 0 0 0 1\n1305031102.3 1 0 0 0 0 0 1\n"
                                    "1305031102.1 1 0 0 0 0 0 1\n");
  std::string out;
  EXPECT_EQ(
      runCommand(evalCommand(fixturePath("eval/freiburg1_xyz-groundtruth.txt") + " " + est), &out),
      1);
  EXPECT_EQ(lineCount(out), 1u) << out;
  EXPECT_NE(out.find(est + ":3:"), std::string::npos) << out;
  EXPECT_NE(out.find("on line 2"), std::string::npos) << out;
}

TEST(RgbdiEvalApp, NoOverlapIsAClearDataError) {
  RGBDI_REQUIRE_FIXTURE(fixturePath("eval/freiburg1_xyz-groundtruth.txt"));
  std::string out;
  EXPECT_EQ(runCommand(evalCommand(fixturePath("eval/freiburg1_xyz-groundtruth.txt") + " " +
                                   fixturePath("eval/euroc_v102_stamped_estimate0.txt")),
                       &out),
            1);
  EXPECT_EQ(lineCount(out), 1u) << out;
  EXPECT_NE(out.find("no estimate stamp is within max_dt"), std::string::npos) << out;
}

TEST(RgbdiEvalApp, UsageErrorsExitWithTwo) {
  std::string out;
  EXPECT_EQ(runCommand(evalCommand("only_one.tum"), &out), 2);
  EXPECT_NE(out.find("expected 2 trajectory files"), std::string::npos) << out;
  EXPECT_EQ(runCommand(evalCommand("a.tum b.tum --align affine"), &out), 2);
  EXPECT_NE(out.find("unknown alignment 'affine'"), std::string::npos) << out;
  EXPECT_EQ(runCommand(evalCommand("a.tum b.tum --max-dt -1"), &out), 2);
  EXPECT_EQ(runCommand(evalCommand("a.tum b.tum --rpe-delta"), &out), 2);
  EXPECT_NE(out.find("--rpe-delta needs a value"), std::string::npos) << out;
  EXPECT_EQ(runCommand(evalCommand("a.tum b.tum --frobnicate"), &out), 2);
  EXPECT_EQ(lineCount(out), 1u) << out;
  EXPECT_EQ(runCommand(evalCommand("--help"), &out), 0);
  EXPECT_NE(out.find("usage: rgbdi-eval GT.tum EST.tum"), std::string::npos) << out;
}

}  // namespace
