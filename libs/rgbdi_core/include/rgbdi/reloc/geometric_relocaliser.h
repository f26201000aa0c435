// Geometric relocalisation in a saved map: the part's latest depth (a local submap in its
// odometry frame, gravity aligned) is searched for globally in the map's plan (ScanSearch over
// x, y, yaw), the height offset follows from the floor both saw, and the fit is refined by
// 4-DOF ICP on the 3-D samples. One fit is one attempt; FitConfirmation decides when fits are
// trusted. Immutable after construction: fit() may run on its own thread.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <utility>
#include <vector>

#include "rgbdi/reloc/plan_grid.h"
#include "rgbdi/reloc/point_index.h"
#include "rgbdi/reloc/reloc_options.h"
#include "rgbdi/reloc/scan_search.h"

namespace rgbdi::reloc {

/// One attempt: the part's latest depth samples (its current frame) and where it is.
struct RelocJob {
  std::uint64_t number = 0;                                    ///< 1, 2, ... in submission order
  int segment = 0;                                             ///< odometry segment of the part
  std::uint64_t anchor_id = 0;                                 ///< newest keyframe of the submap
  Eigen::Isometry3d T_anchor = Eigen::Isometry3d::Identity();  ///< its pose (part frame)
  double travelled_m = 0.0;          ///< [m] odometry path length at the anchor
  double t_query = 0.0;              ///< [s] stamp of the anchor (run clock)
  std::vector<DepthSample> samples;  ///< part frame, newest keyframe first
  /// Per keyframe, newest first: the path from it to the anchor [m] and the end of its samples
  /// in `samples` (samples[0, end) are this keyframe's and the newer ones'). Empty: all samples
  /// are one submap (path 0).
  struct Span {
    double path_m = 0.0;
    std::size_t end = 0;
  };
  std::vector<Span> spans;
  /// A tracking job (GeometricRelocaliser::track): the part is already in the map's frame and
  /// `samples` are placed by its present map-frame poses; `part_poses` are its latest
  /// keyframes' poses then (id, T_map_body), newest first, for the loop edges of the fit.
  bool track = false;
  std::vector<std::pair<std::uint64_t, Eigen::Isometry3d>> part_poses;
};

enum class FitOutcome {
  kTooLittle,  ///< the submap has too few obstacle cells to search
  kNoPlace,    ///< no alignment reaches the overlap, or all conflict with the map's free space
  kAmbiguous,  ///< more than one distinct place fits equally well
  kNoHeight,   ///< the place fits, but the height offset could not be found
  kUnrefined,  ///< the ICP refinement found too few pairs or ended too far from the map
  kFit,        ///< one place
  kTooFar,     ///< a tracking fit that would move the part too far from its present pose
};
const char* toString(FitOutcome o);

struct RelocFit {
  std::uint64_t job = 0;
  int segment = 0;
  std::uint64_t anchor_id = 0;
  Eigen::Isometry3d T_anchor = Eigen::Isometry3d::Identity();
  double travelled_m = 0.0;
  double t_query = 0.0;
  FitOutcome outcome = FitOutcome::kTooLittle;
  int local_obstacles = 0;     ///< [count] occupied cells of the submap's plan
  double submap_path_m = 0.0;  ///< [m] path of the keyframes the submap was made of
  int candidates = 0;          ///< [count] distinct places near the best score
  int places = 0;              ///< [count] of those, agreeing with the map's free space
  /// Where each of those places puts the anchor in the map: x, y [m] and yaw [rad] (plan
  /// resolution, before the refinement), best first; and their scores.
  std::vector<Eigen::Vector3d> place_poses;
  std::vector<int> place_scores;
  /// The part's frame -> the map's frame (yaw about z and a translation); set for kFit.
  Eigen::Isometry3d T_map_part = Eigen::Isometry3d::Identity();
  double overlap = 0.0;            ///< [fraction] of the winner
  double conflict_fraction = 0.0;  ///< [fraction] of the winner
  int refine_pairs = 0;            ///< [count] ICP correspondences at the end
  int refine_samples =
      0;  ///< [count] local samples judged (those on the map's other side excluded)
  double refine_rms_m = 0.0;                  ///< [m] their RMS distance
  double refine_horizontal_constraint = 0.0;  ///< see GeometricRelocaliser::Refinement
  double height_drift_per_m = 0.0;            ///< [m per m] solved by the refinement
  double tilt_rad = 0.0;                      ///< [rad] submap tilt solved by the refinement
  double ms = 0.0;                            ///< [ms] wall time of the attempt
  bool track = false;                         ///< the result of a tracking job
  /// Tracking: the job's part_poses, and the correction of the fit (the anchor's move [m] and
  /// turn [rad]; T_map_part is then the correction from the present map frame).
  std::vector<std::pair<std::uint64_t, Eigen::Isometry3d>> part_poses;
  double correction_m = 0.0;
  double correction_rad = 0.0;
};

/// Optional parts of GeometricRelocaliser::refine().
struct RefineExtras {
  /// Per local point: the unit direction towards its camera (part frame). With a map built
  /// with its views, a pair counts only when the map's normal (facing the map's cameras) has
  /// a cosine of at least min_view_cos with it turned into the map: both sides saw the same
  /// face (a run driven the other way sees the backs of what the map saw; the nearest map
  /// point of a back is the front, and pairing them pulls the fit through the object).
  std::vector<Eigen::Vector3d> local_views;
  double min_view_cos = -1.0;  ///< [cos] -1: every pair
  /// [rad] > 0: also solve a tilt of the submap (rotation about a horizontal axis through
  /// the anchor, prior 0 +- this, weighed as one pair of huber_m noise): its gravity is the
  /// odometry's, which can be off by degrees. The result stays yaw + translation, with the
  /// anchor where the tilted fit puts it.
  double tilt_sigma_rad = 0.0;
  Eigen::Vector3d anchor_part = Eigen::Vector3d::Zero();  ///< [m] the anchor, part frame
};

class GeometricRelocaliser {
 public:
  /// The map's depth samples (map frame).
  GeometricRelocaliser(const std::vector<DepthSample>& map_samples, const RelocOptions& options);
  RelocFit fit(const RelocJob& job) const;
  /// Tracking (job.track): the ICP of the job's latest submap_path_m of samples (already in the
  /// map's frame by the part's present poses) from the identity, no search; kFit when it passes
  /// the checks of a fit and moves the anchor at most track_max_correction_m / _deg (kTooFar
  /// beyond, kUnrefined when the ICP refuses it, kTooLittle with fewer than 10 samples).
  /// T_map_part is the correction (present map frame -> refined).
  RelocFit track(const RelocJob& job) const;
  const ScanSearch& search() const { return search_; }
  const PointIndex& mapPoints() const { return points_; }

