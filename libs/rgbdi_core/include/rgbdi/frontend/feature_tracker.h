// KLT feature tracker of the visual front end: one colour image in, the tracked features out.
#pragma once

#include <cstdint>
#include <memory>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <vector>

#include "rgbdi/common/camera.h"
#include "rgbdi/common/rolling_shutter.h"
#include "rgbdi/common/types.h"
#include "rgbdi/frontend/depth_registration.h"
#include "rgbdi/frontend/feature_frame.h"
#include "rgbdi/frontend/frontend_options.h"
#include "rgbdi/frontend/prepared_image.h"

namespace rgbdi::frontend {

class CornerDetector;

/// The camera's motion from the previous image to this one as the IMU predicts it: where KLT
/// starts features that move beyond the pyramid's reach.
struct CameraMotion {
  /// Rotation only (the gyroscope): implicit, so a rotation can be passed where a motion is asked.
  CameraMotion(const Eigen::Matrix3d& R) : R_previous_current(R) {}  // NOLINT
  CameraMotion(const Eigen::Matrix3d& R, const Eigen::Vector3d& p)
      : R_previous_current(R), p_previous_current(p) {}
  /// This image's camera orientation in the previous image's camera frame.
  Eigen::Matrix3d R_previous_current;
  /// [m] this image's camera centre in the previous image's camera frame (dead reckoning from
  /// the estimated velocity); absent: the rotation alone predicts (points taken as far away).
  std::optional<Eigen::Vector3d> p_previous_current;
  /// [rad/s] the camera's angular velocity at this image's stamp, in its frame (the gyroscope at
  /// the stamp): what moves a rolling-shutter row's observation to the stamp.
  std::optional<Eigen::Vector3d> omega_cam;
  /// [m/s] the camera centre's velocity at this image's stamp, in its frame (dead reckoning).
  std::optional<Eigen::Vector3d> v_cam;
};

/// Tracks Shi-Tomasi corners with pyramidal KLT across consecutive colour images.
///
/// Per image: grey conversion; forward KLT from the previous image and a backward KLT check
/// (dropped when the round trip misses the start by more than klt_max_forward_backward_px);
/// border check; fundamental-matrix RANSAC on undistorted points scaled to the camera's focal
/// length; the survivors are kept longest-tracked first at least min_distance_px apart, and new
/// corners are detected outside their neighbourhoods up to max_features. Each feature gets its
/// undistorted normalised position, its velocity in normalised coordinates and a robust depth
/// (sampleDepth on the depth registered to colour, when the frame has depth).
///
/// Deterministic: the same images give the same ids and positions (ids start at 0).
/// Not thread-safe; use one tracker per camera stream.
class FeatureSpacing;

class FeatureTracker {
 public:
  /// `cam_color` is the colour camera used for undistortion and depth registration (the
  /// intrinsics stored in frames are not used). Throws ConfigError for invalid options and
  /// std::invalid_argument for invalid intrinsics.
  FeatureTracker(const FrontendOptions& options, const PinholeCamera& cam_color);
  ~FeatureTracker();
  FeatureTracker(FeatureTracker&&) noexcept;
  FeatureTracker& operator=(FeatureTracker&&) noexcept;

  /// Throws std::invalid_argument (naming frame.source_label) when the frame has no colour image,
  /// an unsupported image type, a size different from the camera's, or a stamp not after the
  /// previous frame's. `motion`: this image's camera in the previous image's camera frame (the
  /// gyroscope's rotation, and the translation when known); when given and klt_predict_rotation
  /// is on, KLT starts a feature that the motion moves beyond the pyramid's reach where the motion
  /// puts it (a fast turn; with a translation, also a fast move past near surfaces: a feature's
  /// depth in the previous image places it), otherwise at its previous position.
  /// `prepared`: the frame's image prepared ahead (ImagePreparer with these options, e.g. on the
  /// thread that feeds the tracker; read during this call only). Without it
  /// the tracker prepares the image itself; the result is the same. Throws
  /// std::invalid_argument when `prepared` was made from another frame or with other options.
  FeatureFrame track(const RgbdFrame& frame,
                     const std::optional<CameraMotion>& motion = std::nullopt,
                     const PreparedImage* prepared = nullptr);

