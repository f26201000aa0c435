// The librealsense2 adapter of RgbdiRealSense: the only rgbdi code that calls the RealSense SDK.
// Compiled only when CMake finds realsense2 (RGBDI_HAVE_REALSENSE2); see doc/live.md.
//
// One rs2::pipeline streams colour (RGB8), depth (Z16) and, on D435i/D455, accelerometer and
// gyro (MOTION_XYZ32F) into one callback. Motion samples are passed on at once; framesets go
// through a two-slot queue to a worker thread that aligns depth to colour when asked (alignment
// is slow and must not delay IMU samples in the SDK callback) and copies the images out.
// Options are applied to the device's sensors after the pipeline has started: global time on
// every sensor that has it, emitter and auto-exposure on the stereo module, auto-exposure on the
// RGB camera. An SDK .bag (playback_file) is played by the SDK itself in real time at `speed`,
// once; its stamps are re-based onto the wall clock on request (as the recorded adapter does).
#include <mrpt/core/Clock.h>

#include <atomic>
#include <condition_variable>
#include <deque>
#include <librealsense2/rs.hpp>
#include <mutex>
#include <thread>

#include "rgbdi/io/mrpt_conversions.h"
#include "rgbdi/live/playback_clock.h"
#include "rgbdi/live/realsense_device.h"

namespace rgbdi::live {
namespace {

PinholeCamera cameraOf(const rs2::video_stream_profile& p, const std::string& what) {
  const rs2_intrinsics in = p.get_intrinsics();
  PinholeCamera c;
  c.width = in.width;
  c.height = in.height;
  c.fx = in.fx;
  c.fy = in.fy;
  c.cx = in.ppx;
  c.cy = in.ppy;
  bool zero = true;
  for (float k : in.coeffs) zero = zero && k == 0.0f;
  if (!zero && in.model != RS2_DISTORTION_BROWN_CONRADY)
    throw RealSenseError(what + " intrinsics use the " +
                         std::string(rs2_distortion_to_string(in.model)) +
                         " model with non-zero coefficients, which rgbdi's pinhole + "
                         "radial-tangential camera cannot represent");
  if (!zero)
    for (int i = 0; i < 5; ++i) c.dist[i] = in.coeffs[i];
  return c;
}

/// Pose of `from`'s frame in `to`'s frame (p_to = R p_from + t; SDK rotation is column-major).
Eigen::Isometry3d extrinsic(const rs2::stream_profile& from, const rs2::stream_profile& to) {
  const rs2_extrinsics e = from.get_extrinsics_to(to);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) T.linear()(r, c) = e.rotation[c * 3 + r];
    T.translation()(r) = e.translation[r];
  }
  return T;
}

void setIfSupported(rs2::sensor& s, rs2_option o, float v) {
  if (s.supports(o) && !s.is_option_read_only(o)) s.set_option(o, v);
}

/// "Depth Z16 640x480@30, Color RGB8 640x480@30": what a device (a recording) can stream.
std::string describeProfiles(const rs2::device& d) {
  std::string out;
  for (const rs2::sensor& s : d.query_sensors())
    for (const rs2::stream_profile& p : s.get_stream_profiles()) {
      if (!out.empty()) out += ", ";
      out += std::string(rs2_stream_to_string(p.stream_type())) + " " +
             rs2_format_to_string(p.format());
      if (auto v = p.as<rs2::video_stream_profile>())
        out += " " + std::to_string(v.width()) + "x" + std::to_string(v.height());
      out += "@" + std::to_string(p.fps());
    }
  return out.empty() ? "no streams" : out;
}

class LibrealsenseDevice : public RealSenseDevice {
 public:
  LibrealsenseDevice(std::string playback, double speed, bool restamp)
      : playback_(std::move(playback)), speed_(speed), clock_(speed, restamp) {}
  ~LibrealsenseDevice() override { stop(); }

  std::vector<RealSenseDeviceInfo> enumerate() override {
    std::vector<RealSenseDeviceInfo> out;
    for (rs2::device d : ctx_.query_devices()) out.push_back(infoOf(d));
    return out;
  }

