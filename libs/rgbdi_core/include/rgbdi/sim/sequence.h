// A simulated RGB-D-inertial sequence: a motion profile, its scene, the synthesised IMU and
// rendered noisy RGB-D frames, exposed as a source that feeds the same MeasurementSink push
// interface as the rawlog reader (so end-to-end tests stream straight into the estimator), and
// as random-access ground truth.
//
// Clocks: the IMU clock is the reference. IMU sample k is stamped start + k / imu_rate (a
// recording: its own stamps; start is its first replayed ground-truth stamp). Frame i
// is exposed at IMU time start + i / fps and stamped t_cam = t_imu - time_offset_s (so that
// t_imu = t_cam + time_offset_s, the [extrinsic] time_offset_s convention).
// Everything random is a pure function of (seed, sample or frame index): output is identical for
// a seed whatever the access order, and frames can be rendered on another thread.
#pragma once

#include <Eigen/Geometry>
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "rgbdi/common/ini_reader.h"
#include "rgbdi/common/measurement_sink.h"
#include "rgbdi/common/rolling_shutter.h"
#include "rgbdi/common/sensor_options.h"
#include "rgbdi/common/types.h"
#include "rgbdi/sim/depth_artefacts.h"
#include "rgbdi/sim/exposure.h"
#include "rgbdi/sim/imu_split_stream.h"
#include "rgbdi/sim/imu_synth.h"
#include "rgbdi/sim/profile_scene.h"
#include "rgbdi/sim/profiles.h"
#include "rgbdi/sim/recorded_motion.h"
#include "rgbdi/sim/recording.h"
#include "rgbdi/sim/renderer.h"
#include "rgbdi/sim/scene.h"
#include "rgbdi/sim/sensor_noise.h"
#include "rgbdi/sim/wheel_encoder_synth.h"

namespace rgbdi::sim {

struct SimOptions {
  ProfileOptions profile;
  ProfileSceneOptions scene;   ///< [sim] aliased_walls, world_seed, room and furniture keys
  ImuSynthOptions imu;         ///< the TRUE IMU noise (and errors, separate streams)
  CameraOptions camera;        ///< colour (= depth) camera, [camera]
  ExtrinsicOptions extrinsic;  ///< T_body_cam, [extrinsic] (its time_offset_s is not used)
  DepthNoiseOptions depth_noise;
  DepthArtefactOptions depth_artefacts;  ///< flying pixels, dark / grazing holes (default off)
  ColorNoiseOptions color_noise;
  ExposureOptions exposure;  ///< auto-exposure gain of the colour image (default off)
  RenderOptions render;
  double fps = 30.0;           ///< [Hz]
  std::uint64_t seed = 1;      ///< noise and textures
  double time_offset_s = 0.0;  ///< [s] t_cam = t_imu - time_offset_s
  /// [s] image stamps jitter uniformly in +-this around the exposure time (seeded per frame);
  /// the ground truth stays at the true exposure time. 0 = exact stamps.
  double frame_stamp_jitter_s = 0.0;
  double start_time_s = 1000.0;  ///< [s] stamp of the first IMU sample
  /// Densities written to the sequence's config.ini = truth * this (a user never knows them).
  double config_noise_inflation = 2.0;
  /// Render frames on a second thread while the consumer works on the previous one.
  bool prefetch_frames = true;
  /// A forced tracking loss: frames exposed in [start, start + duration) of the sequence's time
  /// are impaired as blackout_kind says; the IMU is unaffected.
  double blackout_start_s = 0.0;     ///< [s] since the first IMU sample
  double blackout_duration_s = 0.0;  ///< [s] 0 = none
  /// "black": lens covered or lights out (black colour, depth 0); "bare": a view without
  /// texture, as of a bare wall (colour the frame's mean, sensor noise on it; depth kept); "blur":
  /// motion blur (colour smeared along a horizontal line of blackout_blur_px; depth kept).
  std::string blackout_kind = "black";
  int blackout_blur_px = 41;  ///< [px] length of the blur line ("blur")
  /// Extreme rotation: the body turns spin_turns times about the world vertical between
  /// spin_start_s and spin_start_s + spin_duration_s (sequence time; smoothstep angle, peak rate
  /// 2 pi * turns * 35/16 / duration at mid-turn), on top of the profile's motion; images and
  /// IMU both see it.
  double spin_start_s = 0.0;     ///< [s] since the first IMU sample
  double spin_duration_s = 0.0;  ///< [s] 0 = none
  double spin_turns = 1.0;       ///< [turns] negative: clockwise seen from above
  /// A hybrid sequence (rgbdi-sim --profile recorded): the recording's real IMU samples and its
  /// ground truth replace the synthesised IMU and motion (profile.kind is then ignored, the
  /// profile's duration_s, when positive, cuts the recording); images are rendered along the
  /// ground truth in a world built around it. nullptr: a synthesised profile.
  std::shared_ptr<const Recording> recording;
  RecordedWorldOptions recorded_world;  ///< [sim] recorded_*
  /// Wheel encoders and odometry ([sim] wheel_*; skid steering on the tracked profile).
  WheelEncoderOptions wheel;
  /// Rolling shutter of the colour camera (common/rolling_shutter.h): [s] time to read all rows
  /// (0 = global shutter), read direction and the row the frame is stamped at (its exposure
  /// time, and the ground truth's). Depth stays a global-shutter image at the reference time.
  double rolling_shutter_readout_s = 0.0;
  std::string rolling_shutter_direction = "top_to_bottom";  ///< or "bottom_to_top"
  std::string rolling_shutter_reference_row = "middle";     ///< or "first" (the first row read)

