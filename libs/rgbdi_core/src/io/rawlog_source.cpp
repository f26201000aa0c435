#include "rgbdi/io/rawlog_source.h"

#include <mrpt/img/CImage.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <functional>
#include <limits>
#include <optional>

#include "io/counting_input_stream.h"
#include "io/rawlog_naming.h"
#include "rgbdi/common/cpu_clock.h"
#include "rgbdi/io/mrpt_conversions.h"
#include "rgbdi/io/stream_checker.h"
#include "rgbdi/io/time_ordering_buffer.h"

namespace rgbdi::io {
namespace {

/// MRPT exception texts carry a call-stack dump after the first lines; keep the message only.
std::string stampText(double t) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6f", t);
  return buf;
}

std::string numText(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

std::string vecText(const Eigen::Vector3d& v) {
  return "[" + numText(v.x()) + " " + numText(v.y()) + " " + numText(v.z()) + "]";
}

std::string firstLine(const std::string& what) {
  std::string s = what;
  const std::string tag = "Message:";
  const auto m = s.find(tag);
  if (m != std::string::npos) s = s.substr(m + tag.size());
  const auto b = s.find_first_not_of(" \t\n");
  s = b == std::string::npos ? std::string() : s.substr(b);
  const auto nl = s.find('\n');
  if (nl != std::string::npos) s.resize(nl);
  return s;
}

}  // namespace

std::string rawlogImagesDirectory(const std::string& rawlog_path) {
  namespace fs = std::filesystem;
  const fs::path p(rawlog_path);
  const std::string name = rawlogBaseName(p);
  std::error_code ec;
  for (const std::string suffix : {"_Images", "_images", "_IMAGES"}) {
    const fs::path d = p.parent_path() / (name + suffix);
    if (fs::is_directory(d, ec)) return d.string();
  }
  return (p.parent_path() / "Images").string();
}

struct RawlogSource::Impl {
  Impl(RawlogSource& owner, const std::string& path_, const StreamConfig& cfg)
      : self(owner),
        path(path_),
        cfg(cfg),
        checker(path_, cfg,
                [this](const std::string& w) { self.logStr(mrpt::system::LVL_WARN, w); }),
        buffer(cfg.stream.imu_reorder_window_s, cfg.stream.image_reorder_window_s) {}

  void open() {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (!fs::exists(path, ec)) throw RawlogError(path + ": rawlog file does not exist");
    if (fs::is_directory(path, ec)) throw RawlogError(path + ": is a directory, not a rawlog file");
    std::string msg;
    if (!file.open(path, std::ref(msg))) throw RawlogError(path + ": cannot open rawlog: " + msg);
    counting.emplace(file);
    archive.emplace(*counting);
    images_dir = rawlogImagesDirectory(path);
    if (fs::is_directory(images_dir, ec)) checker.counters().images_directory = images_dir;
  }

  /// Reads one top-level record and offers its measurements to the buffer.
  void readRecord() {
    ScopedCpuTimer timer(checker.counters().read_cpu_s);
    // Process-wide MRPT setting: make lazy-loaded images of THIS rawlog resolve correctly.
    mrpt::img::CImage::setImagesPathBase(images_dir);
    const uint64_t before = counting->bytes();
    mrpt::serialization::CSerializable::Ptr obj;
    try {
      obj = archive->ReadObject();
    } catch (const mrpt::serialization::CExceptionEOF&) {
      if (counting->bytes() == before) {
        endInput();
      } else {
        fail(truncated(before));
      }
      return;
    } catch (const std::exception& e) {
      if (counting->shortRead()) {
        fail(truncated(before));
      } else {
        fail(checker.at(record) + ": corrupt record (" + firstLine(e.what()) + ")");
      }
      return;
    }
    const std::size_t rec = record++;
    ++checker.counters().records;
    if (!obj) {
      checker.onSkipped(rec, "null object");
      return;
    }
    if (auto sf = std::dynamic_pointer_cast<mrpt::obs::CSensoryFrame>(obj)) {
      for (const auto& o : *sf) handleObservation(o, rec);
    } else if (std::dynamic_pointer_cast<mrpt::obs::CActionCollection>(obj)) {
      ++checker.counters().actions;
    } else if (auto o = std::dynamic_pointer_cast<mrpt::obs::CObservation>(obj)) {
      handleObservation(o, rec);
    } else {
      checker.onSkipped(rec, obj->GetRuntimeClass()->className);
    }
  }

