#include "rgbdi/convert/rawlog_output.h"

#include <mrpt/obs/CObservationIMU.h>

#include <algorithm>
#include <filesystem>
#include <iomanip>
#include <sstream>

#include "rgbdi/common/atomic_file.h"
#include "rgbdi/io/mrpt_conversions.h"
#include "rgbdi/output/tum_writer.h"

namespace rgbdi::convert {
namespace {

bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

std::string stampText(double t) {
  std::ostringstream os;
  os << std::fixed << std::setprecision(6) << t;
  return os.str();
}

}  // namespace

std::string outputStem(const std::string& path) {
  std::string s = path;
  if (endsWith(s, ".gz")) s.resize(s.size() - 3);
  if (endsWith(s, ".rawlog")) s.resize(s.size() - 7);
  return s;
}

RawlogOutput::RawlogOutput(const RawlogOutputOptions& options, bag::ConversionReport& report)
    : options_(options), report_(report) {
  io::RawlogWriterOptions w;
  w.layout = io::RawlogWriterOptions::Layout::Observations;
  w.gzip = endsWith(options.path, ".gz");
  w.external_images = options.external_images;
  w.T_body_cam = options.T_body_cam;
  writer_ = std::make_unique<io::RawlogWriter>(options.path, w);
  gt_path_ = outputStem(options.path) + "_groundtruth.tum";
}

RawlogOutput::~RawlogOutput() = default;

void RawlogOutput::push(double t, int kind, Item item, const std::string& what) {
  // Beyond the window: it would land before data already written. Keep the rawlog ordered.
  if (any_written_ && t < written_t_) {
    ++report_.dropped_by_ordering;
    report_.addIssue("ordering",
                     what + " at t = " + stampText(t) + " s arrived after data up to t = " +
                         stampText(written_t_) + " s was written (more than the " +
                         std::to_string(options_.reorder_window_s) +
                         " s re-ordering window late); dropped",
                     options_.max_listed_issues);
    return;
  }
  newest_ = any_in_ ? std::max(newest_, t) : t;
  any_in_ = true;
  heap_.push(Entry{t, kind, seq_++, std::make_shared<Item>(std::move(item))});
  release(false);
}

void RawlogOutput::release(bool all) {
  while (!heap_.empty() && (all || heap_.top().t <= newest_ - options_.reorder_window_s)) {
    const Entry e = heap_.top();
    heap_.pop();
    write(*e.item);
    written_t_ = e.t;
    any_written_ = true;
  }
}

void RawlogOutput::write(const Item& item) {
  if (const auto* s = std::get_if<ImuSample>(&item)) {
    writer_->write(*s);
    if (imu_count_ == 0) first_imu_t_ = s->t;
    last_imu_t_ = s->t;
    ++imu_count_;
    ++report_.imu_written;
  } else if (const auto* a = std::get_if<Accel>(&item)) {
    auto obs = mrpt::obs::CObservationIMU::Create();
    obs->sensorLabel = "IMU";
    obs->timestamp = io::fromSeconds(a->t);
    obs->set(mrpt::obs::IMU_X_ACC, a->acc.x());
    obs->set(mrpt::obs::IMU_Y_ACC, a->acc.y());
    obs->set(mrpt::obs::IMU_Z_ACC, a->acc.z());
    writer_->writeObservation(obs);
    ++report_.imu_written;
  } else if (const auto* w = std::get_if<WheelOdometrySample>(&item)) {
    writer_->write(*w);
    ++report_.wheel_written;
  } else {
    writer_->write(std::get<RgbdFrame>(item));
    ++report_.frames_written;
  }
}

void RawlogOutput::imu(const ImuSample& sample) { push(sample.t, 0, sample, "IMU sample"); }

void RawlogOutput::accelerometer(double t, const Eigen::Vector3d& acc) {
  push(t, 0, Accel{t, acc}, "accelerometer sample");
}

void RawlogOutput::wheel(const WheelOdometrySample& reading) {
  push(reading.t, 1, reading, "wheel odometry reading");
}

void RawlogOutput::frame(const RgbdFrame& frame) { push(frame.t, 2, frame, frame.source_label); }

void RawlogOutput::groundTruth(const StampedPose& pose) { groundtruth_.push_back(pose); }

void RawlogOutput::finish() {
  release(true);
  writer_->close();
  report_.outputs.push_back(
      options_.path + " (" + std::to_string(writer_->records()) + " observations" +
      (options_.external_images ? ", images in " + writer_->imagesDirectory() : std::string()) +
      ")");
  if (groundtruth_.empty()) return;
  // TUM files need strictly increasing stamps: sort, and keep the first of equal stamps.
  std::stable_sort(groundtruth_.begin(), groundtruth_.end(),
                   [](const StampedPose& a, const StampedPose& b) { return a.t < b.t; });
  Trajectory unique;
  unique.reserve(groundtruth_.size());
  for (const StampedPose& p : groundtruth_) {
    if (!unique.empty() && p.t <= unique.back().t) {
      report_.addIssue("ground truth",
                       "pose at t = " + stampText(p.t) + " s repeats a stamp; dropped",
                       options_.max_listed_issues);
      continue;
    }
    unique.push_back(p);
  }
  try {
    output::writeTum(gt_path_, unique,
                     "ground truth as recorded in the input (the frame its pose source tracks, in "
                     "its world frame); the input's message stamps");
  } catch (const std::invalid_argument& e) {
    throw IoError(e.what());
  }
  report_.groundtruth_written = unique.size();
  report_.outputs.push_back(gt_path_ + " (" + std::to_string(unique.size()) +
                            " poses, TUM format)");
}

double RawlogOutput::imuRateHz() const {
  if (imu_count_ < 2 || !(last_imu_t_ > first_imu_t_)) return 0.0;
  return static_cast<double>(imu_count_ - 1) / (last_imu_t_ - first_imu_t_);
}

}  // namespace rgbdi::convert
