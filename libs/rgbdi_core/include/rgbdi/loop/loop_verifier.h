// Geometric verification of a loop candidate with metric depth: descriptor matching, PnP RANSAC
// of the query's keypoints against the candidate's depth-backed points, a 3-D/3-D agreement check
// (both keyframes have depth) with a refinement on the agreeing pairs, then gates on gravity
// (roll/pitch), relative yaw and translation, and on the drift the odometry can have accumulated
// since the candidate; joins of unrelated parts also pass a free-space check of the two
// keyframes' depth grids. Every rejection carries its reason, so they can be counted per reason.
#pragma once

#include <Eigen/Geometry>
#include <array>
#include <cstdint>
#include <string>

#include "rgbdi/common/camera.h"
#include "rgbdi/common/ini_reader.h"
#include "rgbdi/loop/loop_keyframe.h"

namespace rgbdi::loop {

/// The [loop] verify_* keys. Defaults equal share/config.ini.
struct LoopVerificationOptions {
  // --- descriptor matching ---
  /// [unitless] Lowe ratio: a match needs best distance < ratio * second-best distance
  double match_ratio = 0.8;
  int max_hamming_bits = 64;  ///< [bits] largest Hamming distance of a match
  bool cross_check = true;    ///< [bool] keep only mutual nearest neighbours
  /// [count] matches whose candidate keypoint has a 3-D point (PnP correspondences) needed
  int min_matches = 30;

  // --- PnP RANSAC ---
  double pnp_threshold_px = 3.0;  ///< [px] inlier reprojection error (undistorted pixels)
  int pnp_iterations = 300;       ///< [count] RANSAC iterations at most
  double pnp_confidence = 0.999;  ///< [unitless] RANSAC success probability
  int min_pnp_inliers = 25;       ///< [count]

  // --- 3-D/3-D agreement (both keyframes' depth) ---
  /// [m] tolerance of a pair = depth_tolerance_m + depth_tolerance_sigmas * sigma, with
  /// sigma = depth_noise_coeff * sqrt(z_query^4 + z_candidate^4) (the two sensors' depth noise)
  double depth_tolerance_m = 0.03;
  double depth_noise_coeff = 0.004;     ///< [1/m] depth noise sigma = coeff * z^2 (D435)
  double depth_tolerance_sigmas = 3.0;  ///< [unitless]
  int min_depth_inliers = 20;           ///< [count] agreeing pairs needed
  /// [unitless] agreeing share of the PnP inliers that have depth on both sides
  double min_depth_inlier_fraction = 0.6;
  /// [count] re-selections of the agreeing pairs and maximum-likelihood rigid refinements of
  /// the PnP pose on them (both keyframes' points with anisotropic noise, rigid_fit.h; 0 = keep
  /// the PnP pose)
  int refine_rounds = 2;
  /// [px] keypoint position noise, the lateral part of a 3-D point's noise in that refinement
  double keypoint_sigma_px = 1.0;

  // --- gates on the relative pose ---
  /// [deg] angle between the gravity direction in the query body frame implied by the loop and
  /// the one of the query's own (gravity-aligned) pose
  double max_gravity_deg = 3.0;
  double max_yaw_deg = 30.0;       ///< [deg] heading difference of the two bodies
  double max_translation_m = 4.0;  ///< [m] distance between the two bodies

  // --- drift budget (only when both poses are in one frame) ---
  double drift_base_m = 0.2;     ///< [m] correction of the query position always allowed
  double drift_fraction = 0.05;  ///< [unitless] further metres allowed per metre travelled
  double drift_base_deg = 3.0;   ///< [deg] correction of the query heading always allowed
  double drift_deg_per_m = 0.3;  ///< [deg/m] further degrees allowed per metre travelled

  // --- free space (both keyframes' depth grids) ---
  /// [m] a depth sample of one keyframe conflicts with the other when, under the verified pose,
  /// it is nearer than the other's depth along that ray by more than this plus
  /// freespace_margin_sigmas noise sigmas (the other saw through the place the sample is at)
  double freespace_margin_m = 0.10;
  double freespace_margin_sigmas = 3.0;  ///< [unitless]
  /// [unitless] share of the compared samples (conflicting or agreeing, both directions) allowed
  /// to conflict; 1 = check off
  double freespace_max_conflict_fraction = 0.15;
  int freespace_min_samples = 20;  ///< [count] compared samples needed to judge the share
  /// [bool] check loops within one frame too; joins of unrelated parts are always checked (no
  /// drift budget protects them)
  bool freespace_for_loops = false;

