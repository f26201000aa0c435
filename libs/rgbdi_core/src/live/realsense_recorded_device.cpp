// The recorded RealSense adapter: plays a RealSense SDK .bag (realsense-viewer / rs-record
// layout) through rgbdi's bag reader, at the recording's pace, into the RealSenseDevice
// callbacks: colour and depth paired into framesets (bag::RgbdPairer), accelerometer and gyro as
// separate motion samples (the sensor merges them). Calibration as rawlog-convert reads it.
#include <ros/serialization.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <mutex>
#include <optional>
#include <thread>

#include "rgbdi/bag/bag_converter.h"
#include "rgbdi/bag/bag_reader.h"
#include "rgbdi/bag/rgbd_pairer.h"
#include "rgbdi/bag/ros_image.h"
#include "rgbdi/bag/ros_wire.h"
#include "rgbdi/io/mrpt_conversions.h"
#include "rgbdi/live/playback_clock.h"
#include "rgbdi/live/realsense_device.h"

namespace rgbdi::live {
namespace {

template <typename M>
void deserialize(const bag::BagMessage& m, M& out) {
  ros::serialization::IStream s(const_cast<std::uint8_t*>(m.data), m.size);
  ros::serialization::deserialize(s, out);
}

class RecordedRealSenseDevice : public RealSenseDevice {
 public:
  RecordedRealSenseDevice(std::string path, double speed, bool restamp,
                          const bag::ConvertOptions& options,
                          const bag::FallbackCalibration& fallback)
      : path_(std::move(path)), options_(options), fallback_(fallback), clock_(speed, restamp) {}
  ~RecordedRealSenseDevice() override { stop(); }

  std::vector<RealSenseDeviceInfo> enumerate() override {
    return {{"RealSense SDK recording", path_, ""}};
  }

  RealSenseCalibration open(const RealSenseRequest& request) override {
    try {
      converter_ =
          std::make_unique<bag::BagConverter>(path_, options_, bag::BagInputOptions(), fallback_);
    } catch (const std::exception& e) {
      throw RealSenseError(e.what());
    }
    const bag::BagLayout& l = converter_->layout();
    if (request.align_depth_to_color && !l.depth_aligned)
      throw RealSenseError(path_ +
                           ": the recorded adapter plays depth as recorded (not aligned to "
                           "colour); set align_depth = false, or use device = sdk");
    layout_ = l;
    use_imu_ = request.imu;
    RealSenseCalibration c;
    c.color = converter_->colorCamera();
    c.depth = converter_->depthCamera();
    c.T_color_depth = converter_->T_color_depth();
    c.depth_aligned = l.depth_aligned;
    c.depth_unit_m = converter_->depthUnit();
    c.has_imu = use_imu_ && (!l.imu.empty() || (!l.accel.empty() && !l.gyro.empty()));
    c.T_imu_color = converter_->T_body_cam();
    c.device = enumerate().front();
    return c;
  }

  void start(FramesetCallback on_frameset, MotionCallback on_motion) override {
    if (!converter_) throw RealSenseError(path_ + ": start() before open()");
    on_frameset_ = std::move(on_frameset);
    on_motion_ = std::move(on_motion);
    thread_ = std::thread([this] { play(); });
  }

  void stop() override {
    {
      std::lock_guard<std::mutex> lk(mutex_);
      stop_ = true;
    }
    cv_.notify_all();
    if (thread_.joinable()) thread_.join();
  }

  bool finished() const override { return finished_; }
  std::string error() const override {
    std::lock_guard<std::mutex> lk(mutex_);
    return error_;
  }

 private:
  /// Sleeps until data stamped t is due; false when stopped.
  bool waitFor(double t) {
    if (!clock_.started()) clock_.start(io::toSeconds(mrpt::Clock::now()), t);
    for (;;) {
      const double wait = clock_.dueWall(t) - io::toSeconds(mrpt::Clock::now());
      std::unique_lock<std::mutex> lk(mutex_);
      if (stop_) return false;
      if (wait <= 0.0) return true;
      cv_.wait_for(lk, std::chrono::duration<double>(wait), [this] { return stop_; });
    }
  }

