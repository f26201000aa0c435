#include "rgbdi/live/live_source.h"

#include <mrpt/config/CConfigFile.h>
#include <mrpt/config/CConfigFileMemory.h>
#include <mrpt/hwdrivers/CGenericSensor.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CSensoryFrame.h>

#include <chrono>
#include <cmath>
#include <condition_variable>
#include <deque>
#include <iomanip>
#include <limits>
#include <mutex>
#include <optional>
#include <sstream>
#include <thread>

#include "live/mrpt_message.h"
#include "rgbdi/io/frame_rate_limiter.h"
#include "rgbdi/io/mrpt_conversions.h"
#include "rgbdi/io/rawlog_writer.h"
#include "rgbdi/io/stream_checker.h"
#include "rgbdi/io/time_ordering_buffer.h"
#include "rgbdi/live/finite_sensor.h"
#include "rgbdi/live/rgbdi_sensors.h"

namespace rgbdi::live {
namespace {

using Steady = std::chrono::steady_clock;
using Sensor = mrpt::hwdrivers::CGenericSensor;

double since(Steady::time_point a, Steady::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

std::string fixed(double v, int digits) {
  std::ostringstream os;
  os << std::fixed << std::setprecision(digits) << v;
  return os.str();
}

double wallNow() { return io::toSeconds(mrpt::Clock::now()); }

// Latency histogram resolution: 0.1 ms bins up to 10 s (100k counters per kind).
constexpr double kLatencyBinS = 1e-4;
constexpr double kLatencyRangeS = 10.0;

}  // namespace

struct LiveSource::Impl {
  struct Slot {
    SensorSection section;
    Sensor::Ptr sensor;
    FiniteSensor* finite = nullptr;
    std::thread thread;
    // Guarded by Impl::mutex:
    SensorCounts counts;
    bool has_frames = false, has_imu = false, imu_stalled = false;
    Steady::time_point last_frame_arrival, last_imu_arrival;
    double last_imu_stamp = std::numeric_limits<double>::quiet_NaN();
    std::size_t frame_counter = 0;
    io::FrameRateLimiter rate_limiter{0.0};  ///< [stream] image_rate_limit_hz, per camera
  };

  Impl(const SensorConfig& c, const io::StreamConfig& stream)
      : cfg(c),
        file(c.path.empty() ? std::string("<sensors>") : c.path),
        checker("live " + file, stream),
        image_rate_limit_hz(stream.stream.image_rate_limit_hz),
        buffer(stream.stream.imu_reorder_window_s, stream.stream.image_reorder_window_s),
        imu_latency(kLatencyBinS, kLatencyRangeS),
        frame_latency(kLatencyBinS, kLatencyRangeS) {}

  std::string who(const Slot& s) const {
    return file + " [" + s.section.name + "] (" + s.section.driver + ")";
  }

  void open() {
    registerRgbdiSensors();
    std::unique_ptr<mrpt::config::CConfigFileBase> mcfg;
    if (!cfg.path.empty()) {
      mcfg = std::make_unique<mrpt::config::CConfigFile>(cfg.path);
    } else {
      mcfg = std::make_unique<mrpt::config::CConfigFileMemory>(cfg.text);
    }
    for (const SensorSection& sec : cfg.sensors) {
      auto slot = std::make_unique<Slot>();
      slot->section = sec;
      slot->rate_limiter = io::FrameRateLimiter(image_rate_limit_hz);
      slot->counts.section = sec.name;
      slot->counts.driver = sec.driver;
      slot->sensor = Sensor::createSensorPtr(sec.driver);
      if (!slot->sensor) {
        std::string ours;
        for (const auto& n : rgbdiSensorClassNames()) ours += (ours.empty() ? "" : ", ") + n;
        throw LiveError(LiveError::Kind::UnknownDriver, sec.name,
                        file + " [" + sec.name + "] driver = " + sec.driver +
                            ": unknown sensor class (no CGenericSensor of that name is "
                            "registered; rgbdi's are " +
                            ours + ", MRPT's are listed in its hwdrivers documentation)");
      }
      try {
        slot->sensor->loadConfig(*mcfg, sec.name);
      } catch (const std::exception& e) {
        throw LiveError(LiveError::Kind::OpenFailed, sec.name,
                        who(*slot) + ": invalid configuration: " + exceptionMessage(e));
      }
      try {
        slot->sensor->initialize();
      } catch (const std::exception& e) {
        throw LiveError(LiveError::Kind::OpenFailed, sec.name,
                        who(*slot) + ": cannot open the sensor: " + exceptionMessage(e));
      }
      if (slot->sensor->getState() == Sensor::ssError)
        throw LiveError(LiveError::Kind::OpenFailed, sec.name,
                        who(*slot) +
                            ": cannot open the sensor: it reports an error state after "
                            "initialize()");
      slot->finite = dynamic_cast<FiniteSensor*>(slot->sensor.get());
      slots.push_back(std::move(slot));
    }
  }