  /// [sim] (fps, seed, time_offset_s, frame_stamp_jitter_s, start_time_s, config_noise_inflation,
  /// blackout_start_s, blackout_duration_s, blackout_kind, blackout_blur_px, spin_start_s,
  /// spin_duration_s, spin_turns, rolling_shutter_readout_s, rolling_shutter_direction,
  /// rolling_shutter_reference_row and the keys of ProfileOptions, ProfileSceneOptions,
  /// RecordedWorldOptions, WheelEncoderOptions, ImuSynthOptions, DepthNoiseOptions,
  /// DepthArtefactOptions, ColorNoiseOptions, ExposureOptions), [camera] and [extrinsic]. The
  /// profile kind is not read (command line).
  static SimOptions load(IniReader& ini);
};

/// The values SimOptions::blackout_kind may take: black, bare, blur.
const std::vector<std::string>& blackoutKinds();
/// Whether `kind` is one of blackoutKinds().
bool isBlackoutKind(const std::string& kind);
/// The values of SimOptions::rolling_shutter_direction / rolling_shutter_reference_row.
const std::vector<std::string>& rollingShutterDirections();
const std::vector<std::string>& rollingShutterReferenceRows();

/// Ground truth of the body (IMU) frame at one IMU-clock stamp.
struct GroundTruthState {
  double t = 0.0;  ///< [s] IMU-clock stamp
  Eigen::Isometry3d T_world_body = Eigen::Isometry3d::Identity();
  Eigen::Vector3d v_world = Eigen::Vector3d::Zero();     ///< [m/s]
  Eigen::Vector3d a_world = Eigen::Vector3d::Zero();     ///< [m/s^2], without gravity
  Eigen::Vector3d omega_body = Eigen::Vector3d::Zero();  ///< [rad/s]
  ImuBias bias;                                          ///< true IMU biases
};

class SimulatedSequence {
 public:
  /// Builds profile, scene, IMU and renderer. Throws std::invalid_argument on inconsistent
  /// options (e.g. a duration too short for the profile, fps <= 0).
  explicit SimulatedSequence(const SimOptions& options);
  ~SimulatedSequence();
  SimulatedSequence(const SimulatedSequence&) = delete;
  SimulatedSequence& operator=(const SimulatedSequence&) = delete;

  const SimOptions& options() const { return options_; }
  const MotionProfile& profile() const { return profile_; }
  const Scene& scene() const { return *scene_; }
  /// The IMU synthesiser (synthesised profiles only: throws std::logic_error for a recording).
  const ImuSynthesizer& imu() const;
  /// Whether the IMU and the motion come from a recording (SimOptions::recording).
  bool isRecorded() const { return options_.recording != nullptr; }
  /// The recorded part replayed (isRecorded() only: throws std::logic_error otherwise).
  const RecordedMotion& recordedMotion() const;
  /// True biases at the first IMU sample (a recording: its ground truth's, zero if it has none).
  ImuBias initialBias() const;
  const BodyTrajectory& trajectory() const { return *profile_.trajectory; }

