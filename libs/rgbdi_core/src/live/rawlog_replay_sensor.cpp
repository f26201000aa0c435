#include "rgbdi/live/rawlog_replay_sensor.h"

#include <atomic>
#include <condition_variable>
#include <deque>
#include <filesystem>
#include <mutex>
#include <optional>
#include <thread>

#include "live/bag_playback_keys.h"
#include "live/external_images.h"
#include "live/sensor_keys.h"
#include "rgbdi/bag/bag_converter.h"
#include "rgbdi/io/input_format.h"
#include "rgbdi/io/mrpt_conversions.h"
#include "rgbdi/io/mrpt_image_path.h"
#include "rgbdi/io/rawlog_source.h"
#include "rgbdi/live/playback_clock.h"

IMPLEMENTS_GENERIC_SENSOR(RgbdiRawlogReplay, rgbdi::live)

namespace rgbdi::live {
namespace {

struct Item {
  io::Measurement m;
  Eigen::Isometry3d T_body_cam = Eigen::Isometry3d::Identity();
};

}  // namespace

struct RgbdiRawlogReplay::Impl {
  // Settings (loadConfig).
  std::string section, file, camera_label = "RGBD", imu_label = "IMU",
                             wheel_label = "WHEEL_ODOMETRY";
  double speed = 1.0;
  bool restamp = true;
  int read_ahead = 256;
  std::string external_dir;
  BagPlaybackKeys bag_keys;  ///< how a bag is converted (rawlog-convert's options)

  // Input (initialize).
  std::unique_ptr<io::RawlogSource> rawlog;
  std::unique_ptr<bag::BagConverter> bag;
  std::thread reader;
  std::atomic<bool> stop{false};

  mutable std::mutex mutex;
  std::condition_variable space_cv;
  std::deque<Item> queue;
  bool reader_done = false;
  std::string reader_error;
  std::optional<PlaybackClock> clock;
  std::size_t frames_out = 0;

  /// Reader thread: blocks while the queue is full.
  void push(Item it) {
    std::unique_lock<std::mutex> lk(mutex);
    space_cv.wait(lk,
                  [this] { return stop || queue.size() < static_cast<std::size_t>(read_ahead); });
    if (stop) return;
    queue.push_back(std::move(it));
  }

  struct BagSink : bag::ConversionSink {
    Impl& impl;
    Eigen::Isometry3d T_body_cam;
    BagSink(Impl& i, const Eigen::Isometry3d& T) : impl(i), T_body_cam(T) {}
    void imu(const ImuSample& s) override { impl.push({io::Measurement(s), T_body_cam}); }
    void accelerometer(double, const Eigen::Vector3d&) override {}  // no gyro: not an IMU
    void frame(const RgbdFrame& f) override { impl.push({io::Measurement(f), T_body_cam}); }
    void wheel(const WheelOdometrySample& w) override {
      impl.push({io::Measurement(w), T_body_cam});
    }
    void groundTruth(const StampedPose&) override {}
  };

