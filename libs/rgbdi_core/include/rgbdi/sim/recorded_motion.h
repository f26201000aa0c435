// The body motion of a recording (issue 33, hybrid sequences): the recorded ground truth as a
// smooth trajectory the renderer can sample at any frame time, and the layout of the world built
// around it (room, furniture along the path, a free corridor around every position).
//
// Interpolation between ground-truth samples i and i+1 (h = t_{i+1} - t_i, s = (t - t_i) / h):
// - position: the cubic Hermite spline through p_i, p_{i+1} with the end velocities v_i,
//   v_{i+1}: the recorded velocities where the file gives them, otherwise the central difference
//   of the neighbouring positions (one-sided at the ends). It passes through every sample, has a
//   continuous velocity, and reproduces any motion whose position is a cubic of time exactly
//   (constant velocity, constant acceleration) when the velocities are exact.
// - rotation: slerp, R(t) = R_i exp(s log(R_i^T R_{i+1})) on the shorter arc: exact at every
//   sample, continuous, constant body rate within a segment (a constant-rate rotation is
//   reproduced exactly). The rate jumps at samples, which only the ground truth's omega sees:
//   the IMU is the recorded one, never synthesised from this trajectory.
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

#include "rgbdi/common/ini_reader.h"
#include "rgbdi/sim/profiles.h"
#include "rgbdi/sim/recording.h"
#include "rgbdi/sim/trajectory.h"

namespace rgbdi::sim {

/// The recorded ground truth as a BodyTrajectory; time 0 is the first sample's stamp.
class RecordedTrajectory : public BodyTrajectory {
 public:
  /// At least 2 samples with strictly increasing stamps (std::invalid_argument otherwise).
  explicit RecordedTrajectory(const std::vector<RecordedPose>& samples);

  double duration() const override { return t_.back(); }
  /// [s] recording-clock stamp of trajectory time 0.
  double origin() const { return origin_; }
  /// The velocities used at the samples (recorded or central differences).
  const std::vector<Eigen::Vector3d>& sampleVelocities() const { return v_; }

 protected:
  MotionJet jetAt(double t) const override;

 private:
  /// Slerp of segment i as a rotation chain: R_i A, Rz(theta s), A^T with A e_z = the axis.
  struct SegmentRotation {
    Eigen::Vector3d start_zyx = Eigen::Vector3d::Zero();  ///< Euler z-y-x of R_i A
    Eigen::Vector3d back_zyx = Eigen::Vector3d::Zero();   ///< Euler z-y-x of A^T
    double angle = 0.0;                                   ///< [rad] theta of the segment
  };

  double origin_ = 0.0;
  std::vector<double> t_;  ///< [s] since origin_
  std::vector<Eigen::Vector3d> p_, v_;
  std::vector<SegmentRotation> rot_;
};

/// How the world around a recorded trajectory is built ([sim] recorded_*).
struct RecordedWorldOptions {
  double room_margin_m = 1.5;     ///< [m] room walls this far outside the path's bounding box
  double floor_below_m = 1.0;     ///< [m] floor this far below the lowest body position
  double ceiling_above_m = 1.0;   ///< [m] ceiling this far above the highest body position
  double path_clearance_m = 0.6;  ///< [m] no furniture within this horizontal distance of the path
  double max_gap_s = 0.2;         ///< [s] longest ground-truth gap interpolated over

  /// Reads [sim] recorded_room_margin_m, recorded_floor_below_m, recorded_ceiling_above_m,
  /// recorded_path_clearance_m, recorded_max_gap_s.
  static RecordedWorldOptions load(IniReader& ini);
};

/// The part of a recording a sequence replays.
struct RecordedMotion {
  /// kind Recorded; trajectory a RecordedTrajectory; layout around its path (no ramps).
  MotionProfile profile;
  std::shared_ptr<const RecordedTrajectory> trajectory;
  /// Ground-truth samples used: [first_pose, last_pose] of Recording::ground_truth. The first is
  /// the first sample with IMU samples before and after it; the last the last such sample (or
  /// the last within duration_s of the first).
  std::size_t first_pose = 0, last_pose = 0;
  /// IMU samples replayed: [0, imu_count) of Recording::imu (those up to the last pose).
  std::size_t imu_count = 0;
};

/// Cuts the recording to the span its IMU covers (and to duration_s when positive), builds the
/// trajectory and the world layout. Throws RecordingError when no two ground-truth samples lie
/// inside the IMU's span or a ground-truth gap exceeds options.max_gap_s.
RecordedMotion makeRecordedMotion(const Recording& recording, const RecordedWorldOptions& options,
                                  double duration_s = 0.0);

}  // namespace rgbdi::sim
