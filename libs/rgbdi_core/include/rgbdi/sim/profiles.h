// The simulator's motion profiles (issue 3): analytic body trajectories of a hand-held camera, a
// wheeled robot and a tracked robot, plus the layout of ramps and steps the scene must contain
// for them. Every profile starts at rest for rest_start_s, accelerates smoothly, and ends at
// rest. The motion does not depend on the random seed (only noise and textures do), so several
// seeds give several noise realisations of one motion.
//
// Variants (issue 12): variant 0 is the profile's path; variants 1 and 2 are further sequences of
// the same world (same room, ramps, furniture and, for a seed, textures) along the same closed
// path, started at rest from another point of it: variant 1 drives it in the opposite direction,
// variant 2 in the same direction. The world of a profile is the scene of its variant-0 path at
// the default timing (at least one lap); a variant-0 run of at least one lap has exactly this
// scene. Poses stay in the world frame.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <memory>
#include <string>
#include <vector>

#include "rgbdi/common/ini_reader.h"
#include "rgbdi/sim/trajectory.h"

namespace rgbdi::sim {

/// Recorded: the motion of a real recording (recorded_motion.h); not one of profileNames(), not
/// made by makeMotionProfile.
enum class ProfileKind { Handheld, WheeledCircle, WheeledSlopes, TrackedSlopes, Recorded };
enum class SpeedPreset { Slow, Normal, Fast };

/// Number of path variants of every profile (0 .. kProfileVariants - 1).
inline constexpr int kProfileVariants = 3;

/// "handheld", "wheeled_circle", "wheeled_slopes", "tracked_slopes" (the synthesised profiles).
const std::vector<std::string>& profileNames();
/// A profile name, or "recorded".
std::string toString(ProfileKind kind);
/// One of profileNames(); throws std::invalid_argument listing them.
ProfileKind parseProfileKind(const std::string& name);
std::string toString(SpeedPreset speed);
/// "slow", "normal", "fast"; throws std::invalid_argument otherwise.
SpeedPreset parseSpeedPreset(const std::string& name);

/// Timing and vibration options ([sim] section).
struct ProfileOptions {
  ProfileKind kind = ProfileKind::WheeledCircle;
  /// slow|normal|fast. wheeled_slopes: the paper's runs (31 m in 148 s, 32 m in 74 s, 48 m in
  /// 99 s with intermittent high-speed phases); other profiles: 0.6x / 1x / 1.4x cruise speed.
  SpeedPreset speed = SpeedPreset::Normal;
  double duration_s = 0.0;    ///< [s] total duration; 0 = the profile's default
  double speed_m_s = 0.0;     ///< [m/s] cruise speed; 0 = the profile's / preset's default
  double rest_start_s = 2.0;  ///< [s] at rest before moving
  double rest_end_s = 1.0;    ///< [s] at rest after stopping
  /// Track/wheel vibration (real motion, 10-30 Hz tones, scaled by speed / cruise speed):
  /// RMS of the accelerometer and gyro vibration while cruising.
  double wheeled_vibration_acc_rms = 0.3;   ///< [m/s^2]
  double wheeled_vibration_gyr_rms = 0.01;  ///< [rad/s]
  double tracked_vibration_acc_rms = 2.0;   ///< [m/s^2]
  double tracked_vibration_gyr_rms = 0.08;  ///< [rad/s]
  double tracked_jitter_deg = 0.5;      ///< [deg] RMS of the 1-6 Hz roll/pitch jitter (yaw half)
  double vibration_band_min_hz = 10.0;  ///< [Hz]
  double vibration_band_max_hz = 30.0;  ///< [Hz]
  /// [m] camera height above the floor for the wheeled profiles (SPEC: 0.3 m) and the tracked
  /// robot; the body height follows from T_body_cam.
  double wheeled_camera_height_m = 0.3;
  double tracked_camera_height_m = 0.35;
  double handheld_camera_height_m = 1.35;
  /// [index] 0 = the profile's path; 1 = the same closed path from another start, driven the
  /// other way round; 2 = the same path from a third start, same direction (see file comment).
  int variant = 0;

  /// Reads the keys of [sim] listed above (kind is not read: it comes from the command line).
  static ProfileOptions load(IniReader& ini);
};

/// A ramp in the scene: symmetric up-down ramps rise from `from` to the midpoint and descend to
/// `to`; one-way ramps rise from `from` to `to` (to a platform).
struct RampLayout {
  Eigen::Vector2d from = Eigen::Vector2d::Zero(), to = Eigen::Vector2d::Zero();
  double width = 0.0, height = 0.0;  ///< [m]
  bool symmetric = true;
};

/// A raised platform (box on the floor) the robot drives on and drops off.
struct PlatformLayout {
  Eigen::Vector2d center = Eigen::Vector2d::Zero();
  Eigen::Vector2d size = Eigen::Vector2d::Zero();  ///< along / across the direction of travel [m]
  double yaw = 0.0;                                ///< [rad] direction of travel
  double height = 0.0;                             ///< [m]
};

/// Geometry the scene must match.
/// For variants >= 1 this is the layout of the world (variant 0 at the default timing): the
/// variant's own path runs along the same corridor.
struct ProfileLayout {
  Eigen::Vector3d room_min = Eigen::Vector3d::Zero(), room_max = Eigen::Vector3d::Zero();
  std::vector<RampLayout> ramps;
  std::vector<PlatformLayout> platforms;
  /// Ground path (x, y) every ~0.1 m over the whole run, for keeping objects off the path.
  std::vector<Eigen::Vector2d> path_xy;
  /// [m] free corridor half-width around the path (robot or walker).
  double path_clearance_m = 0.45;
};

struct MotionProfile {
  ProfileKind kind = ProfileKind::WheeledCircle;
  std::shared_ptr<const BodyTrajectory> trajectory;
  double cruise_speed_m_s = 0.0;  ///< nominal cruising speed
  double path_length_m = 0.0;     ///< horizontal distance travelled over the whole run
  double lap_length_m = 0.0;      ///< one lap of the (closed) path
  double moving_start_s = 0.0;    ///< [s] the body starts moving here
  double moving_end_s = 0.0;      ///< [s] and is at rest again from here
  double cruise_start_s = 0.0;    ///< [s] cruise speed reached
  double cruise_end_s = 0.0;      ///< [s] deceleration starts
  ProfileLayout layout;
};

/// The options whose variant-0 path defines the world of `options` (kind and speed preset kept,
/// default timing: at least one lap).
ProfileOptions worldOptions(const ProfileOptions& options);

/// Builds a profile. T_body_cam places the camera at the requested height above the floor.
/// Throws std::invalid_argument when the duration is too short for the profile or the variant
/// is not in [0, kProfileVariants).
MotionProfile makeMotionProfile(const ProfileOptions& options, const Eigen::Isometry3d& T_body_cam);

}  // namespace rgbdi::sim
