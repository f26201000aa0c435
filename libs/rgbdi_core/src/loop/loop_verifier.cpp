#include "rgbdi/loop/loop_verifier.h"

#include <algorithm>
#include <cmath>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "rgbdi/loop/hamming_matcher.h"
#include "rgbdi/loop/rigid_fit.h"

namespace rgbdi::loop {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kRadToDeg = 180.0 / kPi;

/// Heading of a body in a gravity-aligned world: direction of its x (forward) axis about z.
double heading(const Eigen::Matrix3d& R_world_body) {
  return std::atan2(R_world_body(1, 0), R_world_body(0, 0));
}

double wrapAngle(double a) { return std::atan2(std::sin(a), std::cos(a)); }

double angleBetween(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

template <typename... Args>
std::string cat(const Args&... args) {
  std::ostringstream os;
  os.precision(4);
  (os << ... << args);
  return os.str();
}

void checkDescriptors(const LoopKeyframe& kf, const char* role) {
  if (!kf.descriptors.consistent())
    throw std::invalid_argument(cat("LoopVerifier: ", role, " keyframe ", kf.id,
                                    ": inconsistent descriptor set (", kf.descriptors.size(),
                                    " keypoints, ", kf.descriptors.data.size(), " bytes of ",
                                    kf.descriptors.bytes_per_descriptor, "-byte descriptors, ",
                                    kf.descriptors.keypoints_p_cam.size(), " points)"));
}

/// One PnP inlier with depth on both sides.
struct DepthPair {
  Eigen::Vector3d p_query;  ///< query camera frame
  Eigen::Vector3d p_cand;   ///< candidate camera frame
  double tolerance_m;
};

/// Gauss-Newton iterations of one refinement round (it starts at the PnP pose, a few
/// millimetres away: two or three iterations converge; the rest is margin).
constexpr int kRefineIterations = 5;

/// Free-space evidence of one direction: the samples of grid `from` (in its camera frame) moved by
/// T_to_from into the other camera and compared with grid `to` around where they land. A sample
/// nearer than all four surrounding samples of `to` by more than the margin conflicts (`to` saw
/// farther along that ray); one within the margin of them agrees; one behind them was hidden
/// from `to` and says nothing. Samples landing beside a hole of `to` are not compared.
void compareGrids(const DepthGrid& from, const DepthGrid& to, const Eigen::Isometry3d& T_to_from,
                  const PinholeCamera& cam, const Eigen::Vector2d& max_xn,
                  const LoopVerificationOptions& o, FreeSpaceTally& count) {
  for (int r = 0; r < from.rows; ++r)
    for (int c = 0; c < from.cols; ++c) {
      const double z_from = from.at(c, r);
      if (!(z_from > 0.0)) continue;
      const Eigen::Vector3d p =
          T_to_from * cam.backProject(from.pixel(c, r, cam.width, cam.height), z_from);
      if (!(p.z() > 0.0)) continue;
      // Outside the field of view (with margin) a distortion model can fold back into the image.
      const Eigen::Vector2d xn = p.head<2>() / p.z();
      if (std::abs(xn.x()) > max_xn.x() || std::abs(xn.y()) > max_xn.y()) continue;
      Eigen::Vector2d uv;
      if (!cam.project(p, uv)) continue;
      const double gx = uv.x() * to.cols / cam.width - 0.5;
      const double gy = uv.y() * to.rows / cam.height - 0.5;
      const int c0 = static_cast<int>(std::floor(gx)), r0 = static_cast<int>(std::floor(gy));
      if (c0 < 0 || r0 < 0 || c0 + 1 >= to.cols || r0 + 1 >= to.rows) continue;
      const float d[4] = {to.at(c0, r0), to.at(c0 + 1, r0), to.at(c0, r0 + 1),
                          to.at(c0 + 1, r0 + 1)};
      if (!(d[0] > 0.f && d[1] > 0.f && d[2] > 0.f && d[3] > 0.f)) continue;
      const double d_min = std::min(std::min(d[0], d[1]), std::min(d[2], d[3]));
      const double d_max = std::max(std::max(d[0], d[1]), std::max(d[2], d[3]));
      const double zp2 = p.z() * p.z(), zt2 = d_min * d_min;
      const double margin = o.freespace_margin_m + o.freespace_margin_sigmas * o.depth_noise_coeff *
                                                       std::sqrt(zp2 * zp2 + zt2 * zt2);
      if (p.z() < d_min - margin) {
        ++count.compared;
        ++count.conflicts;
      } else if (p.z() <= d_max + margin) {
        ++count.compared;
      }
    }
}

}  // namespace

const char* toString(LoopRejection reason) {
  switch (reason) {
    case LoopRejection::Accepted:
      return "accepted";
    case LoopRejection::TooFewMatches:
      return "too_few_matches";
    case LoopRejection::PnpFailed:
      return "pnp_failed";
    case LoopRejection::TooFewPnpInliers:
      return "too_few_pnp_inliers";
    case LoopRejection::DepthDisagreement:
      return "depth_disagreement";
    case LoopRejection::GravityMismatch:
      return "gravity_mismatch";
    case LoopRejection::YawGate:
      return "yaw_gate";
    case LoopRejection::TranslationGate:
      return "translation_gate";
    case LoopRejection::DriftBudget:
      return "drift_budget";
    case LoopRejection::FreeSpaceConflict:
      return "free_space_conflict";
  }
  return "unknown";
}

LoopVerifier::LoopVerifier(const LoopVerificationOptions& options, const PinholeCamera& colour_cam,
                           const Eigen::Isometry3d& T_body_cam)
    : options_(options),
      cam_(colour_cam),
      T_body_cam_(T_body_cam),
      T_cam_body_(T_body_cam.inverse()) {
  options_.validate();
  if (!cam_.valid()) throw std::invalid_argument("LoopVerifier: invalid colour camera");
  if (!T_body_cam.matrix().allFinite())
    throw std::invalid_argument("LoopVerifier: T_body_cam is not finite");
  // The field of view in normalised coordinates (from the image corners), with 10 % to spare.
  for (const Eigen::Vector2d& corner :
       {Eigen::Vector2d(0.0, 0.0), Eigen::Vector2d(cam_.width, 0.0),
        Eigen::Vector2d(0.0, cam_.height), Eigen::Vector2d(cam_.width, cam_.height)})
    max_xn_ = max_xn_.cwiseMax(1.1 * cam_.pixelToNormalized(corner).cwiseAbs());
}

FreeSpaceTally LoopVerifier::compareFreeSpace(const LoopKeyframe& a,
                                              const Eigen::Isometry3d& T_world_body_a,
                                              const LoopKeyframe& b,
                                              const Eigen::Isometry3d& T_world_body_b) const {
  FreeSpaceTally count;
  if (a.depth_grid.empty() || b.depth_grid.empty()) return count;
  // Camera b <- camera a.
  const Eigen::Isometry3d T_bc_ac =
      T_cam_body_ * T_world_body_b.inverse() * T_world_body_a * T_body_cam_;
  compareGrids(a.depth_grid, b.depth_grid, T_bc_ac, cam_, max_xn_, options_, count);
  compareGrids(b.depth_grid, a.depth_grid, T_bc_ac.inverse(), cam_, max_xn_, options_, count);
  return count;
}

LoopVerification LoopVerifier::verify(const LoopKeyframe& query, const LoopKeyframe& candidate,
                                      bool frames_related) const {
  const LoopVerificationOptions& o = options_;
  checkDescriptors(query, "query");
  checkDescriptors(candidate, "candidate");
  const mapping::DescriptorSet& dq = query.descriptors;
  const mapping::DescriptorSet& dc = candidate.descriptors;
  if (dq.size() > 0 && dc.size() > 0 && dq.bytes_per_descriptor != dc.bytes_per_descriptor)
    throw std::invalid_argument(cat("LoopVerifier: query keyframe ", query.id, " has ",
                                    dq.bytes_per_descriptor, "-byte descriptors, candidate ",
                                    candidate.id, " ", dc.bytes_per_descriptor, "-byte ones"));

  LoopVerification result;
  LoopConstraint& c = result.constraint;
  c.from_id = candidate.id;
  c.to_id = query.id;
  auto reject = [&result](LoopRejection reason, std::string detail) {
    result.accepted = false;
    result.reason = reason;
    result.detail = std::move(detail);
    return result;
  };

  // --- descriptor matches whose candidate keypoint has a 3-D point ---
  const HammingMatchOptions match_options{o.match_ratio, o.max_hamming_bits, o.cross_check};
  const std::vector<DescriptorMatch> all_matches =
      matchDescriptors(dq.data.data(), static_cast<int>(dq.size()), dc.data.data(),
                       static_cast<int>(dc.size()), dq.bytes_per_descriptor, match_options);
  std::vector<DescriptorMatch> matches;
  for (const DescriptorMatch& m : all_matches)
    if (dc.hasPoint(static_cast<std::size_t>(m.train))) matches.push_back(m);
  c.matches = static_cast<int>(matches.size());
  if (c.matches < o.min_matches)
    return reject(LoopRejection::TooFewMatches,
                  cat(all_matches.size(), " descriptor matches, ", c.matches,
                      " with a candidate 3-D point < verify_min_matches ", o.min_matches));

  // --- PnP RANSAC: candidate points (candidate camera) vs undistorted query pixels ---
  std::vector<cv::Point3d> object_points;
  std::vector<cv::Point2d> image_points;
  object_points.reserve(matches.size());
  image_points.reserve(matches.size());
  for (const DescriptorMatch& m : matches) {
    const Eigen::Vector3f& p = dc.keypoints_p_cam[static_cast<std::size_t>(m.train)];
    object_points.emplace_back(p.x(), p.y(), p.z());
    const Eigen::Vector2d xn =
        cam_.pixelToNormalized(dq.keypoints_uv[static_cast<std::size_t>(m.query)].cast<double>());
    image_points.emplace_back(cam_.fx * xn.x() + cam_.cx, cam_.fy * xn.y() + cam_.cy);
  }
  const cv::Matx33d K(cam_.fx, 0.0, cam_.cx, 0.0, cam_.fy, cam_.cy, 0.0, 0.0, 1.0);
  cv::Mat rvec, tvec;
  std::vector<int> inliers;
  bool pnp_ok = false;
  try {
    // Classic RANSAC on AP3P minimal sets (4 points: fewer iterations than EPnP's 5 for the
    // same confidence) with OpenCV's fixed internal seed: the same input gives the same pose.
    pnp_ok = cv::solvePnPRansac(object_points, image_points, K, cv::noArray(), rvec, tvec, false,
                                o.pnp_iterations, static_cast<float>(o.pnp_threshold_px),
                                o.pnp_confidence, inliers, cv::SOLVEPNP_AP3P);
  } catch (const cv::Exception& e) {
    return reject(LoopRejection::PnpFailed, cat("PnP RANSAC threw: ", e.what()));
  }
  if (!pnp_ok || rvec.empty() || tvec.empty())
    return reject(LoopRejection::PnpFailed,
                  cat("PnP RANSAC found no pose from ", c.matches, " correspondences"));
  // RANSAC keeps the inliers of its best minimal sample; re-select them under the pose, refine
  // the pose on them (Levenberg-Marquardt on the reprojection error) and re-select again, so
  // the support reflects the best pose rather than the luckiest sample.
  auto selectInliers = [&](std::vector<int>& out) {
    cv::Matx33d R;
    cv::Rodrigues(rvec, R);
    const cv::Vec3d t(tvec.at<double>(0), tvec.at<double>(1), tvec.at<double>(2));
    const double thr2 = o.pnp_threshold_px * o.pnp_threshold_px;
    out.clear();
    for (std::size_t i = 0; i < object_points.size(); ++i) {
      const cv::Vec3d X = R * cv::Vec3d(object_points[i]) + t;
      if (!(X[2] > 0.0)) continue;
      const double du = cam_.fx * X[0] / X[2] + cam_.cx - image_points[i].x;
      const double dv = cam_.fy * X[1] / X[2] + cam_.cy - image_points[i].y;
      if (du * du + dv * dv <= thr2) out.push_back(static_cast<int>(i));
    }
  };
  selectInliers(inliers);
  if (static_cast<int>(inliers.size()) >= o.min_pnp_inliers) {
    std::vector<cv::Point3d> obj;
    std::vector<cv::Point2d> img;
    for (int i : inliers) {
      obj.push_back(object_points[static_cast<std::size_t>(i)]);
      img.push_back(image_points[static_cast<std::size_t>(i)]);
    }
    cv::solvePnPRefineLM(obj, img, K, cv::noArray(), rvec, tvec);
    selectInliers(inliers);
  }
  c.pnp_inliers = static_cast<int>(inliers.size());
  if (c.pnp_inliers < o.min_pnp_inliers)
    return reject(LoopRejection::TooFewPnpInliers,
                  cat(c.pnp_inliers, " PnP inliers of ", c.matches, " < verify_min_pnp_inliers ",
                      o.min_pnp_inliers));
  cv::Matx33d R_cv;
  cv::Rodrigues(rvec, R_cv);
  Eigen::Matrix3d R_qc_cc;
  cv::cv2eigen(R_cv, R_qc_cc);
  Eigen::Isometry3d T_qc_cc = Eigen::Isometry3d::Identity();
  T_qc_cc.linear() = R_qc_cc;
  T_qc_cc.translation() =
      Eigen::Vector3d(tvec.at<double>(0), tvec.at<double>(1), tvec.at<double>(2));
  Eigen::Isometry3d T_cc_qc = T_qc_cc.inverse();
  if (!T_cc_qc.matrix().allFinite())
    return reject(LoopRejection::PnpFailed, "PnP RANSAC returned a non-finite pose");
  c.T_from_to = T_body_cam_ * T_cc_qc * T_cam_body_;  // PnP pose until refined below

  // --- 3-D/3-D: inliers with depth on both sides must agree under the pose ---
  std::vector<DepthPair> pairs;
  for (int i : inliers) {
    const DescriptorMatch& m = matches[static_cast<std::size_t>(i)];
    if (!dq.hasPoint(static_cast<std::size_t>(m.query))) continue;
    DepthPair p;
    p.p_query = dq.keypoints_p_cam[static_cast<std::size_t>(m.query)].cast<double>();
    p.p_cand = dc.keypoints_p_cam[static_cast<std::size_t>(m.train)].cast<double>();
    const double zq2 = p.p_query.z() * p.p_query.z(), zc2 = p.p_cand.z() * p.p_cand.z();
    const double sigma = o.depth_noise_coeff * std::sqrt(zq2 * zq2 + zc2 * zc2);
    p.tolerance_m = o.depth_tolerance_m + o.depth_tolerance_sigmas * sigma;
    pairs.push_back(p);
  }
  std::vector<char> agree(pairs.size(), 0);
  auto selectAgreeing = [&pairs, &agree](const Eigen::Isometry3d& T) {
    int n = 0;
    for (std::size_t i = 0; i < pairs.size(); ++i) {
      agree[i] = (T * pairs[i].p_query - pairs[i].p_cand).norm() <= pairs[i].tolerance_m;
      n += agree[i];
    }
    return n;
  };
  int n_agree = selectAgreeing(T_cc_qc);
  // Each point's noise: across the ray verify_keypoint_sigma_px at its range, along it the
  // depth noise (coeff z^2, stretched from z to the ray).
  const double f = 0.5 * (cam_.fx + cam_.fy);
  auto rgbdPoint = [&](const Eigen::Vector3d& p) {
    const double range = p.norm();
    // (The floor keeps the covariance invertible when the depth noise is configured as 0.)
    return RgbdPoint{p, o.keypoint_sigma_px * range / f,
                     std::max(1e-6, o.depth_noise_coeff * p.z() * range)};
  };
  for (int round = 0; round < o.refine_rounds; ++round) {
    std::vector<RgbdPoint> src, dst;
    for (std::size_t i = 0; i < pairs.size(); ++i) {
      if (!agree[i]) continue;
      src.push_back(rgbdPoint(pairs[i].p_query));
      dst.push_back(rgbdPoint(pairs[i].p_cand));
    }
    Eigen::Isometry3d T_fit = T_cc_qc;
    if (!refineRigidAnisotropic(src, dst, kRefineIterations, T_fit)) break;
    const Eigen::Isometry3d T_prev = T_cc_qc;
    T_cc_qc = T_fit;
    const int n_new = selectAgreeing(T_cc_qc);
    if (n_new < n_agree) {  // a refit may not lose support: keep the better pose
      T_cc_qc = T_prev;
      n_agree = selectAgreeing(T_cc_qc);
      break;
    }
    n_agree = n_new;
  }
  c.depth_inliers = n_agree;
  const double fraction = pairs.empty() ? 0.0 : static_cast<double>(n_agree) / pairs.size();
  if (n_agree < o.min_depth_inliers || fraction < o.min_depth_inlier_fraction)
    return reject(LoopRejection::DepthDisagreement,
                  cat(n_agree, " of ", pairs.size(),
                      " PnP inliers with depth on both sides agree (verify_min_depth_inliers ",
                      o.min_depth_inliers, ", verify_min_depth_inlier_fraction ",
                      o.min_depth_inlier_fraction, ")"));

  // --- residuals under the final pose ---
  T_qc_cc = T_cc_qc.inverse();
  double sq_px = 0.0;
  int n_px = 0;
  for (int i : inliers) {
    const DescriptorMatch& m = matches[static_cast<std::size_t>(i)];
    Eigen::Vector2d uv;
    if (!cam_.project(
            T_qc_cc * dc.keypoints_p_cam[static_cast<std::size_t>(m.train)].cast<double>(), uv))
      continue;
    sq_px += (uv - dq.keypoints_uv[static_cast<std::size_t>(m.query)].cast<double>()).squaredNorm();
    ++n_px;
  }
  c.reprojection_rms_px = n_px > 0 ? std::sqrt(sq_px / n_px) : 0.0;
  double sq_m = 0.0;
  for (std::size_t i = 0; i < pairs.size(); ++i)
    if (agree[i]) sq_m += (T_cc_qc * pairs[i].p_query - pairs[i].p_cand).squaredNorm();
  c.depth_rms_m = std::sqrt(sq_m / n_agree);
  c.T_from_to = T_body_cam_ * T_cc_qc * T_cam_body_;

  // --- free space: neither keyframe's surfaces where the other saw through ---
  if ((!frames_related || o.freespace_for_loops) && !query.depth_grid.empty() &&
      !candidate.depth_grid.empty()) {
    FreeSpaceTally count;
    compareGrids(query.depth_grid, candidate.depth_grid, T_cc_qc, cam_, max_xn_, o, count);
    compareGrids(candidate.depth_grid, query.depth_grid, T_qc_cc, cam_, max_xn_, o, count);
    c.freespace_compared = count.compared;
    c.freespace_conflicts = count.conflicts;
    if (count.compared >= o.freespace_min_samples &&
        count.conflicts > o.freespace_max_conflict_fraction * count.compared)
      return reject(LoopRejection::FreeSpaceConflict,
                    cat(count.conflicts, " of ", count.compared,
                        " compared depth samples lie in the other keyframe's free space (> "
                        "verify_freespace_max_conflict_fraction ",
                        o.freespace_max_conflict_fraction, ")"));
  }

  // --- gravity: roll/pitch implied by the loop vs the query's own gravity-aligned pose ---
  const Eigen::Matrix3d R_world_cand = candidate.T_world_body.linear();
  const Eigen::Matrix3d R_world_query_loop = R_world_cand * c.T_from_to.linear();
  const Eigen::Vector3d down(0.0, 0.0, -1.0);
  const double gravity_deg = angleBetween(R_world_query_loop.transpose() * down,
                                          query.T_world_body.linear().transpose() * down) *
                             kRadToDeg;
  if (gravity_deg > o.max_gravity_deg)
    return reject(LoopRejection::GravityMismatch,
                  cat("gravity directions differ by ", gravity_deg,
                      " deg > verify_max_gravity_deg ", o.max_gravity_deg));

  // --- yaw and translation of the relative pose ---
  const double yaw_deg =
      std::abs(wrapAngle(heading(R_world_query_loop) - heading(R_world_cand))) * kRadToDeg;
  if (yaw_deg > o.max_yaw_deg)
    return reject(LoopRejection::YawGate,
                  cat("relative yaw ", yaw_deg, " deg > verify_max_yaw_deg ", o.max_yaw_deg));
  const double distance_m = c.T_from_to.translation().norm();
  if (distance_m > o.max_translation_m)
    return reject(LoopRejection::TranslationGate,
                  cat("relative translation ", distance_m, " m > verify_max_translation_m ",
                      o.max_translation_m));

  // --- drift budget: the correction must be one the odometry can have accumulated ---
  if (frames_related) {
    const Eigen::Isometry3d T_world_query_loop = candidate.T_world_body * c.T_from_to;
    const double travelled = std::max(0.0, query.travelled_m - candidate.travelled_m);
    const double dp = (T_world_query_loop.translation() - query.T_world_body.translation()).norm();
    const double dyaw = std::abs(wrapAngle(heading(T_world_query_loop.linear()) -
                                           heading(query.T_world_body.linear()))) *
                        kRadToDeg;
    const double budget_m = o.drift_base_m + o.drift_fraction * travelled;
    const double budget_deg = o.drift_base_deg + o.drift_deg_per_m * travelled;
    if (dp > budget_m)
      return reject(LoopRejection::DriftBudget,
                    cat("position correction ", dp, " m > budget ", budget_m, " m after ",
                        travelled, " m travelled"));
    if (dyaw > budget_deg)
      return reject(LoopRejection::DriftBudget,
                    cat("heading correction ", dyaw, " deg > budget ", budget_deg, " deg after ",
                        travelled, " m travelled"));
  }

  result.accepted = true;
  result.reason = LoopRejection::Accepted;
  return result;
}

}  // namespace rgbdi::loop
