#include "rgbdi/frontend/feature_tracker.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>
#include <sstream>
#include <stdexcept>

#include "frontend/epipolar_ransac.h"
#include "frontend/feature_spacing.h"
#include "frontend/stopwatch.h"
#include "rgbdi/common/motion_field.h"
#include "rgbdi/frontend/corner_detector.h"
#include "rgbdi/frontend/depth_sampling.h"
#include "rgbdi/frontend/occlusion_test.h"

namespace rgbdi::frontend {
namespace {

[[noreturn]] void failFrame(const RgbdFrame& frame, const std::string& what) {
  const std::string where =
      frame.source_label.empty() ? "frame " + std::to_string(frame.index) : frame.source_label;
  throw std::invalid_argument("FeatureTracker: " + where + ": " + what);
}

}  // namespace

FeatureTracker::FeatureTracker(const FrontendOptions& options, const PinholeCamera& cam_color)
    : options_(options),
      cam_(cam_color),
      registrar_(options),
      detector_(std::make_unique<CornerDetector>()),
      preparer_(options) {
  options_.validate();
  if (!cam_.valid())
    throw std::invalid_argument("FeatureTracker: colour camera intrinsics are not valid (size " +
                                std::to_string(cam_.width) + "x" + std::to_string(cam_.height) +
                                ", fx " + std::to_string(cam_.fx) + ", fy " +
                                std::to_string(cam_.fy) + ")");
  // Results do not depend on it (the parallel loops split work over independent pixels/points).
  applyOpenCvThreads(options_);
}

FeatureTracker::~FeatureTracker() = default;
FeatureTracker::FeatureTracker(FeatureTracker&&) noexcept = default;
FeatureTracker& FeatureTracker::operator=(FeatureTracker&&) noexcept = default;

void FeatureTracker::reset() {
  has_previous_ = false;
  previous_pyramid_.clear();
  previous_tracks_.clear();
}

std::vector<FeatureTracker::Track> FeatureTracker::trackPrevious(
    const std::vector<cv::Mat>& pyramid, const std::optional<CameraMotion>& motion,
    FeatureFrame& out) {
  Stopwatch watch;
  const cv::Size window(options_.klt_window_px, options_.klt_window_px);
  const cv::TermCriteria criteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS,
                                  options_.klt_max_iterations, options_.klt_epsilon_px);
  const size_t n = previous_tracks_.size();
  std::vector<cv::Point2f> previous_uv(n), current_uv;
  for (size_t i = 0; i < n; ++i) previous_uv[i] = previous_tracks_[i].uv;
  std::vector<std::uint8_t> status;
  int flags = 0;
  const bool predict = motion && options_.klt_predict_rotation && n > 0;
  // Where the motion moves a point (its bearing turned into the other camera frame; with a
  // translation, its point at its depth moved too), for points it moves beyond the pyramid's
  // reach (half a window at the coarsest level): KLT cannot find those by itself. Nearer points
  // keep their start, as without a prediction: KLT finds them, and the backward check keeps its
  // independence from the forward result, which drops ambiguous features (repetitive texture)
  // that a hint in both passes would let through. (Measured: predicting every feature moved the
  // odometry ATE of single sequences by -24 to +41 %, more often up; doc/frontend.md.)
  const double reach =
      options_.klt_predict_every_feature
          ? 0.0
          : 0.5 * options_.klt_window_px * std::pow(2.0, options_.klt_pyramid_levels);
  // `xn_from`: from's undistorted normalised position (the tracks keep theirs); `depth_from`
  // [m] its depth in from's camera (0: unknown, the rotation alone moves it); `depth_to`
  // receives its depth in to's camera (0 when unknown).
  auto predicted = [&](const cv::Point2f& from, const Eigen::Vector2d& xn_from, double depth_from,
                       const Eigen::Matrix3d& R_to_from, const Eigen::Vector3d* p_to_from,
                       double& depth_to) {
    depth_to = 0.0;
    Eigen::Vector3d point = R_to_from * xn_from.homogeneous();
    if (p_to_from && depth_from > 0.0) {
      point = depth_from * point + *p_to_from;
      depth_to = point.z();
    }
    Eigen::Vector2d uv;
    if (!cam_.project(point, uv)) return from;
    const cv::Point2f to(static_cast<float>(uv.x()), static_cast<float>(uv.y()));
    const cv::Point2f shift = to - from;
    return double(shift.dot(shift)) >= reach * reach ? to : from;
  };
  // The same motion both ways: T_current_previous for the forward pass, its inverse back.
  Eigen::Matrix3d R_current_previous = Eigen::Matrix3d::Identity();
  Eigen::Vector3d p_current_previous = Eigen::Vector3d::Zero();
  const Eigen::Vector3d* p_forward = nullptr;
  const Eigen::Vector3d* p_backward = nullptr;
  std::vector<double> depth_current(n, 0.0);
  if (predict) {
    R_current_previous = motion->R_previous_current.transpose();
    if (motion->p_previous_current) {
      p_current_previous = -(R_current_previous * *motion->p_previous_current);
      p_forward = &p_current_previous;
      p_backward = &*motion->p_previous_current;
    }
    current_uv.resize(n);
    for (size_t i = 0; i < n; ++i)
      current_uv[i] = predicted(previous_uv[i], previous_tracks_[i].xn, previous_tracks_[i].depth_m,
                                R_current_previous, p_forward, depth_current[i]);
    flags = cv::OPTFLOW_USE_INITIAL_FLOW;
  }
  // No error output (cv::noArray()): OpenCV would interpolate every window once more to fill it,
  // and nothing here reads it.
  if (n > 0)
    cv::calcOpticalFlowPyrLK(previous_pyramid_, pyramid, previous_uv, current_uv, status,
                             cv::noArray(), window, options_.klt_pyramid_levels, criteria, flags);