  // ---- sensor threads ----------------------------------------------------------------------

  void sensorLoop(Slot& s) {
    const auto period = std::chrono::duration_cast<Steady::duration>(
        std::chrono::duration<double>(1.0 / s.section.process_rate_hz));
    auto tick = Steady::now();
    for (;;) {
      {
        std::unique_lock<std::mutex> lk(mutex);
        if (stop_grabbing) return;
      }
      bool ended = false;
      try {
        s.sensor->doProcess();
        if (s.finite) ended = s.finite->endOfData();  // before draining: nothing can follow
        handle(s, s.sensor->getObservations());
        if (s.sensor->getState() == Sensor::ssError)
          throw std::runtime_error("the sensor reports an error state (ssError)");
      } catch (const std::exception& e) {
        std::lock_guard<std::mutex> lk(mutex);
        fault(LiveError::Kind::SensorFailed, s.section.name,
              who(s) + ": sensor failed: " + exceptionMessage(e));
        return;
      }
      if (ended) {
        std::lock_guard<std::mutex> lk(mutex);
        s.counts.ended = true;
        return;
      }
      tick += period;
      const auto now = Steady::now();
      if (tick < now) tick = now;  // behind: run again at once, never try to catch up in bursts
      std::unique_lock<std::mutex> lk(mutex);
      stop_cv.wait_until(lk, tick, [this] { return stop_grabbing; });
    }
  }

  void handle(Slot& s, const Sensor::TListObservations& list) {
    std::vector<io::Measurement> ms;
    std::size_t other = 0, unusable = 0, rate_limited = 0;
    std::vector<std::string> problems;
    const auto one = [&](const mrpt::obs::CObservation::Ptr& o) {
      if (auto scan = std::dynamic_pointer_cast<mrpt::obs::CObservation3DRangeScan>(o)) {
        // Before the conversion: a skipped frame costs nothing further.
        if (!s.rate_limiter.admit(io::toSeconds(scan->timestamp))) {
          ++rate_limited;
          return;
        }
        try {
          ms.emplace_back(io::fromMrpt(
              *scan, file + " [" + s.section.name + "] frame " + std::to_string(s.frame_counter)));
          ++s.frame_counter;
        } catch (const io::ConversionError& e) {
          ++unusable;
          problems.push_back(who(s) + ": " + e.what() + "; skipped");
        }
      } else if (auto imu = std::dynamic_pointer_cast<mrpt::obs::CObservationIMU>(o)) {
        try {
          ms.emplace_back(io::fromMrpt(*imu));
        } catch (const io::ConversionError& e) {
          ++unusable;
          problems.push_back(who(s) + ": " + e.what() + "; skipped");
        }
      } else if (auto odo = std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(o)) {
        try {
          const WheelOdometrySample w = io::fromMrpt(*odo);
          if (!isFinite(w))
            throw io::ConversionError("wheel odometry at t = " + fixed(w.t, 6) +
                                      " s has a non-finite value");
          ms.emplace_back(w);
        } catch (const io::ConversionError& e) {
          ++unusable;
          problems.push_back(who(s) + ": " + e.what() + "; skipped");
        }
      } else {
        ++other;
      }
    };
    for (const auto& [stamp, obj] : list) {
      (void)stamp;
      if (auto sf = std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(obj)) {
        for (const auto& o : *sf) one(o);
      } else if (auto o = std::dynamic_pointer_cast<mrpt::obs::CObservation>(obj)) {
        one(o);
      } else {
        ++other;
      }
    }
    std::lock_guard<std::mutex> lk(mutex);
    s.counts.other += other;
    s.counts.unusable += unusable;
    checker.counters().frames_rate_limited += rate_limited;
    for (auto& p : problems) event(p);
    for (auto& m : ms) offer(s, std::move(m));
    drain();
  }

