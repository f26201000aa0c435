// rgbdi-sim end to end: a short tracked_slopes run with every option, its files, MRPT's own
// rawlog-edit reading the rawlog, and the usage / configuration errors.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>

#include "rgbdi/common/ini_reader.h"
#include "rgbdi/common/sensor_options.h"
#include "rgbdi/io/rawlog_source.h"
#include "testing/fixtures.h"

namespace {

namespace fs = std::filesystem;
using rgbdi::test::runCommand;

std::string sim() { return rgbdi::test::binDir() + "/rgbdi-sim"; }

TEST(RgbdiSim, WritesASequenceThatMrptToolsRead) {
  const std::string dir = rgbdi::test::makeTempDir("rgbdi_sim") + "/out";
  std::string out;
  const int rc = runCommand(sim() + " --profile tracked_slopes --out " + dir +
                                " --duration 10 --fps 3 --seed 4 --time-offset 0.01 --speed normal"
                                " --config " +
                                rgbdi::test::sourceDir() +
                                "/share/config.ini"
                                " --bag --bag-compression bz2",
                            &out);
  ASSERT_EQ(rc, 0) << out;
  EXPECT_NE(out.find("rgbdi-sim: frame 31/31 (100.0 %)"), std::string::npos) << out;
  EXPECT_NE(out.find("profile tracked_slopes: 10.0 s"), std::string::npos) << out;
  // Every file written is there and listed in the report.
  for (const char* f : {"sequence.rawlog", "groundtruth.tum", "groundtruth_cam.tum", "config.ini",
                        "simulation.ini", "sequence.bag", "vins_config.yaml"}) {
    EXPECT_TRUE(fs::exists(dir + "/" + f)) << f;
    EXPECT_NE(out.find("  " + dir + "/" + f + "\n"), std::string::npos) << f << "\n" << out;
  }
  EXPECT_TRUE(fs::exists(dir + "/sequence_Images/RGBD_30_color.png"));
  EXPECT_TRUE(fs::exists(dir + "/sequence_Images/RGBD_30_depth.bin"));

  // The written configuration is what rgbdi-slam loads.
  rgbdi::IniReader ini = rgbdi::IniReader::fromFile(dir + "/config.ini");
  rgbdi::CameraOptions::load(ini);
  const rgbdi::ImuOptions imu = rgbdi::ImuOptions::load(ini);
  rgbdi::ExtrinsicOptions::load(ini);
  EXPECT_NO_THROW(ini.checkNoUnknownKeys());
  EXPECT_DOUBLE_EQ(imu.acc_noise_density, 0.04);
  // The settings file records the command line's choices.
  std::ifstream settings(dir + "/simulation.ini");
  const std::string text((std::istreambuf_iterator<char>(settings)),
                         std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("seed = 4 "), std::string::npos) << text;
  EXPECT_NE(text.find("time_offset_s = 0.01 "), std::string::npos) << text;

  // MRPT's rawlog-edit reads it (run from the directory: MRPT 2.5 misses the image directory of
  // an absolute path, see doc/simulator.md).
  if (runCommand("command -v rawlog-edit > /dev/null") != 0) {
    if (rgbdi::test::inCi()) FAIL() << "rawlog-edit (mrpt-apps) missing under CI";
    GTEST_SKIP() << "rawlog-edit not installed";
  }
  std::string info;
  ASSERT_EQ(runCommand("cd " + dir + " && rawlog-edit --info -i sequence.rawlog", &info), 0)
      << info;
  EXPECT_NE(info.find("Observations format               : Yes"), std::string::npos) << info;
  EXPECT_TRUE(std::regex_search(info, std::regex("IMU /\\s+2001 /200\\.000"))) << info;
  EXPECT_TRUE(std::regex_search(info, std::regex("RGBD /\\s+31 /"))) << info;
  EXPECT_NE(info.find("Found external storage directory: sequence_Images"), std::string::npos)
      << info;
}

TEST(RgbdiSim, EmbeddedImagesHoldTheSameFramesAsTheImageFiles) {
  const std::string base = rgbdi::test::makeTempDir("rgbdi_sim_layouts");
  const std::string args = " --profile tracked_slopes --duration 10 --fps 3 --seed 4";
  std::string out;
  ASSERT_EQ(runCommand(sim() + args + " --out " + base + "/files", &out), 0) << out;
  ASSERT_EQ(runCommand(sim() + args + " --embedded-images --out " + base + "/embedded", &out), 0)
      << out;
  EXPECT_TRUE(fs::exists(base + "/files/sequence_Images"));
  EXPECT_FALSE(fs::exists(base + "/embedded/sequence_Images"));
  // Raw 640x480 images: colour 3 bytes and depth 2 bytes per pixel in each of the 31 frames.
  EXPECT_GT(fs::file_size(base + "/embedded/sequence.rawlog"), 31u * 640u * 480u * 5u);
  const auto read = [](const std::string& path) {
    rgbdi::io::RawlogSource src(path);
    std::vector<rgbdi::io::Measurement> all;
    rgbdi::io::Measurement m;
    while (src.next(m)) all.push_back(m);
    EXPECT_TRUE(src.diagnostics().warnings.empty()) << path;
    return all;
  };
  const auto files = read(base + "/files/sequence.rawlog");
  const auto embedded = read(base + "/embedded/sequence.rawlog");
  ASSERT_EQ(files.size(), embedded.size());
  std::size_t frames = 0;
  for (std::size_t i = 0; i < files.size(); ++i) {
    ASSERT_EQ(rgbdi::io::measurementTime(files[i]), rgbdi::io::measurementTime(embedded[i])) << i;
    const auto* a = std::get_if<rgbdi::RgbdFrame>(&files[i]);
    const auto* b = std::get_if<rgbdi::RgbdFrame>(&embedded[i]);
    ASSERT_EQ(a == nullptr, b == nullptr) << i;
    if (!a) continue;
    ++frames;
    ASSERT_EQ(a->rgb.size(), b->rgb.size());
    EXPECT_EQ(cv::norm(a->rgb, b->rgb, cv::NORM_INF), 0.0) << "frame " << a->index;
    EXPECT_EQ(cv::norm(a->depth, b->depth, cv::NORM_INF), 0.0) << "frame " << a->index;
    EXPECT_EQ(a->depth_unit_m, b->depth_unit_m);
    EXPECT_EQ(a->cam_color.fx, b->cam_color.fx);
  }
  EXPECT_EQ(frames, 31u);
}

TEST(RgbdiSim, UsageAndConfigurationErrors) {
  const std::string dir = rgbdi::test::makeTempDir("rgbdi_sim");
  std::string out;
  EXPECT_EQ(runCommand(sim() + " --profile flying --out " + dir, &out), 2);
  EXPECT_NE(out.find("unknown profile 'flying' (valid: handheld, wheeled_circle, wheeled_slopes, "
                     "tracked_slopes)"),
            std::string::npos)
      << out;
  EXPECT_EQ(runCommand(sim() + " --profile handheld", &out), 2);
  EXPECT_NE(out.find("--out is required"), std::string::npos) << out;
  EXPECT_EQ(runCommand(sim() + " --profile handheld --out " + dir + " --speed warp", &out), 2);
  EXPECT_NE(out.find("unknown speed 'warp'"), std::string::npos) << out;
  EXPECT_EQ(runCommand(sim() + " --profile handheld --out " + dir + " --bag-compression zip", &out),
            2);
  EXPECT_NE(out.find("unknown bag compression 'zip'"), std::string::npos) << out;
  EXPECT_EQ(runCommand(sim() + " --profile handheld --out " + dir + " --fps abc", &out), 2);
  EXPECT_NE(out.find("--fps needs a number, got 'abc'"), std::string::npos) << out;
  // The impairments' START:DURATION[:X] values.
  EXPECT_EQ(runCommand(sim() + " --profile handheld --out " + dir + " --blackout 20", &out), 2);
  EXPECT_NE(out.find("--blackout needs START:DURATION[:KIND] in seconds, got '20'"),
            std::string::npos)
      << out;
  EXPECT_EQ(runCommand(sim() + " --profile handheld --out " + dir + " --blackout 20:2:fog", &out),
            2);
  EXPECT_NE(out.find("KIND must be black, bare or blur, got 'fog'"), std::string::npos) << out;
  EXPECT_EQ(runCommand(sim() + " --profile handheld --out " + dir + " --spin 20:0", &out), 2);
  EXPECT_NE(out.find("--spin: START must be >= 0 and DURATION > 0, got '20:0'"), std::string::npos)
      << out;
  EXPECT_EQ(runCommand(sim() + " --profile handheld --out " + dir + " --spin 20:1:x", &out), 2);
  EXPECT_NE(out.find("--spin turns needs a number, got 'x'"), std::string::npos) << out;
  EXPECT_EQ(runCommand(sim() + " --profile handheld --out " + dir + " --spin 20:1:0", &out), 2);
  EXPECT_NE(out.find("TURNS must be non-zero"), std::string::npos) << out;
  EXPECT_EQ(runCommand(sim() + " --profile handheld --out " + dir + " --duration 4", &out), 1);
  EXPECT_NE(out.find("duration 4 s is too short"), std::string::npos) << out;

  EXPECT_EQ(
      runCommand(sim() + " --profile handheld --out " + dir + " --config " + dir + "/missing.ini",
                 &out),
      2);  // configuration errors are usage errors (doc/robustness.md)
  EXPECT_NE(out.find(dir + "/missing.ini"), std::string::npos) << out;
  const std::string bad = dir + "/bad.ini";
  std::ofstream(bad) << "[sim]\nacc_noise_densty = 0.02\n";
  EXPECT_EQ(runCommand(sim() + " --profile handheld --out " + dir + " --config " + bad, &out), 2);
  EXPECT_NE(out.find("acc_noise_densty"), std::string::npos) << out;
  EXPECT_NE(out.find("bad.ini"), std::string::npos) << out;
  std::ofstream(bad) << "[sim]\ngyr_noise_density = -1\n";
  EXPECT_EQ(runCommand(sim() + " --profile handheld --out " + dir + " --config " + bad, &out), 2);
  EXPECT_NE(out.find("[sim] gyr_noise_density"), std::string::npos) << out;
  // Nothing was written by the failed runs.
  EXPECT_FALSE(fs::exists(dir + "/sequence.rawlog"));
  EXPECT_EQ(runCommand(sim() + " --help", &out), 0);
  EXPECT_NE(out.find("usage: rgbdi-sim"), std::string::npos);
  EXPECT_NE(out.find("world_seed"), std::string::npos) << out;
  EXPECT_NE(out.find("Exit status: 0 success"), std::string::npos);
  EXPECT_NE(out.find("Interrupted (130), it writes no rawlog and no bag"), std::string::npos);
  EXPECT_EQ(runCommand(sim() + " --version", &out), 0);
  EXPECT_EQ(out.rfind("rgbdi-sim (rgbdi) ", 0), 0u) << out;
}

TEST(RgbdiSim, InterruptedLeavesNoRawlogAndNoBag) {
  // As --help and doc/tools.md say: exit 130, a sequence is complete or absent. A 60 s sequence
  // cannot finish within the 2 s before SIGINT.
  const std::string dir = rgbdi::test::makeTempDir("rgbdi_sim_int") + "/out";
  std::string out;
  EXPECT_EQ(runCommand("timeout --preserve-status -s INT 2 " + sim() +
                           " --profile handheld --duration 60 --bag --out " + dir,
                       &out),
            130)
      << out;
  EXPECT_NE(out.find("no rawlog or bag was written"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(dir + "/sequence.rawlog"));
  EXPECT_FALSE(fs::exists(dir + "/sequence.bag"));
}

}  // namespace
