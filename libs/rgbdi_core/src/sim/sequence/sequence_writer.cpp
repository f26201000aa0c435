#include "rgbdi/sim/sequence_writer.h"

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <memory>
#include <sstream>

#include "rgbdi/common/atomic_file.h"
#include "rgbdi/common/ini_text.h"
#include "rgbdi/common/progress_gate.h"
#include "rgbdi/convert/vins_yaml.h"
#include "rgbdi/io/rawlog_writer.h"
#include "rgbdi/output/tum_writer.h"
#include "sim/sequence/optional_settings.h"

namespace rgbdi::sim {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

void cameraSection(std::ostream& os, const CameraOptions& c) {
  const PinholeCamera& k = c.camera;
  os << "[camera]\n";
  iniLine(os, "width", std::to_string(k.width), "[px]");
  iniLine(os, "height", std::to_string(k.height), "[px]");
  iniLine(os, "fx", iniNumber(k.fx), "[px]");
  iniLine(os, "fy", iniNumber(k.fy), "[px]");
  iniLine(os, "cx", iniNumber(k.cx), "[px]");
  iniLine(os, "cy", iniNumber(k.cy), "[px]");
  iniLine(os, "distortion", iniDistortion(k), "k1 k2 p1 p2 k3 [unitless]");
  iniLine(os, "intrinsics_source", c.intrinsics_source, "stream|config");
  if (c.rolling_shutter_readout_s != 0.0)  // written only when set: global-shutter files as before
    iniLine(os, "rolling_shutter_readout_s", iniNumber(c.rolling_shutter_readout_s),
            "[s] colour rows read top to bottom in this time, stamped at the middle row");
}

void extrinsicSection(std::ostream& os, const ExtrinsicOptions& e, double time_offset,
                      const std::string& offset_comment) {
  const Eigen::Matrix3d R = e.T_body_cam.rotation();
  Eigen::VectorXd r(9);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r[3 * i + j] = R(i, j);
  os << "[extrinsic]\n";
  iniLine(os, "R_body_cam", iniNumbers(r),
          "row-major [unitless]: colour camera optical frame in the IMU/body frame");
  iniLine(os, "t_body_cam_m", iniNumbers(e.T_body_cam.translation()), "[m]");
  iniLine(os, "time_offset_s", iniNumber(time_offset), offset_comment);
  iniLine(os, "sensor_pose_tolerance_m", iniNumber(e.sensor_pose_tolerance_m), "[m]");
  iniLine(os, "sensor_pose_tolerance_deg", iniNumber(e.sensor_pose_tolerance_deg), "[deg]");
}

/// Writes rawlog + bag as measurements arrive; prints progress.
class WritingSink : public MeasurementSink {
 public:
  WritingSink(const SimulatedSequence& seq, io::RawlogWriter& rawlog, bag::BagWriter* bag,
              const SequenceWriterOptions& options)
      : seq_(seq),
        rawlog_(rawlog),
        bag_(bag),
        options_(options),
        gate_(options.progress_interactive, options.progress_interval_s),
        start_(Clock::now()) {
    // A recording's ground truth goes into the bag at its own stamps, not resampled.
    if (bag_ && seq_.isRecorded()) recorded_truth_ = seq_.bodyTrajectory();
  }

  void feedImu(const ImuSample& imu) override {
    rawlog_.write(imu);
    if (bag_) {
      writeWheelFrame(imu.t);
      bag_->writeImu(imu);
      if (!seq_.isRecorded()) {
        bag_->writePose(imu.t, seq_.groundTruth(imu.t).T_world_body);
      } else {
        for (; next_truth_ < recorded_truth_.size() && recorded_truth_[next_truth_].t <= imu.t;
             ++next_truth_)
          bag_->writePose(recorded_truth_[next_truth_].t, recorded_truth_[next_truth_].isometry());
      }
    }
    ++imu_samples_;
  }

