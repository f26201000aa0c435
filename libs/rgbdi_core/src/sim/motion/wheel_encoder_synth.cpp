#include "rgbdi/sim/wheel_encoder_synth.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace rgbdi::sim {
namespace {

/// Integration substeps of the wheel angles per reading: fine enough that the angle error is far
/// below one encoder tick at the speeds of the profiles.
constexpr int kSubsteps = 20;

WheelEvent::Kind eventKind(const std::string& name, const std::string& item) {
  if (name == "spin") return WheelEvent::Kind::Spin;
  if (name == "stuck") return WheelEvent::Kind::Stuck;
  if (name == "lifted") return WheelEvent::Kind::Lifted;
  if (name == "pushed") return WheelEvent::Kind::Pushed;
  throw std::invalid_argument("wheel event '" + item + "': kind '" + name +
                              "' is none of spin, stuck, lifted, pushed");
}

}  // namespace

std::string toString(WheelEvent::Kind kind) {
  switch (kind) {
    case WheelEvent::Kind::Spin:
      return "spin";
    case WheelEvent::Kind::Stuck:
      return "stuck";
    case WheelEvent::Kind::Lifted:
      return "lifted";
    case WheelEvent::Kind::Pushed:
      return "pushed";
  }
  return "?";
}

std::vector<WheelEvent> WheelEncoderOptions::parseEvents(const std::string& text) {
  std::vector<WheelEvent> events;
  if (text.empty() || text == "none") return events;
  std::stringstream list(text);
  std::string item;
  while (std::getline(list, item, ',')) {
    const auto a = item.find(':');
    const auto b = a == std::string::npos ? a : item.find(':', a + 1);
    if (b == std::string::npos)
      throw std::invalid_argument("wheel event '" + item + "': expected KIND:START_S:DURATION_S");
    WheelEvent e;
    e.kind = eventKind(item.substr(0, a), item);
    try {
      std::size_t used1 = 0, used2 = 0;
      const std::string s1 = item.substr(a + 1, b - a - 1), s2 = item.substr(b + 1);
      e.start_s = std::stod(s1, &used1);
      e.duration_s = std::stod(s2, &used2);
      if (used1 != s1.size() || used2 != s2.size()) throw std::invalid_argument("trailing text");
    } catch (const std::exception&) {
      throw std::invalid_argument("wheel event '" + item +
                                  "': START_S and DURATION_S must be numbers");
    }
    if (!(e.start_s >= 0.0) || !(e.duration_s > 0.0) || !std::isfinite(e.start_s + e.duration_s))
      throw std::invalid_argument("wheel event '" + item +
                                  "': START_S must be >= 0 and DURATION_S > 0");
    events.push_back(e);
  }
  return events;
}

std::string WheelEncoderOptions::eventsText(const std::vector<WheelEvent>& events) {
  if (events.empty()) return "none";
  std::ostringstream os;
  os.precision(17);
  for (std::size_t i = 0; i < events.size(); ++i)
    os << (i ? "," : "") << toString(events[i].kind) << ":" << events[i].start_s << ":"
       << events[i].duration_s;
  return os.str();
}

WheelEncoderOptions WheelEncoderOptions::load(IniReader& ini) {
  WheelEncoderOptions o;
  const std::string s = "sim";
  o.mode = ini.getEnum(s, "wheel_encoders", o.mode, {"off", "on", "auto"});
  o.rate_hz = ini.getDouble(s, "wheel_rate_hz", o.rate_hz, 1.0, 1000.0);
  o.radius_m = ini.getDouble(s, "wheel_radius_m", o.radius_m, 0.005, 2.0);
  o.track_m = ini.getDouble(s, "wheel_track_m", o.track_m, 0.02, 10.0);
  o.radius_error_left = ini.getDouble(s, "wheel_radius_error_left", o.radius_error_left, -0.5, 0.5);
  o.radius_error_right =
      ini.getDouble(s, "wheel_radius_error_right", o.radius_error_right, -0.5, 0.5);
  o.track_error = ini.getDouble(s, "wheel_track_error", o.track_error, -0.5, 0.5);
  o.ticks_per_rev = ini.getInt(s, "wheel_ticks_per_rev", o.ticks_per_rev, 1, 1000000);
  o.time_offset_s = ini.getDouble(s, "wheel_time_offset_s", o.time_offset_s, -0.5, 0.5);
  o.skid_turn_slip = ini.getDouble(s, "wheel_skid_turn_slip", o.skid_turn_slip, 0.0, 10.0);
  o.skid_slope_gain = ini.getDouble(s, "wheel_skid_slope_gain", o.skid_slope_gain, 0.0, 100.0);
  o.event_speed_m_s = ini.getDouble(s, "wheel_event_speed_m_s", o.event_speed_m_s, 0.0, 10.0);
  const std::string events = ini.getString(s, "wheel_events", "none");
  try {
    o.events = parseEvents(events);
  } catch (const std::invalid_argument& e) {
    ini.fail(s, "wheel_events", e.what());
  }
  return o;
}