  /// Result of refine().
  struct Refinement {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    int pairs = 0;       ///< [count] correspondences of the last step
    double rms_m = 0.0;  ///< [m] their RMS point-to-plane distance
    /// [fraction] how well the pairs pin the horizontal position: the smaller eigenvalue of
    /// sum n_xy n_xy^T / its trace over the pairs' map normals (0: free to slide along a wall,
    /// 0.5: walls facing two perpendicular directions equally).
    double horizontal_constraint = 0.0;
    /// [m per m] height drift of the local samples solved with the pose (0 when not solved):
    /// a sample `s` metres of path before the anchor is moved up by s times this.
    double height_drift_per_m = 0.0;
    /// [count] local points of the last step whose nearest map surface faces away from their
    /// camera (seen from the other side by the map): neither pairs nor counted as samples.
    int other_side = 0;
    /// [rad] tilt of the submap solved (0 when not solved): the angle between its vertical and
    /// the map's after the refinement.
    double tilt_rad = 0.0;
  };
  /// 4-DOF point-to-plane ICP of `local` onto `map` from T (yaw about z, translation):
  /// nearest neighbours within max_distance_m, at most `iterations` Gauss-Newton steps, pairs
  /// farther than huber_m down-weighted by huber_m / |r| (Huber). With `path_m` (per local
  /// point: its keyframe's path before the anchor) and drift_sigma_per_m > 0, a fifth unknown,
  /// the odometry's height drift per metre of path (prior 0 +- drift_sigma_per_m, weighed as
  /// one pair of huber_m noise), is solved with the pose: the submap's floor and ramps drift a
  /// few centimetres in height over its path, and a ramp seen at the wrong height pushes a
  /// 4-DOF fit sideways. `horizontal` false: yaw, x and y stay as given (only the height and
  /// the drift are solved; the pairs still judge the fit). `extras`: see RefineExtras.
  static Refinement refine(const std::vector<Eigen::Vector3d>& local, const PointIndex& map,
                           const Eigen::Isometry3d& T, double max_distance_m, int iterations,
                           double huber_m, const std::vector<double>& path_m = {},
                           double drift_sigma_per_m = 0.0, bool horizontal = true,
                           const RefineExtras& extras = {});
  /// Median of map floor height - local floor height over cells both saw as floor, with the
  /// local plan placed by `a`; false with fewer than min_cells such cells.
  static bool floorOffset(const PlanGrid& map, const PlanGrid& local, const PlanAlignment& a,
                          int min_cells, double* dz);
  /// How many of job.samples make the local submap: those of the keyframes within
  /// submap_path_m of the anchor, and when their plan has fewer than submap_min_occupied_cells
  /// obstacle cells, older keyframes one by one (up to submap_max_path_m) until it has. Sets
  /// *plan to the submap's plan and *path_m to its path.
  static std::size_t chooseSubmap(const RelocJob& job, const RelocOptions& options, PlanGrid* plan,
                                  double* path_m);

 private:
  /// The ICP of fit() and track(): refines T (part frame -> map) with the first `used` samples
  /// of the job, fills f's refine_* fields; false when the checks refuse it.
  bool refineSubmap(const RelocJob& job, std::size_t used, Eigen::Isometry3d* T, RelocFit* f) const;
  RelocOptions options_;
  ScanSearch search_;
  PointIndex points_;
};

}  // namespace rgbdi::reloc