  void feedWheel(const WheelOdometrySample& wheel) override {
    rawlog_.write(wheel);
    if (bag_) {
      writeWheelFrame(wheel.t);
      bag_->writeOdometry(wheel);
    }
    ++wheel_readings_;
  }

  void feedRgbd(const RgbdFrame& frame) override {
    rawlog_.write(frame);
    if (bag_) bag_->writeRgbd(frame);
    ++frames_;
    progress(false);
  }

  void endOfStream() override { progress(true); }

  std::size_t frames() const { return frames_; }
  std::size_t imuSamples() const { return imu_samples_; }
  std::size_t wheelReadings() const { return wheel_readings_; }
  double elapsed() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }

 private:
  void progress(bool final) {
    if (!options_.progress) return;
    const std::size_t total = seq_.frameCount();
    const double fraction = static_cast<double>(frames_) / std::max<std::size_t>(1, total);
    if (!final && (frames_ >= total || !gate_.due(fraction, elapsed())))
      return;  // the last frame's line is the final one (endOfStream)
    const double t = elapsed(), fps = frames_ / std::max(1e-9, t);
    std::ostringstream os;
    os << std::fixed << std::setprecision(1) << "rgbdi-sim: frame " << frames_ << "/" << total
       << " (" << 100.0 * fraction << " %), " << fps << " frames/s, elapsed " << t << " s";
    if (!final && fps > 0) os << ", about " << (total - frames_) / fps << " s left";
    if (options_.progress_interactive)
      *options_.progress << "\r" << os.str() << "\x1b[K" << (final ? "\n" : "") << std::flush;
    else
      *options_.progress << os.str() << "\n" << std::flush;
  }

  /// With encoders, once before the first message: the wheel frame (the odometry's child frame)
  /// in the IMU frame on /tf_static, so that rawlog-convert finds the extrinsic. The simulated
  /// wheel frame is the body frame (wheel_encoder_synth.h).
  void writeWheelFrame(double t) {
    if (wheel_frame_written_ || !seq_.hasWheels()) return;
    wheel_frame_written_ = true;
    bag_->writeStaticTransform(t, bag_->topics().imu_frame_id, bag_->topics().wheel_frame_id,
                               Eigen::Isometry3d::Identity());
  }

  const SimulatedSequence& seq_;
  io::RawlogWriter& rawlog_;
  bag::BagWriter* bag_;
  const SequenceWriterOptions& options_;
  ProgressGate gate_;
  Clock::time_point start_;
  std::size_t frames_ = 0, imu_samples_ = 0, wheel_readings_ = 0;
  Trajectory recorded_truth_;  ///< a recording's ground-truth samples (bag only)
  std::size_t next_truth_ = 0;
  bool wheel_frame_written_ = false;
};

}  // namespace

