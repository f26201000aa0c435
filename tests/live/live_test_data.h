// Shared by the live tests: a small deterministic RGB-D-inertial rawlog (200 Hz IMU, 30 Hz
// 32x24 frames whose pixels encode the frame index), a sensors INI writer, and a sink that
// records what a source delivers.
#pragma once

#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "rgbdi/common/measurement_sink.h"
#include "rgbdi/io/rawlog_writer.h"

namespace rgbdi::test {

constexpr double kLiveT0 = 1000.0;    // [s] first stamp
constexpr double kLiveImuDt = 0.005;  // [s] 200 Hz
constexpr double kLiveFrameDt = 1.0 / 30.0;

inline ImuSample liveImu(std::size_t k) {
  ImuSample s;
  s.t = kLiveT0 + k * kLiveImuDt;
  s.acc = Eigen::Vector3d(0.1 + 1e-3 * k, -0.2, 9.81);
  s.gyr = Eigen::Vector3d(0.01, -0.02 + 1e-4 * k, 0.03);
  return s;
}

inline RgbdFrame liveFrame(std::size_t i) {
  RgbdFrame f;
  f.t = kLiveT0 + 0.001 + i * kLiveFrameDt;
  f.rgb = cv::Mat(24, 32, CV_8UC3, cv::Scalar(static_cast<int>(i % 256), 100, 200));
  f.depth = cv::Mat(24, 32, CV_16UC1, cv::Scalar(static_cast<int>(1000 + i)));
  f.depth.at<std::uint16_t>(3, 4) = 0;
  f.depth_unit_m = 1e-3;
  PinholeCamera c;
  c.width = 32;
  c.height = 24;
  c.fx = c.fy = 30.0;
  c.cx = 16.0;
  c.cy = 12.0;
  f.cam_color = f.cam_depth = c;
  f.depth_aligned_to_color = true;
  return f;
}

/// Writes `seconds` of data (IMU and frames interleaved in stamp order) to `path`.
inline void writeLiveRawlog(const std::string& path, double seconds, std::size_t* n_imu = nullptr,
                            std::size_t* n_frames = nullptr) {
  io::RawlogWriter w(path, io::RawlogWriterOptions());
  std::size_t k = 0, i = 0;
  const double end = kLiveT0 + seconds;
  while (true) {
    const double ti = liveImu(k).t, tf = liveFrame(i).t;
    if (ti > end && tf > end) break;
    if (ti <= tf) {
      w.write(liveImu(k++));
    } else {
      w.write(liveFrame(i++));
    }
  }
  w.close();
  if (n_imu) *n_imu = k;
  if (n_frames) *n_frames = i;
}

inline std::string writeFile(const std::string& path, const std::string& text) {
  std::ofstream(path) << text;
  return path;
}

/// Records everything; optionally sleeps in feedRgbd (a consumer that cannot keep up).
struct CollectingSink : MeasurementSink {
  std::vector<ImuSample> imu;
  std::vector<RgbdFrame> frames;
  std::vector<WheelOdometrySample> wheel;
  std::vector<double> stamps;  ///< every stamp in delivery order
  bool ended = false;
  std::chrono::milliseconds frame_sleep{0};

  void feedImu(const ImuSample& s) override {
    imu.push_back(s);
    stamps.push_back(s.t);
  }
  void feedRgbd(const RgbdFrame& f) override {
    frames.push_back(f);
    stamps.push_back(f.t);
    if (frame_sleep.count() > 0) std::this_thread::sleep_for(frame_sleep);
  }
  void feedWheel(const WheelOdometrySample& w) override {
    wheel.push_back(w);
    stamps.push_back(w.t);
  }
  void endOfStream() override { ended = true; }
};

}  // namespace rgbdi::test
