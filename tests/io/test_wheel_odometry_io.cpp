// Wheel odometry through the io stage: MRPT CObservationOdometry <-> WheelOdometrySample, rawlog
// round trip in both layouts, time order across the three kinds, bad readings, and the stream
// checks (rate, gaps, wheels moving while the IMU is at rest, wheels standing while it moves).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "rgbdi/io/mrpt_conversions.h"
#include "rgbdi/io/rawlog_source.h"
#include "rgbdi/io/rawlog_writer.h"
#include "rgbdi/io/time_ordering_buffer.h"
#include "testing/fixtures.h"

namespace rgbdi::io {
namespace {

using Layout = RawlogWriterOptions::Layout;
constexpr double kT0 = 1700000000.0;
constexpr double kImuDt = 0.005;   // 200 Hz
constexpr double kWheelDt = 0.02;  // 50 Hz

ImuSample imuAt(double t, const Eigen::Vector3d& gyr = Eigen::Vector3d::Zero(),
                double acc_z = 9.81) {
  ImuSample s;
  s.t = t;
  s.acc = Eigen::Vector3d(0.0, 0.0, acc_z);
  s.gyr = gyr;
  return s;
}

WheelOdometrySample wheelAt(double t, double x, double yaw = 0.0) {
  WheelOdometrySample w;
  w.t = t;
  w.x_m = x;
  w.y_m = -0.25 * x;
  w.yaw_rad = yaw;
  w.has_velocities = true;
  w.v_forward_m_s = 0.5;
  w.v_lateral_m_s = -0.01;
  w.yaw_rate_rad_s = 0.125;
  w.has_encoders = true;
  w.ticks_left = static_cast<std::int32_t>(std::lround(1000 * x));
  w.ticks_right = -7;
  return w;
}

void expectSame(const WheelOdometrySample& a, const WheelOdometrySample& b) {
  EXPECT_NEAR(a.t, b.t, 1e-6);  // mrpt::Clock has 100 ns ticks
  EXPECT_EQ(a.x_m, b.x_m);
  EXPECT_EQ(a.y_m, b.y_m);
  EXPECT_NEAR(a.yaw_rad, b.yaw_rad, 1e-14);  // MRPT rebuilds the angle from its cos and sin
  EXPECT_EQ(a.has_velocities, b.has_velocities);
  EXPECT_EQ(a.v_forward_m_s, b.v_forward_m_s);
  EXPECT_EQ(a.v_lateral_m_s, b.v_lateral_m_s);
  EXPECT_EQ(a.yaw_rate_rad_s, b.yaw_rate_rad_s);
  EXPECT_EQ(a.has_encoders, b.has_encoders);
  EXPECT_EQ(a.ticks_left, b.ticks_left);
  EXPECT_EQ(a.ticks_right, b.ticks_right);
}

/// Writes `seq` (IMU and wheel readings) to a rawlog and reads it back.
struct ReadBack {
  std::vector<Measurement> out;
  StreamDiagnostics diag;
};
ReadBack roundTrip(const std::string& path, const std::vector<Measurement>& seq,
                   Layout layout = Layout::Observations, const StreamConfig& cfg = {}) {
  {
    RawlogWriterOptions o;
    o.layout = layout;
    RawlogWriter w(path, o);
    for (const auto& m : seq) {
      if (const auto* s = std::get_if<ImuSample>(&m)) {
        w.write(*s);
      } else {
        w.write(std::get<WheelOdometrySample>(m));
      }
    }
    w.close();
  }
  RawlogSource src(path, cfg);
  src.logging_enable_console_output = false;
  ReadBack r;
  Measurement m;
  while (src.next(m)) r.out.push_back(m);
  r.diag = src.diagnostics();
  return r;
}

TEST(WheelOdometryIo, MrptConversionKeepsEveryField) {
  const WheelOdometrySample w = wheelAt(kT0 + 0.25, 1.5, -2.75);
  const auto obs = toMrpt(w, "ODO");
  EXPECT_EQ(obs->sensorLabel, "ODO");
  EXPECT_EQ(obs->odometry.x(), 1.5);
  EXPECT_EQ(obs->odometry.y(), -0.375);
  EXPECT_EQ(obs->odometry.phi(), -2.75);
  EXPECT_TRUE(obs->hasVelocities);
  EXPECT_EQ(obs->velocityLocal.vx, 0.5);
  EXPECT_EQ(obs->velocityLocal.omega, 0.125);
  EXPECT_TRUE(obs->hasEncodersInfo);
  EXPECT_EQ(obs->encoderLeftTicks, 1500);
  expectSame(fromMrpt(*obs), w);

  WheelOdometrySample bare;  // pose only: velocities and ticks stay absent (zero)
  bare.t = kT0;
  bare.x_m = 2.0;
  auto o2 = toMrpt(bare, "ODO");
  o2->velocityLocal = mrpt::math::TTwist2D(9.0, 9.0, 9.0);  // present but not flagged
  o2->encoderLeftTicks = 99;
  const WheelOdometrySample back = fromMrpt(*o2);
  EXPECT_FALSE(back.has_velocities);
  EXPECT_FALSE(back.has_encoders);
  EXPECT_EQ(back.v_forward_m_s, 0.0);
  EXPECT_EQ(back.ticks_left, 0);
}

TEST(WheelOdometryIo, NonFiniteReadingIsDetected) {
  WheelOdometrySample w = wheelAt(kT0, 1.0);
  EXPECT_TRUE(isFinite(w));
  w.yaw_rate_rad_s = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(isFinite(w));
}

TEST(WheelOdometryIo, TimeOrderingReleasesImuThenWheelThenFrameAtEqualStamps) {
  TimeOrderingBuffer b(0.05, 0.1);
  RgbdFrame f;
  f.t = 2.0;
  b.push(f, 0);
  b.push(wheelAt(2.0, 0.0), 1);
  b.push(imuAt(2.0), 2);
  EXPECT_EQ(b.push(wheelAt(2.0, 0.1), 3), TimeOrderingBuffer::Verdict::Duplicate);
  EXPECT_EQ(b.push(wheelAt(1.99, 0.1), 4), TimeOrderingBuffer::Verdict::Reordered);
  EXPECT_EQ(b.push(wheelAt(1.94, 0.1), 5), TimeOrderingBuffer::Verdict::TooLate);  // IMU window
  EXPECT_EQ(b.newestWheel(), 2.0);
  b.finish();
  std::vector<MeasurementKind> kinds;
  TimeOrderingBuffer::Item it;
  while (b.pop(it)) kinds.push_back(kindOf(it.m));
  const std::vector<MeasurementKind> expected = {MeasurementKind::Wheel, MeasurementKind::Imu,
                                                 MeasurementKind::Wheel, MeasurementKind::Rgbd};
  EXPECT_EQ(kinds, expected);
}

TEST(WheelOdometryIo, RawlogRoundTripInBothLayouts) {
  const std::string dir = rgbdi::test::makeTempDir("rgbdi_wheel_io");
  std::vector<Measurement> seq;
  std::vector<WheelOdometrySample> wheels;
  for (int i = 0; i <= 200; ++i) {
    const double t = kT0 + i * kImuDt;
    seq.emplace_back(imuAt(t));
    if (i % 4 == 2) {
      wheels.push_back(wheelAt(t + 0.001, 0.01 * i, 0.002 * i));
      seq.emplace_back(wheels.back());
    }
  }
  for (const Layout layout : {Layout::Observations, Layout::SensoryFrames}) {
    const ReadBack r = roundTrip(dir + "/w.rawlog", seq, layout);
    std::vector<WheelOdometrySample> got;
    for (const auto& m : r.out)
      if (const auto* w = std::get_if<WheelOdometrySample>(&m)) got.push_back(*w);
    ASSERT_EQ(got.size(), wheels.size());
    for (std::size_t i = 0; i < got.size(); ++i) expectSame(got[i], wheels[i]);
    for (std::size_t i = 1; i < r.out.size(); ++i)
      EXPECT_LE(measurementTime(r.out[i - 1]), measurementTime(r.out[i]));
    EXPECT_EQ(r.diag.wheel.delivered, wheels.size());
    EXPECT_EQ(r.diag.wheel_with_velocities, wheels.size());
    EXPECT_EQ(r.diag.wheel_with_encoders, wheels.size());
    EXPECT_NEAR(r.diag.wheel.rate_hz, 50.0, 1e-3);
    EXPECT_NEAR(r.diag.wheel.median_period_s, kWheelDt, 1e-6);
    EXPECT_EQ(r.diag.wheel.gaps, 0u);
    EXPECT_EQ(r.diag.skipped.count("mrpt::obs::CObservationOdometry"), 0u);
    EXPECT_NE(r.diag.report().find("Wheel: 50 readings"), std::string::npos) << r.diag.report();
    EXPECT_NE(r.diag.toJson().find("\"wheel\""), std::string::npos);
  }
}

TEST(WheelOdometryIo, StreamWithoutWheelsReportsNoWheelSection) {
  const std::string dir = rgbdi::test::makeTempDir("rgbdi_wheel_none");
  std::vector<Measurement> seq;
  for (int i = 0; i <= 40; ++i) seq.emplace_back(imuAt(kT0 + i * kImuDt));
  const ReadBack r = roundTrip(dir + "/n.rawlog", seq);
  EXPECT_FALSE(r.diag.hasWheel());
  EXPECT_EQ(r.diag.report().find("Wheel"), std::string::npos);
  EXPECT_EQ(r.diag.toJson().find("\"wheel\""), std::string::npos);
}

TEST(WheelOdometryIo, NonFiniteReadingIsSkippedAndNamed) {
  const std::string dir = rgbdi::test::makeTempDir("rgbdi_wheel_nan");
  WheelOdometrySample bad = wheelAt(kT0 + 0.0125, 0.5);
  bad.x_m = std::numeric_limits<double>::infinity();
  const std::string path = dir + "/nan.rawlog";
  const ReadBack r =
      roundTrip(path, {imuAt(kT0), wheelAt(kT0 + 0.0025, 0.0), bad, imuAt(kT0 + kImuDt * 5)});
  EXPECT_EQ(r.out.size(), 3u);
  EXPECT_EQ(r.diag.non_finite_wheel, 1u);
  EXPECT_EQ(r.diag.unusable, 1u);
  ASSERT_FALSE(r.diag.warnings.empty());
  EXPECT_EQ(r.diag.warnings[0].rfind(path + " record 2: wheel odometry at t = 1700000000.012500 "
                                            "s has a non-finite value (pose inf -0.125 0",
                                     0),
            0u)
      << r.diag.warnings[0];
}

TEST(WheelOdometryIo, GapIsReported) {
  const std::string dir = rgbdi::test::makeTempDir("rgbdi_wheel_gap");
  std::vector<Measurement> seq;
  for (int i = 0; i <= 400; ++i) {
    const double t = kT0 + i * kImuDt;
    seq.emplace_back(imuAt(t));
    // 50 Hz wheels with 0.2 s missing after t0 + 1.0 (record numbers follow the sequence).
    if (i % 4 == 0 && !(i > 200 && i < 240)) seq.emplace_back(wheelAt(t + 0.001, 0.0));
  }
  const ReadBack r = roundTrip(dir + "/g.rawlog", seq);
  EXPECT_EQ(r.diag.wheel.gaps, 1u);
  EXPECT_NEAR(r.diag.wheel.max_gap_s, 0.2, 1e-6);
  EXPECT_NEAR(r.diag.wheel.gap_limit_s, 0.05, 1e-6);
  EXPECT_NEAR(r.diag.wheel_max_gap_t, kT0 + 1.001, 1e-6);  // the reading before the gap
  EXPECT_NE(r.diag.wheelReport().find("gaps 1 (limit 0.0500 s, largest dt 0.2000 s after t = "
                                      "1700000001.001000 s)"),
            std::string::npos)
      << r.diag.wheelReport();
  ASSERT_EQ(r.diag.wheel_warnings.size(), 1u);
  EXPECT_NE(r.diag.wheel_warnings[0].find("wheel-odometry gap of 0.2000 s"), std::string::npos);
  bool named = false;
  for (const auto& w : r.diag.warnings)
    named |= w.find("wheel-odometry gap of 0.2000 s between t = 1700000001.001000 s") !=
             std::string::npos;
  EXPECT_TRUE(named);
}

TEST(WheelOdometryIo, WheelsMovingWhileImuRestsAreFoundOnce) {
  // 4 s: the IMU at rest throughout; the wheels stand for 1.5 s, turn at 0.4 m/s for 1 s (a
  // lifted robot's free-running wheels), then stand again.
  const std::string dir = rgbdi::test::makeTempDir("rgbdi_wheel_rest");
  std::vector<Measurement> seq;
  double x = 0.0;
  for (int i = 0; i <= 800; ++i) {
    const double t = kT0 + i * kImuDt;
    seq.emplace_back(imuAt(t));
    if (i % 4 == 0) {
      const double since = i * kImuDt;
      if (since > 1.5 && since <= 2.5) x += 0.4 * kWheelDt;
      seq.emplace_back(wheelAt(t + 0.001, x));
    }
  }
  const ReadBack r = roundTrip(dir + "/r.rawlog", seq);
  EXPECT_EQ(r.diag.wheel_moving_at_rest, 1u);
  // Windows of 1 s whose wheel speed exceeds 0.05 m/s: ends from t0 + 1.5 + 0.125 s to
  // t0 + 2.5 + 0.875 s; the episode spans from the first such window's start.
  EXPECT_NEAR(r.diag.wheel_moving_at_rest_s, 2.75, 0.05);

  // The same wheels on a robot whose IMU turns at 0.1 rad/s: no finding.
  std::vector<Measurement> turning;
  for (const auto& m : seq)
    turning.push_back(isImu(m) ? Measurement(imuAt(measurementTime(m), {0.0, 0.0, 0.1})) : m);
  const ReadBack t = roundTrip(dir + "/t.rawlog", turning);
  EXPECT_EQ(t.diag.wheel_moving_at_rest, 0u);
}

TEST(WheelOdometryIo, WheelsStandingWhileTheImuMovesAreFoundOnce) {
  // 4 s: the wheels stand throughout; the IMU rests, turns at 0.3 rad/s from 1.5 s to 2.5 s (a
  // robot turned by hand with its wheels blocked), then rests again.
  const std::string dir = rgbdi::test::makeTempDir("rgbdi_wheel_still");
  std::vector<Measurement> seq;
  for (int i = 0; i <= 800; ++i) {
    const double t = kT0 + i * kImuDt;
    const double since = i * kImuDt;
    const bool turning = since > 1.5 && since <= 2.5;
    seq.emplace_back(imuAt(t, {0.0, 0.0, turning ? 0.3 : 0.0}));
    if (i % 4 == 0) seq.emplace_back(wheelAt(t + 0.001, 0.0));
  }
  const ReadBack r = roundTrip(dir + "/s.rawlog", seq);
  EXPECT_EQ(r.diag.wheel_moving_at_rest, 0u);
  EXPECT_EQ(r.diag.wheel_still_imu_moving, 1u);
  // Windows of 1 s whose mean rate exceeds 0.1 rad/s overlap the turn by more than 1/3 s: they
  // end from t0 + 1.833 s to t0 + 3.167 s; the episode spans from the first one's start.
  EXPECT_NEAR(r.diag.wheel_still_imu_moving_s, 3.167 - 0.833, 0.05);
  ASSERT_EQ(r.diag.wheel_warnings.size(), 1u);
  EXPECT_NE(r.diag.wheel_warnings[0].find(": wheel odometry stands while the IMU moves (mean "
                                          "angular rate up to 0.300 rad/s"),
            std::string::npos)
      << r.diag.wheel_warnings[0];
  EXPECT_NE(r.diag.wheelReport().find("moving while the IMU is at rest: 0 times (0.000 s); "
                                      "standing while the IMU moves: 1 times"),
            std::string::npos)
      << r.diag.wheelReport();

  // Wheels driving at 0.4 m/s while the IMU turns at 0.3 rad/s throughout: neither verdict.
  std::vector<Measurement> driving;
  for (const auto& m : seq) {
    if (isImu(m)) {
      driving.emplace_back(imuAt(measurementTime(m), {0.0, 0.0, 0.3}));
    } else {
      const double t = measurementTime(m);
      driving.emplace_back(wheelAt(t, 0.4 * (t - kT0)));
    }
  }
  const ReadBack d = roundTrip(dir + "/d.rawlog", driving);
  EXPECT_EQ(d.diag.wheel_still_imu_moving, 0u);
  EXPECT_EQ(d.diag.wheel_moving_at_rest, 0u);

  // Pushed back and forth without turning (x acceleration +/- 0.8 m/s^2, switching every
  // 0.25 s): the block means spread by about 0.8 m/s^2 > wheel_still_acc_m_s2, moving as well.
  // Sample-to-sample noise of the same size averages out in the blocks: no finding.
  std::vector<Measurement> pushed, noisy;
  int k = 0;
  for (const auto& m : seq) {
    if (!isImu(m)) {
      pushed.push_back(m);
      noisy.push_back(m);
      continue;
    }
    const double t = measurementTime(m);
    ImuSample a = imuAt(t), b = imuAt(t);
    a.acc.x() = std::fmod(t - kT0, 0.5) < 0.25 ? 0.8 : -0.8;
    b.acc.x() = (k++ % 2) ? 0.8 : -0.8;
    pushed.emplace_back(a);
    noisy.emplace_back(b);
  }
  const ReadBack p = roundTrip(dir + "/p.rawlog", pushed);
  EXPECT_EQ(p.diag.wheel_still_imu_moving, 1u);
  // From the first reading (t0 + 0.001 s, the start of the first window with half a window of
  // data) to the last (t0 + 4.001 s).
  EXPECT_NEAR(p.diag.wheel_still_imu_moving_s, 4.0, 1e-6);
  const ReadBack n = roundTrip(dir + "/n.rawlog", noisy);
  EXPECT_EQ(n.diag.wheel_still_imu_moving, 0u);
}

}  // namespace
}  // namespace rgbdi::io