std::string slamConfigText(const SimulatedSequence& seq) {
  const SimOptions& o = seq.options();
  const double k = o.config_noise_inflation;
  std::ostringstream os;
  if (seq.isRecorded()) {
    const Recording& r = *o.recording;
    os << "; rgbdi-slam configuration for the hybrid sequence next to this file: the real IMU of\n"
       << "; the " << r.format << " recording " << r.directory << ", images rendered along its"
       << " ground truth (seed " << o.seed << ").\n"
       << "; Camera and extrinsic are the ones used to render. The IMU noise densities are the\n"
       << "; sensor's (" << r.sensor.name
       << ") inflated by config_noise_inflation = " << iniNumber(k)
       << ", as for the simulated profiles.\n\n";
  } else {
    os << "; rgbdi-slam configuration for the simulated sequence next to this file (profile "
       << toString(seq.profile().kind) << ", seed " << o.seed << ").\n"
       << "; Camera and extrinsic are the ones used to render. The IMU noise densities are the "
          "true\n"
       << "; ones inflated by config_noise_inflation = " << iniNumber(k)
       << ", as a user would set them (a real user never knows the truth; see simulation.ini).\n\n";
  }
  // The rolling shutter rendered is the calibration a user would have: rgbdi-slam compensates it
  // when it is the model it knows (top to bottom, stamped at the middle row).
  CameraOptions camera = o.camera;
  const RollingShutter rs = seq.rollingShutter();
  const bool known_model = !rs.bottom_to_top && rs.reference_middle;
  camera.rolling_shutter_readout_s = known_model ? rs.readout_s : 0.0;
  cameraSection(os, camera);
  if (!rs.global() && !known_model)
    os << "; The colour images have a rolling shutter (simulation.ini) that rgbdi-slam's model\n"
       << "; (top to bottom, stamped at the middle row) does not describe: not compensated.\n";
  os << "\n[imu]\n";
  iniLine(os, "rate_hz", iniNumber(o.imu.rate_hz), "[Hz]");
  iniLine(os, "acc_noise_density", iniNumber(k * o.imu.acc_noise_density), "[m/s^2/sqrt(Hz)]");
  iniLine(os, "gyr_noise_density", iniNumber(k * o.imu.gyr_noise_density), "[rad/s/sqrt(Hz)]");
  iniLine(os, "acc_random_walk", iniNumber(k * o.imu.acc_random_walk), "[m/s^3/sqrt(Hz)]");
  iniLine(os, "gyr_random_walk", iniNumber(k * o.imu.gyr_random_walk), "[rad/s^2/sqrt(Hz)]");
  iniLine(os, "gravity_m_s2", iniNumber(o.imu.gravity_m_s2), "[m/s^2]");
  os << "\n";
  // A user would not know the camera-IMU time offset either: start from 0 (rgbdi-slam
  // estimates it online when [estimator] estimate_time_offset is on).
  extrinsicSection(os, o.extrinsic, 0.0,
                   "[s] initial value; the true offset of this sequence is " +
                       iniNumber(o.time_offset_s) + " s (simulation.ini)");
  return os.str();
}

std::string vinsConfigText(const SimulatedSequence& seq) {
  const SimOptions& o = seq.options();
  // The IMU noise of config.ini (slamConfigText): the truth inflated.
  const double k = o.config_noise_inflation;
  ImuOptions imu;
  imu.rate_hz = o.imu.rate_hz;
  imu.gravity_m_s2 = o.imu.gravity_m_s2;
  imu.acc_noise_density = k * o.imu.acc_noise_density;
  imu.gyr_noise_density = k * o.imu.gyr_noise_density;
  imu.acc_random_walk = k * o.imu.acc_random_walk;
  imu.gyr_random_walk = k * o.imu.gyr_random_walk;
  // td 0, as in config.ini: a user does not know the offset. The rolling shutter as in config.ini:
  // VINS-Mono's model is rgbdi's (top to bottom, stamped at the middle row).
  const RollingShutter rs = seq.rollingShutter();
  const bool known_model = !rs.bottom_to_top && rs.reference_middle;
  return convert::vinsYamlText(o.camera.camera, o.extrinsic.T_body_cam, imu, 0.0,
                               known_model ? rs.readout_s : 0.0);
}