  void deliverPairs(bag::RgbdPairer& pairer) {
    bag::PairedImages p;
    while (pairer.pop(p)) {
      if (!p.depth) continue;  // colour without depth is dropped, as rawlog-convert does
      if (!p.color && options_.require_colour) continue;  // [convert] require_colour
      RealSenseFrameset fs;
      fs.t = clock_.outputStamp(p.color ? p.color->t : p.depth->t);
      fs.number = frames_++;
      if (p.color) fs.rgb = p.color->image;
      if (p.depth) fs.depth = p.depth->image;
      on_frameset_(std::move(fs));
    }
  }

  void play() {
    std::vector<std::string> topics = {layout_.color, layout_.depth};
    if (use_imu_) {
      topics.push_back(layout_.imu);
      topics.push_back(layout_.accel);
      topics.push_back(layout_.gyro);
    }
    topics.erase(std::remove(topics.begin(), topics.end(), std::string()), topics.end());
    bag::RgbdPairer pairer(options_.pair_tolerance_s, options_.max_wait_s);
    try {
      bag::BagReader reader(path_, topics);
      bag::BagMessage m;
      while (reader.next(m)) {
        const std::string& topic = *m.topic;
        const auto stampOf = [&](const std_msgs::Header& h) {
          return h.stamp.isZero() ? m.bag_time : h.stamp.toSec();
        };
        const std::string label = path_ + " " + topic + " message " + std::to_string(m.ordinal);
        if (topic == layout_.color || topic == layout_.depth) {
          const bool color = topic == layout_.color;
          const bool compressed = color ? layout_.color_compressed : layout_.depth_compressed;
          bag::StampedImage img;
          auto decode = [&](auto&& msg) {
            bag::deserializeImage(m.data, m.size, msg, label);  // lengths checked first
            img.t = stampOf(msg.header);
            img.label = label;
            if (color) {
              img.image = bag::decodeColorImage(msg, label);
            } else {
              bag::DepthImage d = bag::decodeDepthImage(msg, converter_->depthUnit(),
                                                        options_.float_depth_unit_m, label);
              img.image = d.depth;
              img.unit_m = d.unit_m;
            }
          };
          if (compressed) {
            decode(sensor_msgs::CompressedImage());
          } else {
            decode(sensor_msgs::Image());
          }
          if (!waitFor(img.t)) break;
          if (color) {
            pairer.pushColor(std::move(img));
          } else {
            pairer.pushDepth(std::move(img));
          }
          deliverPairs(pairer);
        } else {
          sensor_msgs::Imu msg;
          deserialize(m, msg);
          const double t = stampOf(msg.header);
          if (!waitFor(t)) break;
          const Eigen::Vector3d acc(msg.linear_acceleration.x, msg.linear_acceleration.y,
                                    msg.linear_acceleration.z);
          const Eigen::Vector3d gyr(msg.angular_velocity.x, msg.angular_velocity.y,
                                    msg.angular_velocity.z);
          const double ts = clock_.outputStamp(t);
          if (topic != layout_.gyro) on_motion_({RealSenseMotion::Kind::Accel, ts, acc});
          if (topic != layout_.accel) on_motion_({RealSenseMotion::Kind::Gyro, ts, gyr});
        }
      }
    } catch (const std::exception& e) {
      // Damage ends the recording: what was read before it is still delivered, then reported.
      std::lock_guard<std::mutex> lk(mutex_);
      error_ = e.what();
    }
    pairer.finish();
    deliverPairs(pairer);
    finished_ = true;
  }

  std::string path_;
  bag::ConvertOptions options_;
  bag::FallbackCalibration fallback_;
  PlaybackClock clock_;
  std::unique_ptr<bag::BagConverter> converter_;
  bag::BagLayout layout_;
  bool use_imu_ = true;
  FramesetCallback on_frameset_;
  MotionCallback on_motion_;
  std::thread thread_;
  mutable std::mutex mutex_;
  std::condition_variable cv_;
  std::string error_;
  bool stop_ = false;
  std::atomic<bool> finished_{false};
  std::uint64_t frames_ = 0;
};

}  // namespace

std::unique_ptr<RealSenseDevice> makeRecordedRealSenseDevice(
    const std::string& bag_path, double speed, bool restamp, const bag::ConvertOptions& options,
    const bag::FallbackCalibration& fallback) {
  return std::make_unique<RecordedRealSenseDevice>(bag_path, speed, restamp, options, fallback);
}

}  // namespace rgbdi::live
