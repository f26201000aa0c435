// bench_live [SECONDS] [CONSUMER_MS]: the live source on a 30 Hz 640x480 RGB-D + 200 Hz IMU
// stream replayed with RgbdiRawlogReplay (stamps re-based onto the wall clock) at increasing
// speeds, with a consumer that spends CONSUMER_MS per frame (default 0: delivery only). Prints,
// per speed: wall time against the data's duration, frames dropped, IMU delivered, latency from
// stamp to delivery (p50/p95/max) and the queue high-water marks, then the highest speed that
// ran without drops. The stream is generated once in a temporary directory (external images).
// Every row ends with the 1-minute load average after it (load1): the machine is shared.
//
// bench_live --slam SEQ.rawlog CONFIG.ini [SPEED...]: end to end, exactly `rgbdi-slam --live`
// (system::runLive, the full threaded SLAM system) on a replay of SEQ.rawlog (e.g. rgbdi-sim's
// output, 30 Hz 640x480) at each speed (default 1 1.5 2 3 4). Prints per speed: wall time of
// the stream and of the whole run (final solve and map included) against the data's duration,
// frames received / dropped, latency stamp -> delivery and stamp -> pose (p50/p95/max), poses
// and resets; then the highest speed without drops and whether speed 1 ended within 10 % of
// the data's duration.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <thread>
#include <vector>

#include "rgbdi/io/rawlog_writer.h"
#include "rgbdi/live/live_source.h"
#include "rgbdi/system/live_runner.h"