std::string simulationSettingsText(const SimulatedSequence& seq) {
  const SimOptions& o = seq.options();
  const ProfileOptions& p = o.profile;
  const MotionProfile& prof = seq.profile();
  const ImuBias b0 = seq.initialBias();
  std::ostringstream os;
  if (seq.isRecorded()) {
    const Recording& r = *o.recording;
    const RecordedMotion& m = seq.recordedMotion();
    os << "; Settings of this hybrid sequence: rgbdi-sim --profile recorded --recording "
       << r.directory << " --recording-format " << r.format
       << " --config simulation.ini regenerates it.\n"
       << "; IMU: the recording's " << m.imu_count << " samples (" << r.sensor.name
       << "); motion: its ground-truth samples " << m.first_pose << " to " << m.last_pose
       << " (stamps " << iniNumber(r.ground_truth[m.first_pose].t) << " to "
       << iniNumber(r.ground_truth[m.last_pose].t) << " s); the [sim] IMU noise below is the"
       << " sensor's\n";
  } else {
    os << "; Settings of this simulated sequence: rgbdi-sim --profile " << toString(prof.kind)
       << " --config simulation.ini regenerates it.\n";
  }
  os << "; profile " << toString(prof.kind)
     << (p.variant != 0 ? " variant " + std::to_string(p.variant) : std::string()) << ": duration "
     << iniNumber(seq.duration()) << " s, cruise speed " << iniNumber(prof.cruise_speed_m_s)
     << " m/s, path length " << iniNumber(prof.path_length_m) << " m, " << seq.frameCount()
     << " frames, " << seq.imuCount() << " IMU samples\n"
     << (seq.isRecorded() ? "; ground truth's initial accelerometer bias "
                          : "; true initial accelerometer bias ")
     << iniNumbers(b0.acc) << " m/s^2, gyro bias " << iniNumbers(b0.gyr) << " rad/s\n\n[sim]\n";
  iniLine(os, "fps", iniNumber(o.fps), "[Hz]");
  iniLine(os, "imu_rate_hz", iniNumber(o.imu.rate_hz), "[Hz]");
  iniLine(os, "seed", std::to_string(o.seed), "[integer]");
  iniLine(os, "gravity_m_s2", iniNumber(o.imu.gravity_m_s2), "[m/s^2]");
  iniLine(os, "acc_noise_density", iniNumber(o.imu.acc_noise_density), "[m/s^2/sqrt(Hz)] true");
  iniLine(os, "gyr_noise_density", iniNumber(o.imu.gyr_noise_density), "[rad/s/sqrt(Hz)] true");
  iniLine(os, "acc_random_walk", iniNumber(o.imu.acc_random_walk), "[m/s^3/sqrt(Hz)] true");
  iniLine(os, "gyr_random_walk", iniNumber(o.imu.gyr_random_walk), "[rad/s^2/sqrt(Hz)] true");
  iniLine(os, "acc_bias_max", iniNumber(o.imu.acc_bias_max), "[m/s^2]");
  iniLine(os, "gyr_bias_max", iniNumber(o.imu.gyr_bias_max), "[rad/s]");
  iniLine(os, "config_noise_inflation", iniNumber(o.config_noise_inflation), "[unitless]");
  iniLine(os, "depth_sigma_coeff", iniNumber(o.depth_noise.sigma_coeff), "[1/m]");
  iniLine(os, "depth_min_m", iniNumber(o.depth_noise.min_m), "[m]");
  iniLine(os, "depth_max_m", iniNumber(o.depth_noise.max_m), "[m]");
  iniLine(os, "depth_hole_fraction", iniNumber(o.depth_noise.hole_fraction), "[unitless]");
  iniLine(os, "photometric_noise_sigma", iniNumber(o.color_noise.sigma), "[grey levels]");
  iniLine(os, "time_offset_s", iniNumber(o.time_offset_s), "[s] true: t_imu = t_cam + this");
  iniLine(os, "start_time_s", iniNumber(o.start_time_s), "[s]");
  iniLine(os, "aliased_walls", o.scene.aliased_walls ? "true" : "false",
          "[bool] the +x wall repeats the -x wall (perceptual aliasing)");
  if (o.scene.twin_rooms)  // written only when set: other sequences' files stay as they were
    iniLine(os, "twin_rooms", "true", "[bool] two identical rooms (wheeled_circle)");
  if (o.scene.nav_features)
    iniLine(os, "nav_features", "true", "[bool] step, hole and table beside the path");
  iniLine(os, "blackout_start_s", iniNumber(o.blackout_start_s), "[s] since the start");
  iniLine(os, "blackout_duration_s", iniNumber(o.blackout_duration_s),
          "[s] frames impaired as blackout_kind says (0 = none)");
  iniLine(os, "blackout_kind", o.blackout_kind,
          "black (no colour, no depth) | bare (no texture) | blur (motion blur)");
  iniLine(os, "blackout_blur_px", std::to_string(o.blackout_blur_px), "[px] blur line length");
  iniLine(os, "spin_start_s", iniNumber(o.spin_start_s), "[s] since the start");
  iniLine(os, "spin_duration_s", iniNumber(o.spin_duration_s),
          "[s] extra turn about the vertical (0 = none)");
  iniLine(os, "spin_turns", iniNumber(o.spin_turns), "[turns] of the extra turn");
  iniLine(os, "duration_s", iniNumber(seq.duration()), "[s]");
  iniLine(os, "speed", toString(p.speed), "slow|normal|fast");
  iniLine(os, "speed_m_s", iniNumber(p.speed_m_s), "[m/s] 0 = profile default");
  iniLine(os, "rest_start_s", iniNumber(p.rest_start_s), "[s]");
  iniLine(os, "rest_end_s", iniNumber(p.rest_end_s), "[s]");
  iniLine(os, "wheeled_vibration_acc_rms", iniNumber(p.wheeled_vibration_acc_rms), "[m/s^2]");
  iniLine(os, "wheeled_vibration_gyr_rms", iniNumber(p.wheeled_vibration_gyr_rms), "[rad/s]");
  iniLine(os, "tracked_vibration_acc_rms", iniNumber(p.tracked_vibration_acc_rms), "[m/s^2]");
  iniLine(os, "tracked_vibration_gyr_rms", iniNumber(p.tracked_vibration_gyr_rms), "[rad/s]");
  iniLine(os, "tracked_jitter_deg", iniNumber(p.tracked_jitter_deg), "[deg]");
  iniLine(os, "vibration_band_min_hz", iniNumber(p.vibration_band_min_hz), "[Hz]");
  iniLine(os, "vibration_band_max_hz", iniNumber(p.vibration_band_max_hz), "[Hz]");
  iniLine(os, "wheeled_camera_height_m", iniNumber(p.wheeled_camera_height_m), "[m]");
  iniLine(os, "tracked_camera_height_m", iniNumber(p.tracked_camera_height_m), "[m]");
  iniLine(os, "handheld_camera_height_m", iniNumber(p.handheld_camera_height_m), "[m]");
  if (seq.hasWheels()) {  // otherwise the defaults (encoders off) regenerate the sequence
    const WheelEncoderOptions& w = o.wheel;
    iniLine(os, "wheel_encoders", "on", "off|on|auto");
    iniLine(os, "wheel_rate_hz", iniNumber(w.rate_hz), "[Hz]");
    iniLine(os, "wheel_radius_m", iniNumber(w.radius_m), "[m] nominal");
    iniLine(os, "wheel_track_m", iniNumber(w.track_m), "[m] nominal");
    iniLine(os, "wheel_radius_error_left", iniNumber(w.radius_error_left), "[unitless]");
    iniLine(os, "wheel_radius_error_right", iniNumber(w.radius_error_right), "[unitless]");
    iniLine(os, "wheel_track_error", iniNumber(w.track_error), "[unitless]");
    iniLine(os, "wheel_ticks_per_rev", std::to_string(w.ticks_per_rev), "[ticks]");
    iniLine(os, "wheel_time_offset_s", iniNumber(w.time_offset_s), "[s]");
    iniLine(os, "wheel_skid_turn_slip", iniNumber(w.skid_turn_slip), "[unitless] tracked only");
    iniLine(os, "wheel_skid_slope_gain", iniNumber(w.skid_slope_gain), "[1/rad] tracked only");
    iniLine(os, "wheel_event_speed_m_s", iniNumber(w.event_speed_m_s), "[m/s]");
    iniLine(os, "wheel_events", WheelEncoderOptions::eventsText(w.events),
            "KIND:START_S:DURATION_S,... (spin|stuck|lifted|pushed)");
  }
  if (seq.isRecorded()) {
    const RecordedWorldOptions& w = o.recorded_world;
    iniLine(os, "recorded_room_margin_m", iniNumber(w.room_margin_m), "[m]");
    iniLine(os, "recorded_floor_below_m", iniNumber(w.floor_below_m), "[m]");
    iniLine(os, "recorded_ceiling_above_m", iniNumber(w.ceiling_above_m), "[m]");
    iniLine(os, "recorded_path_clearance_m", iniNumber(w.path_clearance_m), "[m]");
    iniLine(os, "recorded_max_gap_s", iniNumber(w.max_gap_s), "[s]");
  }
  // Written only for the other paths: a variant-0 sequence's files stay as they always were.
  if (p.variant != 0)
    iniLine(os, "variant", std::to_string(p.variant),
            "[index] path variant in the same world (0 = the profile's path)");
  writeOptionalSimSettings(os, o);  // likewise: only settings that differ from the defaults
  os << "\n";
  cameraSection(os, o.camera);
  os << "\n";
  extrinsicSection(os, o.extrinsic, o.extrinsic.time_offset_s, "[s] (not used by the simulator)");
  return os.str();
}

