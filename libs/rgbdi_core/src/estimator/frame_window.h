// The frames of the sliding window and the feature tracks observed in them (window
// bookkeeping): a frame joins with its IMU pre-integration from the previous one, which also
// decides whether the frame before it is a keyframe; frames leave as the oldest (marginalised)
// or as the second newest (no keyframe: its IMU interval is merged into the next one).
//
// The slots' state arrays are parameter blocks of the solver and of the marginalisation prior:
// the slots are reserved once and never reallocated (removing a slot moves the later ones down,
// and the prior's block addresses are remapped by the caller).
#pragma once

#include <Eigen/Geometry>
#include <cstddef>
#include <vector>

#include "estimator/window_slot.h"
#include "rgbdi/common/sensor_options.h"
#include "rgbdi/estimator/estimator_options.h"
#include "rgbdi/estimator/feature_manager.h"
#include "rgbdi/estimator/rolling_shutter_compensation.h"
#include "rgbdi/estimator/sliding_window_estimator.h"
#include "rgbdi/frontend/feature_frame.h"

namespace rgbdi::imu {
class ImuBuffer;
}

namespace rgbdi::estimator {

class FrameWindow {
 public:
  FrameWindow(const EstimatorOptions& opt, const ImuOptions& imu);

  /// Appends `frame` at IMU-clock time `t` (its observations stamped with time offset `td`),
  /// pre-integrated from the previous slot over the samples of `imu`; the states start as the
  /// previous slot's, or its IMU prediction with `predict_from_previous`. `bridged`: blind frames
  /// lie between the previous slot and this one. T_body_cam: for the keyframe parallax without
  /// rotation. Returns the [ms] CPU time of the pre-integration (0 for the first slot).
  double add(const frontend::FeatureFrame& frame, double t, double td, const imu::ImuBuffer& imu,
             bool predict_from_previous, bool bridged, const Eigen::Isometry3d& T_body_cam);
  /// The second-newest slot (decided by the newest add) shows a view the window needs.
  bool newestButOneIsKeyframe() const { return newest_but_one_keyframe_; }
  /// Removes the second-newest slot, merging its IMU interval into the newest one's.
  void dropSecondNewest();
  /// Removes the oldest slot; its tracks' depths move to their next observation (T_body_cam).
  void removeOldest(const Eigen::Isometry3d& T_body_cam);
  /// Keeps only the newest slot, as the first of a new chain (a moving start whose PnP failed).
  void restartFromNewest(double td);
  void clear();
  /// The row timing of the images to come (rolling shutter; default global). With the readout
  /// estimated, set again with each new estimate: observations are moved to the stamp with the
  /// estimate of their entry time (FeatureMeasurement::readout_at_stamp_s).
  void setRollingShutter(const RollingShutter& rs) { rolling_shutter_ = rs; }
  const RollingShutter& rollingShutter() const { return rolling_shutter_; }

  /// Marks and removes the usable tracks whose mean reprojection error over their observations
  /// exceeds `threshold_norm` (normalised-plane units).
  void rejectOutliers(double threshold_norm, const Eigen::Isometry3d& T_body_cam);

  SlotPoses poses() const;
  /// Every slot as a keyframe state of odometry segment `segment`.
  /// With `imu`, each state's rate (gyro minus bias at its time) too.
  std::vector<KeyframeState> keyframeStates(int segment, const imu::ImuBuffer* imu = nullptr) const;

  std::size_t size() const { return slots_.size(); }
  bool empty() const { return slots_.empty(); }
  WindowSlot& operator[](std::size_t k) { return slots_[k]; }
  const WindowSlot& operator[](std::size_t k) const { return slots_[k]; }
  WindowSlot& front() { return slots_.front(); }
  const WindowSlot& front() const { return slots_.front(); }
  WindowSlot& back() { return slots_.back(); }
  const WindowSlot& back() const { return slots_.back(); }
  std::vector<WindowSlot>::iterator begin() { return slots_.begin(); }
  std::vector<WindowSlot>::iterator end() { return slots_.end(); }
  std::vector<WindowSlot>::const_iterator begin() const { return slots_.begin(); }
  std::vector<WindowSlot>::const_iterator end() const { return slots_.end(); }
  FeatureManager& features() { return features_; }
  const FeatureManager& features() const { return features_; }

 private:
  /// The frame's features as track observations (stamped with time offset `td`), moved to the
  /// frame's reference time along their tracked velocity. `at_reference_time`: the features'
  /// xn were already moved (a slot's raw_features).
  std::vector<std::pair<std::uint64_t, TrackObservation>> toObservations(
      const std::vector<frontend::FeatureObservation>& features, double td,
      bool at_reference_time) const;

  EstimatorOptions opt_;
  ImuOptions imu_opt_;
  RollingShutter rolling_shutter_;  ///< of the colour images; global by default
  std::vector<WindowSlot> slots_;   ///< capacity window_size + 2, never reallocated
  FeatureManager features_;
  bool newest_but_one_keyframe_ = true;
};

}  // namespace rgbdi::estimator