namespace {

using namespace rgbdi;

/// The 1-minute load average (/proc/loadavg; -1 where there is none): the machine is shared,
/// and a figure means little without the load it was measured at.
double loadAverage1() {
  std::ifstream in("/proc/loadavg");
  double l = -1.0;
  in >> l;
  return in ? l : -1.0;
}

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

double ms(const nlohmann::json& latency, const char* key) {
  return latency[key].get<double>() * 1e3;
}

int slamMode(const std::string& rawlog, const std::string& config, std::vector<double> speeds) {
  if (speeds.empty()) speeds = {1.0, 1.5, 2.0, 3.0, 4.0};
  const auto dir = std::filesystem::temp_directory_path() / "rgbdi_bench_live_slam";
  std::filesystem::create_directories(dir);
  // Speed 1 re-stamps onto the wall clock, so that latency is measured as for a camera; other
  // speeds keep the recorded stamps (re-stamped faster data would be faster motion for the same
  // accelerations: the odometry would fail), so their latency columns are left empty.
  std::printf(
      "rgbdi-slam --live on a replay of %s (speed 1: stamps = now, others: source), "
      "config %s\n",
      rawlog.c_str(), config.c_str());
  std::printf("%6s %8s %8s %8s %7s %8s | %8s %8s %8s | %8s %8s %8s | %6s %6s %6s\n", "speed",
              "ideal_s", "stream_s", "run_s", "frames", "dropped", "dlv_p50", "dlv_p95", "dlv_max",
              "pose_p50", "pose_p95", "pose_max", "poses", "resets", "load1");
  double best = 0.0;
  double wall_at_1 = -1.0, ideal_at_1 = 0.0;
  for (double speed : speeds) {
    const std::string ini = (dir / "replay.ini").string();
    std::ofstream(ini) << "[global]\n[REPLAY]\ndriver = RgbdiRawlogReplay\nprocess_rate = 200\n"
                          "file = "
                       << std::filesystem::absolute(rawlog).string() << "\nspeed = " << speed
                       << "\nstamps = " << (speed == 1.0 ? "now" : "source") << "\n";
    system::LiveRunOptions o;
    o.sensors_path = ini;
    o.config_path = config;
    o.out_dir = (dir / "out").string();
    o.quiet = true;
    std::ostream quiet(nullptr);  // the run's report is not part of the benchmark's output
    const system::LiveRunResult r = system::runLive(o, quiet);
    const nlohmann::json& s = r.summary;
    const nlohmann::json& l = s["live"];
    // [s] wall time the data should take: its duration (re-stamped or not) over the speed.
    const double ideal = s["stream_diagnostics"]["imu"]["duration_s"].get<double>() / speed;
    const double stream_s = l["wall_duration_s"].get<double>();
    const double run_s = s["wall_time_s"].get<double>();
    const auto& dlv = l["latency"]["stamp_to_delivery_frame"];
    const auto& pose = l["latency"]["stamp_to_pose"];
    const std::size_t dropped = l["dropped"]["frames"].get<std::size_t>();
    std::printf("%6.1f %8.2f %8.2f %8.2f %7zu %8zu", speed, ideal, stream_s, run_s,
                l["received"]["frames"].get<std::size_t>(), dropped);
    if (speed == 1.0) {
      std::printf(" | %8.1f %8.1f %8.1f | %8.1f %8.1f %8.1f", ms(dlv, "p50_s"), ms(dlv, "p95_s"),
                  ms(dlv, "max_s"), ms(pose, "p50_s"), ms(pose, "p95_s"), ms(pose, "max_s"));
    } else {
      std::printf(" | %8s %8s %8s | %8s %8s %8s", "-", "-", "-", "-", "-", "-");
    }
    std::printf(" | %6zu %6d %6.2f\n", s["poses"].get<std::size_t>(), s["resets"].get<int>(),
                loadAverage1());
    std::fflush(stdout);
    if (dropped == 0 && speed > best) best = speed;
    if (speed == 1.0) {
      wall_at_1 = run_s;
      ideal_at_1 = ideal;
    }
  }
  std::printf(
      "latency in ms; dlv = sensor stamp -> delivery to the system, pose = sensor stamp -> "
      "pose out of the odometry;\np50/p95 of 10000.0 are the histogram's 10 s limit (the max is "
      "exact)\n");
  if (best > 0.0)
    std::printf("highest replay speed without drops: %.1fx\n", best);
  else
    std::printf("highest replay speed without drops: none of those tried\n");
  if (wall_at_1 >= 0.0)
    std::printf("speed 1.0: the run ended after %.2f s for %.2f s of data (%+.1f %%, %s 10 %%)\n",
                wall_at_1, ideal_at_1, 100.0 * (wall_at_1 / ideal_at_1 - 1.0),
                wall_at_1 <= 1.1 * ideal_at_1 ? "within" : "NOT within");
  std::filesystem::remove_all(dir);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc > 1 && std::string(argv[1]) == "--slam") {
    if (argc < 4) {
      std::fprintf(stderr, "usage: bench_live --slam SEQ.rawlog CONFIG.ini [SPEED...]\n");
      return 2;
    }
    std::vector<double> speeds;
    for (int i = 4; i < argc; ++i) speeds.push_back(std::stod(argv[i]));
    return slamMode(argv[2], argv[3], speeds);
  }
  const double seconds = argc > 1 ? std::stod(argv[1]) : 4.0;
  const double consumer_ms = argc > 2 ? std::stod(argv[2]) : 0.0;
  const auto dir = std::filesystem::temp_directory_path() / "rgbdi_bench_live";
  std::filesystem::create_directories(dir);
  const std::string rawlog = (dir / "stream.rawlog").string();
  std::printf("generating %.1f s of 640x480 @ 30 Hz + IMU @ 200 Hz in %s ...\n", seconds,
              dir.c_str());
  writeStream(rawlog, seconds);

  std::printf("consumer: %.1f ms per frame\n", consumer_ms);
  std::printf("%6s %8s %8s %8s %8s %9s %9s %9s %6s %6s %6s\n", "speed", "wall_s", "ideal_s",
              "frames", "dropped", "p50_ms", "p95_ms", "max_ms", "qimu", "qimg", "load1");
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
    std::printf("%6.1f %8.2f %8.2f %8zu %8zu %9.2f %9.2f %9.2f %6zu %6zu %6.2f\n", speed,
                s.wall_duration_s, seconds / speed, s.frames_received, s.frames_dropped,
                s.frame_latency.p50_s * 1e3, s.frame_latency.p95_s * 1e3,
                s.frame_latency.max_s * 1e3, s.imu_queue_high_water, s.frame_queue_high_water,
                loadAverage1());
    if (s.frames_dropped == 0) best = speed;
  }
  std::printf("highest replay speed without drops: %.0fx\n", best);
  std::filesystem::remove_all(dir);
  return 0;
}
