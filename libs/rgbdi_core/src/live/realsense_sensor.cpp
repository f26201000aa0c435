#include "rgbdi/live/realsense_sensor.h"

#include <atomic>
#include <deque>
#include <mutex>

#include "live/bag_playback_keys.h"
#include "live/external_images.h"
#include "live/sensor_keys.h"
#include "rgbdi/io/mrpt_conversions.h"

IMPLEMENTS_GENERIC_SENSOR(RgbdiRealSense, rgbdi::live)

namespace rgbdi::live {

struct RgbdiRealSense::Impl {
  // Settings.
  RealSenseRequest request;
  std::string adapter = "sdk", playback_file, camera_label = "RGBD", imu_label = "IMU";
  std::string external_dir;
  double max_accel_gap_s = 0.05, max_merge_wait_s = 0.1, speed = 1.0;
  bool restamp = true;
  int frameset_queue_len = 8;
  BagPlaybackKeys bag_keys;  ///< device = recorded: rawlog-convert's calibration options

  std::unique_ptr<RealSenseDevice> device;
  RealSenseCalibration calib;
  Eigen::Isometry3d T_body_cam = Eigen::Isometry3d::Identity();
  bool started = false;

  // Filled by the device's callbacks, drained by doProcess().
  mutable std::mutex mutex;
  std::deque<RealSenseFrameset> framesets;
  std::deque<RealSenseMotion> motion;
  RealSenseSensorStats stats;

  // doProcess() thread only.
  std::unique_ptr<bag::AccelGyroMerger> merger;
  std::size_t frames_out = 0;
  std::atomic<bool> ended{false};

  void onFrameset(RealSenseFrameset&& f) {
    std::lock_guard<std::mutex> lk(mutex);
    ++stats.framesets;
    framesets.push_back(std::move(f));
    while (framesets.size() > static_cast<std::size_t>(frameset_queue_len)) {
      framesets.pop_front();
      ++stats.framesets_dropped;
    }
  }
  void onMotion(const RealSenseMotion& m) {
    std::lock_guard<std::mutex> lk(mutex);
    ++(m.kind == RealSenseMotion::Kind::Accel ? stats.accel : stats.gyro);
    motion.push_back(m);
  }