  RealSenseCalibration open(const RealSenseRequest& r) override {
    request_ = r;
    try {
      if (!playback_.empty()) {
        cfg_.enable_device_from_file(playback_, false);
      } else {
        if (ctx_.query_devices().size() == 0)
          throw RealSenseError(
              "no RealSense device found (is it plugged into a USB 3 port, and "
              "are Intel's udev rules installed?)");
        if (!r.serial.empty()) cfg_.enable_device(r.serial);
      }
      cfg_.enable_stream(RS2_STREAM_COLOR, r.color_width, r.color_height, RS2_FORMAT_RGB8,
                         r.color_fps);
      cfg_.enable_stream(RS2_STREAM_DEPTH, r.depth_width, r.depth_height, RS2_FORMAT_Z16,
                         r.depth_fps);
      if (r.imu) {
        cfg_.enable_stream(RS2_STREAM_ACCEL, RS2_FORMAT_MOTION_XYZ32F, r.accel_hz);
        cfg_.enable_stream(RS2_STREAM_GYRO, RS2_FORMAT_MOTION_XYZ32F, r.gyro_hz);
      }
      pipe_ = std::make_unique<rs2::pipeline>(ctx_);
      if (!cfg_.can_resolve(*pipe_)) {
        // A recording has exactly the streams it was recorded with: name them.
        std::string recorded;
        if (!playback_.empty()) {
          // A context of its own: the pipeline's already holds the file.
          rs2::context listing;
          recorded = "; " + playback_ + " has " + describeProfiles(listing.load_device(playback_));
        }
        throw RealSenseError(
            (playback_.empty() ? "the device" : "the recording") +
            std::string(" cannot stream colour ") + std::to_string(r.color_width) + "x" +
            std::to_string(r.color_height) + "@" + std::to_string(r.color_fps) + ", depth " +
            std::to_string(r.depth_width) + "x" + std::to_string(r.depth_height) + "@" +
            std::to_string(r.depth_fps) +
            (r.imu
                 ? ", accel @" + std::to_string(r.accel_hz) + ", gyro @" + std::to_string(r.gyro_hz)
                 : std::string()) +
            recorded +
            " (check the keys against rs-enumerate-devices; a D435 has no IMU: imu = false)");
      }
      const rs2::pipeline_profile prof = cfg_.resolve(*pipe_);
      const auto color = prof.get_stream(RS2_STREAM_COLOR).as<rs2::video_stream_profile>();
      const auto depth = prof.get_stream(RS2_STREAM_DEPTH).as<rs2::video_stream_profile>();
      RealSenseCalibration c;
      c.device = infoOf(prof.get_device());
      c.color = cameraOf(color, "colour");
      c.depth_aligned = r.align_depth_to_color;
      c.depth = c.depth_aligned ? c.color : cameraOf(depth, "depth");
      c.T_color_depth = c.depth_aligned ? Eigen::Isometry3d::Identity() : extrinsic(depth, color);
      for (rs2::sensor s : prof.get_device().query_sensors())
        if (auto ds = s.as<rs2::depth_sensor>()) c.depth_unit_m = ds.get_depth_scale();
      if (r.imu) {
        c.has_imu = true;
        c.T_imu_color = extrinsic(color, prof.get_stream(RS2_STREAM_GYRO));
      }
      calib_ = c;
      return c;
    } catch (const rs2::error& e) {
      throw RealSenseError(std::string("librealsense2: ") + e.get_failed_function() + "(" +
                           e.get_failed_args() + "): " + e.what());
    }
  }

  void start(FramesetCallback on_frameset, MotionCallback on_motion) override {
    on_frameset_ = std::move(on_frameset);
    on_motion_ = std::move(on_motion);
    worker_ = std::thread([this] { work(); });
    try {
      const rs2::pipeline_profile prof = pipe_->start(cfg_, [this](const rs2::frame& f) {
        ++received_;
        if (auto m = f.as<rs2::motion_frame>()) {
          const rs2_vector v = m.get_motion_data();
          const auto kind = m.get_profile().stream_type() == RS2_STREAM_ACCEL
                                ? RealSenseMotion::Kind::Accel
                                : RealSenseMotion::Kind::Gyro;
          on_motion_({kind, stamp(m.get_timestamp() * 1e-3), Eigen::Vector3d(v.x, v.y, v.z)});
        } else if (auto fs = f.as<rs2::frameset>()) {
          std::lock_guard<std::mutex> lk(mutex_);
          pending_.push_back(fs);
          while (pending_.size() > 2) pending_.pop_front();  // the worker is behind: keep new
          cv_.notify_one();
        }
      });
      device_ = prof.get_device();
      if (playback_.empty()) {
        for (rs2::sensor s : device_.query_sensors()) {
          setIfSupported(s, RS2_OPTION_GLOBAL_TIME_ENABLED, request_.global_time ? 1.f : 0.f);
          if (s.as<rs2::depth_sensor>()) {
            setIfSupported(s, RS2_OPTION_EMITTER_ENABLED, request_.emitter_enabled ? 1.f : 0.f);
            setIfSupported(s, RS2_OPTION_ENABLE_AUTO_EXPOSURE,
                           request_.depth_auto_exposure ? 1.f : 0.f);
          } else if (s.supports(RS2_CAMERA_INFO_NAME) &&
                     std::string(s.get_info(RS2_CAMERA_INFO_NAME)) == "RGB Camera") {
            setIfSupported(s, RS2_OPTION_ENABLE_AUTO_EXPOSURE,
                           request_.color_auto_exposure ? 1.f : 0.f);
          }
        }
      } else if (auto pb = device_.as<rs2::playback>()) {
        pb.set_real_time(true);
        pb.set_playback_speed(static_cast<float>(speed_));
      }
      running_ = true;
    } catch (const rs2::error& e) {
      stop();
      throw RealSenseError(std::string("librealsense2: cannot start streaming: ") + e.what());
    }
  }