void WheelEncoderSynth::wheelSpeeds(const BodyTrajectory& trajectory, double t, double& left,
                                    double& right) const {
  const KinematicState st = trajectory.state(t);
  const Eigen::Matrix3d R = st.T_world_body.rotation();
  const double v = (R.transpose() * st.v_world).x();
  const double w = st.omega_body.z();
  double track = options_.track_m * (1.0 + options_.track_error);
  if (options_.skid_steering) {
    const double pitch = std::asin(std::clamp(R(2, 0), -1.0, 1.0));
    track *= 1.0 + options_.skid_turn_slip * (1.0 + options_.skid_slope_gain * std::abs(pitch));
  }
  left = v - 0.5 * w * track;
  right = v + 0.5 * w * track;
}

WheelEncoderSynth::WheelEncoderSynth(const WheelEncoderOptions& options,
                                     const BodyTrajectory& trajectory, double start_time_s)
    : options_(options) {
  if (!(options.rate_hz > 0.0) || !(options.radius_m > 0.0) || !(options.track_m > 0.0) ||
      options.ticks_per_rev < 1)
    throw std::invalid_argument(
        "WheelEncoderSynth: rate, radius, track and ticks per revolution must be positive");
  const double r_left = options.radius_m * (1.0 + options.radius_error_left);
  const double r_right = options.radius_m * (1.0 + options.radius_error_right);
  const double metres_per_tick = 2.0 * M_PI * options.radius_m / options.ticks_per_rev;
  const double ticks_per_rad = options.ticks_per_rev / (2.0 * M_PI);

  // Speeds of the wheels when each "lifted" event starts (they run on at them).
  std::vector<double> lifted_speed(options.events.size(), 0.0);
  for (std::size_t e = 0; e < options.events.size(); ++e) {
    double l = 0.0, r = 0.0;
    wheelSpeeds(trajectory, options.events[e].start_s, l, r);
    lifted_speed[e] = std::max(0.5 * (l + r), options.event_speed_m_s);
  }
  const auto encoderSpeeds = [&](double t, double& l, double& r) {
    wheelSpeeds(trajectory, t, l, r);
    for (std::size_t e = 0; e < options.events.size(); ++e) {
      const WheelEvent& ev = options.events[e];
      if (!ev.covers(t)) continue;
      switch (ev.kind) {
        case WheelEvent::Kind::Spin:
          l += options.event_speed_m_s;
          break;
        case WheelEvent::Kind::Stuck:
          l = 0.0;
          break;
        case WheelEvent::Kind::Lifted:
          l = r = lifted_speed[e];
          break;
        case WheelEvent::Kind::Pushed:
          l = r = 0.0;
          break;
      }
    }
  };

  const double duration = trajectory.duration();
  const std::size_t n = static_cast<std::size_t>(std::floor(duration * options.rate_hz)) + 1;
  samples_.reserve(n);
  double angle_left = 0.0, angle_right = 0.0;  // [rad] wheel angles
  double x = 0.0, y = 0.0, yaw = 0.0;          // the robot's dead reckoning
  std::int32_t prev_left = 0, prev_right = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const double t = sampleTime(k);
    if (k > 0) {
      const double t0 = sampleTime(k - 1), h = (t - t0) / kSubsteps;
      for (int j = 0; j < kSubsteps; ++j) {
        double l = 0.0, r = 0.0;
        encoderSpeeds(t0 + (j + 0.5) * h, l, r);
        angle_left += l / r_left * h;
        angle_right += r / r_right * h;
      }
    }
    WheelOdometrySample s;
    s.t = start_time_s + t - options.time_offset_s;
    s.has_encoders = true;
    s.ticks_left = static_cast<std::int32_t>(std::floor(angle_left * ticks_per_rad));
    s.ticks_right = static_cast<std::int32_t>(std::floor(angle_right * ticks_per_rad));
    const double dl = (s.ticks_left - prev_left) * metres_per_tick;
    const double dr = (s.ticks_right - prev_right) * metres_per_tick;
    const double d = 0.5 * (dl + dr), dyaw = (dr - dl) / options.track_m;
    x += d * std::cos(yaw + 0.5 * dyaw);
    y += d * std::sin(yaw + 0.5 * dyaw);
    yaw += dyaw;
    s.x_m = x;
    s.y_m = y;
    s.yaw_rad = std::remainder(yaw, 2.0 * M_PI);
    s.has_velocities = true;
    if (k > 0) {
      s.v_forward_m_s = d * options.rate_hz;
      s.yaw_rate_rad_s = dyaw * options.rate_hz;
    }
    prev_left = s.ticks_left;
    prev_right = s.ticks_right;
    samples_.push_back(s);
  }
}

}  // namespace rgbdi::sim