  // Forward success, border and texture checks first, so the backward pass only runs on
  // candidates. KLT converges on sensor noise too: on an image with no corner above the texture
  // floor anywhere (a bare wall filling the view, the lights out) no track is kept.
  const bool textureless = n > 0 && options_.min_gradient_grey_per_px > 0.0 &&
                           !detector_->hasCorner(pyramid[1], options_.shi_tomasi_block_size,
                                                 options_.min_gradient_grey_per_px);
  std::vector<size_t> candidates;
  for (size_t i = 0; i < n; ++i) {
    if (!status[i]) {
      ++out.n_klt_lost;
      continue;
    }
    if (!cam_.inImage({current_uv[i].x, current_uv[i].y}, options_.border_px)) {
      ++out.n_border_rejected;
      continue;
    }
    if (textureless) {
      ++out.n_low_texture;
      continue;
    }
    candidates.push_back(i);
  }

  // Backward check: track the new positions back to the previous image. It starts from the new
  // positions themselves, moved back by the motion when one is given (no hint from the old
  // positions; the depth is the one the forward prediction gave the point here), so a wrong
  // forward match cannot be pulled back onto its starting point by the initial guess.
  std::vector<cv::Point2f> forward(candidates.size()), backward;
  for (size_t k = 0; k < candidates.size(); ++k) forward[k] = current_uv[candidates[k]];
  if (predict) {
    backward.resize(forward.size());
    double unused_depth = 0.0;
    for (size_t k = 0; k < forward.size(); ++k)
      backward[k] = predicted(forward[k], cam_.pixelToNormalized({forward[k].x, forward[k].y}),
                              depth_current[candidates[k]], motion->R_previous_current, p_backward,
                              unused_depth);
  }
  std::vector<std::uint8_t> back_status;
  if (!forward.empty())
    cv::calcOpticalFlowPyrLK(pyramid, previous_pyramid_, forward, backward, back_status,
                             cv::noArray(), window, options_.klt_pyramid_levels, criteria, flags);
  const double max_fb2 =
      options_.klt_max_forward_backward_px * options_.klt_max_forward_backward_px;
  std::vector<Track> survivors;
  std::vector<Eigen::Vector2d> previous_xn, current_xn;
  for (size_t k = 0; k < candidates.size(); ++k) {
    const cv::Point2f miss = backward[k] - previous_uv[candidates[k]];
    if (!back_status[k] || double(miss.dot(miss)) > max_fb2) {
      ++out.n_klt_lost;
      continue;
    }
    const Track& old = previous_tracks_[candidates[k]];
    Track moved{old.id,         forward[k], cam_.pixelToNormalized({forward[k].x, forward[k].y}),
                old.length + 1, old.xn,     0.0};
    previous_xn.push_back(old.xn);
    current_xn.push_back(moved.xn);
    survivors.push_back(moved);
  }
  out.timings.klt_ms = watch.lapMs();