  void stop() override {
    if (running_.exchange(false)) {
      try {
        pipe_->stop();
      } catch (const rs2::error&) {
        // Already stopped (device unplugged, playback ended).
      }
    }
    {
      std::lock_guard<std::mutex> lk(mutex_);
      quit_ = true;
    }
    cv_.notify_all();
    if (worker_.joinable()) worker_.join();
  }

  bool finished() const override {
    if (playback_.empty() || !device_) return false;
    auto pb = device_.as<rs2::playback>();
    // The SDK stops the playback after its sensors have delivered every frame (so every frameset
    // is in pending_ by then); it is over for us once the worker has passed them all on.
    // It also reports STOPPED before it has begun to play: over only once something came.
    if (!pb || received_ == 0 || pb.current_status() != RS2_PLAYBACK_STATUS_STOPPED) return false;
    std::lock_guard<std::mutex> lk(mutex_);
    return pending_.empty() && !busy_;
  }

  std::string error() const override {
    std::lock_guard<std::mutex> lk(mutex_);
    return error_;
  }

 private:
  static RealSenseDeviceInfo infoOf(const rs2::device& d) {
    const auto get = [&](rs2_camera_info i) {
      return d.supports(i) ? std::string(d.get_info(i)) : std::string();
    };
    return {get(RS2_CAMERA_INFO_NAME), get(RS2_CAMERA_INFO_SERIAL_NUMBER),
            get(RS2_CAMERA_INFO_FIRMWARE_VERSION)};
  }

  /// A device stamp [s] as delivered: re-based onto the wall clock for a re-stamped playback.
  double stamp(double t) {
    if (playback_.empty() || !clock_.restamp()) return t;
    std::lock_guard<std::mutex> lk(clock_mutex_);
    if (!clock_.started()) clock_.start(io::toSeconds(mrpt::Clock::now()), t);
    return clock_.outputStamp(t);
  }

  void work() {
    rs2::align align(RS2_STREAM_COLOR);
    for (;;) {
      rs2::frameset fs;
      {
        std::unique_lock<std::mutex> lk(mutex_);
        busy_ = false;
        cv_.wait(lk, [this] { return quit_ || !pending_.empty(); });
        if (quit_) return;
        fs = pending_.front();
        pending_.pop_front();
        busy_ = true;
      }
      try {
        if (request_.align_depth_to_color) fs = align.process(fs);
        RealSenseFrameset out;
        out.number = frames_++;
        if (rs2::video_frame c = fs.get_color_frame()) {
          out.t = stamp(c.get_timestamp() * 1e-3);
          out.rgb = cv::Mat(c.get_height(), c.get_width(), CV_8UC3, const_cast<void*>(c.get_data()),
                            c.get_stride_in_bytes())
                        .clone();
        }
        if (rs2::depth_frame d = fs.get_depth_frame()) {
          if (out.rgb.empty()) out.t = stamp(d.get_timestamp() * 1e-3);
          out.depth = cv::Mat(d.get_height(), d.get_width(), CV_16UC1,
                              const_cast<void*>(d.get_data()), d.get_stride_in_bytes())
                          .clone();
        }
        on_frameset_(std::move(out));
      } catch (const rs2::error& e) {
        std::lock_guard<std::mutex> lk(mutex_);
        if (error_.empty()) error_ = std::string("librealsense2: ") + e.what();
      }
    }
  }

  std::string playback_;
  double speed_;
  PlaybackClock clock_;  // playback re-stamping; guarded by clock_mutex_
  std::mutex clock_mutex_;
  RealSenseRequest request_;
  RealSenseCalibration calib_;
  rs2::context ctx_;
  rs2::config cfg_;
  std::unique_ptr<rs2::pipeline> pipe_;
  rs2::device device_;
  FramesetCallback on_frameset_;
  MotionCallback on_motion_;
  std::thread worker_;
  mutable std::mutex mutex_;
  std::condition_variable cv_;
  std::deque<rs2::frameset> pending_;
  bool quit_ = false;
  bool busy_ = false;  // the worker is passing a frameset on (guarded by mutex_)
  std::atomic<bool> running_{false};
  std::atomic<std::uint64_t> received_{0};  // frames and framesets from the SDK callback
  std::string error_;
  std::uint64_t frames_ = 0;
};

}  // namespace

std::unique_ptr<RealSenseDevice> makeLibrealsenseDevice(const std::string& playback_bag,
                                                        double speed, bool restamp) {
  return std::make_unique<LibrealsenseDevice>(playback_bag, speed, restamp);
}

}  // namespace rgbdi::live
