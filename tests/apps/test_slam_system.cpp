// The SLAM system object on generated sequences: threaded and sequential runs give identical
// results, loop closures included (threaded runs prepare the images for tracking on the feeding
// thread, sequential ones in the tracker); an odometry reset starts a new segment without losing
// the window's keyframes and without an invented odometry edge between the segments.
#include <gtest/gtest.h>

#include <opencv2/core/utility.hpp>

#include "rgbdi/common/fan_out_sink.h"
#include "rgbdi/loop/loop_closer.h"
#include "rgbdi/sim/sequence.h"
#include "rgbdi/sim/sequence_writer.h"
#include "rgbdi/system/slam_outputs.h"
#include "rgbdi/system/slam_system.h"

using namespace rgbdi;

namespace {

sim::SimOptions shortSequence(const std::string& profile, double duration_s) {
  auto ini = IniReader::empty();
  sim::SimOptions so = sim::SimOptions::load(ini);
  so.profile.kind = sim::parseProfileKind(profile);
  so.fps = 15.0;
  so.profile.duration_s = duration_s;
  return so;
}

system::SystemConfig configOf(const sim::SimulatedSequence& seq) {
  auto ini = IniReader::fromText(sim::slamConfigText(seq), "generated config.ini");
  return system::SystemConfig::load(ini);
}

/// Forwards everything, with a 30 m/s^2 accelerometer shock in [t_from, t_to) (a knock on the
/// sensor the odometry cannot follow: it detects the failure and restarts).
class ImuShockSink : public MeasurementSink {
 public:
  ImuShockSink(MeasurementSink& next, double t_from, double t_to)
      : next_(next), from_(t_from), to_(t_to) {}
  void feedImu(const ImuSample& s) override {
    ImuSample m = s;
    if (s.t >= from_ && s.t < to_) m.acc.x() += 30.0;
    next_.feedImu(m);
  }
  void feedRgbd(const RgbdFrame& f) override { next_.feedRgbd(f); }
  void endOfStream() override { next_.endOfStream(); }

 private:
  MeasurementSink& next_;
  double from_, to_;
};

void expectSameTrajectory(const Trajectory& a, const Trajectory& b, const char* what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a[i].t, b[i].t) << what << " pose " << i;
    ASSERT_EQ(a[i].p, b[i].p) << what << " pose " << i;
    ASSERT_EQ(a[i].q.coeffs(), b[i].q.coeffs()) << what << " pose " << i;
  }
}

}  // namespace

TEST(SlamSystem, ThreadedAndSequentialRunsGiveIdenticalResults) {
  // At twice the profile's speed (a 16 s lap) long enough to come back to the start once, so loop
  // detection and graph solves run while the odometry goes on. Both systems get the same
  // measurements from one rendering. A third, threaded with two-packet queues and no images
  // prepared ahead ([pipeline]), waits on its stages all the time: the same results again.
  sim::SimOptions so = shortSequence("wheeled_circle", 26.0);
  so.profile.speed_m_s = 0.8;
  sim::SimulatedSequence seq(so);
  const system::SystemConfig cfg = configOf(seq);
  system::SlamSystemOptions threaded, sequential;
  threaded.threaded = true;
  sequential.threaded = false;
  system::SystemConfig tight_cfg = cfg;
  tight_cfg.pipeline.queue_capacity_packets = 2;
  tight_cfg.pipeline.images_prepared_ahead = 0;
  system::SlamSystem a(cfg, threaded), b(cfg, sequential), c(tight_cfg, threaded);
  FanOutSink all({&a, &b, &c});
  seq.pump(all);
  ASSERT_GT(a.frames().size(), 100u);
  EXPECT_GE(a.imagesPreparedAhead(), a.frames().size());  // every image, posed or not
  EXPECT_EQ(b.imagesPreparedAhead(), 0u);
  EXPECT_EQ(c.imagesPreparedAhead(), 0u);
  EXPECT_LE(c.mapQueueHighWater(), 2u);
  ASSERT_NE(a.loopCloser(), nullptr);
  ASSERT_NE(b.loopCloser(), nullptr);
  EXPECT_GT(a.loopCloser()->stats().accepted, 0u);
  EXPECT_EQ(a.loopCloser()->stats().accepted, b.loopCloser()->stats().accepted);
  expectSameTrajectory(a.odometryTrajectory(), b.odometryTrajectory(), "odometry");
  expectSameTrajectory(a.onlineTrajectory(), b.onlineTrajectory(), "online");
  expectSameTrajectory(a.finalTrajectory(), b.finalTrajectory(), "final");
  expectSameTrajectory(c.odometryTrajectory(), b.odometryTrajectory(), "odometry, tight queues");
  expectSameTrajectory(c.onlineTrajectory(), b.onlineTrajectory(), "online, tight queues");
  expectSameTrajectory(c.finalTrajectory(), b.finalTrajectory(), "final, tight queues");
  ASSERT_EQ(a.keyframeStates().size(), b.keyframeStates().size());
  EXPECT_GT(a.keyframeStates().size(), 10u);
  EXPECT_EQ(a.mapper().pointMap().pointCount(), b.mapper().pointMap().pointCount());
  EXPECT_EQ(a.mapper().store().size(), a.keyframeStates().size());
}

