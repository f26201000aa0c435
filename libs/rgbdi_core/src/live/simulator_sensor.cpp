#include "rgbdi/live/simulator_sensor.h"

#include <atomic>
#include <optional>

#include "live/external_images.h"
#include "live/sensor_keys.h"
#include "rgbdi/io/mrpt_conversions.h"
#include "rgbdi/live/playback_clock.h"
#include "rgbdi/sim/sequence.h"

IMPLEMENTS_GENERIC_SENSOR(RgbdiSimulator, rgbdi::live)

namespace rgbdi::live {

struct RgbdiSimulator::Impl {
  std::string profile = "wheeled_circle", speed_preset = "normal", config;
  std::string camera_label = "RGBD", imu_label = "IMU", external_dir;
  double duration_s = 0.0, fps = 0.0, speed = 1.0, max_frame_lateness_s = 0.1;
  int seed = -1;
  bool restamp = true;

  std::unique_ptr<sim::SimulatedSequence> seq;
  std::optional<PlaybackClock> clock;
  std::size_t next_imu = 0, next_frame = 0;
  std::atomic<std::size_t> skipped{0};
  std::atomic<bool> ended{false};
};

RgbdiSimulator::RgbdiSimulator() : impl_(std::make_unique<Impl>()) {}
RgbdiSimulator::~RgbdiSimulator() = default;

void RgbdiSimulator::loadConfig_sensorSpecific(const mrpt::config::CConfigFileBase& cfg,
                                               const std::string& section) {
  Impl& d = *impl_;
  const SensorKeys k(cfg, section);
  d.profile = k.getEnum("profile", d.profile,
                        {"handheld", "wheeled_circle", "wheeled_slopes", "tracked_slopes"});
  d.speed_preset = k.getEnum("speed_preset", d.speed_preset, {"slow", "normal", "fast"});
  d.duration_s = k.getDouble("duration_s", d.duration_s, 0.0, 1e6);
  d.fps = k.getDouble("fps", d.fps, 0.0, 1000.0);
  d.seed = k.getInt("seed", d.seed, -1, 2000000000);
  d.config = k.getPath("config", false);
  d.speed = k.getDouble("speed", d.speed, 1e-3, 1000.0);
  d.restamp = k.getEnum("stamps", "now", {"now", "source"}) == "now";
  d.max_frame_lateness_s = k.getDouble("max_frame_lateness_s", d.max_frame_lateness_s, 0.0, 3600.0);
  d.camera_label = k.getString("camera_label", d.camera_label);
  d.imu_label = k.getString("imu_label", d.imu_label);
}

void RgbdiSimulator::setPathForExternalImages(const std::string& directory) {
  impl_->external_dir = directory;
}

void RgbdiSimulator::initialize() {
  Impl& d = *impl_;
  IniReader ini = d.config.empty() ? IniReader::empty() : IniReader::fromFile(d.config);
  sim::SimOptions o = sim::SimOptions::load(ini);
  o.profile.kind = sim::parseProfileKind(d.profile);
  o.profile.speed = sim::parseSpeedPreset(d.speed_preset);
  if (d.duration_s > 0.0) o.profile.duration_s = d.duration_s;
  if (d.fps > 0.0) o.fps = d.fps;
  if (d.seed >= 0) o.seed = static_cast<std::uint64_t>(d.seed);
  o.prefetch_frames = false;  // frames are rendered on demand in doProcess()
  d.seq = std::make_unique<sim::SimulatedSequence>(o);
  m_state = ssWorking;
}

void RgbdiSimulator::doProcess() {
  Impl& d = *impl_;
  if (!d.seq || d.ended) return;
  const double now = io::toSeconds(mrpt::Clock::now());
  if (!d.clock) {
    d.clock.emplace(d.speed, d.restamp);
    d.clock->start(now, d.seq->startTime());
  }
  const double horizon = d.clock->horizon(now);
  const sim::SimulatedSequence& s = *d.seq;
  const Eigen::Isometry3d& T_body_cam = s.options().extrinsic.T_body_cam;
  // In stamp order (an IMU sample before a frame with the same stamp), as the offline pump.
  bool appended = false;
  for (;;) {
    const bool imu_left = d.next_imu < s.imuCount();
    const bool frame_left = d.next_frame < s.frameCount();
    if (!imu_left && !frame_left) {
      d.ended = true;
      break;
    }
    const double ti = imu_left ? s.imuSample(d.next_imu).t : 0.0;
    const double tf = frame_left ? s.frameStamp(d.next_frame) : 0.0;
    const bool take_imu = imu_left && (!frame_left || ti <= tf);
    if ((take_imu ? ti : tf) > horizon) break;
    if (!take_imu && (horizon - tf) / d.speed > d.max_frame_lateness_s) {
      // Rendering fell behind: skip the frame, as a camera whose host is too slow loses it.
      ++d.next_frame;
      ++d.skipped;
      continue;
    }
    // Rendering takes a while (tens of ms, more on a loaded machine) and LiveSource collects
    // what was appended only when doProcess() returns: hand the IMU samples over first, render
    // on the next call, so that rendering never holds IMU samples back (a real camera's IMU
    // does not wait for its images).
    if (!take_imu && appended) break;
    appended = true;
    if (take_imu) {
      ImuSample imu = s.imuSample(d.next_imu++);
      imu.t = d.clock->outputStamp(imu.t);
      appendObservation(io::toMrpt(imu, d.imu_label));
    } else {
      RgbdFrame f = s.renderFrame(d.next_frame);
      f.t = d.clock->outputStamp(f.t);
      auto obs = io::toMrpt(f, T_body_cam, d.camera_label);
      if (!d.external_dir.empty())
        storeImagesExternally(*obs, d.external_dir,
                              d.camera_label + "_" + std::to_string(d.next_frame),
                              m_external_images_format);
      ++d.next_frame;
      appendObservation(obs);
    }
  }
}

bool RgbdiSimulator::endOfData() const { return impl_->ended; }

std::size_t RgbdiSimulator::framesSkipped() const { return impl_->skipped; }

}  // namespace rgbdi::live
