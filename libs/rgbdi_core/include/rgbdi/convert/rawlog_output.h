// The writing end of a conversion: re-orders what a converter delivers by stamp (within a
// window; sources deliver in bag or file order, stamps come from message headers) and writes the
// MRPT rawlog (CObservation3DRangeScan, CObservationIMU, CObservationOdometry) plus the ground
// truth as a TUM file. Both are written under temporary names and renamed by finish(), so they are
// always complete files; after damage in the input, finish() still leaves a valid rawlog of what
// was converted.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <queue>
#include <string>
#include <variant>
#include <vector>

#include "rgbdi/bag/conversion_report.h"
#include "rgbdi/bag/conversion_sink.h"
#include "rgbdi/io/rawlog_writer.h"

namespace rgbdi::convert {

/// "<dir>/<stem>": the output path without ".rawlog" / ".rawlog.gz" (what "<OUT stem>" means).
std::string outputStem(const std::string& rawlog_path);

struct RawlogOutputOptions {
  std::string path;              ///< *.rawlog (plain) or *.rawlog.gz (gzip)
  bool external_images = false;  ///< colour PNG + depth files in <stem>_Images/
  Eigen::Isometry3d T_body_cam = Eigen::Isometry3d::Identity();  ///< sensorPose of the frames
  double reorder_window_s = 0.5;
  int max_listed_issues = 10;
};

class RawlogOutput : public bag::ConversionSink {
 public:
  /// Creates the (temporary) rawlog; throws IoError.
  RawlogOutput(const RawlogOutputOptions& options, bag::ConversionReport& report);
  ~RawlogOutput() override;

  void imu(const ImuSample& sample) override;
  void accelerometer(double t, const Eigen::Vector3d& acc) override;
  void frame(const RgbdFrame& frame) override;
  void groundTruth(const StampedPose& pose) override;
  /// Written as CObservationOdometry (RawlogWriter: sensorLabel WHEEL_ODOMETRY).
  void wheel(const WheelOdometrySample& reading) override;

  /// Writes what is buffered, renames the rawlog into place and writes <stem>_groundtruth.tum
  /// when there were poses; adds the files to the report. Throws IoError.
  void finish();

  /// IMU samples written and their mean rate (n-1)/(t_last-t_first) [Hz] (0 with < 2 samples).
  double imuRateHz() const;
  const std::string& groundTruthPath() const { return gt_path_; }

 private:
  struct Accel {
    double t;
    Eigen::Vector3d acc;
  };
  using Item = std::variant<ImuSample, Accel, WheelOdometrySample, RgbdFrame>;
  struct Entry {
    double t;
    int kind;           ///< IMU data, then wheel odometry, then frames at equal stamps
    std::uint64_t seq;  ///< arrival order
    std::shared_ptr<Item> item;
    bool operator>(const Entry& o) const {
      if (t != o.t) return t > o.t;
      if (kind != o.kind) return kind > o.kind;
      return seq > o.seq;
    }
  };
  void push(double t, int kind, Item item, const std::string& what);
  void release(bool all);
  void write(const Item& item);

  RawlogOutputOptions options_;
  bag::ConversionReport& report_;
  std::unique_ptr<io::RawlogWriter> writer_;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> heap_;
  double newest_ = 0.0, written_t_ = 0.0;
  bool any_in_ = false, any_written_ = false;
  std::uint64_t seq_ = 0;
  double first_imu_t_ = 0.0, last_imu_t_ = 0.0;
  std::size_t imu_count_ = 0;
  Trajectory groundtruth_;
  std::string gt_path_;
};

}  // namespace rgbdi::convert