  double startTime() const { return options_.start_time_s; }
  double duration() const { return profile_.trajectory->duration(); }
  /// IMU samples: combined samples at imu_rate_hz, the merged separate streams
  /// (ImuSynthOptions::accel_rate_hz / gyro_rate_hz), or a recording's.
  std::size_t imuCount() const { return imu_count_; }
  /// The separate streams when on (null otherwise).
  const ImuSplitStream* imuSplitStream() const { return split_.get(); }
  std::size_t frameCount() const { return frame_count_; }
  /// Wheel-odometry readings (none unless the encoders are on for this profile:
  /// SimOptions::wheel; never for a recording).
  bool hasWheels() const { return wheel_ != nullptr; }
  const std::vector<WheelOdometrySample>& wheelSamples() const;

  /// IMU sample k (simulated, or the recording's as read) with its IMU-clock stamp.
  ImuSample imuSample(std::size_t k) const;
  /// [s] IMU-clock stamp of sample k.
  double imuStamp(std::size_t k) const;
  /// IMU-clock time at which frame i is exposed, and its (camera-clock) stamp.
  double frameExposureTime(std::size_t i) const;
  /// The stamp carries frame_stamp_jitter_s; frameTrueStamp is the exposure on the camera clock.
  double frameStamp(std::size_t i) const;
  double frameTrueStamp(std::size_t i) const {
    return frameExposureTime(i) - options_.time_offset_s;
  }
  /// The colour camera's row timing (SimOptions::rolling_shutter_*): row y of frame i is exposed
  /// at frameExposureTime(i) + rollingShutter().rowTime(y).
  RollingShutter rollingShutter() const;
  /// Whether frame i is exposed during the blackout.
  bool inBlackout(std::size_t i) const;
  /// Renders frame i: colour with the exposure gain and photometric noise, depth with D435-like
  /// noise in mm, both
  /// cameras the configured colour camera (cam_color = cam_depth, depth aligned). A frame in
  /// the blackout is impaired as SimOptions::blackout_kind says.
  RgbdFrame renderFrame(std::size_t i) const;
  /// Same rendering without any noise: rgb CV_8UC3, depth CV_32FC1 in metres (0 = no hit). No
  /// blackout either. With a rolling shutter each colour row is rendered from the camera pose at
  /// its own time; depth is global shutter from the pose at the reference time, pixel-aligned
  /// to the colour camera's intrinsics (as the D435i's aligned depth: the alignment is by the
  /// calibrated geometry only and ignores the time between a colour row and the depth exposure).
  void renderIdeal(std::size_t i, cv::Mat& rgb, cv::Mat& depth_m) const;

  /// Ground truth at an IMU-clock stamp (clamped to the sequence).
  GroundTruthState groundTruth(double t_imu) const;
  /// Pose of the colour camera optical frame in the world at an IMU-clock stamp.
  Eigen::Isometry3d cameraPose(double t_imu) const;
  /// Body poses at every IMU sample (IMU clock); for a recording, its ground-truth samples at
  /// their own stamps within the replayed IMU span.
  Trajectory bodyTrajectory() const;
  /// Camera poses at every frame, stamped with the frames' true stamps (camera clock, without
  /// the stamp jitter), each the pose at the frame's exposure time.
  Trajectory cameraTrajectory() const;

  /// Delivers all IMU samples, wheel readings and frames in non-decreasing stamp order (at equal
  /// stamps: IMU, wheel, frame), then endOfStream() (also when stopped early via *stop).
  void pump(MeasurementSink& sink, const std::atomic<bool>* stop = nullptr) const;

 private:
  void impairColour(cv::Mat& rgb) const;  ///< colour of a blackout frame ("bare", "blur")
  /// The recording's ground-truth biases at t_imu (linear between samples, clamped; zero when
  /// the recording has none).
  ImuBias recordedBias(double t_imu) const;
  void checkFrameIndex(std::size_t i) const;  ///< throws std::out_of_range
  double imuTime(std::size_t k) const;        ///< [s] sequence time of IMU sample k

  SimOptions options_;
  MotionProfile profile_;
  std::unique_ptr<Scene> scene_;
  std::unique_ptr<ImuSynthesizer> imu_;    ///< null for a recording
  std::unique_ptr<ImuSplitStream> split_;  ///< separate streams, when on
  RecordedMotion recorded_;                ///< empty unless isRecorded()
  std::unique_ptr<Renderer> renderer_;
  std::unique_ptr<ExposureGain> exposure_;
  std::unique_ptr<WheelEncoderSynth> wheel_;  ///< null when the encoders are off
  std::size_t frame_count_ = 0, imu_count_ = 0;
};

}  // namespace rgbdi::sim
