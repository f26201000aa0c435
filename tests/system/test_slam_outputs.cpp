// The output writers of a SLAM run: the header lines that say each TUM file's frame and clock,
// the colour-camera twins stamped with the image stamps of the same frames (also when a run in
// a loaded map keeps only some frames), the plot's alignment text, and an output list that names
// only files that were written (a run without keyframes writes no pose graph).
#include <gtest/gtest.h>

#include <deque>
#include <filesystem>
#include <fstream>
#include <memory>
#include <set>

#include "rgbdi/eval/tum_reader.h"
#include "rgbdi/output/tum_writer.h"
#include "rgbdi/system/slam_outputs.h"
#include "rgbdi/system/slam_summary.h"
#include "rgbdi/system/slam_system.h"
#include "rgbdi/system/system_config.h"
#include "testing/fixtures.h"

namespace fs = std::filesystem;
using namespace rgbdi;
using system::TumFrames;
using system::TumOutput;

namespace {

bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

std::deque<system::FrameRecord> threeFrames() {
  std::deque<system::FrameRecord> frames(3);
  for (int i = 0; i < 3; ++i) {
    frames[i].t_image = 10.0 + 0.1 * i;
    frames[i].t_imu = frames[i].t_image + 0.004 + 0.001 * i;  // the offset is estimated online
  }
  return frames;
}

/// A sequential system that has seen nothing but the end of its stream.
std::unique_ptr<system::SlamSystem> emptyRun() {
  system::SlamSystemOptions so;
  so.threaded = false;
  auto sys = std::make_unique<system::SlamSystem>(system::SystemConfig::load(""), so);
  sys->endOfStream();
  return sys;
}

}  // namespace

TEST(SlamOutputs, TumHeadersNameFrameReferenceFrameClockAndKindOfPose) {
  TumFrames f;
  const std::string final_body = system::tumFrameAndClock(TumOutput::kFinal, f);
  EXPECT_TRUE(has(final_body, "body (IMU) frame")) << final_body;
  EXPECT_TRUE(has(final_body, "this run's world frame")) << final_body;
  EXPECT_TRUE(has(final_body, "IMU time (image stamp + estimated camera-IMU time offset)"))
      << final_body;
  EXPECT_TRUE(has(final_body, "the input's clock")) << final_body;
  EXPECT_TRUE(has(final_body, "optimised")) << final_body;
  EXPECT_FALSE(has(final_body, "map")) << final_body;

  f.camera = true;
  const std::string online_cam = system::tumFrameAndClock(TumOutput::kOnline, f);
  EXPECT_TRUE(has(online_cam, "colour camera optical frame")) << online_cam;
  EXPECT_TRUE(has(online_cam, "stamps: image stamps")) << online_cam;
  EXPECT_FALSE(has(online_cam, "IMU time")) << online_cam;
  EXPECT_TRUE(has(online_cam, "online: causal")) << online_cam;

  f.camera = false;
  f.loaded_map = true;
  f.live = true;
  const std::string final_map = system::tumFrameAndClock(TumOutput::kFinal, f);
  EXPECT_TRUE(has(final_map, "in: the frame of the map loaded with --load-map")) << final_map;
  EXPECT_TRUE(has(final_map, "the live sensors' clock")) << final_map;
  const std::string odom_map = system::tumFrameAndClock(TumOutput::kOdometry, f);
  EXPECT_TRUE(has(odom_map, "in: this run's world frame")) << odom_map;
  EXPECT_TRUE(has(odom_map, "not the loaded map's frame")) << odom_map;
  EXPECT_TRUE(has(odom_map, "odometry alone")) << odom_map;
  const std::string kf_map = system::tumFrameAndClock(TumOutput::kKeyframes, f);
  EXPECT_TRUE(has(kf_map, "keyframes at their final")) << kf_map;
  EXPECT_TRUE(has(kf_map, "their segment's odometry frame for the others")) << kf_map;
}

TEST(SlamOutputs, HeaderLinesComeBeforeTheColumnsAndTheFileReadsBack) {
  const std::string dir = test::makeTempDir("slam_outputs_header");
  Trajectory t;
  t.push_back(StampedPose::fromIsometry(1.0, Eigen::Isometry3d::Identity()));
  TumFrames f;
  output::writeTum(dir + "/t.tum", t, system::tumFrameAndClock(TumOutput::kOdometry, f));
  std::ifstream in(dir + "/t.tum");
  std::vector<std::string> lines;
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  ASSERT_EQ(lines.size(), 6u);  // poses, in, stamps, kind, columns, one pose
  EXPECT_EQ(lines[0], "# poses: body (IMU) frame");
  EXPECT_EQ(lines[3], "# odometry alone: no loop correction");
  EXPECT_EQ(lines[4], "# timestamp tx ty tz qx qy qz qw");
  EXPECT_EQ(eval::readTum(dir + "/t.tum").size(), 1u);
}

