// WheelEncoderSynth: known answers of the differential-drive and skid-steering encoder model on
// analytic motions (straight line, circle, circle on a pitched body), the calibration errors,
// time offset, events, the [sim] wheel_events syntax, and the sequence stream with wheels.
#include <gtest/gtest.h>

#include <cmath>

#include "rgbdi/sim/sequence.h"
#include "rgbdi/sim/wheel_encoder_synth.h"
#include "testing/fixtures.h"

namespace rgbdi::sim {
namespace {

constexpr double kStart = 1000.0;

/// Constant speed v along a circle of radius rho (rho = 0: a straight line along x), the body
/// pitched by a constant angle (nose up positive).
class CircleTrajectory : public BodyTrajectory {
 public:
  CircleTrajectory(double v, double rho, double duration, double pitch = 0.0)
      : v_(v), rho_(rho), duration_(duration), pitch_(pitch) {}
  double duration() const override { return duration_; }

 protected:
  MotionJet jetAt(double t) const override {
    const Taylor<3> time = Taylor<3>::variable(t);
    MotionJet jet;
    if (rho_ == 0.0) {
      jet.position[0] = time * v_;
      jet.rotate(2, Taylor<2>(0.0));
    } else {
      const Taylor<3> heading = time * (v_ / rho_);
      jet.position[0] = sin(heading) * rho_;
      jet.position[1] = (Taylor<3>(1.0) - cos(heading)) * rho_;
      jet.rotate(2, heading.truncated<2>());
    }
    jet.rotate(1, Taylor<2>(-pitch_));
    return jet;
  }

