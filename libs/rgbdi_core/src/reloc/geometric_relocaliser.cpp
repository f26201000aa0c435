#include "rgbdi/reloc/geometric_relocaliser.h"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace rgbdi::reloc {
namespace {
// The samples within max_range of their camera, and per sample the direction towards it.
PointIndex indexOf(const std::vector<DepthSample>& samples, const RelocOptions& o) {
  std::vector<Eigen::Vector3d> p, v;
  p.reserve(samples.size());
  v.reserve(samples.size());
  for (const DepthSample& s : samples)
    if ((s.point - s.origin).norm() <= o.refine_max_range_m) {
      p.push_back(s.point);
      v.push_back((s.origin - s.point).normalized());
    }
  return PointIndex(p, v, o.grid.resolution_m, o.refine_max_distance_m);
}
Eigen::Isometry3d yawPose(double yaw, const Eigen::Vector3d& t) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = t;
  return T;
}
}  // namespace

const char* toString(FitOutcome o) {
  switch (o) {
    case FitOutcome::kTooLittle:
      return "too little structure";
    case FitOutcome::kNoPlace:
      return "no place fits";
    case FitOutcome::kAmbiguous:
      return "ambiguous";
    case FitOutcome::kNoHeight:
      return "no height";
    case FitOutcome::kUnrefined:
      return "not confirmed by ICP";
    case FitOutcome::kFit:
      return "fit";
    case FitOutcome::kTooFar:
      return "too far from the present pose";
  }
  return "?";
}

GeometricRelocaliser::GeometricRelocaliser(const std::vector<DepthSample>& map_samples,
                                           const RelocOptions& options)
    : options_(options),
      search_(PlanGrid::build(map_samples, options.grid), options.search),
      points_(indexOf(map_samples, options)) {}

bool GeometricRelocaliser::floorOffset(const PlanGrid& map, const PlanGrid& local,
                                       const PlanAlignment& a, int min_cells, double* dz) {
  std::vector<double> d;
  for (int iy = 0; iy < local.height(); ++iy)
    for (int ix = 0; ix < local.width(); ++ix) {
      double zl = 0.0, zm = 0.0;
      if (!local.floorHeight(ix, iy, &zl)) continue;
      const Eigen::Vector2i m = map.cellOf(a.apply(local.centre(ix, iy)));
      if (!map.floorHeight(m.x(), m.y(), &zm)) continue;
      d.push_back(zm - zl);
    }
  if (static_cast<int>(d.size()) < min_cells || d.empty()) return false;
  const auto mid = d.begin() + static_cast<long>(d.size() / 2);
  std::nth_element(d.begin(), mid, d.end());
  *dz = *mid;
  return true;
}

std::size_t GeometricRelocaliser::chooseSubmap(const RelocJob& job, const RelocOptions& o,
                                               PlanGrid* plan, double* path_m) {
  const auto build = [&](std::size_t end) {
    const std::vector<DepthSample> part(job.samples.begin(),
                                        job.samples.begin() + static_cast<long>(end));
    return PlanGrid::build(part, o.grid);
  };
  if (job.spans.empty()) {
    *plan = PlanGrid::build(job.samples, o.grid);
    *path_m = 0.0;
    return job.samples.size();
  }
  // The keyframes within submap_path_m (the newest one always).
  std::size_t k = 0;
  while (k + 1 < job.spans.size() && job.spans[k + 1].path_m <= o.submap_path_m) ++k;
  *plan = build(job.spans[k].end);
  // Thin structure: a longer path, one keyframe at a time, rather than no search.
  while (static_cast<int>(plan->count(CellState::kOccupied)) < o.submap_min_occupied_cells &&
         k + 1 < job.spans.size() && job.spans[k + 1].path_m <= o.submap_max_path_m) {
    ++k;
    *plan = build(job.spans[k].end);
  }
  *path_m = job.spans[k].path_m;
  return job.spans[k].end;
}

namespace {

/// A fit's record with what it inherits from its job.
RelocFit fitOfJob(const RelocJob& job) {
  RelocFit f;
  f.job = job.number;
  f.segment = job.segment;
  f.anchor_id = job.anchor_id;
  f.T_anchor = job.T_anchor;
  f.travelled_m = job.travelled_m;
  f.t_query = job.t_query;
  return f;
}

/// The fit with its outcome and the milliseconds since t0.
RelocFit finished(RelocFit f, FitOutcome o, std::chrono::steady_clock::time_point t0) {
  f.outcome = o;
  f.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return f;
}

}  // namespace