  std::string truncated(uint64_t record_start) const {
    return checker.at(record) + ": truncated: the file ends inside this record (" +
           std::to_string(counting->bytes() - record_start) + " bytes of it read)";
  }

  void handleObservation(const mrpt::obs::CObservation::Ptr& o, std::size_t rec) {
    if (!o) return;
    ++checker.counters().observations;
    if (auto scan = std::dynamic_pointer_cast<mrpt::obs::CObservation3DRangeScan>(o)) {
      try {
        std::optional<Measurement> m;
        {
          ScopedCpuTimer timer(checker.counters().rgbd_decode_cpu_s);
          m.emplace(fromMrpt(*scan, checker.at(rec)));
        }
        offer(std::move(*m), rec);
      } catch (const ConversionError& e) {
        checker.onUnusable(rec, std::string(e.what()) + "; skipped");
      }
    } else if (auto imu = std::dynamic_pointer_cast<mrpt::obs::CObservationIMU>(o)) {
      ImuSample sample;
      try {
        sample = fromMrpt(*imu);
      } catch (const ConversionError& e) {
        checker.onUnusable(rec, checker.at(rec) + ": " + e.what() + "; skipped");
        return;
      }
      if (!sample.acc.allFinite() || !sample.gyr.allFinite()) {
        ++checker.counters().non_finite_imu;
        checker.onUnusable(rec, checker.at(rec) + ": IMU sample at t = " + stampText(sample.t) +
                                    " s has a non-finite value (acc = " + vecText(sample.acc) +
                                    ", gyr = " + vecText(sample.gyr) + "); skipped");
        return;
      }
      sample.acc *= cfg.stream.accel_scale;
      offer(Measurement(sample), rec);
    } else {
      checker.onSkipped(rec, o->GetRuntimeClass()->className);
    }
  }

  void offer(Measurement m, std::size_t rec) {
    const bool imu = isImu(m);
    const double t = measurementTime(m);
    const double newest = imu ? buffer.newestImu() : buffer.newestRgbd();
    if (t < newest - cfg.stream.time_jump_back_s) {
      // A clock reset or two recordings joined: re-ordering cannot repair it and dropping a
      // second of data silently distorts the trajectory. Stop here; what came before is used.
      fail(checker.at(rec) + ": " + (imu ? "IMU" : "RGB-D") + " stamp t = " + stampText(t) +
           " s is " + stampText(newest - t) + " s older than the newest one read before it (" +
           stampText(newest) +
           " s): time goes backwards (clock reset or recordings joined?); reading stops at this "
           "record, the data before it is used (limit [stream] time_jump_back_s = " +
           numText(cfg.stream.time_jump_back_s) + " s; split the rawlog here to use the rest)");
      return;
    }
    if (imu) accountAcc(std::get<ImuSample>(m), rec);
    if (std::isfinite(t) && !(t >= first_t)) first_t = t;
    const auto verdict = buffer.push(std::move(m), rec);
    checker.onArrival(imu, t, rec, verdict, newest);
    if (!units_decided && (acc_n >= static_cast<std::size_t>(cfg.stream.accel_check_samples) ||
                           t - first_t > cfg.stream.accel_check_max_s))
      decideUnits();
  }

  void accountAcc(const ImuSample& s, std::size_t rec) {
    if (units_decided) return;
    if (acc_n == 0) first_acc_record = rec;
    last_acc_record = rec;
    acc_sum += s.acc.norm();
    ++acc_n;
  }

  /// The accelerometer-unit check on the first accel_check_samples samples: deliveries wait for
  /// it so that nothing in the wrong unit reaches the consumer.
  void decideUnits() {
    units_decided = true;
    if (acc_n == 0 || cfg.report_only) return;
    const double mean = acc_sum / static_cast<double>(acc_n);
    if (mean < cfg.stream.g_units_min_m_s2 || mean > cfg.stream.g_units_max_m_s2) return;
    const std::string where = first_acc_record == last_acc_record
                                  ? checker.at(first_acc_record)
                                  : path + " records " + std::to_string(first_acc_record) + "-" +
                                        std::to_string(last_acc_record);
    refuse(where + ": mean IMU acceleration magnitude " + numText(mean) + " m/s^2 over the first " +
           std::to_string(acc_n) + " samples looks like g units (expected about " +
           numText(cfg.imu.gravity_m_s2) +
           " m/s^2); the stream is refused: set [stream] accel_scale = 9.80665 to read an "
           "accelerometer recorded in g");
  }

