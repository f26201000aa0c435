#include "rgbdi/io/rawlog_source.h"

#include <mrpt/img/CImage.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationOdometry.h>
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
#include <stdexcept>
#include <vector>

#include "io/cimage_guard.h"
#include "io/counting_input_stream.h"
#include "io/mrpt_aligned_malloc.h"
#include "io/rawlog_naming.h"
#include "rgbdi/common/cpu_clock.h"
#include "rgbdi/io/frame_rate_limiter.h"
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
        buffer(cfg.stream.imu_reorder_window_s, cfg.stream.image_reorder_window_s),
        // An inspection (rawlog-convert --info) looks at every frame.
        rate_limiter(cfg.report_only ? 0.0 : cfg.stream.image_rate_limit_hz) {}

  void open() {
    namespace fs = std::filesystem;
    // Links rgbdi's mrpt::aligned_malloc into this program (finding 9, mrpt_aligned_malloc.cpp).
    if (!mrptAllocationFailureThrows()) throw RawlogError(path + ": MRPT allocation check missing");
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
    std::optional<SensoryFrame> frame;
    bool actions = false;
    try {
      const auto header = peekHeader();
      if (header &&
          storedClassIs(reinterpret_cast<const std::uint8_t*>(header->class_name.data()),
                        header->class_name.size(), "CSensoryFrame") &&
          header->version >= 0 && header->version <= 2) {
        frame = readSensoryFrame(*header);
      } else if (header &&
                 storedClassIs(reinterpret_cast<const std::uint8_t*>(header->class_name.data()),
                               header->class_name.size(), "CActionCollection") &&
                 header->version == 0) {
        skipActionCollection(*header);
        actions = true;
      } else {
        obj = archive->ReadObject();
      }
    } catch (const mrpt::serialization::CExceptionEOF& e) {
      if (counting->bytes() == before && counting->guardError().empty()) {
        endInput();
      } else {
        fail(damaged(before, e, true));
      }
      return;
    } catch (const std::exception& e) {
      fail(damaged(before, e, false));
      return;
    }
    const std::size_t rec = record++;
    ++checker.counters().records;
    if (actions) {
      ++checker.counters().actions;
      return;
    }
    if (frame) {
      for (const auto& issue : frame->issues)
        checker.onUnusable(rec, checker.at(rec) + ": " + issue + "; skipped");
      for (const auto& o : frame->observations) handleObservation(o, rec);
      return;
    }
    if (!obj) {
      checker.onSkipped(rec, "null object");
      return;
    }
    if (std::dynamic_pointer_cast<mrpt::obs::CActionCollection>(obj)) {
      ++checker.counters().actions;
    } else if (auto o = std::dynamic_pointer_cast<mrpt::obs::CObservation>(obj)) {
      handleObservation(o, rec);
    } else {
      checker.onSkipped(rec, obj->GetRuntimeClass()->className);
    }
  }

  /// The class name and version of the object the archive reads next, as CArchive stores them
  /// (a length byte with bit 7 set, the name, a version byte; or the format before MRPT 0.5.5:
  /// the length, three zero bytes, the name, an int32 version). nullopt if that is not what
  /// follows: MRPT then reads (and refuses) it.
  struct StoredHeader {
    std::string class_name;
    int version = 0;
    bool old_format = false;
    std::size_t size = 0;  ///< bytes of the header
  };
  std::optional<StoredHeader> peekHeader() {
    const auto& first = counting->peek(1);
    if (first.empty()) return std::nullopt;
    StoredHeader h;
    h.old_format = (first[0] & 0x80) == 0;
    const std::size_t name_length = first[0] & 0x7f, name_at = h.old_format ? 4 : 1;
    h.size = name_at + name_length + (h.old_format ? 4 : 1);
    const auto& b = counting->peek(h.size);
    if (b.size() < h.size) return std::nullopt;
    if (h.old_format && (b[1] != 0 || b[2] != 0 || b[3] != 0)) return std::nullopt;
    h.class_name.assign(b.begin() + static_cast<std::ptrdiff_t>(name_at),
                        b.begin() + static_cast<std::ptrdiff_t>(name_at + name_length));
    const std::size_t v = name_at + name_length;
    h.version = h.old_format ? static_cast<int>(b[v] | b[v + 1] << 8 | b[v + 2] << 16 |
                                                static_cast<unsigned>(b[v + 3]) << 24)
                             : b[v];
    return h;
  }

  /// A CSensoryFrame record, read here instead of by MRPT (fuzzing finding 10): MRPT's
  /// CSensoryFrame::serializeFrom (version 0) writes the frame's time stamp through every element
  /// pointer, and an element stored as a null object, or as an object that is no observation,
  /// is a null pointer there (SIGSEGV). Every element is checked: empty ones and ones of another
  /// class are reported as damage of this record and skipped. The elements are used only once
  /// the whole record (up to its end flag) has been read.
  struct SensoryFrame {
    std::vector<mrpt::obs::CObservation::Ptr> observations;
    std::vector<std::string> issues;
  };
  SensoryFrame readSensoryFrame(const StoredHeader& header) {
    std::vector<std::uint8_t> skip(header.size);
    if (counting->Read(skip.data(), skip.size()) != skip.size())
      throw std::runtime_error("cannot read the sensory frame header");
    auto& in = *archive;
    std::optional<mrpt::Clock::time_point> stamp;
    if (header.version < 2) (void)in.ReadAs<uint32_t>();  // an ID, dropped in version 2
    if (header.version == 0)
      stamp = mrpt::Clock::time_point(mrpt::Clock::duration(in.ReadAs<int64_t>()));
    const uint32_t n = in.ReadAs<uint32_t>();
    SensoryFrame frame;
    for (uint32_t i = 0; i < n; ++i) {
      auto element = in.ReadObject();
      const std::string which =
          "sensory frame element " + std::to_string(i) + " of " + std::to_string(n);
      auto o = std::dynamic_pointer_cast<mrpt::obs::CObservation>(element);
      if (!element) {
        frame.issues.push_back(which + " is empty (stored as a null object)");
      } else if (!o) {
        frame.issues.push_back(which + " is a " + element->GetRuntimeClass()->className +
                               ", not an observation");
      } else {
        if (stamp) o->timestamp = *stamp;
        frame.observations.push_back(std::move(o));
      }
    }
    if (!header.old_format && in.ReadAs<uint8_t>() != 0x88)  // CArchive's end flag
      throw std::runtime_error("the sensory frame's end flag is missing");
    return frame;
  }

  /// A CActionCollection record (robot actions, not used), read here instead of by MRPT (open
  /// finding 1, fuzz_rawlog 2026-12-03 evening: MRPT resizes a deque to the stored element
  /// count before it reads any element, so a damaged count grew the process past 2.7 GB). The
  /// actions are read one by one and dropped; a damaged count ends at the data.
  void skipActionCollection(const StoredHeader& header) {
    std::vector<std::uint8_t> skip(header.size);
    if (counting->Read(skip.data(), skip.size()) != skip.size())
      throw std::runtime_error("cannot read the action collection header");
    auto& in = *archive;
    const uint32_t n = in.ReadAs<uint32_t>();
    for (uint32_t i = 0; i < n; ++i) (void)in.ReadObject();
    if (in.ReadAs<uint8_t>() != 0x88)  // CArchive's end flag
      throw std::runtime_error("the action collection's end flag is missing");
  }

  /// The refusal of a record that could not be read: what the image check found, a record the
  /// file ends in, or MRPT's reason. MRPT reports any error inside a nested object as an end of
  /// data (`eof`), which is only one if the file really ended.
  std::string damaged(uint64_t record_start, const std::exception& e, bool eof) const {
    if (!counting->guardError().empty())
      return checker.at(record) + ": corrupt record (" + counting->guardError() + ")";
    if (counting->shortRead()) return truncated(record_start);
    if (eof)
      return checker.at(record) +
             ": corrupt record (an object inside it cannot be read; MRPT: " + firstLine(e.what()) +
             ")";
    return checker.at(record) + ": corrupt record (" + firstLine(e.what()) + ")";
  }

  std::string truncated(uint64_t record_start) const {
    return checker.at(record) + ": truncated: the file ends inside this record (" +
           std::to_string(counting->bytes() - record_start) + " bytes of it read)";
  }

  void handleObservation(const mrpt::obs::CObservation::Ptr& o, std::size_t rec) {
    if (!o) return;
    ++checker.counters().observations;
    if (auto scan = std::dynamic_pointer_cast<mrpt::obs::CObservation3DRangeScan>(o)) {
      // Before anything is decoded: a skipped frame costs only its record.
      if (!rate_limiter.admit(toSeconds(scan->timestamp))) {
        ++checker.counters().frames_rate_limited;
        return;
      }
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
    } else if (auto odo = std::dynamic_pointer_cast<mrpt::obs::CObservationOdometry>(o)) {
      WheelOdometrySample wheel;
      try {
        wheel = fromMrpt(*odo);
      } catch (const ConversionError& e) {
        checker.onUnusable(rec, checker.at(rec) + ": " + e.what() + "; skipped");
        return;
      }
      if (!isFinite(wheel)) {
        ++checker.counters().non_finite_wheel;
        checker.onUnusable(rec, checker.at(rec) + ": wheel odometry at t = " + stampText(wheel.t) +
                                    " s has a non-finite value (pose " + numText(wheel.x_m) + " " +
                                    numText(wheel.y_m) + " " + numText(wheel.yaw_rad) +
                                    ", velocity " + numText(wheel.v_forward_m_s) + " " +
                                    numText(wheel.v_lateral_m_s) + " " +
                                    numText(wheel.yaw_rate_rad_s) + "); skipped");
        return;
      }
      offer(Measurement(wheel), rec);
    } else {
      checker.onSkipped(rec, o->GetRuntimeClass()->className);
    }
  }

  void offer(Measurement m, std::size_t rec) {
    const MeasurementKind kind = kindOf(m);
    const bool imu = kind == MeasurementKind::Imu;
    const double t = measurementTime(m);
    const double newest = buffer.newest(kind);
    if (t < newest - cfg.stream.time_jump_back_s) {
      // A clock reset or two recordings joined: re-ordering cannot repair it and dropping a
      // second of data silently distorts the trajectory. Stop here; what came before is used.
      fail(checker.at(rec) + ": " + kindName(kind) + " stamp t = " + stampText(t) + " s is " +
           stampText(newest - t) + " s older than the newest one read before it (" +
           stampText(newest) +
           " s): time goes backwards (clock reset or recordings joined?); reading stops at this "
           "record, the data before it is used (limit [stream] time_jump_back_s = " +
           numText(cfg.stream.time_jump_back_s) + " s; split the rawlog here to use the rest)");
      return;
    }
    if (imu) accountAcc(std::get<ImuSample>(m), rec);
    if (std::isfinite(t) && !(t >= first_t)) first_t = t;
    const auto verdict = buffer.push(std::move(m), rec);
    checker.onArrival(kind, t, rec, verdict, newest);
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
  FrameRateLimiter rate_limiter;
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