RelocFit GeometricRelocaliser::fit(const RelocJob& job) const {
  const auto t0 = std::chrono::steady_clock::now();
  RelocFit f = fitOfJob(job);
  const auto finish = [&](FitOutcome o) { return finished(f, o, t0); };
  PlanGrid local;
  const std::size_t used = chooseSubmap(job, options_, &local, &f.submap_path_m);
  f.local_obstacles = static_cast<int>(local.count(CellState::kOccupied));
  if (f.local_obstacles < options_.submap_min_occupied_cells) return finish(FitOutcome::kTooLittle);
  const Eigen::Vector2d pivot = (job.T_anchor.translation()).head<2>();
  const ScanSearchResult r = search_.search(local, pivot);
  f.candidates = static_cast<int>(r.candidates.size());
  f.places = static_cast<int>(r.places.size());
  if (r.places.empty()) return finish(FitOutcome::kNoPlace);
  // Ambiguity: other places within the margin of the best place that passed the check.
  const PlanHypothesis& best = r.places.front();
  int near_best = 0;
  const double anchor_yaw = std::atan2(job.T_anchor.linear()(1, 0), job.T_anchor.linear()(0, 0));
  for (const PlanHypothesis& h : r.places)
    if (h.agreement >= (1.0 - options_.search.hypothesis_margin) * best.agreement) {
      ++near_best;
      const double yaw = std::remainder(anchor_yaw + h.alignment.yaw, 2.0 * M_PI);
      f.place_poses.emplace_back(h.alignment.t.x(), h.alignment.t.y(), yaw);
      f.place_scores.push_back(h.score);
    }
  f.places = near_best;
  if (near_best > 1 || r.truncated) return finish(FitOutcome::kAmbiguous);
  f.overlap = best.overlap;
  f.conflict_fraction = best.conflict_fraction;

  double dz = 0.0;
  if (!floorOffset(search_.map(), local, best.alignment, options_.min_floor_cells, &dz))
    return finish(FitOutcome::kNoHeight);
  const PlanAlignment& a = best.alignment;
  const Eigen::Rotation2Dd R(a.yaw);
  const Eigen::Vector2d t2 = a.t - R.toRotationMatrix() * a.pivot;
  Eigen::Isometry3d T = yawPose(a.yaw, Eigen::Vector3d(t2.x(), t2.y(), dz));
  if (options_.refine_iterations > 0 && !refineSubmap(job, used, &T, &f))
    return finish(FitOutcome::kUnrefined);
  f.T_map_part = T;
  return finish(FitOutcome::kFit);
}

bool GeometricRelocaliser::refineSubmap(const RelocJob& job, std::size_t used, Eigen::Isometry3d* T,
                                        RelocFit* f) const {
  // Each sample's keyframe path before the anchor (for the height drift).
  std::vector<Eigen::Vector3d> pts, views;
  std::vector<double> paths;
  std::size_t span = 0;
  for (std::size_t i = 0; i < used; ++i) {
    while (span < job.spans.size() && job.spans[span].end <= i) ++span;
    if ((job.samples[i].point - job.samples[i].origin).norm() > options_.refine_max_range_m)
      continue;
    pts.push_back(job.samples[i].point);
    views.push_back((job.samples[i].origin - job.samples[i].point).normalized());
    paths.push_back(span < job.spans.size() ? job.spans[span].path_m : 0.0);
  }
  std::vector<double> local_paths;
  const std::vector<Eigen::Vector3d> local_points =
      PointIndex::thin(pts, paths, options_.grid.resolution_m, &local_paths);
  RefineExtras extras;
  PointIndex::thinDirections(pts, views, options_.grid.resolution_m, &extras.local_views);
  extras.min_view_cos = options_.refine_min_view_cos;
  extras.tilt_sigma_rad = options_.refine_tilt_sigma_deg * M_PI / 180.0;
  extras.anchor_part = job.T_anchor.translation();
  const Refinement r3 =
      refine(local_points, points_, *T, options_.refine_max_distance_m, options_.refine_iterations,
             options_.refine_huber_m, local_paths, options_.refine_height_drift_sigma_per_m,
             options_.refine_horizontal, extras);
  f->height_drift_per_m = r3.height_drift_per_m;
  f->tilt_rad = r3.tilt_rad;
  *T = r3.T;
  f->refine_pairs = r3.pairs;
  f->refine_samples = static_cast<int>(local_points.size()) - r3.other_side;
  f->refine_rms_m = r3.rms_m;
  f->refine_horizontal_constraint = r3.horizontal_constraint;
  // A fit the 3-D samples do not confirm (few pairs, far apart at the end, or free to slide
  // along a wall) is no fit.
  if (r3.pairs < options_.refine_min_pair_fraction * static_cast<double>(f->refine_samples) ||
      r3.rms_m > options_.refine_max_rms_m ||
      r3.horizontal_constraint < options_.refine_min_horizontal_constraint)
    return false;
  return true;
}

RelocFit GeometricRelocaliser::track(const RelocJob& job) const {
  const auto t0 = std::chrono::steady_clock::now();
  RelocFit f = fitOfJob(job);
  f.track = true;
  f.part_poses = job.part_poses;
  const auto finish = [&](FitOutcome o) { return finished(f, o, t0); };
  // The keyframes within submap_path_m of the anchor (no search: no need of more structure).
  std::size_t used = job.samples.size();
  f.submap_path_m = 0.0;
  for (const RelocJob::Span& sp : job.spans) {
    if (sp.path_m > options_.submap_path_m) break;
    used = sp.end;
    f.submap_path_m = sp.path_m;
  }
  if (used < 10 || options_.refine_iterations <= 0) return finish(FitOutcome::kTooLittle);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  if (!refineSubmap(job, used, &T, &f)) return finish(FitOutcome::kUnrefined);
  f.T_map_part = T;
  const Eigen::Vector3d a = job.T_anchor.translation();
  f.correction_m = (T * a - a).norm();
  f.correction_rad = std::abs(std::atan2(T.linear()(1, 0), T.linear()(0, 0)));
  if (f.correction_m > options_.track_max_correction_m ||
      f.correction_rad > options_.track_max_correction_deg * M_PI / 180.0)
    return finish(FitOutcome::kTooFar);
  return finish(FitOutcome::kFit);
}

}  // namespace rgbdi::reloc
