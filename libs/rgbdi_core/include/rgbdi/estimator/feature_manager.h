// Feature tracks inside the sliding window: observations per window slot, the inverse depth in the
// track's reference (first) frame, and where that depth came from.
//
// A track's observations are in consecutive window slots starting at `start_slot` (KLT tracks are
// continuous; when a slot is removed from the window its observation is removed with it).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <map>
#include <vector>

#include "rgbdi/estimator/reprojection_factor.h"

namespace rgbdi::estimator {

struct TrackObservation {
  /// Normalised point, velocity, td at stamping. With a rolling shutter meas.xn is the point
  /// moved to the frame's reference time: xn_row - row_time_s * meas.velocity.
  FeatureMeasurement meas;
  Eigen::Vector2d uv;       ///< distorted pixel (for diagnostics)
  double depth_m = 0.0;     ///< sensor depth at this observation; 0 = none
  double row_time_s = 0.0;  ///< [s] exposure of its image row minus the frame's stamp
  Eigen::Vector2d xn_row = Eigen::Vector2d::Zero();  ///< normalised point as observed

  /// Moves meas.xn to the frame's reference time along meas.velocity (first-order motion).
  void compensateRollingShutter() {
    if (row_time_s != 0.0) meas.xn.head<2>() = xn_row - row_time_s * meas.velocity;
  }
};

enum class DepthSource { kNone, kVerified, kTriangulated };

struct FeatureTrack {
  std::uint64_t id = 0;
  int start_slot = 0;
  std::vector<TrackObservation> obs;
  /// Optimisation variable: inverse depth [1/m] in the reference frame (slot start_slot). Lives in
  /// a std::map node, so its address is stable while the track exists (Ceres parameter block).
  double inv_depth = 0.0;
  DepthSource source = DepthSource::kNone;
  int verified_observations = 0;    ///< observations whose depth agreed with another one
  double verified_inv_depth = 0.0;  ///< [1/m] inverse of the verified mean depth
  bool outlier = false;

  int endSlot() const { return start_slot + static_cast<int>(obs.size()) - 1; }
  bool hasDepth() const { return source != DepthSource::kNone && inv_depth > 0.0; }
  /// Depth passed verification (paper Algorithm 1); held constant or used as a prior.
  bool depthVerified() const { return source == DepthSource::kVerified; }
};

/// Pose of each window slot (T_world_body), used for verification and triangulation.
using SlotPoses = std::vector<Eigen::Isometry3d>;

struct DepthCheckOptions {
  double tolerance_norm = 10.0 / 460.0;  ///< agreement on the normalised plane
  double min_depth_m = 0.1;
  double max_depth_m = 3.0;
  double min_triangulation_depth_m = 0.1;
  /// true: a verified depth overwrites the estimate every frame (it is held constant);
  /// false: it only seeds the estimate when the feature first becomes verified.
  bool hold_constant = true;
};

class FeatureManager {
 public:
  /// What links a newly added frame to the window (the keyframe criterion of slot-1).
  struct FrameLinks {
    double parallax = 0.0;  ///< [normalised units] mean parallax between slots slot-2 and slot-1
    int n_parallax = 0;     ///< features seen in both slots slot-2 and slot-1 (parallax's support)
    int n_tracked = 0;      ///< features of the new frame that were already tracked
  };
  /// Adds the features of the frame in `slot` and says how it links to the window. With
  /// R_c2_c1 (camera of slot-1 -> camera of slot-2), the parallax is measured after rotating the
  /// slot-1 observations into the slot-2 camera: what the rotation alone explains is left out.
  FrameLinks addFrame(int slot,
                      const std::vector<std::pair<std::uint64_t, TrackObservation>>& features,
                      const Eigen::Matrix3d* R_c2_c1 = nullptr);

  /// Paper Algorithm 1 for every feature with >= 2 observations (re-run each frame so the mean
  /// uses every observation in the window):
  /// each sensor depth is projected into every other observation; agreeing pairs contribute the
  /// depth transformed into the reference frame; the mean is accepted if in range.
  /// Features without a verified depth are triangulated (if they have >= 2 observations).
  void updateDepths(const SlotPoses& T_world_body, const Eigen::Isometry3d& T_body_cam,
                    const DepthCheckOptions& opt);

  /// Removes the oldest slot (0): observations in it are dropped; features whose reference frame
  /// was slot 0 get their depth moved into the new reference frame and lose "verified" (they are
  /// re-verified for the new reference frame). All slots shift down by one.
  void removeOldest(const SlotPoses& T_world_body_before_shift,
                    const Eigen::Isometry3d& T_body_cam);
  /// Removes slot `slot` (the second newest, not a keyframe): its observations are dropped, later
  /// slots shift down by one.
  void removeSlot(int slot);
  /// Forgets features marked outlier and features with depth not positive.
  void removeOutliers();
  void clear() { tracks_.clear(); }

  std::map<std::uint64_t, FeatureTrack>& tracks() { return tracks_; }
  const std::map<std::uint64_t, FeatureTrack>& tracks() const { return tracks_; }
  int countUsable(int newest_slot) const;

  /// True when the feature should enter the optimisation (>= 2 observations, has depth, starts
  /// early enough for its depth to be constrained).
  static bool usable(const FeatureTrack& f, int newest_slot);

 private:
  std::map<std::uint64_t, FeatureTrack> tracks_;
};

}  // namespace rgbdi::estimator
