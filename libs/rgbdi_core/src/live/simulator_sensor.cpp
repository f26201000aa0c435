#include "rgbdi/live/simulator_sensor.h"

#include <atomic>
#include <cmath>
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
  std::string camera_label = "RGBD", imu_label = "IMU", wheel_label = "WHEEL_ODOMETRY";
  std::string wheel_encoders = "auto", external_dir;
  double duration_s = 0.0, fps = 0.0, speed = 1.0, max_frame_lateness_s = 0.1;
  int seed = -1;
  bool restamp = true;

  std::unique_ptr<sim::SimulatedSequence> seq;
  std::optional<PlaybackClock> clock;
  std::size_t next_imu = 0, next_wheel = 0, next_frame = 0;
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
  d.wheel_encoders = k.getEnum("wheel_encoders", d.wheel_encoders, {"off", "on", "auto"});
  d.wheel_label = k.getString("wheel_label", d.wheel_label);
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
  // The rest of the encoder model (rate, radius, track, errors, time offset, events) is the
  // config's [sim] wheel_*, so the readings are the ones rgbdi-sim writes for that file.
  o.wheel.mode = d.wheel_encoders;
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
  const std::vector<WheelOdometrySample>& wheels = s.wheelSamples();
  // In stamp order, at equal stamps IMU, then wheel, then frame, as SimulatedSequence::pump()
  // and the offline reader deliver them.
  enum class Next { Imu, Wheel, Frame };
  bool appended = false;
  for (;;) {
    const double ti = d.next_imu < s.imuCount() ? s.imuStamp(d.next_imu) : INFINITY;
    const double tw = d.next_wheel < wheels.size() ? wheels[d.next_wheel].t : INFINITY;
    const double tf = d.next_frame < s.frameCount() ? s.frameStamp(d.next_frame) : INFINITY;
    if (std::isinf(ti) && std::isinf(tw) && std::isinf(tf)) {
      d.ended = true;
      break;
    }
    const Next next = ti <= tf && ti <= tw ? Next::Imu : (tw <= tf ? Next::Wheel : Next::Frame);
    const double t = next == Next::Imu ? ti : (next == Next::Wheel ? tw : tf);
    if (t > horizon) break;
    if (next == Next::Frame && (horizon - tf) / d.speed > d.max_frame_lateness_s) {
      // Rendering fell behind: skip the frame, as a camera whose host is too slow loses it.
      ++d.next_frame;
      ++d.skipped;
      continue;
    }
    // Rendering takes a while (tens of ms, more on a loaded machine) and LiveSource collects
    // what was appended only when doProcess() returns: hand the IMU samples and wheel readings
    // over first, render on the next call, so that rendering never holds them back (a real
    // camera's IMU and a robot's odometry do not wait for the images).
    if (next == Next::Frame && appended) break;
    appended = true;
    if (next == Next::Imu) {
      ImuSample imu = s.imuSample(d.next_imu++);
      imu.t = d.clock->outputStamp(imu.t);
      appendObservation(io::toMrpt(imu, d.imu_label));
    } else if (next == Next::Wheel) {
      WheelOdometrySample w = wheels[d.next_wheel++];
      w.t = d.clock->outputStamp(w.t);
      appendObservation(io::toMrpt(w, d.wheel_label));
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