  RgbdFrame frameOf(RealSenseFrameset&& fs) const {
    RgbdFrame f;
    f.t = fs.t;
    f.rgb = std::move(fs.rgb);
    f.depth = std::move(fs.depth);
    f.depth_unit_m = calib.depth_unit_m;
    f.cam_color = calib.color;
    f.cam_depth = calib.depth;
    f.T_color_depth = calib.T_color_depth;
    f.depth_aligned_to_color = calib.depth_aligned;
    return f;
  }
};

RgbdiRealSense::RgbdiRealSense() : impl_(std::make_unique<Impl>()) {}

RgbdiRealSense::~RgbdiRealSense() {
  if (impl_->device) impl_->device->stop();
}

void RgbdiRealSense::loadConfig_sensorSpecific(const mrpt::config::CConfigFileBase& cfg,
                                               const std::string& section) {
  Impl& d = *impl_;
  const SensorKeys k(cfg, section);
  RealSenseRequest& r = d.request;
  d.adapter = k.getEnum("device", d.adapter, {"sdk", "recorded"});
  d.playback_file = k.getPath("playback_file", d.adapter == "recorded");
  r.serial = k.getString("serial", r.serial);
  r.color_width = k.getInt("color_width", r.color_width, 1, 10000);
  r.color_height = k.getInt("color_height", r.color_height, 1, 10000);
  r.color_fps = k.getInt("color_fps", r.color_fps, 1, 1000);
  r.depth_width = k.getInt("depth_width", r.depth_width, 1, 10000);
  r.depth_height = k.getInt("depth_height", r.depth_height, 1, 10000);
  r.depth_fps = k.getInt("depth_fps", r.depth_fps, 1, 1000);
  r.imu = k.getBool("imu", r.imu);
  r.accel_hz = k.getInt("accel_hz", r.accel_hz, 1, 10000);
  r.gyro_hz = k.getInt("gyro_hz", r.gyro_hz, 1, 10000);
  r.align_depth_to_color = k.getBool("align_depth", r.align_depth_to_color);
  r.emitter_enabled = k.getBool("emitter_enabled", r.emitter_enabled);
  r.depth_auto_exposure = k.getBool("depth_auto_exposure", r.depth_auto_exposure);
  r.color_auto_exposure = k.getBool("color_auto_exposure", r.color_auto_exposure);
  r.global_time = k.getBool("global_time", r.global_time);
  d.max_accel_gap_s = k.getDouble("max_accel_gap_s", d.max_accel_gap_s, 1e-4, 10.0);
  d.max_merge_wait_s = k.getDouble("max_merge_wait_s", d.max_merge_wait_s, 1e-4, 10.0);
  d.frameset_queue_len = k.getInt("frameset_queue_len", d.frameset_queue_len, 1, 1000);
  d.speed = k.getDouble("speed", d.speed, 1e-3, 1000.0);
  d.restamp = k.getEnum("stamps", "now", {"now", "source"}) == "now";
  d.camera_label = k.getString("camera_label", d.camera_label);
  d.imu_label = k.getString("imu_label", d.imu_label);
  d.bag_keys = BagPlaybackKeys::load(k, false);
  // The SDK takes the calibration from the camera or its recording; a key it ignored would
  // leave the user believing it applied.
  if (d.adapter == "sdk" && !d.bag_keys.given.empty())
    k.fail(d.bag_keys.given.front(),
           "applies to device = recorded only (the SDK reads the calibration from the camera or "
           "its recording)");
}

void RgbdiRealSense::setDevice(std::unique_ptr<RealSenseDevice> device) {
  impl_->device = std::move(device);
}

void RgbdiRealSense::setPathForExternalImages(const std::string& directory) {
  impl_->external_dir = directory;
}

void RgbdiRealSense::initialize() {
  Impl& d = *impl_;
  if (!d.device) {
    if (d.adapter == "recorded") {
      d.device =
          makeRecordedRealSenseDevice(d.playback_file, d.speed, d.restamp,
                                      d.bag_keys.settings.options, d.bag_keys.settings.calibration);
    } else {
      d.device = makeSdkRealSenseDevice(d.playback_file, d.speed, d.restamp);
    }
  }
  d.calib = d.device->open(d.request);
  // rgbdi's body frame is the IMU; without an IMU the camera is the body.
  d.T_body_cam = d.calib.has_imu ? d.calib.T_imu_color : Eigen::Isometry3d::Identity();
  d.merger = std::make_unique<bag::AccelGyroMerger>(d.max_accel_gap_s, d.max_merge_wait_s);
  d.device->start([&d](RealSenseFrameset&& f) { d.onFrameset(std::move(f)); },
                  [&d](const RealSenseMotion& m) { d.onMotion(m); });
  d.started = true;
  m_state = ssWorking;
}

void RgbdiRealSense::doProcess() {
  Impl& d = *impl_;
  if (!d.started || d.ended) return;
  // Read finished() before draining: whatever it covered is in the queues now.
  const bool device_done = d.device->finished();
  std::deque<RealSenseFrameset> framesets;
  std::deque<RealSenseMotion> motion;
  {
    std::lock_guard<std::mutex> lk(d.mutex);
    framesets.swap(d.framesets);
    motion.swap(d.motion);
  }
  for (const RealSenseMotion& m : motion) {
    if (m.kind == RealSenseMotion::Kind::Accel) {
      d.merger->pushAccel(m.t, m.value);
    } else {
      d.merger->pushGyro(m.t, m.value);
    }
  }
  if (device_done) d.merger->finish();
  ImuSample s;
  while (d.merger->pop(s)) appendObservation(io::toMrpt(s, d.imu_label));
  for (RealSenseFrameset& fs : framesets) {
    auto obs = io::toMrpt(d.frameOf(std::move(fs)), d.T_body_cam, d.camera_label);
    if (!d.external_dir.empty())
      storeImagesExternally(*obs, d.external_dir,
                            d.camera_label + "_" + std::to_string(d.frames_out),
                            m_external_images_format);
    ++d.frames_out;
    appendObservation(obs);
  }
  {
    std::lock_guard<std::mutex> lk(d.mutex);
    d.stats.merge = d.merger->stats();
  }
  if (device_done) {
    const std::string e = d.device->error();
    if (!e.empty()) {
      m_state = ssError;
      throw RealSenseError(e);
    }
    d.ended = true;
  }
}

bool RgbdiRealSense::endOfData() const { return impl_->ended; }

const RealSenseRequest& RgbdiRealSense::request() const { return impl_->request; }
const RealSenseCalibration& RgbdiRealSense::calibration() const { return impl_->calib; }

RealSenseSensorStats RgbdiRealSense::stats() const {
  std::lock_guard<std::mutex> lk(impl_->mutex);
  return impl_->stats;
}

}  // namespace rgbdi::live
