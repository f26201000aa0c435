#include "rgbdi/system/live_runner.h"

#include <chrono>
#include <condition_variable>
#include <filesystem>
#include <iomanip>
#include <mutex>
#include <sstream>
#include <thread>

#include "rgbdi/common/atomic_file.h"
#include "rgbdi/common/command_line.h"
#include "rgbdi/io/mrpt_conversions.h"
#include "rgbdi/live/live_source.h"
#include "rgbdi/live_run/pose_latency.h"
#include "rgbdi/system/navmap_refresher.h"
#include "rgbdi/system/progress_reporter.h"
#include "rgbdi/system/slam_system.h"

namespace rgbdi::system {
namespace fs = std::filesystem;

namespace {

// The source's latency resolution (live_source.cpp): 0.1 ms bins up to 10 s.
constexpr double kLatencyBinS = 1e-4;
constexpr double kLatencyRangeS = 10.0;
// Images delivered but not yet posed that are remembered for delivery -> pose: far more than the
// odometry queue and window hold, so only images that never get a pose are forgotten.
constexpr std::size_t kMaxPendingImages = 4096;
// How often the stop watcher looks at the stop flag and the duration.
constexpr auto kWatchPeriod = std::chrono::milliseconds(10);

/// The same clock as the sensors' host stamps (LiveSource measures its latency with it).
double wallNow() { return io::toSeconds(mrpt::Clock::now()); }

std::string ms(double s) {
  std::ostringstream os;
  os << std::fixed << std::setprecision(1) << s * 1e3;
  return os.str();
}

/// Between the source and the progress reporter: notes when each image is handed over.
class DeliveryTap : public MeasurementSink {
 public:
  DeliveryTap(MeasurementSink& next, PoseLatencyMeter& meter) : next_(next), meter_(meter) {}
  void feedImu(const ImuSample& imu) override { next_.feedImu(imu); }
  void feedWheel(const WheelOdometrySample& wheel) override { next_.feedWheel(wheel); }
  void feedRgbd(const RgbdFrame& frame) override {
    meter_.delivered(frame.t, wallNow());  // before feeding: the odometry queue may block
    next_.feedRgbd(frame);
  }
  void endOfStream() override { next_.endOfStream(); }

 private:
  MeasurementSink& next_;
  PoseLatencyMeter& meter_;
};

/// Stops the source on the stop flag or after the duration (next() may be waiting for data, so
/// the check cannot live in the consumer's loop).
class StopWatcher {
 public:
  StopWatcher(live::LiveSource& source, const std::atomic<bool>* stop, double duration_s)
      : source_(source), stop_(stop), duration_s_(duration_s) {
    thread_ = std::thread([this] { run(); });
  }
  ~StopWatcher() { finish(); }
  /// Ends the watcher (the stream has ended); returns why it stopped the source, if it did.
  void finish() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      done_ = true;
    }
    cv_.notify_all();
    if (thread_.joinable()) thread_.join();
  }
  bool fired() const { return fired_; }
  LiveStopReason reason() const { return reason_; }

 private:
  void run() {
    const auto start = std::chrono::steady_clock::now();
    std::unique_lock<std::mutex> lock(mutex_);
    while (!done_) {
      cv_.wait_for(lock, kWatchPeriod);
      if (done_) return;
      const double elapsed =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      if (stop_ && stop_->load()) {
        reason_ = LiveStopReason::Interrupted;
      } else if (duration_s_ > 0.0 && elapsed >= duration_s_) {
        reason_ = LiveStopReason::Duration;
      } else {
        continue;
      }
      fired_ = true;
      lock.unlock();
      source_.stopReading();  // joins the sensor threads; what was received is still delivered
      return;
    }
  }

  live::LiveSource& source_;
  const std::atomic<bool>* stop_;
  double duration_s_;
  std::mutex mutex_;
  std::condition_variable cv_;
  bool done_ = false;
  std::atomic<bool> fired_{false};
  LiveStopReason reason_ = LiveStopReason::EndOfData;
  std::thread thread_;
};

