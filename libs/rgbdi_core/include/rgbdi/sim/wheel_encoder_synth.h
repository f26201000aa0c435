// Simulated wheel encoders and the robot's own dead reckoning from them, as an MRPT
// CObservationOdometry stream reports it (WheelOdometrySample).
//
// Model. The wheel frame is the body frame (T_body_wheel = identity, x forward, z up). At IMU-clock
// time t the true motion of the wheel frame gives the forward speed v = (R_world_body^T v_world).x
// and the yaw rate w = omega_body.z. A differential drive with true track B (nominal track times
// 1 + track_error) turns its wheels at ground speeds v_l,r = v -/+ w B_eff / 2, where B_eff = B for
// wheels and, for skid steering (the tracked profile), B (1 + s): the tracks slip sideways in
// every turn, so they must differ in speed by more than the geometry says; s = skid_turn_slip
// (1 + skid_slope_gain |pitch|), much more on slopes. Each wheel turns at v_side / r_side, r_side
// the nominal radius times 1 + radius_error_(left|right), and its encoder counts floor(angle /
// 2 pi * ticks_per_rev). The readings come at rate_hz, stamped t - time_offset_s, with the
// cumulative ticks, the pose the robot integrates from the tick increments with its NOMINAL
// radius and track (midpoint rule), and the velocities of the last increment. Events make the
// encoders disagree with the motion for a while (a fault to be detected):
//   spin    the left wheel spins without traction: its speed + event_speed_m_s
//   stuck   the left wheel is blocked and dragged: its encoder stands
//   lifted  the robot is off the ground: both wheels run on at the speed they had when it was
//           lifted (at least event_speed_m_s)
//   pushed  the robot is moved with its wheels locked: both encoders stand
// Everything is a pure function of the options and the trajectory (no random numbers): the
// encoder quantisation is the noise.
#pragma once

#include <string>
#include <vector>

#include "rgbdi/common/ini_reader.h"
#include "rgbdi/common/wheel_odometry.h"
#include "rgbdi/sim/trajectory.h"

namespace rgbdi::sim {

/// One event window of the encoders (see above).
struct WheelEvent {
  enum class Kind { Spin, Stuck, Lifted, Pushed };
  Kind kind = Kind::Spin;
  double start_s = 0.0;     ///< [s] since the first IMU sample
  double duration_s = 0.0;  ///< [s]
  bool covers(double t) const { return t >= start_s && t < start_s + duration_s; }
};
/// "spin", "stuck", "lifted", "pushed".
std::string toString(WheelEvent::Kind kind);

struct WheelEncoderOptions {
  /// [sim] wheel_encoders: "off", "on", or "auto" (on for the wheeled and tracked profiles, off
  /// for the hand-held one).
  std::string mode = "off";
  double rate_hz = 50.0;            ///< [Hz] readings per second
  double radius_m = 0.05;           ///< [m] nominal wheel radius (what the robot assumes)
  double track_m = 0.30;            ///< [m] nominal track width (wheel to wheel)
  double radius_error_left = 0.0;   ///< [unitless] true radius = nominal * (1 + this)
  double radius_error_right = 0.0;  ///< [unitless]
  double track_error = 0.0;         ///< [unitless] true track = nominal * (1 + this)
  int ticks_per_rev = 2048;         ///< [ticks] encoder resolution
  double time_offset_s = 0.0;       ///< [s] stamp = IMU-clock time - this
  bool skid_steering = false;       ///< not an INI key: set for the tracked profile
  double skid_turn_slip = 0.3;      ///< [unitless] s on flat ground (skid steering only)
  double skid_slope_gain = 3.0;     ///< [1/rad] s grows by this per radian of pitch
  double event_speed_m_s = 0.5;     ///< [m/s] spin: extra wheel speed; lifted: least speed
  std::vector<WheelEvent> events;   ///< [sim] wheel_events = KIND:START_S:DURATION_S,...

  /// Reads [sim] wheel_encoders, wheel_rate_hz, wheel_radius_m, wheel_track_m,
  /// wheel_radius_error_left, wheel_radius_error_right, wheel_track_error, wheel_ticks_per_rev,
  /// wheel_time_offset_s, wheel_skid_turn_slip, wheel_skid_slope_gain, wheel_event_speed_m_s,
  /// wheel_events.
  static WheelEncoderOptions load(IniReader& ini);
  /// Parses "KIND:START_S:DURATION_S[,...]" (empty or "none": no event); throws
  /// std::invalid_argument naming the bad item.
  static std::vector<WheelEvent> parseEvents(const std::string& text);
  /// The text parseEvents reads back.
  static std::string eventsText(const std::vector<WheelEvent>& events);
};

/// The readings of a whole sequence, computed once.
class WheelEncoderSynth {
 public:
  /// `start_time_s`: IMU-clock stamp of trajectory time 0; readings cover [0, duration].
  WheelEncoderSynth(const WheelEncoderOptions& options, const BodyTrajectory& trajectory,
                    double start_time_s);

  const std::vector<WheelOdometrySample>& samples() const { return samples_; }
  /// [s] trajectory time (since the first IMU sample) of reading k, before the time offset.
  double sampleTime(std::size_t k) const { return static_cast<double>(k) / options_.rate_hz; }
  /// The true ground speeds [m/s] of the left and right wheel at trajectory time t, with slip
  /// but without events.
  void wheelSpeeds(const BodyTrajectory& trajectory, double t, double& left, double& right) const;

 private:
  WheelEncoderOptions options_;
  std::vector<WheelOdometrySample> samples_;
};

}  // namespace rgbdi::sim