  /// An error that makes the whole stream unusable: nothing more is delivered.
  void refuse(const std::string& message) {
    buffer = TimeOrderingBuffer(cfg.stream.imu_reorder_window_s, cfg.stream.image_reorder_window_s);
    held.clear();
    refused = true;
    checker.counters().refused = true;
    finished = true;  // the end-of-stream checks would describe data that was never delivered
    fail(message);
  }

  void fail(const std::string& message) {
    checker.counters().error = message;
    pending_error = message;
    endInput();
  }

  void endInput() {
    input_done = true;
    buffer.finish();
    archive.reset();
    counting.reset();
    file.close();
  }

  void finish() {
    if (finished) return;
    finished = true;
    checker.finish();
    const auto& d = checker.diagnostics();
    self.logStr(mrpt::system::LVL_INFO, path + ": " + std::to_string(d.records) + " records, " +
                                            std::to_string(d.imu.delivered) + " IMU samples, " +
                                            std::to_string(d.images.delivered) + " RGB-D frames, " +
                                            std::to_string(d.warnings.size()) + " warnings");
  }

  RawlogSource& self;
  std::string path;
  StreamConfig cfg;
  std::string images_dir;
  mrpt::io::CFileGZInputStream file;
  std::optional<CountingInputStream> counting;
  std::optional<mrpt::serialization::CArchiveStreamBase<mrpt::io::CStream>> archive;
  StreamChecker checker;
  TimeOrderingBuffer buffer;
  std::deque<TimeOrderingBuffer::Item> held;  ///< ordered output waiting for the unit check
  std::size_t record = 0;
  std::uint64_t frames_delivered = 0;
  bool input_done = false;
  bool finished = false;
  bool refused = false;
  bool units_decided = false;
  double first_t = std::numeric_limits<double>::quiet_NaN();  ///< [s] oldest stamp offered
  double acc_sum = 0.0;  ///< [m/s^2] sum of |acc| over the samples of the unit check
  std::size_t acc_n = 0, first_acc_record = 0, last_acc_record = 0;
  std::string pending_error;
};

RawlogSource::RawlogSource(const std::string& path, const StreamConfig& cfg)
    : mrpt::system::COutputLogger("RawlogSource"), impl_(std::make_unique<Impl>(*this, path, cfg)) {
  impl_->open();
}

RawlogSource::~RawlogSource() = default;

bool RawlogSource::next(Measurement& out) {
  Impl& s = *impl_;
  for (;;) {
    if (s.input_done && !s.units_decided) s.decideUnits();
    TimeOrderingBuffer::Item item;
    bool have = false;
    if (s.units_decided && !s.held.empty()) {
      item = std::move(s.held.front());
      s.held.pop_front();
      have = true;
    } else if (s.buffer.pop(item)) {
      if (!s.units_decided) {
        s.held.push_back(std::move(item));  // released in order once the unit check is done
        continue;
      }
      have = true;
    }
    if (have) {
      if (auto* f = std::get_if<RgbdFrame>(&item.m)) f->index = s.frames_delivered++;
      s.checker.onDelivered(item.m, item.record);
      out = std::move(item.m);
      return true;
    }
    if (s.input_done) {
      s.finish();
      if (!s.pending_error.empty()) {
        const std::string e = std::move(s.pending_error);
        s.pending_error.clear();
        logStr(mrpt::system::LVL_ERROR, e);
        throw RawlogError(e);
      }
      return false;
    }
    s.readRecord();
  }
}

void RawlogSource::stopReading() {
  if (!impl_->input_done) impl_->endInput();
}

const StreamDiagnostics& RawlogSource::diagnostics() const { return impl_->checker.diagnostics(); }

const std::string& RawlogSource::path() const { return impl_->path; }

const std::string& RawlogSource::imagesDirectory() const { return impl_->images_dir; }

double RawlogSource::progress() const {
  if (!impl_->file.fileOpenCorrectly()) return 1.0;
  const double total = static_cast<double>(impl_->file.getTotalBytesCount());
  return total > 0 ? std::min(1.0, static_cast<double>(impl_->file.getPosition()) / total) : 1.0;
}

}  // namespace rgbdi::io