SequenceWriteSummary writeSequence(const SimulatedSequence& seq, const std::string& out_dir,
                                   const SequenceWriterOptions& options,
                                   const std::atomic<bool>* stop) {
  std::error_code ec;
  fs::create_directories(out_dir, ec);
  if (ec) throw IoError(out_dir + ": cannot create output directory: " + ec.message());
  const fs::path dir(out_dir);
  SequenceWriteSummary s;
  s.rawlog_path = (dir / "sequence.rawlog").string();
  s.groundtruth_path = (dir / "groundtruth.tum").string();
  s.groundtruth_cam_path = (dir / "groundtruth_cam.tum").string();
  s.config_path = (dir / "config.ini").string();
  s.simulation_path = (dir / "simulation.ini").string();
  if (options.write_bag) {
    s.bag_path = (dir / "sequence.bag").string();
    s.vins_config_path = (dir / "vins_config.yaml").string();
  }

  // Small files first: they document the run even if it is interrupted.
  const std::string config = slamConfigText(seq), settings = simulationSettingsText(seq);
  writeFileAtomically(s.config_path, [&](std::ostream& os) { os << config; });
  writeFileAtomically(s.simulation_path, [&](std::ostream& os) { os << settings; });
  if (options.write_bag) {
    const std::string vins = vinsConfigText(seq);
    writeFileAtomically(s.vins_config_path, [&](std::ostream& os) { os << vins; });
  }
  output::writeTum(s.groundtruth_path, seq.bodyTrajectory(),
                   seq.isRecorded()
                       ? "ground truth: the recording's own samples of the body (IMU) frame in "
                         "its world frame, at their stamps; IMU clock (the rawlog's IMU stamps; "
                         "image stamps are t_imu - [sim] time_offset_s)"
                       : "ground truth: body (IMU) frame in the world frame; IMU clock (the "
                         "rawlog's IMU stamps; image stamps are t_imu - [sim] time_offset_s)");
  output::writeTum(s.groundtruth_cam_path, seq.cameraTrajectory(),
                   "ground truth: colour camera optical frame in the world frame; IMU clock (the "
                   "rawlog's IMU stamps; image stamps are t_imu - [sim] time_offset_s)");

  io::RawlogWriterOptions ro;
  ro.layout = io::RawlogWriterOptions::Layout::Observations;
  ro.external_images = options.external_images;
  ro.T_body_cam = seq.options().extrinsic.T_body_cam;
  io::RawlogWriter rawlog(s.rawlog_path, ro);
  std::unique_ptr<bag::BagWriter> bag;
  if (options.write_bag)
    bag = std::make_unique<bag::BagWriter>(s.bag_path, options.bag_compression);

  WritingSink sink(seq, rawlog, bag.get(), options);
  seq.pump(sink, stop);
  s.frames = sink.frames();
  s.imu_samples = sink.imuSamples();
  s.wheel_readings = sink.wheelReadings();
  s.completed = s.frames == seq.frameCount() && s.imu_samples == seq.imuCount();
  if (s.completed) {
    rawlog.close();
    if (bag) bag->close();
  }
  s.wall_time_s = sink.elapsed();
  return s;
}

}  // namespace rgbdi::sim