  /// Throws ConfigError when a value is outside its range.
  void validate() const;
  /// Reads the verify_* keys of [loop]; missing keys keep the defaults above.
  static LoopVerificationOptions load(IniReader& ini);
};

enum class LoopRejection {
  Accepted,           ///< not rejected (X11 defines None as a macro)
  TooFewMatches,      ///< fewer descriptor matches with a candidate 3-D point than min_matches
  PnpFailed,          ///< PnP RANSAC found no pose
  TooFewPnpInliers,   ///< fewer PnP inliers than min_pnp_inliers
  DepthDisagreement,  ///< the two keyframes' depths do not agree under the pose
  GravityMismatch,    ///< roll/pitch implied by the loop disagree with the odometry's
  YawGate,            ///< relative heading above max_yaw_deg
  TranslationGate,    ///< relative distance above max_translation_m
  DriftBudget,        ///< correction larger than the odometry can have drifted
  FreeSpaceConflict,  ///< one keyframe's surfaces lie where the other saw free space
};

/// Every reason, Accepted first (for per-reason counters).
constexpr std::array<LoopRejection, 10> kAllLoopRejections = {
    LoopRejection::Accepted,          LoopRejection::TooFewMatches,
    LoopRejection::PnpFailed,         LoopRejection::TooFewPnpInliers,
    LoopRejection::DepthDisagreement, LoopRejection::GravityMismatch,
    LoopRejection::YawGate,           LoopRejection::TranslationGate,
    LoopRejection::DriftBudget,       LoopRejection::FreeSpaceConflict};

/// snake_case name ("too_few_matches", ...; "accepted"), used as summary.json key.
const char* toString(LoopRejection reason);

/// A verified relative pose between two keyframes.
struct LoopConstraint {
  std::uint64_t from_id = 0;  ///< candidate (older keyframe)
  std::uint64_t to_id = 0;    ///< query (newer keyframe)
  /// Body frame of the candidate <- body frame of the query.
  Eigen::Isometry3d T_from_to = Eigen::Isometry3d::Identity();
  int matches = 0;        ///< descriptor matches whose candidate keypoint has a 3-D point
  int pnp_inliers = 0;    ///< PnP RANSAC inliers
  int depth_inliers = 0;  ///< agreeing 3-D/3-D pairs under the final pose
  double reprojection_rms_px = 0.0;  ///< [px] PnP inliers under the final pose
  double depth_rms_m = 0.0;          ///< [m] 3-D distance of the agreeing pairs, final pose
  /// Free-space check: depth-grid samples compared (conflicting + agreeing, both directions) and
  /// the conflicting ones; 0 / 0 when it was not made (no depth grid, or a loop with the check
  /// off for loops).
  int freespace_compared = 0;
  int freespace_conflicts = 0;
};

/// Free-space evidence between two keyframes' depth grids (step 7 of verification): samples
/// compared (conflicting or agreeing, both directions) and the conflicting ones.
struct FreeSpaceTally {
  int compared = 0;
  int conflicts = 0;
  FreeSpaceTally& operator+=(const FreeSpaceTally& o) {
    compared += o.compared;
    conflicts += o.conflicts;
    return *this;
  }
};

struct LoopVerification {
  bool accepted = false;
  /// Filled as far as verification got: counts up to the failed step; T_from_to from PnP on (the
  /// refined pose once the 3-D/3-D check passed).
  LoopConstraint constraint;
  LoopRejection reason = LoopRejection::Accepted;
  std::string detail;  ///< the measured value and the gate it failed (empty when accepted)
};

class LoopVerifier {
 public:
  /// colour_cam: intrinsics of the images the keypoints come from; T_body_cam: pose of the
  /// colour camera optical frame in the body frame. Throws ConfigError on invalid options and
  /// std::invalid_argument on an invalid camera.
  LoopVerifier(const LoopVerificationOptions& options, const PinholeCamera& colour_cam,
               const Eigen::Isometry3d& T_body_cam);

  /// Verifies that query (newer) sees the place of candidate (older). frames_related: both
  /// keyframes' T_world_body are in one frame (same segment or segments already joined), which
  /// enables the drift budget. Deterministic. Throws std::invalid_argument naming the keyframe
  /// when a descriptor set is inconsistent or the two sets have different descriptor sizes.
  LoopVerification verify(const LoopKeyframe& query, const LoopKeyframe& candidate,
                          bool frames_related) const;

  /// The free-space comparison of step 7 for two keyframes placed at the given body poses (one
  /// frame), both directions; 0 / 0 when either has no depth grid. Used to check a join against
  /// the other keyframes around the place it puts a part (LoopCloser).
  FreeSpaceTally compareFreeSpace(const LoopKeyframe& a, const Eigen::Isometry3d& T_world_body_a,
                                  const LoopKeyframe& b,
                                  const Eigen::Isometry3d& T_world_body_b) const;

  const LoopVerificationOptions& options() const { return options_; }

 private:
  LoopVerificationOptions options_;
  PinholeCamera cam_;
  Eigen::Isometry3d T_body_cam_;
  Eigen::Isometry3d T_cam_body_;
  Eigen::Vector2d max_xn_ = Eigen::Vector2d::Zero();  ///< |x/z|, |y/z| bound of the view
};

}  // namespace rgbdi::loop