  void readLoop() {
    try {
      if (rawlog) {
        io::Measurement m;
        for (;;) {
          {
            // RawlogSource resolves external images through MRPT's ONE process-wide image
            // path: no other replay, recorder or grabber may use it meanwhile.
            std::lock_guard<std::mutex> lk(io::mrptImagePathMutex());
            if (stop || !rawlog->next(m)) break;
          }
          Item it{std::move(m), Eigen::Isometry3d::Identity()};
          if (auto* f = std::get_if<RgbdFrame>(&it.m))
            if (f->has_source_T_body_cam) it.T_body_cam = f->source_T_body_cam;
          push(std::move(it));
        }
      } else if (bag) {
        BagSink sink(*this, bag->T_body_cam());
        const bag::ConversionReport r = bag->run(sink, {}, &stop);
        if (!r.error.empty()) throw std::runtime_error(r.error);
      }
    } catch (const std::exception& e) {
      std::lock_guard<std::mutex> lk(mutex);
      reader_error = file + ": " + e.what();
    }
    std::lock_guard<std::mutex> lk(mutex);
    reader_done = true;
  }
};

RgbdiRawlogReplay::RgbdiRawlogReplay() : impl_(std::make_unique<Impl>()) {}

RgbdiRawlogReplay::~RgbdiRawlogReplay() {
  impl_->stop = true;
  impl_->space_cv.notify_all();
  if (impl_->reader.joinable()) impl_->reader.join();
}

void RgbdiRawlogReplay::loadConfig_sensorSpecific(const mrpt::config::CConfigFileBase& cfg,
                                                  const std::string& section) {
  Impl& d = *impl_;
  const SensorKeys k(cfg, section);
  d.section = section;
  d.file = k.getPath("file", true);
  d.speed = k.getDouble("speed", d.speed, 1e-3, 1000.0);
  d.restamp = k.getEnum("stamps", "now", {"now", "source"}) == "now";
  d.read_ahead = k.getInt("read_ahead", d.read_ahead, 1, 1000000);
  d.camera_label = k.getString("camera_label", d.camera_label);
  d.imu_label = k.getString("imu_label", d.imu_label);
  d.wheel_label = k.getString("wheel_label", d.wheel_label);
  d.bag_keys = BagPlaybackKeys::load(k, true);
}

void RgbdiRawlogReplay::setPathForExternalImages(const std::string& directory) {
  impl_->external_dir = directory;
}

void RgbdiRawlogReplay::initialize() {
  Impl& d = *impl_;
  namespace fs = std::filesystem;
  std::error_code ec;
  if (d.file.empty()) throw std::runtime_error("no file given (key 'file')");
  if (!fs::exists(d.file, ec)) throw std::runtime_error(d.file + ": file does not exist");
  const io::InputFormat fmt = io::detectInputFormat(d.file);
  if (fmt == io::InputFormat::Rawlog) {
    // A rawlog's observations carry their calibration; silently ignoring a bag key would leave
    // the user believing it applied.
    if (!d.bag_keys.given.empty())
      throw std::runtime_error(d.bag_keys.givenList() + " apply to ROS1 bags only; " + d.file +
                               " is an MRPT rawlog (its observations carry their calibration)");
    d.rawlog = std::make_unique<io::RawlogSource>(d.file);
    d.rawlog->logging_enable_console_output = false;
  } else if (fmt == io::InputFormat::Ros1Bag) {
    d.bag = std::make_unique<bag::BagConverter>(d.file, d.bag_keys.settings.options,
                                                d.bag_keys.input, d.bag_keys.settings.calibration);
  } else {
    throw std::runtime_error(d.file + ": " + io::formatName(fmt) +
                             " input cannot be replayed directly; convert it with rawlog-convert "
                             "first (rawlogs and ROS1 bags are played)");
  }
  d.reader = std::thread([&d] { d.readLoop(); });
  m_state = ssWorking;
}

void RgbdiRawlogReplay::doProcess() {
  Impl& d = *impl_;
  std::vector<mrpt::serialization::CSerializable::Ptr> out;
  {
    std::lock_guard<std::mutex> lk(d.mutex);
    const double now = io::toSeconds(mrpt::Clock::now());
    if (!d.clock && !d.queue.empty()) {
      d.clock.emplace(d.speed, d.restamp);
      d.clock->start(now, io::measurementTime(d.queue.front().m));
    }
    if (d.clock) {
      const double horizon = d.clock->horizon(now);
      while (!d.queue.empty() && io::measurementTime(d.queue.front().m) <= horizon) {
        Item it = std::move(d.queue.front());
        d.queue.pop_front();
        if (auto* imu = std::get_if<ImuSample>(&it.m)) {
          imu->t = d.clock->outputStamp(imu->t);
          out.push_back(io::toMrpt(*imu, d.imu_label));
        } else if (auto* wheel = std::get_if<WheelOdometrySample>(&it.m)) {
          wheel->t = d.clock->outputStamp(wheel->t);
          out.push_back(io::toMrpt(*wheel, d.wheel_label));
        } else {
          auto& f = std::get<RgbdFrame>(it.m);
          f.t = d.clock->outputStamp(f.t);
          auto obs = io::toMrpt(f, it.T_body_cam, d.camera_label);
          if (!d.external_dir.empty())
            storeImagesExternally(*obs, d.external_dir,
                                  d.camera_label + "_" + std::to_string(d.frames_out),
                                  m_external_images_format);
          ++d.frames_out;
          out.push_back(obs);
        }
      }
    }
    if (d.queue.empty() && d.reader_done && !d.reader_error.empty()) {
      const std::string e = std::move(d.reader_error);
      d.reader_error.clear();
      m_state = ssError;
      throw std::runtime_error(e);
    }
  }
  d.space_cv.notify_all();
  for (const auto& o : out) appendObservation(o);
}

bool RgbdiRawlogReplay::endOfData() const {
  std::lock_guard<std::mutex> lk(impl_->mutex);
  return impl_->reader_done && impl_->queue.empty() && impl_->reader_error.empty();
}

}  // namespace rgbdi::live