LiveStopReason faultReason(live::LiveError::Kind kind) {
  switch (kind) {
    case live::LiveError::Kind::CameraTimeout:
      return LiveStopReason::CameraGone;
    case live::LiveError::Kind::Overload:
      return LiveStopReason::Overload;
    default:
      return LiveStopReason::SensorFailed;
  }
}

nlohmann::json latencyJson(const live::LatencySummary& s) {
  return {{"count", s.count}, {"p50_s", s.p50_s}, {"p95_s", s.p95_s}, {"max_s", s.max_s}};
}

std::unique_ptr<live::LiveSource> openSensors(const std::string& path,
                                              const io::StreamConfig& stream) {
  if (path.empty()) throw UserError("no sensors file given (--live SENSORS.ini)");
  if (!fs::exists(path)) throw UserError(path + ": sensors file does not exist");
  live::SensorConfig sensors;
  try {
    sensors = live::SensorConfig::fromFile(path);
  } catch (const ConfigError& e) {
    throw RunConfigError(std::string("sensors file error: ") + e.what());
  }
  try {
    return std::make_unique<live::LiveSource>(sensors, stream);
  } catch (const live::LiveError& e) {
    throw UserError(e.what());  // names the file, the section, the driver and the reason
  }
}

}  // namespace

const char* toString(LiveStopReason reason) {
  switch (reason) {
    case LiveStopReason::EndOfData:
      return "end_of_data";
    case LiveStopReason::Duration:
      return "duration";
    case LiveStopReason::Interrupted:
      return "interrupted";
    case LiveStopReason::CameraGone:
      return "camera_gone";
    case LiveStopReason::SensorFailed:
      return "sensor_failed";
    case LiveStopReason::Overload:
      return "overload";
  }
  return "?";
}

bool isFault(LiveStopReason reason) {
  return reason == LiveStopReason::CameraGone || reason == LiveStopReason::SensorFailed ||
         reason == LiveStopReason::Overload;
}

int liveExitStatus(const LiveRunResult& result) {
  const nlohmann::json& s = result.summary;
  if (s.contains("stream_diagnostics") && s["stream_diagnostics"].value("refused", false))
    return kExitError;
  if (isFault(result.stop_reason)) return kExitDamaged;  // outputs written
  if (result.stop_reason == LiveStopReason::Interrupted) return kExitInterrupted;
  if (s.contains("no_pose_reason")) return kExitNoPose;
  return kExitOk;
}