TEST(SlamOutputs, CameraTwinTakesTheImageStampOfTheSameFrameAndTheExtrinsic) {
  const auto frames = threeFrames();
  Eigen::Isometry3d T_body_cam = Eigen::Isometry3d::Identity();
  T_body_cam.linear() = Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T_body_cam.translation() = Eigen::Vector3d(0.1, 0.0, 0.02);
  Eigen::Isometry3d T_world_body = Eigen::Isometry3d::Identity();
  T_world_body.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()).toRotationMatrix();
  T_world_body.translation() = Eigen::Vector3d(1.0, 2.0, 3.0);
  // Frames 0 and 2 only: a run in a loaded map drops the frames not placed in it.
  Trajectory body;
  body.push_back(StampedPose::fromIsometry(frames[0].t_imu, T_world_body));
  body.push_back(StampedPose::fromIsometry(frames[2].t_imu, Eigen::Isometry3d::Identity()));
  const Trajectory cam = system::cameraTwin(body, frames, T_body_cam);
  ASSERT_EQ(cam.size(), 2u);
  EXPECT_EQ(cam[0].t, frames[0].t_image);
  EXPECT_EQ(cam[1].t, frames[2].t_image);  // not frames[1]'s, the next by index
  const Eigen::Isometry3d expected = T_world_body * T_body_cam;
  EXPECT_TRUE(cam[0].isometry().isApprox(expected, 1e-12));
  // The camera centre: body origin + R_world_body * (0.1, 0, 0.02) = (1.1, 2 - 0.02, 3 + 0).
  EXPECT_NEAR(cam[0].p.x(), 1.1, 1e-12);
  EXPECT_NEAR(cam[0].p.y(), 2.0 - 0.02, 1e-12);
  EXPECT_NEAR(cam[0].p.z(), 3.0, 1e-12);
  EXPECT_TRUE(cam[1].isometry().isApprox(T_body_cam, 1e-12));
}

TEST(SlamOutputs, CameraTwinRefusesAStampThatIsNoFramesImuTime) {
  const auto frames = threeFrames();
  Trajectory body;
  body.push_back(StampedPose::fromIsometry(frames[1].t_image, Eigen::Isometry3d::Identity()));
  EXPECT_THROW(system::cameraTwin(body, frames, Eigen::Isometry3d::Identity()), std::logic_error);
}

TEST(SlamOutputs, PlotSaysHowTheGroundTruthWasAligned) {
  EXPECT_EQ(system::plotAlignmentText(true),
            "ground truth aligned to the estimate: position + yaw");
  EXPECT_EQ(system::plotAlignmentText(false), "no alignment applied");
}

TEST(SlamOutputs, ARunWithoutKeyframesListsOnlyTheFilesItWrote) {
  const std::unique_ptr<system::SlamSystem> run = emptyRun();
  const system::SlamSystem& sys = *run;
  ASSERT_TRUE(sys.keyframeStates().empty());
  const std::string dir = test::makeTempDir("slam_outputs_empty");
  const nlohmann::json out = system::writeSlamOutputs(sys, dir, nullptr, false);
  EXPECT_FALSE(out.contains("pose_graph"));  // no keyframe, no node: no pose_graph.graph
  EXPECT_FALSE(fs::exists(dir + "/pose_graph.graph"));
  EXPECT_FALSE(out.contains("plot"));  // fewer than two poses
  std::set<std::string> listed;
  for (const auto& [name, path] : out.items()) {
    EXPECT_TRUE(fs::is_regular_file(path.get<std::string>())) << name;
    listed.insert(fs::path(path.get<std::string>()).filename().string());
  }
  for (const auto& e : fs::directory_iterator(dir))
    EXPECT_TRUE(listed.count(e.path().filename().string())) << e.path() << " written, not listed";
  for (const char* name :
       {"trajectory", "trajectory_cam", "trajectory_online", "trajectory_online_cam",
        "trajectory_odometry", "trajectory_odometry_cam", "keyframes"}) {
    ASSERT_TRUE(out.contains(name)) << name;
    // Header lines only (no pose): the file still says what it would hold.
    std::ifstream in(out[name].get<std::string>());
    std::size_t lines = 0;
    for (std::string l; std::getline(in, l); ++lines) EXPECT_EQ(l.rfind("# ", 0), 0u) << l;
    EXPECT_EQ(lines, 5u) << name;
  }
}

TEST(SlamOutputs, ReportExplainsALateFirstPoseByTheReasonsTheOdometryWaited) {
  nlohmann::json s =
      system::slamSummary(*emptyRun(), system::RunInfo{}, system::RunEvaluation{}, {});
  s["initialisation_waits"] = {{"moving start: not enough parallax yet", 40},
                               {"static start: gyro mean above init_static_max_gyro_rad_s", 45},
                               {"moving start: too few frames", 4},
                               {"static start: not enough IMU history", 1}};
  s["first_pose_time_s"] = 3.25;
  const std::string late = system::formatRunReport(s, {}, "");
  EXPECT_TRUE(has(late,
                  "First pose 3.25 s after the first image; the odometry waited for: static "
                  "start: gyro mean above init_static_max_gyro_rad_s (45 frames); moving start: "
                  "not enough parallax yet (40 frames); moving start: too few frames (4 frames)\n"))
      << late;
  s["first_pose_time_s"] = 0.3;  // a normal start: nothing to explain
  EXPECT_FALSE(has(system::formatRunReport(s, {}, ""), "First pose")) << late;
  EXPECT_EQ(system::initWaitsLine(nlohmann::json::object()), "nothing: no frame reached a start");
  EXPECT_EQ(system::initWaitsLine({{"b", 2}, {"a", 2}, {"c", 5}, {"d", 1}}),
            "c (5 frames); a (2 frames); b (2 frames)");
  EXPECT_EQ(system::initWaitsLine({{"x", 1}}), "x (1 frame)");
}