  /// Under the lock.
  void offer(Slot& s, io::Measurement m) {
    if (input_ended) return;  // after a fault or stop: nothing more enters the stream
    const auto now = Steady::now();
    const io::MeasurementKind kind = io::kindOf(m);
    const bool imu = kind == io::MeasurementKind::Imu;
    const double t = io::measurementTime(m);
    if (kind == io::MeasurementKind::Wheel) {
      // Wheel odometry: ordered and checked with the rest; its stalls are not watched.
    } else if (imu) {
      if (s.imu_stalled) {
        s.imu_stalled = false;
        event(who(s) + ": IMU data resumed after " + fixed(since(s.last_imu_arrival, now), 3) +
              " s");
      }
      s.has_imu = true;
      s.last_imu_arrival = now;
      if (std::isfinite(s.last_imu_stamp)) {
        const double dt = t - s.last_imu_stamp;
        if (dt > cfg.live.imu_time_jump_s || dt <= 0.0) {
          ++stats.imu_time_jumps;
          event(who(s) + ": IMU time jump of " + fixed(dt, 6) + " s (stamp " + fixed(t, 6) +
                " after " + fixed(s.last_imu_stamp, 6) +
                "; live_imu_time_jump_s = " + fixed(cfg.live.imu_time_jump_s, 3) + ")");
        }
      }
      s.last_imu_stamp = t;
      ++s.counts.imu;
      ++stats.imu_received;
    } else {
      s.has_frames = true;
      s.last_frame_arrival = now;
      ++s.counts.frames;
      ++stats.frames_received;
    }
    const double newest = buffer.newest(kind);
    const std::size_t rec = arrivals++;
    const auto verdict = buffer.push(std::move(m), rec);
    checker.onArrival(kind, t, rec, verdict, newest);
    const bool kept = verdict == io::TimeOrderingBuffer::Verdict::Accepted ||
                      verdict == io::TimeOrderingBuffer::Verdict::Reordered;
    if (!kept && kind != io::MeasurementKind::Wheel)
      ++(imu ? stats.imu_rejected : stats.frames_rejected);
    stats.ordering_high_water = std::max(stats.ordering_high_water, buffer.size());
  }

  /// Moves released measurements into the delivery queues (under the lock).
  void drain() {
    io::TimeOrderingBuffer::Item item;
    bool any = false;
    while (buffer.pop(item)) {
      any = true;
      if (!std::holds_alternative<RgbdFrame>(item.m)) {  // IMU and wheel odometry: never dropped
        imu_q.push_back(std::move(item));
      } else {
        frame_q.push_back(std::move(item));
        while (frame_q.size() > static_cast<std::size_t>(cfg.live.image_queue_len)) {
          frame_q.pop_front();  // the oldest: what is delivered stays as recent as possible
          ++stats.frames_dropped;
        }
      }
    }
    stats.imu_queue_high_water = std::max(stats.imu_queue_high_water, imu_q.size());
    stats.frame_queue_high_water = std::max(stats.frame_queue_high_water, frame_q.size());
    if (!input_ended && imu_q.size() > static_cast<std::size_t>(cfg.live.imu_queue_len)) {
      fault(LiveError::Kind::Overload, "",
            file + ": the consumer is too slow even for the IMU stream: " +
                std::to_string(imu_q.size()) + " IMU samples waiting (live_imu_queue_len = " +
                std::to_string(cfg.live.imu_queue_len) + "); stopping the run");
    }
    if (any) data_cv.notify_all();
  }

  void event(const std::string& message) {
    if (stats.events.size() < static_cast<std::size_t>(cfg.live.max_listed_events)) {
      stats.events.push_back(message);
    } else {
      ++unlisted_events;
    }
  }

  /// Under the lock: the first fault ends the input; later ones are only listed.
  void fault(LiveError::Kind kind, const std::string& section, const std::string& message) {
    if (error.empty() && !input_ended) {
      error = message;
      error_kind = kind;
      error_section = section;
      stats.error = message;
    }
    event(message);
    endInput();
  }

  /// Under the lock: no more input; everything buffered becomes deliverable.
  void endInput() {
    if (input_ended) return;
    input_ended = true;
    stop_grabbing = true;
    stop_cv.notify_all();
    buffer.finish();
    drain();
    end_time = Steady::now();
    data_cv.notify_all();
  }

  // ---- watchdog ----------------------------------------------------------------------------

