#include "rgbdi/estimator/visual_sfm.h"

#include <ceres/ceres.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <map>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>

#include "rgbdi/common/so3.h"
#include "rgbdi/estimator/initializer.h"

namespace rgbdi::estimator {

namespace {

// Rays meeting at less than this give depths too uncertain to build on (the rays of a pure
// rotation never do; recoverPose's 50-baseline distance limit is a similar ~1.1 degree bound).
constexpr double kMinRayAngleRad = 1.0 * M_PI / 180.0;
// Observations further than this many reprojection sigmas from their point are outliers.
constexpr double kOutlierSigmas = 5.0;

struct Observation {
  int frame = 0;
  Eigen::Vector2d xn;
  bool inlier = true;
};

struct Track {
  std::vector<Observation> obs;                    // ordered by frame
  Eigen::Vector3d p_cl = Eigen::Vector3d::Zero();  // in the base camera l
  bool has_point = false;
};

// std::map: iteration order (hence the Ceres problem and the result) depends only on the ids.
using Tracks = std::map<std::uint64_t, Track>;

// T_ck_cl, the map from base-camera points into camera k, is what projection needs. Stored as
// one Ceres parameter block [q (x, y, z, w), t]: a single 6-DOF camera block lets Ceres use its
// fixed-size Schur elimination.
struct FramePose {
  Eigen::Matrix<double, 7, 1> x = (Eigen::Matrix<double, 7, 1>() << 0, 0, 0, 1, 0, 0, 0).finished();
  bool registered = false;
  Eigen::Map<Eigen::Quaterniond> q() { return Eigen::Map<Eigen::Quaterniond>(x.data()); }
  Eigen::Map<const Eigen::Quaterniond> q() const {
    return Eigen::Map<const Eigen::Quaterniond>(x.data());
  }
  Eigen::Map<Eigen::Vector3d> t() { return Eigen::Map<Eigen::Vector3d>(x.data() + 4); }
  Eigen::Map<const Eigen::Vector3d> t() const {
    return Eigen::Map<const Eigen::Vector3d>(x.data() + 4);
  }
  Eigen::Vector3d map(const Eigen::Vector3d& p) const { return q() * p + t(); }
};

Tracks buildTracks(const std::vector<std::vector<frontend::FeatureObservation>>& frames) {
  Tracks tracks;
  for (size_t k = 0; k < frames.size(); ++k) {
    for (const auto& f : frames[k]) {
      Track& tr = tracks[f.id];
      // A repeated id within one frame is a front-end glitch: keep the first one.
      if (!tr.obs.empty() && tr.obs.back().frame == static_cast<int>(k)) continue;
      tr.obs.push_back({static_cast<int>(k), f.xn, true});
    }
  }
  return tracks;
}

const Observation* findObs(const Track& tr, int frame) {
  for (const auto& o : tr.obs)
    if (o.frame == frame) return &o;
  return nullptr;
}

double rayAngle(const FramePose& a, const Eigen::Vector2d& xa, const FramePose& b,
                const Eigen::Vector2d& xb) {
  // Bearings rotated into the base camera (the rotation part of T_cl_ck is q^-1).
  const Eigen::Vector3d ra = (a.q().conjugate() * xa.homogeneous()).normalized();
  const Eigen::Vector3d rb = (b.q().conjugate() * xb.homogeneous()).normalized();
  return std::atan2(ra.cross(rb).norm(), ra.dot(rb));
}

double reprojectionError(const FramePose& P, const Eigen::Vector3d& p_cl,
                         const Eigen::Vector2d& xn) {
  const Eigen::Vector3d pc = P.map(p_cl);
  return pc.z() > 0.0 ? (pc.head<2>() / pc.z() - xn).norm()
                      : std::numeric_limits<double>::infinity();
}

/// Linear (DLT) triangulation; nullopt for a point at infinity. The homogeneous point is the
/// eigenvector of A^T A with the smallest eigenvalue (fixed 4x4 size: this runs for every
/// two-view hypothesis of every track, and the bundle adjustment polishes the result anyway).
std::optional<Eigen::Vector3d> dlt(const std::vector<FramePose>& poses,
                                   const std::vector<const Observation*>& use) {
  Eigen::Matrix4d AtA = Eigen::Matrix4d::Zero();
  for (const Observation* o : use) {
    const FramePose& P = poses[static_cast<size_t>(o->frame)];
    Eigen::Matrix<double, 3, 4> M;
    M << P.q().toRotationMatrix(), P.t();
    const Eigen::RowVector4d rx = o->xn.x() * M.row(2) - M.row(0);
    const Eigen::RowVector4d ry = o->xn.y() * M.row(2) - M.row(1);
    AtA += rx.transpose() * rx + ry.transpose() * ry;
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> eig(AtA);
  const Eigen::Vector4d X = eig.eigenvectors().col(0);
  if (!(std::abs(X.w()) > 1e-12 * X.head<3>().norm())) return std::nullopt;
  return Eigen::Vector3d(X.head<3>() / X.w());
}

/// Observations of tr in registered frames within max_err of p_cl.
std::vector<const Observation*> consistent(const std::vector<FramePose>& poses,
                                           const Eigen::Vector3d& p_cl, double max_err,
                                           const Track& tr) {
  std::vector<const Observation*> out;
  for (const auto& o : tr.obs) {
    const FramePose& P = poses[static_cast<size_t>(o.frame)];
    if (P.registered && reprojectionError(P, p_cl, o.xn) <= max_err) out.push_back(&o);
  }
  return out;
}

/// Sets every registered observation's inlier flag from p_cl; the point is kept only with two
/// or more inliers.
void adoptPoint(const std::vector<FramePose>& poses, const Eigen::Vector3d& p_cl, double max_err,
                Track* tr) {
  int inliers = 0;
  for (auto& o : tr->obs) {
    const FramePose& P = poses[static_cast<size_t>(o.frame)];
    if (!P.registered) continue;
    o.inlier = reprojectionError(P, p_cl, o.xn) <= max_err;
    inliers += o.inlier ? 1 : 0;
  }
  tr->p_cl = p_cl;
  tr->has_point = inliers >= 2;
}

/// Robust triangulation from all observations in registered frames, whatever their flags: every
/// pair whose rays meet at >= kMinRayAngleRad proposes a point, the one consistent with most
/// observations wins and is re-solved from those (DLT). The flags are then re-set from it, so an
/// observation once rejected against a point built on an outlier gets back in. A track whose
/// rays are all too parallel gets no point (that is "not yet", not an outlier).
void triangulate(const std::vector<FramePose>& poses, double max_err, Track* tr) {
  tr->has_point = false;
  std::vector<const Observation*> reg;
  for (const auto& o : tr->obs)
    if (poses[static_cast<size_t>(o.frame)].registered) reg.push_back(&o);
  std::vector<const Observation*> best;
  for (size_t i = 0; i < reg.size(); ++i) {
    for (size_t j = i + 1; j < reg.size(); ++j) {
      const FramePose& Pi = poses[static_cast<size_t>(reg[i]->frame)];
      const FramePose& Pj = poses[static_cast<size_t>(reg[j]->frame)];
      if (rayAngle(Pi, reg[i]->xn, Pj, reg[j]->xn) < kMinRayAngleRad) continue;
      const auto p = dlt(poses, {reg[i], reg[j]});
      if (!p) continue;
      auto in = consistent(poses, *p, max_err, *tr);
      if (in.size() > best.size()) best = std::move(in);
    }
  }
  if (best.size() < 2) return;
  const auto p = dlt(poses, best);
  if (p) adoptPoint(poses, *p, max_err, tr);
}

void triangulateAll(const std::vector<FramePose>& poses, double max_err, bool redo_points,
                    Tracks* tracks) {
  for (auto& [id, tr] : *tracks)
    if (redo_points || !tr.has_point) triangulate(poses, max_err, &tr);
}

/// Frame l becomes the identity, the newest frame gets the essential-matrix pose (|t| = 1) and
/// the inliers shared by both are triangulated. False (state untouched) when any step fails.
bool initBasePair(int l, int newest, const SfmOptions& opt, std::vector<FramePose>* poses,
                  Tracks* tracks) {
  std::vector<cv::Point2d> xl, xn;
  std::vector<std::uint64_t> ids;
  double parallax = 0.0;
  for (const auto& [id, tr] : *tracks) {
    const Observation* a = findObs(tr, l);
    const Observation* b = findObs(tr, newest);
    if (a == nullptr || b == nullptr) continue;
    xl.emplace_back(a->xn.x(), a->xn.y());
    xn.emplace_back(b->xn.x(), b->xn.y());
    ids.push_back(id);
    parallax += (a->xn - b->xn).norm();
  }
  const int n = static_cast<int>(ids.size());
  if (n < std::max(opt.min_correspondences, 5) || parallax / n < opt.min_parallax_norm)
    return false;
  // Normalised coordinates: identity camera matrix, threshold on the normalised plane.
  const cv::Mat K = cv::Mat::eye(3, 3, CV_64F);
  cv::Mat mask;
  cv::theRNG().state = opt.seed;
  const cv::Mat E =
      cv::findEssentialMat(xl, xn, K, cv::RANSAC, 0.999, opt.ransac_threshold_norm, 1000, mask);
  if (E.rows != 3 || E.cols != 3) return false;
  cv::Mat R_cv, t_cv;
  const int inliers = cv::recoverPose(E, xl, xn, K, R_cv, t_cv, mask);
  if (inliers < opt.min_inliers) return false;
  Eigen::Matrix3d R;
  Eigen::Vector3d t;
  cv::cv2eigen(R_cv, R);
  cv::cv2eigen(t_cv, t);

  std::vector<FramePose> trial(poses->size());
  trial[static_cast<size_t>(l)].registered = true;
  FramePose& pn = trial[static_cast<size_t>(newest)];
  pn.q() = Eigen::Quaterniond(R).normalized();
  pn.t() = t.normalized();
  pn.registered = true;
  // Every shared track, not only the RANSAC inliers: the triangulation gate (5 sigma) is looser
  // than the RANSAC threshold, which may be tight for the pixel noise, and few points here would
  // starve the PnP of the next frames.
  Tracks trial_tracks = *tracks;
  int points = 0;
  for (int i = 0; i < n; ++i) {
    Track& tr = trial_tracks[ids[static_cast<size_t>(i)]];
    triangulate(trial, kOutlierSigmas * opt.reprojection_sigma_norm, &tr);
    points += tr.has_point ? 1 : 0;
  }
  if (points < opt.min_correspondences) return false;
  *poses = std::move(trial);
  *tracks = std::move(trial_tracks);
  return true;
}

/// Inlier observations in frame k of tracks that already have a point.
std::vector<std::pair<Observation*, const Track*>> correspondences(int k, Tracks* tracks) {
  std::vector<std::pair<Observation*, const Track*>> out;
  for (auto& [id, tr] : *tracks) {
    if (!tr.has_point) continue;
    for (auto& o : tr.obs)
      if (o.frame == k && o.inlier) out.emplace_back(&o, &tr);
  }
  return out;
}

/// Levenberg-Marquardt from *P with a shrinking gate: each round fits the correspondences within
/// the gate of the previous pose (all of them first, since a neighbour's pose as the start can
/// be tens of pixels off), so gross outliers cannot drag the pose far enough to lose the
/// inliers. Returns the number within max_err of the final pose (points behind count as out).
int refinePose(const std::vector<Eigen::Vector3d>& pts, const std::vector<Eigen::Vector2d>& xn,
               double max_err, FramePose* P, std::vector<bool>* inlier) {
  const cv::Mat K = cv::Mat::eye(3, 3, CV_64F);
  for (const double gate : {std::numeric_limits<double>::infinity(), 8.0, 3.0, 1.0}) {
    std::vector<cv::Point3d> obj;
    std::vector<cv::Point2d> img;
    for (size_t i = 0; i < pts.size(); ++i) {
      if (reprojectionError(*P, pts[i], xn[i]) > gate * max_err) continue;
      obj.emplace_back(pts[i].x(), pts[i].y(), pts[i].z());
      img.emplace_back(xn[i].x(), xn[i].y());
    }
    if (obj.size() < 6) return 0;
    cv::Mat rvec, tvec;
    cv::eigen2cv(Eigen::Vector3d(logSO3(P->q().toRotationMatrix())), rvec);
    cv::eigen2cv(Eigen::Vector3d(P->t()), tvec);
    cv::solvePnP(obj, img, K, cv::noArray(), rvec, tvec, true, cv::SOLVEPNP_ITERATIVE);
    Eigen::Vector3d r, t;
    cv::cv2eigen(rvec, r);
    cv::cv2eigen(tvec, t);
    P->q() = Eigen::Quaterniond(expSO3(r)).normalized();
    P->t() = t;
  }
  inlier->assign(pts.size(), false);
  int count = 0;
  for (size_t i = 0; i < pts.size(); ++i) {
    (*inlier)[i] = reprojectionError(*P, pts[i], xn[i]) <= max_err;
    count += (*inlier)[i] ? 1 : 0;
  }
  return count;
}

/// Registers frame k against the points triangulated so far. First guess: the pose of the
/// nearest registered frame (frames are close in time); if too few correspondences agree with
/// it after refinement, the RANSAC PnP result is the guess instead. EPnP alone is not enough:
/// on minimal samples of a shallow scene it can return a mirrored pose with the points behind
/// the camera, which the projection alone cannot tell apart. Rejected observations are marked
/// outliers.
bool registerByPnP(int k, const SfmOptions& opt, std::vector<FramePose>* poses, Tracks* tracks) {
  const auto corr = correspondences(k, tracks);
  if (static_cast<int>(corr.size()) < opt.min_correspondences) return false;
  std::vector<Eigen::Vector3d> pts;
  std::vector<Eigen::Vector2d> xn;
  for (const auto& [o, tr] : corr) {
    pts.push_back(tr->p_cl);
    xn.push_back(o->xn);
  }
  // The gross-outlier gate, not the RANSAC threshold: points triangulated from a short baseline
  // carry depth errors that would otherwise cost the frame its inliers.
  const double max_err = kOutlierSigmas * opt.reprojection_sigma_norm;
  int nearest = -1;
  for (int j = 0; j < static_cast<int>(poses->size()); ++j)
    if ((*poses)[static_cast<size_t>(j)].registered &&
        (nearest < 0 || std::abs(j - k) < std::abs(nearest - k)))
      nearest = j;
  FramePose P = (*poses)[static_cast<size_t>(nearest)];
  std::vector<bool> inlier;
  int count = refinePose(pts, xn, max_err, &P, &inlier);
  if (count < opt.min_inliers) {
    PnpOptions popt;
    popt.min_inliers = opt.min_inliers;
    popt.ransac_threshold_norm = max_err;
    popt.seed = opt.seed + static_cast<std::uint64_t>(k) + 1;
    const auto pnp = relativePoseByPnP(pts, xn, popt);
    if (!pnp) return false;
    P.q() = Eigen::Quaterniond(pnp->T_curr_prev.rotation()).normalized();
    P.t() = pnp->T_curr_prev.translation();
    count = refinePose(pts, xn, max_err, &P, &inlier);
    if (count < opt.min_inliers) return false;
  }
  P.registered = true;
  (*poses)[static_cast<size_t>(k)] = P;
  for (size_t i = 0; i < corr.size(); ++i) corr[i].first->inlier = inlier[i];
  return true;
}

/// Normalised-plane reprojection error divided by sigma, so the Cauchy loss has scale 1.
struct WhitenedReprojection {
  Eigen::Vector2d xn;
  double inv_sigma;
  template <typename T>
  bool operator()(const T* pose, const T* p, T* r) const {
    const Eigen::Map<const Eigen::Quaternion<T>> Q(pose);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> tt(pose + 4), P(p);
    const Eigen::Matrix<T, 3, 1> pc = Q * P + tt;
    r[0] = (pc.x() / pc.z() - xn.x()) * inv_sigma;
    r[1] = (pc.y() / pc.z() - xn.y()) * inv_sigma;
    return true;
  }
};

bool bundleAdjust(int l, int newest, const SfmOptions& opt, std::vector<FramePose>* poses,
                  Tracks* tracks) {
  ceres::CauchyLoss loss(1.0);
  ceres::ProductManifold<ceres::EigenQuaternionManifold, ceres::EuclideanManifold<3>> pose_manifold;
  ceres::ProductManifold<ceres::EigenQuaternionManifold, ceres::SphereManifold<3>> scale_gauge;
  ceres::Problem::Options popt;
  popt.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  popt.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(popt);
  for (auto& [id, tr] : *tracks) {
    if (!tr.has_point) continue;
    for (const auto& o : tr.obs) {
      if (!o.inlier) continue;
      FramePose& P = (*poses)[static_cast<size_t>(o.frame)];
      auto* cost = new ceres::AutoDiffCostFunction<WhitenedReprojection, 2, 7, 3>(
          new WhitenedReprojection{o.xn, 1.0 / opt.reprojection_sigma_norm});
      problem.AddResidualBlock(cost, &loss, P.x.data(), tr.p_cl.data());
    }
  }
  // A registered frame that lost all its observations would keep an unrefined pose.
  for (int k = 0; k < static_cast<int>(poses->size()); ++k) {
    double* x = (*poses)[static_cast<size_t>(k)].x.data();
    if (!problem.HasParameterBlock(x)) return false;
    // Gauge: frame l fixes rotation and position, the newest camera's distance from it the scale.
    if (k == l) problem.SetParameterBlockConstant(x);
    problem.SetManifold(x,
                        k == newest ? static_cast<ceres::Manifold*>(&scale_gauge) : &pose_manifold);
  }

  ceres::Solver::Options sopt;
  sopt.linear_solver_type = ceres::DENSE_SCHUR;
  sopt.max_num_iterations = opt.ba_iterations;
  sopt.num_threads = 1;  // bit-identical results run to run
  ceres::Solver::Summary summary;
  ceres::Solve(sopt, &problem, &summary);
  // Hitting the iteration limit is accepted: the RMS gate below judges the result.
  return summary.IsSolutionUsable();
}

/// Re-judges every observation of every point against the current solution (re-admitting those
/// that fit again); points left with fewer than two inliers are dropped.
void rejudge(const std::vector<FramePose>& poses, double max_err, Tracks* tracks) {
  for (auto& [id, tr] : *tracks)
    if (tr.has_point) adoptPoint(poses, tr.p_cl, max_err, &tr);
}

std::optional<SfmResult> solve(const std::vector<std::vector<frontend::FeatureObservation>>& frames,
                               const SfmOptions& opt) {
  const int n = static_cast<int>(frames.size());
  if (n < 3) return std::nullopt;
  const int newest = n - 1;
  Tracks tracks = buildTracks(frames);
  std::vector<FramePose> poses(static_cast<size_t>(n));
  int l = 0;
  while (l < newest && !initBasePair(l, newest, opt, &poses, &tracks)) ++l;
  if (l == newest) return std::nullopt;

  const double tri_err = kOutlierSigmas * opt.reprojection_sigma_norm;
  // Next best view: always register the frame seeing the most points. This walks outwards from
  // the pair, and a frame that sees few base points waits until its neighbours add more.
  for (int registered = 2; registered < n; ++registered) {
    int best = -1;
    size_t best_count = 0;
    for (int k = 0; k < n; ++k) {
      if (poses[static_cast<size_t>(k)].registered) continue;
      const size_t c = correspondences(k, &tracks).size();
      if (best < 0 || c > best_count) {
        best = k;
        best_count = c;
      }
    }
    if (!registerByPnP(best, opt, &poses, &tracks)) return std::nullopt;
    triangulateAll(poses, tri_err, false, &tracks);
  }

  // With every pose known, triangulate all tracks afresh: points made early from two views
  // (one possibly an outlier) are replaced by the hypothesis most observations agree with.
  triangulateAll(poses, tri_err, true, &tracks);
  // Two passes: the second one without the observations the first showed to be outliers.
  for (int pass = 0; pass < 2; ++pass) {
    if (!bundleAdjust(l, newest, opt, &poses, &tracks)) return std::nullopt;
    rejudge(poses, tri_err, &tracks);
  }

  // Inlier statistics over the tracks that kept a point.
  SfmResult res;
  int n_in = 0, n_all = 0;
  double sq = 0.0;
  for (const auto& [id, tr] : tracks) {
    if (!tr.has_point) continue;
    for (const auto& o : tr.obs) {
      ++n_all;
      if (!o.inlier) continue;
      const Eigen::Vector3d pc = poses[static_cast<size_t>(o.frame)].map(tr.p_cl);
      sq += (pc.head<2>() / pc.z() - o.xn).squaredNorm();
      ++n_in;
    }
  }
  if (n_in == 0 || 2 * n_in < n_all) return std::nullopt;
  res.base_frame = l;
  res.reprojection_rms_norm = std::sqrt(sq / n_in);
  res.n_outlier_observations = n_all - n_in;
  if (!std::isfinite(res.reprojection_rms_norm) ||
      res.reprojection_rms_norm > 3.0 * opt.reprojection_sigma_norm)
    return std::nullopt;

  // Re-express in camera 0 and fix the scale by |t_c0_cnewest| = 1.
  auto T_of = [&](int k) {
    const FramePose& P = poses[static_cast<size_t>(k)];
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = P.q().toRotationMatrix();
    T.translation() = P.t();
    return T;  // T_ck_cl
  };
  const Eigen::Isometry3d T_c0_cl = T_of(0);
  const double d = (T_c0_cl * T_of(newest).inverse()).translation().norm();
  if (!(d > 1e-12) || !std::isfinite(d)) return std::nullopt;
  for (int k = 0; k < n; ++k) {
    Eigen::Isometry3d T = T_c0_cl * T_of(k).inverse();
    T.translation() /= d;
    res.T_c0_c.push_back(T);
  }
  for (const auto& [id, tr] : tracks)
    if (tr.has_point) res.points_c0[id] = T_c0_cl * tr.p_cl / d;
  res.n_points = static_cast<int>(res.points_c0.size());
  if (res.n_points < opt.min_inliers) return std::nullopt;
  return res;
}

}  // namespace

std::optional<SfmResult> solveVisualSfm(
    const std::vector<std::vector<frontend::FeatureObservation>>& frames, const SfmOptions& opt) {
  try {
    return solve(frames, opt);
  } catch (const cv::Exception&) {
    return std::nullopt;  // degenerate input OpenCV refuses (the checks above should prevent it)
  }
}

}  // namespace rgbdi::estimator