  const std::vector<std::uint8_t> inlier = epipolarInliers(
      previous_xn, current_xn, cam_, options_.ransac_threshold_px, options_.ransac_confidence);
  std::vector<Track> kept;
  kept.reserve(survivors.size());
  for (size_t k = 0; k < survivors.size(); ++k) {
    if (!inlier[k]) {
      ++out.n_ransac_rejected;
      continue;
    }
    kept.push_back(survivors[k]);
  }
  out.timings.ransac_ms = watch.lapMs();
  return kept;
}

FeatureSpacing FeatureTracker::distribute(const cv::Size& image, std::vector<Track>& tracks,
                                          FeatureFrame& out) {
  // Longest-tracked features claim their neighbourhood first: they carry the most constraints
  // for the estimator. Ties go to the older (smaller) id, which keeps the result deterministic.
  std::vector<size_t> order(tracks.size());
  std::iota(order.begin(), order.end(), size_t{0});
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    if (tracks[a].length != tracks[b].length) return tracks[a].length > tracks[b].length;
    return tracks[a].id < tracks[b].id;
  });
  FeatureSpacing spacing(image.width, image.height, options_.min_distance_px);
  std::vector<bool> keep(tracks.size(), false);
  for (size_t i : order) {
    if (spacing.isFree(tracks[i].uv)) {
      spacing.accept(tracks[i].uv);
      keep[i] = true;
    } else {
      ++out.n_too_close;
    }
  }
  std::vector<Track> kept;
  for (size_t i = 0; i < tracks.size(); ++i)
    if (keep[i]) kept.push_back(tracks[i]);  // stays in id order
  tracks.swap(kept);
  return spacing;
}

int FeatureTracker::depthWindowRadius() const {
  // sampleDepth reads depth_neighbourhood_px around the rounded position plus the bilinear
  // support one pixel further; the occlusion test reads its whole window.
  return std::max(options_.depth_neighbourhood_px + 1, options_.occlusion_window_px);
}

Eigen::Vector2d FeatureTracker::depthPixel(const Track& t, double dt,
                                           const std::optional<CameraMotion>& motion) const {
  const Eigen::Vector2d uv(t.uv.x, t.uv.y);
  if (rolling_shutter_.global() || !(dt > 0.0)) return uv;
  Eigen::Vector2d v;  // [1/s] normalised-plane velocity
  if (motion && motion->omega_cam && (t.length <= 1 || (t.depth_m > 0.0 && motion->v_cam))) {
    // The motion field at the stamp: the gyroscope's rate there, and the camera's velocity at
    // the feature's last depth (a new feature: the rotation's part).
    const Eigen::Vector3d v_cam =
        t.depth_m > 0.0 && motion->v_cam ? *motion->v_cam : Eigen::Vector3d::Zero();
    v = motionFieldVelocity(t.xn, t.depth_m, *motion->omega_cam, v_cam);
  } else if (t.length > 1) {
    v = (t.xn - t.xn_velocity_from) / dt;  // as the observation's velocity
  } else if (motion) {
    // Where the rotation alone had the bearing in the previous image.
    const Eigen::Vector3d b = motion->R_previous_current * t.xn.homogeneous();
    if (!(b.z() > 0.0)) return uv;
    v = (t.xn - b.head<2>() / b.z()) / dt;
  } else {
    return uv;
  }
  return uv - rolling_shutter_.rowTime(uv.y()) * Eigen::Vector2d(cam_.fx * v.x(), cam_.fy * v.y());
}

void FeatureTracker::dropOccluded(std::vector<Track>& tracks, std::vector<cv::Point2f>& occupied,
                                  int& dropped, double dt,
                                  const std::optional<CameraMotion>& motion) const {
  std::vector<Track> kept;
  kept.reserve(tracks.size());
  for (const Track& t : tracks) {
    if (straddlesOcclusion(depth_m_, depthPixel(t, dt, motion), options_)) {
      occupied.push_back(t.uv);
      ++dropped;
    } else {
      kept.push_back(t);
    }
  }
  tracks.swap(kept);
}