TEST(SlamSystem, AppliesOpenCvsThreadCountBeforeItsThreadsStart) {
  // OpenCV's thread count is process-wide; changing it while the feeding thread prepares an
  // image (cv::cvtColor in a parallel loop) left both threads spinning in TBB forever. The
  // system sets it when it is built, so the tracker built later on the odometry thread finds it
  // set and leaves it.
  sim::SimulatedSequence seq(shortSequence("wheeled_circle", 9.0));
  system::SystemConfig cfg = configOf(seq);
  ASSERT_EQ(cfg.frontend.opencv_threads, 1);
  cv::setNumThreads(2);
  ASSERT_EQ(cv::getNumThreads(), 2);
  {
    system::SlamSystem threaded(cfg, system::SlamSystemOptions());
    EXPECT_EQ(cv::getNumThreads(), 1);
    seq.pump(threaded);
    EXPECT_EQ(cv::getNumThreads(), 1);
    EXPECT_GT(threaded.imagesPreparedAhead(), 20u);
  }
  cv::setNumThreads(-1);  // OpenCV's default for the other tests
}

TEST(SlamSystem, AResetStartsANewSegmentWithoutLosingTheWindowOrJoiningTheSegments) {
  sim::SimulatedSequence seq(shortSequence("wheeled_circle", 14.0));
  const system::SystemConfig cfg = configOf(seq);
  system::SlamSystemOptions so;
  system::SlamSystem sys(cfg, so);
  const double t_gap = seq.startTime() + 7.0;
  ImuShockSink shock(sys, t_gap, t_gap + 0.4);
  seq.pump(shock);
  ASSERT_GE(sys.odometry().estimatorStats().resets, 1);

  const auto& kfs = sys.keyframeStates();
  ASSERT_FALSE(kfs.empty());
  const int resets = sys.odometry().estimatorStats().resets;
  double last_seg0 = -1.0, first_seg1 = -1.0;
  for (const auto& k : kfs) {
    if (k.state.segment == 0) last_seg0 = k.state.t_imu;
    if (k.state.segment == 1 && first_seg1 < 0) first_seg1 = k.state.t_imu;
    EXPECT_LE(k.state.segment, resets);
  }
  ASSERT_GT(first_seg1, 0.0) << "the odometry did not restart after the gap";
  // The window (about ten keyframes, the last ones within a second of the gap) was handed out.
  EXPECT_GT(last_seg0, t_gap - 1.0);
  EXPECT_LT(last_seg0, t_gap + 0.5);
  EXPECT_GT(first_seg1, t_gap);
  // Keyframes are in time order and ids follow that order.
  for (std::size_t i = 1; i < kfs.size(); ++i) {
    EXPECT_LT(kfs[i - 1].state.t_imu, kfs[i].state.t_imu);
    EXPECT_EQ(kfs[i].id, kfs[i - 1].id + 1);
  }
  // The pose graph has no odometry edge from segment 0 to segment 1.
  const output::PoseGraph g = system::slamPoseGraph(sys);
  std::size_t seg1_first_id = 0;
  for (const auto& k : kfs)
    if (k.state.segment == 1) {
      seg1_first_id = k.id;
      break;
    }
  for (const auto& e : g.edges)
    if (e.kind == "odometry") {
      EXPECT_FALSE(e.from < seg1_first_id && e.to >= seg1_first_id);
    }
  EXPECT_EQ(g.nodes.size(), kfs.size());
}
