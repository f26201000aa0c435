// bench_live [SECONDS] [CONSUMER_MS]: the live source on a 30 Hz 640x480 RGB-D + 200 Hz IMU
// stream replayed with RgbdiRawlogReplay (stamps re-based onto the wall clock) at increasing
// speeds, with a consumer that spends CONSUMER_MS per frame (default 0: delivery only). Prints,
// per speed: wall time against the data's duration, frames dropped, IMU delivered, latency from
// stamp to delivery (p50/p95/max) and the queue high-water marks, then the highest speed that
// ran without drops. The stream is generated once in a temporary directory (external images).
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <thread>

#include "rgbdi/io/rawlog_writer.h"
#include "rgbdi/live/live_source.h"

namespace {

using namespace rgbdi;

RgbdFrame frame(std::size_t i, double t) {
  RgbdFrame f;
  f.t = t;
  f.rgb = cv::Mat(480, 640, CV_8UC3);
  f.depth = cv::Mat(480, 640, CV_16UC1);
  for (int r = 0; r < 480; ++r)
    for (int c = 0; c < 640; ++c) {
      f.rgb.at<cv::Vec3b>(r, c) = cv::Vec3b((r + i) % 256, (c * 3) % 256, (r * c + i) % 256);
      f.depth.at<std::uint16_t>(r, c) = static_cast<std::uint16_t>(800 + (r * 7 + c + i) % 3000);
    }
  PinholeCamera cam;
  cam.width = 640;
  cam.height = 480;
  cam.fx = cam.fy = 616.0;
  cam.cx = 320.0;
  cam.cy = 240.0;
  f.cam_color = f.cam_depth = cam;
  return f;
}

void writeStream(const std::string& path, double seconds) {
  io::RawlogWriterOptions o;
  o.external_images = true;
  io::RawlogWriter w(path, o);
  const double t0 = 1000.0;
  std::size_t k = 0, i = 0;
  for (;;) {
    const double ti = t0 + k * 0.005, tf = t0 + i / 30.0;
    if (ti > t0 + seconds && tf > t0 + seconds) break;
    if (ti <= tf) {
      ImuSample s;
      s.t = ti;
      s.acc = Eigen::Vector3d(0.0, 0.0, 9.81);
      w.write(s);
      ++k;
    } else {
      w.write(frame(i++, tf));
    }
  }
  w.close();
}

struct Consumer : MeasurementSink {
  std::chrono::microseconds per_frame{0};
  void feedImu(const ImuSample&) override {}
  void feedRgbd(const RgbdFrame&) override {
    if (per_frame.count() > 0) std::this_thread::sleep_for(per_frame);
  }
};

}  // namespace

int main(int argc, char** argv) {
  const double seconds = argc > 1 ? std::stod(argv[1]) : 4.0;
  const double consumer_ms = argc > 2 ? std::stod(argv[2]) : 0.0;
  const auto dir = std::filesystem::temp_directory_path() / "rgbdi_bench_live";
  std::filesystem::create_directories(dir);
  const std::string rawlog = (dir / "stream.rawlog").string();
  std::printf("generating %.1f s of 640x480 @ 30 Hz + IMU @ 200 Hz in %s ...\n", seconds,
              dir.c_str());
  writeStream(rawlog, seconds);

  std::printf("consumer: %.1f ms per frame\n", consumer_ms);
  std::printf("%6s %8s %8s %8s %8s %9s %9s %9s %6s %6s\n", "speed", "wall_s", "ideal_s", "frames",
              "dropped", "p50_ms", "p95_ms", "max_ms", "qimu", "qimg");
  double best = 0.0;
  for (double speed : {1.0, 2.0, 4.0, 8.0, 16.0, 32.0}) {
    const std::string ini = (dir / "sensors.ini").string();
    std::ofstream(ini) << "[global]\nlive_first_frame_timeout_s = 30\n[REPLAY]\n"
                          "driver = RgbdiRawlogReplay\nprocess_rate = 400\nfile = stream.rawlog\n"
                          "stamps = now\nspeed = "
                       << speed << "\n";
    live::LiveSource src(live::SensorConfig::fromFile(ini));
    Consumer c;
    c.per_frame = std::chrono::microseconds(static_cast<long>(consumer_ms * 1000.0));
    src.pump(c);
    const live::LiveStats s = src.stats();
    std::printf("%6.1f %8.2f %8.2f %8zu %8zu %9.2f %9.2f %9.2f %6zu %6zu\n", speed,
                s.wall_duration_s, seconds / speed, s.frames_received, s.frames_dropped,
                s.frame_latency.p50_s * 1e3, s.frame_latency.p95_s * 1e3,
                s.frame_latency.max_s * 1e3, s.imu_queue_high_water, s.frame_queue_high_water);
    if (s.frames_dropped == 0) best = speed;
  }
  std::printf("highest replay speed without drops: %.0fx\n", best);
  std::filesystem::remove_all(dir);
  return 0;
}