void FeatureTracker::detectNew(const RgbdFrame& frame, const cv::Mat& derivatives,
                               std::vector<Track>& tracks, std::vector<cv::Point2f>& occupied,
                               FeatureSpacing& spacing, FeatureFrame& out) {
  int missing = options_.max_features - static_cast<int>(tracks.size());
  if (missing <= 0 || missing < options_.detect_min_missing) return;
  detector_->computeResponse(derivatives, options_.shi_tomasi_block_size);
  // The mask keeps the detector away from the border band and from existing features (which
  // also makes the quality threshold relative to the strongest corner where new ones can go);
  // its circles are one pixel wider than min_distance_px because they are drawn around rounded
  // centres. The exact distance test in the detector has the last word.
  cv::Mat& mask = detection_mask_;
  mask.create(frame.rgb.size(), CV_8UC1);
  mask.setTo(0);
  const int b = options_.border_px;
  if (mask.cols > 2 * b && mask.rows > 2 * b)
    mask(cv::Rect(b, b, mask.cols - 2 * b, mask.rows - 2 * b)).setTo(255);
  const int radius = static_cast<int>(std::ceil(options_.min_distance_px)) + 1;
  for (const Track& t : tracks)
    cv::circle(mask, cv::Point(cvRound(t.uv.x), cvRound(t.uv.y)), radius, cv::Scalar(0),
               cv::FILLED);
  for (const cv::Point2f& p : occupied)
    cv::circle(mask, cv::Point(cvRound(p.x), cvRound(p.y)), radius, cv::Scalar(0), cv::FILLED);
  std::vector<cv::Point2f> corners = detector_->detect(mask, missing, options_.shi_tomasi_quality,
                                                       options_.min_gradient_grey_per_px, spacing);
  const bool with_depth = frame.hasDepth();
  const bool check = with_depth && options_.occlusion_window_px > 0;
  // Refused corners are replaced by the next candidates; a few rounds at most bound the cost
  // when a scene is full of edges (what is still missing then is detected in the next image).
  constexpr int kMaxRounds = 4;
  for (int round = 0; !corners.empty(); ++round) {
    std::vector<Eigen::Vector2d> centres;
    for (const cv::Point2f& c : corners) centres.emplace_back(c.x, c.y);
    if (with_depth)
      registrar_.registerMoreDepthAround(frame, cam_, centres, depthWindowRadius(), depth_m_);
    for (size_t k = 0; k < corners.size(); ++k) {
      if (check && straddlesOcclusion(depth_m_, centres[k], options_)) {
        ++out.n_occluded_skipped;
        continue;
      }
      const cv::Point2f& c = corners[k];
      tracks.push_back(Track{next_id_++, c, cam_.pixelToNormalized({c.x, c.y}), 1,
                             Eigen::Vector2d::Zero(), 0.0});
      ++out.n_new;
      --missing;
    }
    if (missing <= 0 || round + 1 == kMaxRounds) break;
    corners = detector_->detectMore(missing, spacing);
  }
}