  void watchdogLoop() {
    const auto period = std::chrono::duration_cast<Steady::duration>(
        std::chrono::duration<double>(cfg.live.watchdog_period_s));
    std::unique_lock<std::mutex> lk(mutex);
    while (!input_ended && !stop_watchdog) {
      stop_cv.wait_for(lk, period, [this] { return input_ended || stop_watchdog; });
      if (input_ended || stop_watchdog) break;
      check(Steady::now());
    }
  }

  /// Under the lock.
  void check(Steady::time_point now) {
    bool any_finite = false, all_finite_ended = true, any_camera = false;
    for (const auto& sp : slots) {
      const Slot& s = *sp;
      if (s.finite) {
        any_finite = true;
        all_finite_ended = all_finite_ended && s.counts.ended;
      }
      any_camera = any_camera || s.has_frames;
    }
    if (any_finite && all_finite_ended) {
      endInput();
      return;
    }
    for (auto& sp : slots) {
      Slot& s = *sp;
      if (s.counts.ended) continue;
      if (s.has_frames && since(s.last_frame_arrival, now) > cfg.live.camera_timeout_s) {
        fault(LiveError::Kind::CameraTimeout, s.section.name,
              who(s) + ": no RGB-D frame for " + fixed(since(s.last_frame_arrival, now), 2) +
                  " s (live_camera_timeout_s = " + fixed(cfg.live.camera_timeout_s, 2) +
                  "): the camera stopped sending or was disconnected");
        return;
      }
      if (s.has_imu && !s.imu_stalled && since(s.last_imu_arrival, now) > cfg.live.imu_stall_s) {
        s.imu_stalled = true;
        ++stats.imu_stalls;
        event(who(s) + ": IMU stall: no sample for more than " + fixed(cfg.live.imu_stall_s, 3) +
              " s (live_imu_stall_s)");
      }
    }
    if (!any_camera && since(start_time, now) > cfg.live.first_frame_timeout_s) {
      std::string list;
      for (const auto& sp : slots)
        list += (list.empty() ? "" : ", ") + ("[" + sp->section.name + "] " + sp->section.driver);
      fault(LiveError::Kind::CameraTimeout, slots.size() == 1 ? slots[0]->section.name : "",
            file + ": no RGB-D frame from any sensor (" + list + ") within " +
                fixed(cfg.live.first_frame_timeout_s, 2) +
                " s of starting (live_first_frame_timeout_s)");
    }
  }

  // ---- consumer ----------------------------------------------------------------------------

  /// Under the lock: the earliest waiting measurement (IMU first at equal stamps).
  bool popNext(io::Measurement& out) {
    if (imu_q.empty() && frame_q.empty()) return false;
    bool take_imu = !imu_q.empty();
    if (!imu_q.empty() && !frame_q.empty())
      take_imu = io::measurementTime(imu_q.front().m) <= io::measurementTime(frame_q.front().m);
    auto& q = take_imu ? imu_q : frame_q;
    io::TimeOrderingBuffer::Item item = std::move(q.front());
    q.pop_front();
    const double latency = wallNow() - io::measurementTime(item.m);
    if (auto* f = std::get_if<RgbdFrame>(&item.m)) {
      f->index = stats.frames_delivered++;
      frame_latency.add(latency);
    } else if (io::isImu(item.m)) {
      ++stats.imu_delivered;
      imu_latency.add(latency);
    }
    checker.onDelivered(item.m, item.record);
    out = std::move(item.m);
    return true;
  }

  void startThreads() {
    std::lock_guard<std::mutex> lk(mutex);
    if (started) return;
    started = true;
    start_time = Steady::now();
    for (auto& sp : slots) {
      sp->last_frame_arrival = sp->last_imu_arrival = start_time;
      Slot* s = sp.get();
      s->thread = std::thread([this, s] { sensorLoop(*s); });
    }
    watchdog = std::thread([this] { watchdogLoop(); });
  }

  /// Safe from several threads at once (the consumer at the end of the stream, stopReading()
  /// from a signal-watching thread, the destructor).
  void joinAll() {
    std::lock_guard<std::mutex> join_lock(join_mutex);
    {
      std::lock_guard<std::mutex> lk(mutex);
      stop_grabbing = true;
      stop_watchdog = true;
      stop_cv.notify_all();
    }
    for (auto& sp : slots)
      if (sp->thread.joinable()) sp->thread.join();
    if (watchdog.joinable()) watchdog.join();
  }