LiveRunResult runLive(const LiveRunOptions& opt, std::ostream& log) {
  SystemConfig cfg = loadRunConfig(opt.config_path);
  if (opt.no_loop) cfg.loop.enable = false;
  if (opt.no_wheels) cfg.estimator.wheel.enable = false;
  prepareOutputDir(opt.out_dir);
  std::unique_ptr<live::LiveSource> source = openSensors(opt.sensors_path, cfg.streamConfig());
  if (!opt.record_path.empty()) {
    try {
      source->record(live::RecordingOptions{opt.record_path, cfg.extrinsic.T_body_cam});
    } catch (const std::exception& e) {
      throw UserError(opt.record_path + ": cannot record: " + e.what());
    }
  }

  PoseLatencyMeter latency(kLatencyBinS, kLatencyRangeS, kMaxPendingImages);
  SlamSystemOptions so;
  so.use_depth = !opt.no_depth;
  so.threaded = true;
  so.live = true;
  so.keep_observations = opt.save_simplemap;
  so.on_pose = [&latency](const FrameRecord& r) { latency.posed(r.t_image, wallNow()); };
  so.map = loadRunMap(opt.map, cfg);
  so.localize_only = opt.map.localize_only;
  // The navigation maps in the output directory follow the map while the run goes on.
  NavMapRefresher navmap_refresher(opt.out_dir, cfg.navmap);
  so.on_map_update = [&navmap_refresher](const mapping::Mapper& m, bool correction) {
    navmap_refresher.update(m, correction);
  };
  SlamSystem system(cfg, so);
  ProgressReporter progress(system, log, opt.quiet, cfg.output.progress_interval_s, nullptr);
  progress.setLiveStatus([&] {
    return source->stats().line() + ", pose p50 " + ms(latency.summary().stamp_to_pose.p50_s) +
           " ms";
  });
  DeliveryTap tap(progress, latency);

  LiveRunResult result;
  RunInfo run;
  run.input = opt.sensors_path;
  run.no_depth = opt.no_depth;
  const auto wall0 = std::chrono::steady_clock::now();
  source->start();
  StopWatcher watcher(*source, opt.stop, opt.duration_s);
  try {
    source->pump(tap);
  } catch (const live::LiveError& e) {
    result.stop_reason = faultReason(e.kind());
    result.error = e.what();
  }
  watcher.finish();
  if (result.error.empty() && watcher.fired()) result.stop_reason = watcher.reason();
  run.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  run.interrupted = result.stop_reason == LiveStopReason::Interrupted;
  run.read_error = result.error;
  run.stream_t0 = progress.firstStamp();
  run.stream_t_last = progress.lastStamp();
  run.frames = progress.framesSeen();
  if (!result.error.empty()) log << "rgbdi-slam: live run stopped: " << result.error << "\n";

  const live::LiveStats st = source->stats();
  const PoseLatencyMeter::Summary pl = latency.summary();
  nlohmann::json live = nlohmann::json::parse(st.toJson());
  live["sensors_file"] = opt.sensors_path;
  live["stop_reason"] = toString(result.stop_reason);
  live["duration_limit_s"] = opt.duration_s > 0.0 ? nlohmann::json(opt.duration_s) : nullptr;
  live["navmap_refreshes"] = navmap_refresher.refreshes();
  if (!navmap_refresher.lastError().empty())
    live["navmap_refresh_error"] = navmap_refresher.lastError();
  live["recording"] = opt.record_path.empty() ? nlohmann::json() : nlohmann::json(opt.record_path);
  live["received"] = {{"imu", st.imu_received}, {"frames", st.frames_received}};
  live["delivered"] = {{"imu", st.imu_delivered}, {"frames", st.frames_delivered}};
  // IMU samples are never dropped by design; the figure is what was received and neither
  // delivered nor rejected by the ordering checks, so a violation would show.
  const auto lost = [](std::size_t in, std::size_t out, std::size_t rejected) {
    return in >= out + rejected ? in - out - rejected : 0;
  };
  live["dropped"] = {{"imu", lost(st.imu_received, st.imu_delivered, st.imu_rejected)},
                     {"frames", st.frames_dropped},
                     {"frames_by_odometry", system.odometry().framesDropped()}};
  live["latency"] = {{"stamp_to_delivery_imu", latencyJson(st.imu_latency)},
                     {"stamp_to_delivery_frame", latencyJson(st.frame_latency)},
                     {"delivery_to_pose", latencyJson(pl.delivery_to_pose)},
                     {"stamp_to_pose", latencyJson(pl.stamp_to_pose)}};
  log << "rgbdi-slam: live: " << toString(result.stop_reason) << ", " << st.line()
      << ", stamp to pose p50 " << ms(pl.stamp_to_pose.p50_s) << " ms p95 "
      << ms(pl.stamp_to_pose.p95_s) << " ms max " << ms(pl.stamp_to_pose.max_s) << " ms\n";
  result.summary = finishRun(system, run, source->diagnostics(), Trajectory(),
                             RunOutputOptions{opt.out_dir, "", opt.save_simplemap, opt.map},
                             nlohmann::json{{"live", live}}, log);
  return result;
}

}  // namespace rgbdi::system