FeatureFrame FeatureTracker::track(const RgbdFrame& frame,
                                   const std::optional<CameraMotion>& motion,
                                   const PreparedImage* prepared) {
  Stopwatch total, step;
  if (!frame.hasColor()) failFrame(frame, "no colour image (the front end tracks colour images)");
  if (frame.rgb.type() != CV_8UC3 && frame.rgb.type() != CV_8UC1)
    failFrame(frame, "colour image must be CV_8UC3 (RGB) or CV_8UC1, got OpenCV type " +
                         std::to_string(frame.rgb.type()));
  if (frame.rgb.cols != cam_.width || frame.rgb.rows != cam_.height)
    failFrame(frame, "colour image is " + std::to_string(frame.rgb.cols) + "x" +
                         std::to_string(frame.rgb.rows) + " but the camera is " +
                         std::to_string(cam_.width) + "x" + std::to_string(cam_.height));
  if (!std::isfinite(frame.t)) failFrame(frame, "timestamp is not finite");
  if (has_previous_ && !(frame.t > previous_t_)) {
    std::ostringstream os;
    os.precision(17);
    os << "timestamp " << frame.t << " s is not after the previous image's " << previous_t_ << " s";
    failFrame(frame, os.str());
  }

  FeatureFrame out;
  out.t = frame.t;
  out.frame_index = frame.index;

  // Grey image and corner response: prepared ahead by the caller, or here.
  cv::Mat grey;
  if (prepared) {
    if (!prepared->matches(frame, preparer_.recipe()))
      failFrame(frame,
                "the prepared image given with it was made from another frame or with "
                "other front-end options");
    grey = prepared->grey;
    out.timings.grey_ms = prepared->grey_ms;
  } else {
    grey = preparer_.grey(frame);
    out.timings.grey_ms = step.lapMs();
  }
  // Two pyramids alternate: the one of the image before last is rebuilt in place (no new
  // allocations). Derivatives are stored with the pyramid: this image is the source of the
  // backward check now and of the forward pass next time, so they are computed once, not twice.
  std::vector<cv::Mat>& pyramid = spare_pyramid_;
  const cv::Size window(options_.klt_window_px, options_.klt_window_px);
  cv::buildOpticalFlowPyramid(grey, pyramid, window, options_.klt_pyramid_levels, true);
  out.timings.pyramid_ms = step.lapMs();

  std::vector<Track> tracks;
  if (has_previous_) tracks = trackPrevious(pyramid, motion, out);
  step.lapMs();  // klt_ms and ransac_ms were taken inside
  FeatureSpacing spacing = distribute(frame.rgb.size(), tracks, out);
  out.timings.detect_ms = step.lapMs();

  const double dt = has_previous_ ? frame.t - previous_t_ : 0.0;
  const bool with_depth = frame.hasDepth();
  // Depth is registered only in the windows around features (the full image would cost several
  // times more): first around the tracked ones, which are checked for occlusion boundaries
  // before new corners are placed, then around each batch of new corners.
  std::vector<cv::Point2f> occupied;
  if (with_depth) {
    std::vector<Eigen::Vector2d> centres;
    centres.reserve(tracks.size());
    for (const Track& t : tracks) centres.push_back(depthPixel(t, dt, motion));
    registrar_.registerDepthAround(frame, cam_, centres, depthWindowRadius(), depth_m_);
    dropOccluded(tracks, occupied, out.n_occluded, dt, motion);
  }
  out.n_tracked = static_cast<int>(tracks.size());
  out.timings.depth_ms = step.lapMs();
  // New corners come from the corner response of pyramid[1] (the base image's Scharr
  // derivatives); tracked ones were checked against its texture floor.
  detectNew(frame, pyramid[1], tracks, occupied, spacing, out);
  out.timings.detect_ms += step.lapMs();
  // tracks: the tracked ones in id order, then the new ones with larger ids.

  // Where the depth of each feature is read (rolling shutter: at the stamp's position); the new
  // features' windows were registered around where they were seen.
  std::vector<Eigen::Vector2d> depth_at;
  depth_at.reserve(tracks.size());
  for (const Track& t : tracks) depth_at.push_back(depthPixel(t, dt, motion));
  if (with_depth && !rolling_shutter_.global())
    registrar_.registerMoreDepthAround(frame, cam_, depth_at, depthWindowRadius(), depth_m_);
  out.features.reserve(tracks.size());
  for (std::size_t k = 0; k < tracks.size(); ++k) {
    Track& t = tracks[k];
    FeatureObservation obs;
    obs.id = t.id;
    obs.uv = Eigen::Vector2d(t.uv.x, t.uv.y);
    obs.xn = t.xn;
    obs.track_length = t.length;
    if (t.length > 1) obs.velocity_xn = (t.xn - t.xn_velocity_from) / dt;
    if (with_depth) obs.depth_m = sampleDepth(depth_m_, depth_at[k], options_);
    if (obs.depth_m > 0.0) ++out.n_with_depth;
    t.depth_m = obs.depth_m;  // where the next image's prediction places it
    out.features.push_back(obs);
  }
  out.timings.depth_ms += step.lapMs();

  std::swap(previous_pyramid_, spare_pyramid_);
  previous_tracks_ = std::move(tracks);
  previous_t_ = frame.t;
  has_previous_ = true;
  // The preparation counts wherever it ran (this thread's CPU has it only when it ran here).
  out.timings.total_ms = total.lapMs() + (prepared ? prepared->cpuMs() : 0.0);
  return out;
}

}  // namespace rgbdi::frontend