  void closeRecording() {
    if (!recorder) return;
    std::unique_ptr<io::RawlogWriter> r = std::move(recorder);
    r->close();
  }

  SensorConfig cfg;
  std::string file;
  std::vector<std::unique_ptr<Slot>> slots;

  mutable std::mutex mutex;
  std::mutex join_mutex;            ///< serialises joinAll()
  std::condition_variable data_cv;  ///< consumer: data or the end is there
  std::condition_variable stop_cv;  ///< sensor threads and watchdog: stop requested
  io::StreamChecker checker;
  double image_rate_limit_hz;  ///< [Hz] [stream] image_rate_limit_hz, for each camera's limiter
  io::TimeOrderingBuffer buffer;
  std::deque<io::TimeOrderingBuffer::Item> imu_q, frame_q;
  LiveStats stats;
  std::size_t unlisted_events = 0;
  LatencyHistogram imu_latency, frame_latency;
  std::size_t arrivals = 0;
  bool started = false, stop_grabbing = false, stop_watchdog = false, input_ended = false;
  bool finished = false, error_thrown = false;
  std::string error, error_section;
  LiveError::Kind error_kind = LiveError::Kind::SensorFailed;
  Steady::time_point start_time, end_time;
  std::thread watchdog;
  std::unique_ptr<io::RawlogWriter> recorder;
};

LiveSource::LiveSource(const SensorConfig& sensors, const io::StreamConfig& stream)
    : impl_(std::make_unique<Impl>(sensors, stream)) {
  impl_->open();
}

LiveSource::~LiveSource() {
  impl_->joinAll();
  try {
    impl_->closeRecording();
  } catch (const std::exception&) {
    // A destructor cannot report; next() reports recording errors at the end of the stream.
  }
}

void LiveSource::record(const RecordingOptions& options) {
  io::RawlogWriterOptions w;
  w.external_images = true;
  w.T_body_cam = options.T_body_cam;
  impl_->recorder = std::make_unique<io::RawlogWriter>(options.path, w);
}

void LiveSource::start() { impl_->startThreads(); }

bool LiveSource::next(io::Measurement& out) {
  Impl& s = *impl_;
  s.startThreads();
  std::unique_lock<std::mutex> lk(s.mutex);
  const auto period = std::chrono::duration<double>(s.cfg.live.watchdog_period_s);
  for (;;) {
    if (s.popNext(out)) {
      lk.unlock();
      if (s.recorder) {
        if (auto* imu = std::get_if<ImuSample>(&out)) {
          s.recorder->write(*imu);
        } else if (auto* wheel = std::get_if<WheelOdometrySample>(&out)) {
          s.recorder->write(*wheel);
        } else {
          s.recorder->write(std::get<RgbdFrame>(out));
        }
      }
      return true;
    }
    if (s.input_ended) {
      if (!s.finished) {
        s.finished = true;
        s.checker.finish();
        lk.unlock();
        s.joinAll();
        s.closeRecording();
        lk.lock();
      }
      if (!s.error.empty() && !s.error_thrown) {
        s.error_thrown = true;
        throw LiveError(s.error_kind, s.error_section, s.error);
      }
      return false;
    }
    s.data_cv.wait_for(lk, period);
  }
}

void LiveSource::stopReading() {
  Impl& s = *impl_;
  s.joinAll();  // threads first: nothing is appended after the input ends
  std::lock_guard<std::mutex> lk(s.mutex);
  s.endInput();
}

const io::StreamDiagnostics& LiveSource::diagnostics() const {
  return impl_->checker.diagnostics();
}

LiveStats LiveSource::stats() const {
  const Impl& s = *impl_;
  std::lock_guard<std::mutex> lk(s.mutex);
  LiveStats out = s.stats;
  out.imu_latency = s.imu_latency.summary();
  out.frame_latency = s.frame_latency.summary();
  for (const auto& sp : s.slots) out.sensors.push_back(sp->counts);
  if (s.unlisted_events > 0)
    out.events.push_back(std::to_string(s.unlisted_events) + " more events not listed");
  if (s.started) {
    out.wall_duration_s = since(s.start_time, s.input_ended ? s.end_time : Steady::now());
  }
  return out;
}

const SensorConfig& LiveSource::config() const { return impl_->cfg; }

}  // namespace rgbdi::live
