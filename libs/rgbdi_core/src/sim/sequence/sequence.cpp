#include "rgbdi/sim/sequence.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <random>
#include <stdexcept>
#include <string>

#include "rgbdi/sim/profile_scene.h"
#include "sim/motion/counter_gaussian.h"
#include "sim/motion/spin_overlay.h"
#include "sim/sequence/frame_prefetcher.h"

namespace rgbdi::sim {
namespace {

// Random streams of the sequence seed (the IMU uses its own streams 1-3 of the same seed).
constexpr std::uint64_t kFrameNoiseStream = 100;
constexpr std::uint64_t kStampJitterStream = 300;
constexpr std::uint64_t kDepthArtefactStream = 400;
// Frames waiting for the consumer when prefetching (each ~2 MB).
constexpr std::size_t kPrefetchDepth = 3;

}  // namespace

const std::vector<std::string>& blackoutKinds() {
  static const std::vector<std::string> kinds{"black", "bare", "blur"};
  return kinds;
}

bool isBlackoutKind(const std::string& kind) {
  const std::vector<std::string>& kinds = blackoutKinds();
  return std::find(kinds.begin(), kinds.end(), kind) != kinds.end();
}

const std::vector<std::string>& rollingShutterDirections() {
  static const std::vector<std::string> v{"top_to_bottom", "bottom_to_top"};
  return v;
}

const std::vector<std::string>& rollingShutterReferenceRows() {
  static const std::vector<std::string> v{"middle", "first"};
  return v;
}

SimOptions SimOptions::load(IniReader& ini) {
  SimOptions o;
  const std::string s = "sim";
  o.profile = ProfileOptions::load(ini);
  o.imu = ImuSynthOptions::load(ini);
  o.depth_noise = DepthNoiseOptions::load(ini);
  o.depth_artefacts = DepthArtefactOptions::load(ini);
  o.color_noise = ColorNoiseOptions::load(ini);
  o.exposure = ExposureOptions::load(ini);
  o.scene = ProfileSceneOptions::load(ini);
  o.camera = CameraOptions::load(ini);
  o.extrinsic = ExtrinsicOptions::load(ini);
  o.fps = ini.getDouble(s, "fps", o.fps, 1.0, 1000.0);
  o.seed = static_cast<std::uint64_t>(ini.getInt(s, "seed", static_cast<int>(o.seed), 0, INT_MAX));
  o.time_offset_s = ini.getDouble(s, "time_offset_s", o.time_offset_s, -0.5, 0.5);
  o.frame_stamp_jitter_s =
      ini.getDouble(s, "frame_stamp_jitter_s", o.frame_stamp_jitter_s, 0.0, 0.01);
  o.start_time_s = ini.getDouble(s, "start_time_s", o.start_time_s, 1.0, 4.0e9);
  o.config_noise_inflation =
      ini.getDouble(s, "config_noise_inflation", o.config_noise_inflation, 1.0, 100.0);
  o.blackout_start_s = ini.getDouble(s, "blackout_start_s", o.blackout_start_s, 0.0, 1.0e6);
  o.blackout_duration_s =
      ini.getDouble(s, "blackout_duration_s", o.blackout_duration_s, 0.0, 1.0e6);
  o.blackout_kind = ini.getEnum(s, "blackout_kind", o.blackout_kind, blackoutKinds());
  o.blackout_blur_px = ini.getInt(s, "blackout_blur_px", o.blackout_blur_px, 1, 1001);
  o.spin_start_s = ini.getDouble(s, "spin_start_s", o.spin_start_s, 0.0, 1.0e6);
  o.spin_duration_s = ini.getDouble(s, "spin_duration_s", o.spin_duration_s, 0.0, 1.0e6);
  o.spin_turns = ini.getDouble(s, "spin_turns", o.spin_turns, -100.0, 100.0);
  o.recorded_world = RecordedWorldOptions::load(ini);
  o.wheel = WheelEncoderOptions::load(ini);
  o.rolling_shutter_readout_s =
      ini.getDouble(s, "rolling_shutter_readout_s", o.rolling_shutter_readout_s, 0.0, 1.0);
  o.rolling_shutter_direction = ini.getEnum(
      s, "rolling_shutter_direction", o.rolling_shutter_direction, rollingShutterDirections());
  o.rolling_shutter_reference_row =
      ini.getEnum(s, "rolling_shutter_reference_row", o.rolling_shutter_reference_row,
                  rollingShutterReferenceRows());
  return o;
}

SimulatedSequence::SimulatedSequence(const SimOptions& options) : options_(options) {
  if (!(options.fps > 0.0) || !std::isfinite(options.fps))
    throw std::invalid_argument("SimulatedSequence: fps must be positive (got " +
                                std::to_string(options.fps) + ")");
  if (!options.camera.camera.valid())
    throw std::invalid_argument("SimulatedSequence: invalid camera intrinsics");
  if (!(options.blackout_start_s >= 0.0) || !(options.blackout_duration_s >= 0.0) ||
      !std::isfinite(options.blackout_start_s + options.blackout_duration_s))
    throw std::invalid_argument("SimulatedSequence: blackout start and duration must be >= 0");
  if (!isBlackoutKind(options.blackout_kind))
    throw std::invalid_argument(
        "SimulatedSequence: blackout kind must be black, bare or blur (got '" +
        options.blackout_kind + "')");
  if (!(options.spin_start_s >= 0.0) || !(options.spin_duration_s >= 0.0) ||
      !std::isfinite(options.spin_start_s + options.spin_duration_s + options.spin_turns))
    throw std::invalid_argument(
        "SimulatedSequence: spin start and duration must be >= 0, turns finite");
  const std::vector<std::string>&dirs = rollingShutterDirections(),
        &refs = rollingShutterReferenceRows();
  if (!(options.rolling_shutter_readout_s >= 0.0 && options.rolling_shutter_readout_s <= 1.0) ||
      std::find(dirs.begin(), dirs.end(), options.rolling_shutter_direction) == dirs.end() ||
      std::find(refs.begin(), refs.end(), options.rolling_shutter_reference_row) == refs.end())
    throw std::invalid_argument(
        "SimulatedSequence: rolling_shutter_readout_s must be in [0, 1] s, the direction "
        "top_to_bottom or bottom_to_top, the reference row middle or first");
  if (options.blackout_blur_px < 1)
    throw std::invalid_argument("SimulatedSequence: blackout_blur_px must be >= 1");
  if (!(options.frame_stamp_jitter_s >= 0.0 && options.frame_stamp_jitter_s < 0.25 / options.fps))
    throw std::invalid_argument(
        "SimulatedSequence: frame_stamp_jitter_s must be >= 0 and below a quarter frame period");
  if (options.start_time_s - options.time_offset_s - options.frame_stamp_jitter_s <= 0.0)
    throw std::invalid_argument("SimulatedSequence: start_time_s - time_offset_s must be positive");
  // The dataset extrinsic is given to 7 digits (not exactly orthonormal): use the nearest
  // rotation so that rendering, ground truth and written files agree exactly.
  Eigen::Isometry3d& T = options_.extrinsic.T_body_cam;
  T.linear() = Eigen::Quaterniond(T.rotation()).normalized().toRotationMatrix();
  if (options_.recording) {
    if (options_.spin_duration_s > 0.0)
      throw std::invalid_argument(
          "SimulatedSequence: a recorded sequence cannot spin (its IMU is the recorded one)");
    const Recording& rec = *options_.recording;
    recorded_ = makeRecordedMotion(rec, options_.recorded_world, options_.profile.duration_s);
    profile_ = recorded_.profile;
    // The recording's clock is kept: frames start at its first replayed ground-truth sample.
    options_.start_time_s = recorded_.trajectory->origin();
    // The recording's sensor, for config.ini (inflated there as for every profile).
    options_.imu.rate_hz = rec.sensor.rate_hz;
    options_.imu.gravity_m_s2 = rec.sensor.gravity_m_s2;
    options_.imu.acc_noise_density = rec.sensor.acc_noise_density;
    options_.imu.gyr_noise_density = rec.sensor.gyr_noise_density;
    options_.imu.acc_random_walk = rec.sensor.acc_random_walk;
    options_.imu.gyr_random_walk = rec.sensor.gyr_random_walk;
    options_.imu.acc_bias_max = options_.imu.gyr_bias_max = 0.0;
    imu_count_ = recorded_.imu_count;
  } else {
    profile_ = makeMotionProfile(options_.profile, options_.extrinsic.T_body_cam);
    if (options_.spin_duration_s > 0.0)
      profile_.trajectory =
          std::make_shared<SpinOverlayTrajectory>(profile_.trajectory, options_.spin_start_s,
                                                  options_.spin_duration_s, options_.spin_turns);
    if (options_.imu.accel_rate_hz > 0.0 || options_.imu.gyro_rate_hz > 0.0) {
      // Separate streams: the combined samples come on the gyro stamps, so imu_rate_hz is the
      // gyro rate (written so to config.ini and simulation.ini).
      options_.imu.rate_hz = options_.imu.gyro_rate_hz;
      split_ = std::make_unique<ImuSplitStream>(profile_.trajectory, options_.imu, options_.seed);
    }
    imu_ = std::make_unique<ImuSynthesizer>(profile_.trajectory, options_.imu, options_.seed);
    imu_count_ = split_ ? split_->samples().size() : imu_->sampleCount();
    const bool wheeled = options_.profile.kind != ProfileKind::Handheld;
    if (options_.wheel.mode == "on" || (options_.wheel.mode == "auto" && wheeled)) {
      options_.wheel.skid_steering = options_.profile.kind == ProfileKind::TrackedSlopes;
      wheel_ = std::make_unique<WheelEncoderSynth>(options_.wheel, *profile_.trajectory,
                                                   options_.start_time_s);
    }
  }
  scene_ = std::make_unique<Scene>(buildProfileScene(profile_, options_.seed, options_.scene));
  // Aliased end walls must also be lit alike: a light without an x component shades the -x and
  // +x walls equally (otherwise one would be a darker copy of the other).
  if (options_.scene.aliased_walls) options_.render.light_dir_world.x() = 0.0;
  renderer_ = std::make_unique<Renderer>(*scene_, options_.camera.camera, options_.render);
  exposure_ = std::make_unique<ExposureGain>(options_.exposure, options_.seed);
  // A recording's duration is a difference of stamps near 1e9 s (resolution 0.24 us): a frame
  // that falls a microsecond after its end is still taken (its pose is the last sample's).
  const double slack = isRecorded() ? 1e-6 * options_.fps : 1e-9;
  frame_count_ =
      static_cast<std::size_t>(std::floor(profile_.trajectory->duration() * options_.fps + slack)) +
      1;
}

SimulatedSequence::~SimulatedSequence() = default;

const std::vector<WheelOdometrySample>& SimulatedSequence::wheelSamples() const {
  static const std::vector<WheelOdometrySample> kNone;
  return wheel_ ? wheel_->samples() : kNone;
}

double SimulatedSequence::imuTime(std::size_t k) const {
  return split_ ? split_->samples()[k].t : imu_->sampleTime(k);
}

const ImuSynthesizer& SimulatedSequence::imu() const {
  if (!imu_) throw std::logic_error("SimulatedSequence::imu: the IMU of this sequence is recorded");
  return *imu_;
}

const RecordedMotion& SimulatedSequence::recordedMotion() const {
  if (!isRecorded()) throw std::logic_error("SimulatedSequence: not a recorded sequence");
  return recorded_;
}

ImuSample SimulatedSequence::imuSample(std::size_t k) const {
  if (isRecorded()) {
    if (k >= imu_count_)
      throw std::out_of_range("SimulatedSequence: IMU sample " + std::to_string(k) + " of " +
                              std::to_string(imu_count_));
    return options_.recording->imu[k];
  }
  ImuSample s = split_ ? split_->samples().at(k) : imu_->measured(k);
  s.t += options_.start_time_s;
  return s;
}

double SimulatedSequence::imuStamp(std::size_t k) const {
  if (isRecorded()) return imuSample(k).t;
  return options_.start_time_s + imuTime(k);
}

ImuBias SimulatedSequence::initialBias() const {
  // Separate streams share the combined synthesiser's seed, hence its initial bias.
  return isRecorded() ? groundTruth(imuStamp(0)).bias : imu_->biasAtSample(0);
}

double SimulatedSequence::frameExposureTime(std::size_t i) const {
  return options_.start_time_s + static_cast<double>(i) / options_.fps;
}

double SimulatedSequence::frameStamp(std::size_t i) const {
  if (options_.frame_stamp_jitter_s == 0.0) return frameTrueStamp(i);
  return frameTrueStamp(i) +
         CounterRng(options_.seed, kStampJitterStream).symmetric(i, options_.frame_stamp_jitter_s);
}

Eigen::Isometry3d SimulatedSequence::cameraPose(double t_imu) const {
  return trajectory().pose(t_imu - options_.start_time_s) * options_.extrinsic.T_body_cam;
}

void SimulatedSequence::checkFrameIndex(std::size_t i) const {
  if (i >= frame_count_)
    throw std::out_of_range("SimulatedSequence: frame " + std::to_string(i) + " of " +
                            std::to_string(frame_count_));
}

RollingShutter SimulatedSequence::rollingShutter() const {
  RollingShutter rs;
  rs.readout_s = options_.rolling_shutter_readout_s;
  rs.rows = options_.camera.camera.height;
  rs.bottom_to_top = options_.rolling_shutter_direction == "bottom_to_top";
  rs.reference_middle = options_.rolling_shutter_reference_row == "middle";
  return rs;
}

void SimulatedSequence::renderIdeal(std::size_t i, cv::Mat& rgb, cv::Mat& depth_m) const {
  checkFrameIndex(i);
  const double t_ref = frameExposureTime(i);
  const RollingShutter rs = rollingShutter();
  if (rs.global()) {
    renderer_->render(cameraPose(t_ref), rgb, depth_m);
    return;
  }
  std::vector<Eigen::Isometry3d> rows(static_cast<std::size_t>(rs.rows));
  for (int v = 0; v < rs.rows; ++v)
    rows[static_cast<std::size_t>(v)] = cameraPose(t_ref + rs.rowTime(v));
  renderer_->renderRollingShutter(rows, cameraPose(t_ref), rgb, depth_m);
}

void SimulatedSequence::impairColour(cv::Mat& rgb) const {
  if (options_.blackout_kind == "bare") {
    // No texture left: every pixel the frame's mean colour (the sensor noise comes after).
    rgb.setTo(cv::mean(rgb));
  } else if (options_.blackout_kind == "blur") {
    // A smear along a horizontal line, as a fast pan during the exposure.
    const int n = options_.blackout_blur_px;
    cv::Mat kernel = cv::Mat::ones(1, n, CV_32F) / static_cast<float>(n);
    cv::filter2D(rgb, rgb, -1, kernel, cv::Point(-1, -1), 0.0, cv::BORDER_REFLECT);
  }
}

bool SimulatedSequence::inBlackout(std::size_t i) const {
  const double t = static_cast<double>(i) / options_.fps;
  return options_.blackout_duration_s > 0.0 && t >= options_.blackout_start_s &&
         t < options_.blackout_start_s + options_.blackout_duration_s;
}

RgbdFrame SimulatedSequence::renderFrame(std::size_t i) const {
  RgbdFrame f;
  if (inBlackout(i) && options_.blackout_kind == "black") {
    checkFrameIndex(i);
    const int w = options_.camera.camera.width, h = options_.camera.camera.height;
    f.rgb = cv::Mat::zeros(h, w, CV_8UC3);
    f.depth = cv::Mat::zeros(h, w, CV_16UC1);
  } else {
    cv::Mat depth_m;
    renderIdeal(i, f.rgb, depth_m);
    if (options_.depth_artefacts.any()) {
      // A generator of its own, so that the range noise below draws as without artefacts.
      std::mt19937_64 artefact_rng(CounterRng(options_.seed, kDepthArtefactStream).bits(i));
      applyDepthArtefacts(depth_m, f.rgb, options_.camera.camera, options_.depth_artefacts,
                          artefact_rng);
    }
    if (inBlackout(i)) impairColour(f.rgb);
    if (!exposure_->constant())
      applyExposureGain(f.rgb, exposure_->gain(frameExposureTime(i) - options_.start_time_s));
    // One generator per frame, seeded from (seed, frame): frames are independent of order.
    std::mt19937_64 rng(CounterRng(options_.seed, kFrameNoiseStream).bits(i));
    f.depth = applyDepthNoise(depth_m, options_.depth_noise, rng);
    applyColorNoise(f.rgb, options_.color_noise, rng);
  }
  f.t = frameStamp(i);
  f.index = i;
  f.depth_unit_m = 1e-3;
  f.cam_color = options_.camera.camera;
  f.cam_depth = options_.camera.camera;
  f.T_color_depth = Eigen::Isometry3d::Identity();
  f.depth_aligned_to_color = true;
  f.has_source_T_body_cam = true;
  f.source_T_body_cam = options_.extrinsic.T_body_cam;
  f.source_label = "simulated " + toString(profile_.kind) + " frame " + std::to_string(i);
  return f;
}

GroundTruthState SimulatedSequence::groundTruth(double t_imu) const {
  const double t = t_imu - options_.start_time_s;
  const KinematicState s = trajectory().state(t);
  GroundTruthState g;
  g.t = t_imu;
  g.T_world_body = s.T_world_body;
  g.v_world = s.v_world;
  g.a_world = s.a_world;
  g.omega_body = s.omega_body;
  g.bias = isRecorded() ? recordedBias(t_imu) : split_ ? split_->biasAt(t) : imu_->biasAt(t);
  return g;
}

ImuBias SimulatedSequence::recordedBias(double t_imu) const {
  const std::vector<RecordedPose>& gt = options_.recording->ground_truth;
  const auto it = std::upper_bound(gt.begin(), gt.end(), t_imu,
                                   [](double t, const RecordedPose& g) { return t < g.t; });
  if (it == gt.begin()) return it->has_bias ? it->bias : ImuBias{};
  if (it == gt.end()) return gt.back().has_bias ? gt.back().bias : ImuBias{};
  const RecordedPose &a = *(it - 1), &b = *it;
  if (!a.has_bias || !b.has_bias) return ImuBias{};
  const double w = (t_imu - a.t) / (b.t - a.t);
  ImuBias r;
  r.acc = (1.0 - w) * a.bias.acc + w * b.bias.acc;
  r.gyr = (1.0 - w) * a.bias.gyr + w * b.bias.gyr;
  return r;
}

Trajectory SimulatedSequence::bodyTrajectory() const {
  Trajectory traj;
  if (isRecorded()) {
    const double begin = imuStamp(0), end = imuStamp(imu_count_ - 1);
    for (const RecordedPose& g : options_.recording->ground_truth)
      if (g.t >= begin && g.t <= end) {
        StampedPose p;
        p.t = g.t;
        p.q = g.q_world_body;
        p.p = g.p_world;
        traj.push_back(p);
      }
    return traj;
  }
  traj.reserve(imuCount());
  for (std::size_t k = 0; k < imuCount(); ++k)
    traj.push_back(StampedPose::fromIsometry(options_.start_time_s + imuTime(k),
                                             trajectory().pose(imuTime(k))));
  return traj;
}

Trajectory SimulatedSequence::cameraTrajectory() const {
  Trajectory traj;
  traj.reserve(frame_count_);
  for (std::size_t i = 0; i < frame_count_; ++i)
    traj.push_back(StampedPose::fromIsometry(frameTrueStamp(i), cameraPose(frameExposureTime(i))));
  return traj;
}

void SimulatedSequence::pump(MeasurementSink& sink, const std::atomic<bool>* stop) const {
  std::unique_ptr<FramePrefetcher> prefetch;
  if (options_.prefetch_frames)
    prefetch = std::make_unique<FramePrefetcher>([this](std::size_t i) { return renderFrame(i); },
                                                 frame_count_, kPrefetchDepth);
  std::size_t k = 0, i = 0, w = 0;
  const std::size_t n_imu = imuCount();
  const std::vector<WheelOdometrySample>& wheels = wheelSamples();
  while (k < n_imu || i < frame_count_ || w < wheels.size()) {
    if (stop && stop->load()) break;
    const double t_imu = k < n_imu ? imuStamp(k) : INFINITY;
    const double t_frame = i < frame_count_ ? frameStamp(i) : INFINITY;
    const double t_wheel = w < wheels.size() ? wheels[w].t : INFINITY;
    if (t_imu <= t_frame && t_imu <= t_wheel) {
      sink.feedImu(imuSample(k++));
    } else if (t_wheel <= t_frame) {
      sink.feedWheel(wheels[w++]);
    } else {
      sink.feedRgbd(prefetch ? prefetch->next() : renderFrame(i));
      ++i;
    }
  }
  sink.endOfStream();
}

}  // namespace rgbdi::sim