 private:
  double v_, rho_, duration_, pitch_;
};

WheelEncoderOptions baseOptions() {
  WheelEncoderOptions o;
  o.mode = "on";
  return o;
}

double metresPerTick(const WheelEncoderOptions& o) {
  return 2.0 * M_PI * o.radius_m / o.ticks_per_rev;
}

TEST(WheelEncoderSynth, StraightLineCountsTheDistanceToOneTick) {
  const WheelEncoderOptions o = baseOptions();
  const CircleTrajectory line(0.5, 0.0, 10.0);
  const WheelEncoderSynth synth(o, line, kStart);
  const auto& s = synth.samples();
  ASSERT_EQ(s.size(), 501u);  // 10 s at 50 Hz, both ends
  EXPECT_EQ(s.front().t, kStart);
  EXPECT_EQ(s.front().ticks_left, 0);
  EXPECT_DOUBLE_EQ(s.back().t, kStart + 10.0);
  // 5 m on wheels of 0.05 m at 2048 ticks per turn: 32594.93 ticks.
  EXPECT_EQ(s.back().ticks_left, 32594);
  EXPECT_EQ(s.back().ticks_right, 32594);
  EXPECT_NEAR(s.back().x_m, 5.0, metresPerTick(o));
  EXPECT_EQ(s.back().y_m, 0.0);
  EXPECT_EQ(s.back().yaw_rad, 0.0);
  for (std::size_t k = 1; k < s.size(); ++k) {
    EXPECT_NEAR(s[k].v_forward_m_s, 0.5, metresPerTick(o) * o.rate_hz);
    EXPECT_TRUE(s[k].has_encoders && s[k].has_velocities);
  }
}

TEST(WheelEncoderSynth, CircleGivesItsYawRateAndPosition) {
  const WheelEncoderOptions o = baseOptions();
  const CircleTrajectory circle(0.4, 2.0, 10.0);  // 0.2 rad/s
  const auto& s = WheelEncoderSynth(o, circle, kStart).samples();
  const double tick_yaw = metresPerTick(o) / o.track_m;
  EXPECT_NEAR(s.back().yaw_rad, 2.0, 2 * tick_yaw);
  EXPECT_NEAR(s.back().x_m, 2.0 * std::sin(2.0), 2e-3);
  EXPECT_NEAR(s.back().y_m, 2.0 * (1.0 - std::cos(2.0)), 2e-3);
  EXPECT_NEAR(s[250].yaw_rate_rad_s, 0.2, 2 * tick_yaw * o.rate_hz);
  EXPECT_NEAR(s[250].v_forward_m_s, 0.4, 2 * metresPerTick(o) * o.rate_hz);
}

TEST(WheelEncoderSynth, RadiusAndTrackErrorsScaleDistanceAndYaw) {
  WheelEncoderOptions o = baseOptions();
  o.radius_error_left = o.radius_error_right = 0.03;  // wheels 3 % larger than assumed
  const auto& line = WheelEncoderSynth(o, CircleTrajectory(0.5, 0.0, 10.0), kStart).samples();
  EXPECT_NEAR(line.back().x_m, 5.0 / 1.03, metresPerTick(o));

  o = baseOptions();
  o.track_error = 0.1;  // wheels 10 % further apart than assumed: turns look 10 % larger
  const auto& c = WheelEncoderSynth(o, CircleTrajectory(0.4, 2.0, 10.0), kStart).samples();
  EXPECT_NEAR(c.back().yaw_rad, 2.2, 2 * metresPerTick(o) / o.track_m);
}

TEST(WheelEncoderSynth, SkidSteeringSlipsInTurnsAndMoreOnSlopes) {
  WheelEncoderOptions o = baseOptions();
  o.skid_steering = true;
  o.skid_turn_slip = 0.3;
  o.skid_slope_gain = 3.0;
  const double tick_yaw = metresPerTick(o) / o.track_m;
  const auto& flat = WheelEncoderSynth(o, CircleTrajectory(0.4, 2.0, 5.0), kStart).samples();
  EXPECT_NEAR(flat.back().yaw_rad, 1.0 * 1.3, 2 * tick_yaw);
  // Pitched by 0.1 rad: the body's yaw rate about its own z is 0.2 cos(0.1); slip 0.3 * 1.3.
  const auto& slope = WheelEncoderSynth(o, CircleTrajectory(0.4, 2.0, 5.0, 0.1), kStart).samples();
  EXPECT_NEAR(slope.back().yaw_rad, 1.0 * std::cos(0.1) * (1.0 + 0.3 * 1.3), 2 * tick_yaw);
  // A straight drive does not slip.
  const auto& line = WheelEncoderSynth(o, CircleTrajectory(0.5, 0.0, 5.0), kStart).samples();
  EXPECT_EQ(line.back().yaw_rad, 0.0);
}

TEST(WheelEncoderSynth, TimeOffsetShiftsTheStamps) {
  WheelEncoderOptions o = baseOptions();
  o.time_offset_s = 0.015;
  o.rate_hz = 20.0;
  const auto& s = WheelEncoderSynth(o, CircleTrajectory(0.5, 0.0, 1.0), kStart).samples();
  ASSERT_EQ(s.size(), 21u);
  EXPECT_DOUBLE_EQ(s[3].t, kStart + 0.15 - 0.015);
}

TEST(WheelEncoderSynth, EventsMakeTheEncodersDisagreeOnlyWhileTheyLast) {
  WheelEncoderOptions o = baseOptions();
  o.events = WheelEncoderOptions::parseEvents("stuck:2:1,pushed:4:1,spin:6:1");
  const auto& s = WheelEncoderSynth(o, CircleTrajectory(0.5, 0.0, 8.0), kStart).samples();
  const auto at = [&](double t) { return s[static_cast<std::size_t>(std::lround(t * 50))]; };
  const double ticks_per_m = 1.0 / metresPerTick(o);
  // stuck: the left encoder stands for 1 s, the right one counts 0.5 m.
  EXPECT_EQ(at(3.0).ticks_left - at(2.0).ticks_left, 0);
  EXPECT_NEAR(at(3.0).ticks_right - at(2.0).ticks_right, 0.5 * ticks_per_m, 1.0);
  EXPECT_NEAR(at(3.0).yaw_rad - at(2.0).yaw_rad, 0.5 / o.track_m, 1e-3);
  // pushed: both stand.
  EXPECT_EQ(at(5.0).ticks_left, at(4.0).ticks_left);
  EXPECT_EQ(at(5.0).ticks_right, at(4.0).ticks_right);
  // spin: the left wheel counts 0.5 m more than the right one.
  EXPECT_NEAR(
      (at(7.0).ticks_left - at(6.0).ticks_left) - (at(7.0).ticks_right - at(6.0).ticks_right),
      0.5 * ticks_per_m, 2.0);
  // Outside the events both wheels agree.
  EXPECT_NEAR(at(8.0).ticks_left - at(7.0).ticks_left, at(8.0).ticks_right - at(7.0).ticks_right,
              1.0);

  // lifted at a standstill: the wheels run free at event_speed_m_s.
  o.events = WheelEncoderOptions::parseEvents("lifted:0.5:1");
  const auto& l = WheelEncoderSynth(o, CircleTrajectory(0.0, 0.0, 2.0), kStart).samples();
  EXPECT_NEAR(l[75].ticks_left - l[25].ticks_left, 0.5 * ticks_per_m, 1.0);
  EXPECT_EQ(l[100].ticks_left, l[75].ticks_left);
}

TEST(WheelEncoderOptions, EventSyntaxIsCheckedAndRoundTrips) {
  const auto e = WheelEncoderOptions::parseEvents("spin:1.5:2,lifted:10:0.25");
  ASSERT_EQ(e.size(), 2u);
  EXPECT_EQ(e[1].kind, WheelEvent::Kind::Lifted);
  EXPECT_EQ(e[1].start_s, 10.0);
  EXPECT_EQ(e[1].duration_s, 0.25);
  EXPECT_EQ(WheelEncoderOptions::eventsText(e), "spin:1.5:2,lifted:10:0.25");
  EXPECT_TRUE(WheelEncoderOptions::parseEvents("none").empty());
  for (const std::string bad : {"fly:1:2", "spin:1", "spin:x:2", "spin:1:0", "spin:-1:2"}) {
    try {
      WheelEncoderOptions::parseEvents(bad);
      ADD_FAILURE() << bad;
    } catch (const std::invalid_argument& err) {
      EXPECT_NE(std::string(err.what()).find("'" + bad + "'"), std::string::npos) << err.what();
    }
  }
  IniReader ini = IniReader::fromText("[sim]\nwheel_events = spin:1:1,jump:2:1\n", "w.ini");
  EXPECT_THROW(WheelEncoderOptions::load(ini), std::exception);
}

TEST(WheelEncoderOptions, DefaultsEqualTheSharedConfig) {
  IniReader ini = IniReader::fromFile(test::sourceDir() + "/share/config.ini");
  const WheelEncoderOptions o = WheelEncoderOptions::load(ini);
  const WheelEncoderOptions d;
  EXPECT_EQ(o.mode, d.mode);
  EXPECT_EQ(o.rate_hz, d.rate_hz);
  EXPECT_EQ(o.radius_m, d.radius_m);
  EXPECT_EQ(o.track_m, d.track_m);
  EXPECT_EQ(o.radius_error_left, d.radius_error_left);
  EXPECT_EQ(o.radius_error_right, d.radius_error_right);
  EXPECT_EQ(o.track_error, d.track_error);
  EXPECT_EQ(o.ticks_per_rev, d.ticks_per_rev);
  EXPECT_EQ(o.time_offset_s, d.time_offset_s);
  EXPECT_EQ(o.skid_turn_slip, d.skid_turn_slip);
  EXPECT_EQ(o.skid_slope_gain, d.skid_slope_gain);
  EXPECT_EQ(o.event_speed_m_s, d.event_speed_m_s);
  EXPECT_TRUE(o.events.empty());
}

struct KindRecorder : MeasurementSink {
  std::vector<double> stamps;
  std::vector<int> kinds;  ///< 0 IMU, 1 wheel, 2 frame
  void feedImu(const ImuSample& s) override { add(s.t, 0); }
  void feedWheel(const WheelOdometrySample& w) override { add(w.t, 1); }
  void feedRgbd(const RgbdFrame& f) override { add(f.t, 2); }
  void add(double t, int k) {
    stamps.push_back(t);
    kinds.push_back(k);
  }
};

TEST(SimulatedSequence, WheeledProfilesCarryWheelOdometryInTheStream) {
  SimOptions o;
  o.profile.kind = ProfileKind::WheeledCircle;
  o.profile.duration_s = 9.0;
  o.fps = 2.0;
  o.wheel.mode = "auto";
  const SimulatedSequence seq(o);
  ASSERT_TRUE(seq.hasWheels());
  EXPECT_EQ(seq.wheelSamples().size(), 451u);
  KindRecorder rec;
  seq.pump(rec);
  EXPECT_EQ(std::count(rec.kinds.begin(), rec.kinds.end(), 1), 451);
  for (std::size_t i = 1; i < rec.stamps.size(); ++i) {
    ASSERT_LE(rec.stamps[i - 1], rec.stamps[i]) << i;
    if (rec.stamps[i - 1] == rec.stamps[i]) EXPECT_LT(rec.kinds[i - 1], rec.kinds[i]) << i;
  }
  // The odometry's distance is the ground truth's path length (to a few encoder ticks).
  double path = 0.0, odo = 0.0;
  const auto& w = seq.wheelSamples();
  for (std::size_t k = 1; k < w.size(); ++k) {
    path += (seq.groundTruth(w[k].t).T_world_body.translation() -
             seq.groundTruth(w[k - 1].t).T_world_body.translation())
                .norm();
    odo += std::hypot(w[k].x_m - w[k - 1].x_m, w[k].y_m - w[k - 1].y_m);
  }
  EXPECT_GT(path, 1.0);
  EXPECT_NEAR(odo, path, 0.01 * path);

  o.profile.kind = ProfileKind::Handheld;
  o.profile.duration_s = 0.0;
  EXPECT_FALSE(SimulatedSequence(o).hasWheels());  // auto: never hand-held
  o.profile.kind = ProfileKind::WheeledCircle;
  o.profile.duration_s = 9.0;
  o.wheel.mode = "off";
  EXPECT_FALSE(SimulatedSequence(o).hasWheels());
}

}  // namespace
}  // namespace rgbdi::sim
