// Up-to-scale structure from motion over an initialisation window, for starting without depth
// (the --no-depth baseline). The result is aligned with the IMU by alignWithScale()
// (scale_alignment.h), which recovers the metric scale.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <unordered_map>
#include <vector>

#include "rgbdi/frontend/feature_frame.h"

namespace rgbdi::estimator {

struct SfmOptions {
  /// Features shared by the base pair, points triangulated from it, and 2-D/3-D matches per PnP.
  int min_correspondences = 20;
  double min_parallax_norm = 30.0 / 460.0;     ///< mean raw parallax of the base pair
  double ransac_threshold_norm = 1.0 / 460.0;  ///< essential-matrix RANSAC threshold
  int min_inliers = 15;                        ///< of the essential matrix, of each PnP
  int ba_iterations = 20;                      ///< Ceres iterations of each of the two BA passes
  /// Cauchy scale of the BA; observations beyond 5 sigma are outliers (triangulation, PnP, BA).
  double reprojection_sigma_norm = 1.5 / 460.0;
  std::uint64_t seed = 1;  ///< RANSAC sampling is made deterministic
};

struct SfmResult {
  /// Pose of every input frame's camera in frame 0's camera; translations (and points) share one
  /// scale, fixed by |T_c0_c.back().translation()| = 1.
  std::vector<Eigen::Isometry3d> T_c0_c;
  std::unordered_map<std::uint64_t, Eigen::Vector3d> points_c0;  ///< landmarks, same scale
  int base_frame = -1;                 ///< frame l paired with the newest one
  double reprojection_rms_norm = 0.0;  ///< RMS of inlier reprojection errors after BA
  int n_points = 0;                    ///< == points_c0.size()
  int n_outlier_observations = 0;      ///< observations of the returned points judged outliers
};

/// Solves the poses of all frames and the landmarks up to one common scale; deterministic.
///
/// frames[k] holds the features of frame k (ids consistent across frames, only xn is used).
/// 1. Base pair: the oldest frame l that shares >= min_correspondences features with the newest
///    frame at a mean raw parallax >= min_parallax_norm, whose essential matrix (RANSAC +
///    cheirality) keeps >= min_inliers inliers, and from which >= min_correspondences points
///    triangulate; otherwise the next newer candidate is tried.
/// 2. The other frames are registered one at a time, the one seeing most points first (this
///    walks outwards from the pair): pose refined from the nearest registered frame's pose with a
///    shrinking outlier gate, falling back to RANSAC PnP (relativePoseByPnP) as the start; new
///    points are triangulated after each frame.
/// 3. All tracks are re-triangulated robustly (best two-view hypothesis, then DLT on the
///    observations that agree with it); two bundle adjustments with a Cauchy loss follow, each
///    followed by re-judging every observation (outlier beyond 5 sigma; re-admitted if it fits).
/// Gauge of the adjustment: frame l's pose is constant and the newest camera's translation
/// t_cn_cl lives on the unit sphere (ceres::SphereManifold), which fixes the scale while leaving
/// the direction free, so no measurement is biased by the gauge.
/// A point needs two rays meeting at >= 1 degree and must lie in front of its cameras.
///
/// Returns nullopt (never throws) when: fewer than 3 frames; no base pair (too few shared
/// features or points, too little parallax, RANSAC failure, too few inliers; pure rotation
/// ends here too: recoverPose finds no point in front within 50 baselines and no ray pair reaches
/// 1 degree); a frame fails registration; Ceres returns an unusable solution;
/// fewer than half the observations of the points are inliers; the inlier RMS exceeds
/// 3 * reprojection_sigma_norm; fewer than min_inliers points remain.
std::optional<SfmResult> solveVisualSfm(
    const std::vector<std::vector<frontend::FeatureObservation>>& frames, const SfmOptions& opt);

}  // namespace rgbdi::estimator
