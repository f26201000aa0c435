// ProgressReporter: the percentage follows the odometry (the stamp of the last frame it
// finished against the stream's span), not the reader that runs ahead of it behind bounded
// queues; known answers of odometryFraction and the printed line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "rgbdi/system/progress_reporter.h"

namespace rgbdi::system {
namespace {

struct CountingSink : MeasurementSink {
  int imu = 0, frames = 0, ends = 0;
  void feedImu(const ImuSample&) override { ++imu; }
  void feedRgbd(const RgbdFrame&) override { ++frames; }
  void endOfStream() override { ++ends; }
};

TEST(ProgressReporter, OdometryFractionKnownAnswers) {
  // Whole input read: the span is what was read.
  EXPECT_DOUBLE_EQ(ProgressReporter::odometryFraction(0.0, 1.0, 4.0, 1.0), 0.25);
  // Half of the file read over 4 s of stream: an 8 s stream, the odometry 2 s into it.
  EXPECT_DOUBLE_EQ(ProgressReporter::odometryFraction(10.0, 12.0, 14.0, 0.5), 0.25);
  // The extrapolation may undershoot: never above 1, never below 0.
  EXPECT_DOUBLE_EQ(ProgressReporter::odometryFraction(0.0, 9.0, 4.0, 0.5), 1.0);
  EXPECT_DOUBLE_EQ(ProgressReporter::odometryFraction(5.0, 4.0, 6.0, 1.0), 0.0);
  // Nothing known yet.
  EXPECT_DOUBLE_EQ(ProgressReporter::odometryFraction(0.0, NAN, 4.0, 1.0), 0.0);
  EXPECT_DOUBLE_EQ(ProgressReporter::odometryFraction(NAN, NAN, NAN, 0.0), 0.0);
  EXPECT_DOUBLE_EQ(ProgressReporter::odometryFraction(0.0, 1.0, 4.0, 0.0), 0.0);
  // A stream of one instant, read whole (or not).
  EXPECT_DOUBLE_EQ(ProgressReporter::odometryFraction(3.0, 3.0, 3.0, 1.0), 1.0);
  EXPECT_DOUBLE_EQ(ProgressReporter::odometryFraction(3.0, 3.0, 3.0, 0.5), 0.0);
}

class ReaderAhead : public ::testing::Test {
 protected:
  // The reader has read a whole 4 s stream (41 frames, IMU at 100 Hz); the odometry has
  // finished 11 frames, the last one at 1.0 s.
  void readStream(ProgressReporter& r) {
    for (int i = 0; i <= 400; ++i) {
      ImuSample s;
      s.t = 100.0 + 0.01 * i;
      r.feedImu(s);
      if (i % 10 == 0) {
        RgbdFrame f;
        f.t = s.t;
        r.feedRgbd(f);
      }
    }
  }
  CountingSink sink;
  SlamProgress odometry;
  double read_fraction = 1.0;
  std::ostringstream os;
  ProgressReporter reporter{sink,   [this] { return odometry; },     os, false,
                            3600.0, [this] { return read_fraction; }};
};

TEST_F(ReaderAhead, LineFollowsTheOdometryNotTheReader) {
  odometry.frames = 11;
  odometry.last_frame_t = 101.0;
  readStream(reporter);
  EXPECT_EQ(sink.imu, 401);
  EXPECT_EQ(sink.frames, 41);
  EXPECT_EQ(reporter.framesSeen(), 41u);  // the reader's count (summary.json "frames")
  EXPECT_TRUE(os.str().empty());          // within the interval
  reporter.update(true);
  const std::string line = os.str();
  EXPECT_EQ(line.rfind("\r[rgbdi-slam] 25.0 %, 11 frames, ", 0), 0u) << line;
  EXPECT_NE(line.find(", stream 1.0 s, "), std::string::npos) << line;
  EXPECT_EQ(line.find("ETA ?"), std::string::npos) << line;
}

TEST_F(ReaderAhead, NothingProcessedYetHasNoEta) {
  readStream(reporter);
  reporter.update(true);
  const std::string line = os.str();
  EXPECT_EQ(line.rfind("\r[rgbdi-slam] 0.0 %, 0 frames, ", 0), 0u) << line;
  EXPECT_NE(line.find("ETA ?, stream 0.0 s, "), std::string::npos) << line;
}

TEST_F(ReaderAhead, EndOfStreamShowsAllOrWhereTheReaderStopped) {
  readStream(reporter);
  odometry.frames = 41;
  odometry.last_frame_t = 104.0;
  reporter.endOfStream();
  EXPECT_EQ(sink.ends, 1);
  EXPECT_EQ(os.str().rfind("\r[rgbdi-slam] 100.0 %, 41 frames, ", 0), 0u) << os.str();
  EXPECT_EQ(os.str().back(), '\n');  // the line is ended

  // Ctrl-C after 4 s of a stream the reader had read a fifth of: 20 %.
  CountingSink sink2;
  std::ostringstream os2;
  ProgressReporter stopped(
      sink2, [this] { return odometry; }, os2, false, 3600.0, [] { return 0.2; });
  readStream(stopped);
  stopped.endOfStream();
  EXPECT_EQ(os2.str().rfind("\r[rgbdi-slam] 20.0 %, 41 frames, ", 0), 0u) << os2.str();
}

TEST(ProgressReporter, ALogGetsOneLinePerTenthOfTheStreamAndTheFinalOneOnce) {
  // stderr redirected to a file: lines of their own (no '\r'), one per tenth however short the
  // interval, as rgbdi-sim and rawlog-convert do; before, a '\r' line every interval.
  CountingSink sink;
  SlamProgress odometry;  // keeps up with the reader
  double read_fraction = 0.0;
  std::ostringstream os;
  ProgressReporter r(
      sink, [&] { return odometry; }, os, false, 1e-9, [&] { return read_fraction; });
  r.setInteractive(false);
  for (int i = 0; i <= 400; ++i) {
    ImuSample s;
    s.t = 0.01 * i;
    r.feedImu(s);
    read_fraction = i / 400.0;
    if (i % 10 == 0) {
      RgbdFrame f;
      f.t = s.t;
      odometry.frames = static_cast<std::size_t>(i / 10 + 1);
      odometry.last_frame_t = f.t;
      r.feedRgbd(f);
    }
  }
  r.endOfStream();
  const std::string log = os.str();
  EXPECT_EQ(log.find('\r'), std::string::npos) << log;
  EXPECT_EQ(std::count(log.begin(), log.end(), '\n'), 10) << log;
  EXPECT_EQ(log.rfind("[rgbdi-slam] 10.0 %, 5 frames, ", 0), 0u) << log;
  EXPECT_NE(log.find("\n[rgbdi-slam] 100.0 %, 41 frames, "), std::string::npos) << log;
  r.endLine();  // nothing left to end
  EXPECT_EQ(os.str(), log);
}

}  // namespace
}  // namespace rgbdi::system
