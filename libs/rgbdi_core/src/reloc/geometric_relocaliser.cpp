#include "rgbdi/reloc/geometric_relocaliser.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <cmath>

namespace rgbdi::reloc {
namespace {
std::vector<Eigen::Vector3d> pointsOf(const std::vector<DepthSample>& samples, double max_range) {
  std::vector<Eigen::Vector3d> p;
  p.reserve(samples.size());
  for (const DepthSample& s : samples)
    if ((s.point - s.origin).norm() <= max_range) p.push_back(s.point);
  return p;
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
  }
  return "?";
}

GeometricRelocaliser::GeometricRelocaliser(const std::vector<DepthSample>& map_samples,
                                           const RelocOptions& options)
    : options_(options),
      search_(PlanGrid::build(map_samples, options.grid), options.search),
      points_(pointsOf(map_samples, options.refine_max_range_m), options.grid.resolution_m,
              options.refine_max_distance_m) {}

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

GeometricRelocaliser::Refinement GeometricRelocaliser::refine(
    const std::vector<Eigen::Vector3d>& local, const PointIndex& map, const Eigen::Isometry3d& T0,
    double max_distance_m, int iterations, double huber_m, const std::vector<double>& path_m,
    double drift_sigma_per_m, bool horizontal) {
  // Point-to-plane: each local point's distance along the normal of its nearest map point,
  // linearised in (yaw step, tx, ty, tz[, height drift per metre]) about the current estimate;
  // the yaw keeps T 4-DOF. Pairs farther than huber_m weigh huber_m / |r| (Huber): surfaces
  // the map saw differently (the backs of things) must not drag the fit sideways.
  using Matrix5d = Eigen::Matrix<double, 5, 5>;
  using Vector5d = Eigen::Matrix<double, 5, 1>;
  const bool drift = drift_sigma_per_m > 0.0 && path_m.size() == local.size();
  Refinement out;
  Eigen::Isometry3d T = T0;
  double b = 0.0;  // height drift per metre of path
  const std::vector<Eigen::Vector3d>& mp = map.points();
  const std::vector<Eigen::Vector3d>& mn = map.normals();
  for (int it = 0; it < iterations; ++it) {
    Matrix5d H = Matrix5d::Zero();
    Vector5d g = Vector5d::Zero();
    Eigen::Matrix2d nn = Eigen::Matrix2d::Zero();
    double sq = 0.0;
    int n = 0;
    for (std::size_t k = 0; k < local.size(); ++k) {
      const double s = drift ? path_m[k] : 0.0;
      const Eigen::Vector3d p = T * local[k] + Eigen::Vector3d(0.0, 0.0, b * s);
      const long i = map.nearest(p, max_distance_m);
      if (i < 0 || mn[static_cast<std::size_t>(i)].isZero()) continue;
      const Eigen::Vector3d& nrm = mn[static_cast<std::size_t>(i)];
      const double r = nrm.dot(p - mp[static_cast<std::size_t>(i)]);
      // d p / d yaw = z x (p - t): rotation about the vertical through T's origin.
      const Eigen::Vector3d q = p - T.translation();
      Vector5d J;
      J << nrm.dot(Eigen::Vector3d(-q.y(), q.x(), 0.0)), nrm.x(), nrm.y(), nrm.z(), nrm.z() * s;
      const double w = std::abs(r) > huber_m ? huber_m / std::abs(r) : 1.0;
      H += w * J * J.transpose();
      g += w * J * r;
      nn += nrm.head<2>() * nrm.head<2>().transpose();
      sq += r * r;
      ++n;
    }
    out.pairs = n;
    out.rms_m = n > 0 ? std::sqrt(sq / n) : 0.0;
    out.horizontal_constraint =
        nn.trace() > 0.0
            ? Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(nn / nn.trace()).eigenvalues()(0)
            : 0.0;
    if (n < 10) break;
    if (drift) {
      // The prior b ~ 0 +- sigma, as one pair whose noise is huber_m.
      const double prior = (huber_m / drift_sigma_per_m) * (huber_m / drift_sigma_per_m);
      H(4, 4) += prior;
      g(4) += prior * b;
    }
    // The unknowns solved: yaw, x, y unless only the height is refined; z; the drift.
    std::vector<int> active;
    for (int k = horizontal ? 0 : 3; k < (drift ? 5 : 4); ++k) active.push_back(k);
    const int m = static_cast<int>(active.size());
    Eigen::MatrixXd Hs(m, m);
    Eigen::VectorXd gs(m);
    for (int r = 0; r < m; ++r) {
      gs(r) = g(active[r]);
      for (int c = 0; c < m; ++c) Hs(r, c) = H(active[r], active[c]);
    }
    const Eigen::VectorXd sub = -Hs.ldlt().solve(gs);
    Vector5d step = Vector5d::Zero();
    for (int r = 0; r < m; ++r) step(active[r]) = sub(r);
    if (!step.allFinite()) break;
    Eigen::Isometry3d next = yawPose(step(0), Eigen::Vector3d::Zero());
    next.linear() = next.linear() * T.linear();
    next.translation() = T.translation() + step.segment<3>(1);
    T = next;
    b += step(4);
    if (step.segment<3>(1).norm() < 1e-7 && std::abs(step(0)) < 1e-8 && std::abs(step(4)) < 1e-8)
      break;
  }
  out.T = T;
  out.height_drift_per_m = b;
  return out;
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

RelocFit GeometricRelocaliser::fit(const RelocJob& job) const {
  const auto t0 = std::chrono::steady_clock::now();
  RelocFit f;
  f.job = job.number;
  f.segment = job.segment;
  f.anchor_id = job.anchor_id;
  f.T_anchor = job.T_anchor;
  f.travelled_m = job.travelled_m;
  f.t_query = job.t_query;
  const auto finish = [&](FitOutcome o) {
    f.outcome = o;
    f.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return f;
  };
  PlanGrid local;
  const std::size_t used = chooseSubmap(job, options_, &local, &f.submap_path_m);
  const std::vector<DepthSample> submap(job.samples.begin(),
                                        job.samples.begin() + static_cast<long>(used));
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
  if (options_.refine_iterations > 0) {
    // Each sample's keyframe path before the anchor (for the height drift).
    std::vector<Eigen::Vector3d> pts;
    std::vector<double> paths;
    std::size_t span = 0;
    for (std::size_t i = 0; i < submap.size(); ++i) {
      while (span < job.spans.size() && job.spans[span].end <= i) ++span;
      if ((submap[i].point - submap[i].origin).norm() > options_.refine_max_range_m) continue;
      pts.push_back(submap[i].point);
      paths.push_back(span < job.spans.size() ? job.spans[span].path_m : 0.0);
    }
    std::vector<double> local_paths;
    const std::vector<Eigen::Vector3d> local_points =
        PointIndex::thin(pts, paths, options_.grid.resolution_m, &local_paths);
    const Refinement r3 =
        refine(local_points, points_, T, options_.refine_max_distance_m, options_.refine_iterations,
               options_.refine_huber_m, local_paths, options_.refine_height_drift_sigma_per_m,
               options_.refine_horizontal);
    f.height_drift_per_m = r3.height_drift_per_m;
    T = r3.T;
    f.refine_pairs = r3.pairs;
    f.refine_rms_m = r3.rms_m;
    f.refine_horizontal_constraint = r3.horizontal_constraint;
    // A fit the 3-D samples do not confirm (few pairs, far apart at the end, or free to slide
    // along a wall) is no fit.
    if (r3.pairs < options_.refine_min_pair_fraction * static_cast<double>(local_points.size()) ||
        r3.rms_m > options_.refine_max_rms_m ||
        r3.horizontal_constraint < options_.refine_min_horizontal_constraint)
      return finish(FitOutcome::kUnrefined);
  }
  f.T_map_part = T;
  return finish(FitOutcome::kFit);
}

}  // namespace rgbdi::reloc