  /// Forgets all tracks (e.g. after the estimator resets); ids keep increasing.
  void reset();

  const FrontendOptions& options() const { return options_; }
  const PinholeCamera& camera() const { return cam_; }
  /// The colour images' row timing (default global shutter). With a rolling shutter the depth of
  /// a tracked feature is sampled where the feature is at the image's stamp (the depth image is a
  /// global-shutter image at the stamp): its pixel moved back by its row's time along its image
  /// velocity. The feature's uv and xn stay as observed (the estimator compensates those).
  void setRollingShutter(const RollingShutter& rs) { rolling_shutter_ = rs; }

 private:
  /// State of one feature between images.
  struct Track {
    std::uint64_t id;
    cv::Point2f uv;
    Eigen::Vector2d xn;
    int length;
    Eigen::Vector2d xn_velocity_from;  ///< xn in the previous image (for the velocity)
    double depth_m = 0.0;  ///< [m] sensor depth in the image it was last seen in; 0 = none
  };

  /// Forward/backward KLT, border and RANSAC checks; returns the surviving tracks moved to the
  /// current image (positions updated, lengths incremented).
  std::vector<Track> trackPrevious(const std::vector<cv::Mat>& pyramid,
                                   const std::optional<CameraMotion>& motion, FeatureFrame& out);
  /// Keeps features min_distance_px apart (longest-tracked first); returns the spacing of those
  /// kept.
  FeatureSpacing distribute(const cv::Size& image, std::vector<Track>& tracks, FeatureFrame& out);
  /// Drops the tracks whose window straddles an occlusion boundary in depth_m_ (their places stay
  /// taken in `spacing` and in `occupied`, so no corner on the same edge replaces them at once).
  void dropOccluded(std::vector<Track>& tracks, std::vector<cv::Point2f>& occupied, int& dropped,
                    double dt, const std::optional<CameraMotion>& motion) const;
  /// [px] where `t` is at the image's stamp, for the depth image: its pixel, moved back along its
  /// image velocity by its row's time under a rolling shutter (pixel velocity from fx, fy:
  /// distortion neglected over the few pixels of the shift). The velocity is the motion field
  /// at the stamp from `motion`'s omega_cam and v_cam at the feature's last depth (a new
  /// feature: the rotation's part); a tracked feature without either its tracked velocity
  /// (over `dt` [s]); without omega_cam, a new feature's velocity is what R_previous_current
  /// explains, and none without a motion.
  Eigen::Vector2d depthPixel(const Track& t, double dt,
                             const std::optional<CameraMotion>& motion) const;
  /// Tops `tracks` up to max_features with new corners away from `occupied` once at least
  /// detect_min_missing are missing (corner response from `derivatives`, the base image's CV_16SC2
  /// Scharr derivatives); with depth, corners on occlusion boundaries are refused and the next
  /// candidates taken instead.
  void detectNew(const RgbdFrame& frame, const cv::Mat& derivatives, std::vector<Track>& tracks,
                 std::vector<cv::Point2f>& occupied, FeatureSpacing& spacing, FeatureFrame& out);
  /// Half-size of the depth windows registered around features.
  int depthWindowRadius() const;

  FrontendOptions options_;
  PinholeCamera cam_;
  RollingShutter rolling_shutter_;  ///< of the colour images; global by default
  DepthRegistrar registrar_;
  std::unique_ptr<CornerDetector> detector_;  ///< keeps its work buffers between images
  ImagePreparer preparer_;  ///< grey images of frames that come without a prepared one
  cv::Mat depth_m_;         ///< registered depth around the current features (reused buffer)
  cv::Mat detection_mask_;  ///< per-image work buffer, reused

  bool has_previous_ = false;
  double previous_t_ = 0.0;
  std::vector<cv::Mat> previous_pyramid_;
  std::vector<cv::Mat> spare_pyramid_;  ///< rebuilt for each new image (keeps its memory)
  std::vector<Track> previous_tracks_;
  std::uint64_t next_id_ = 0;
};

}  // namespace rgbdi::frontend
