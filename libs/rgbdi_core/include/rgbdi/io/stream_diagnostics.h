// What a measurement source found in its data: counts, rates, gaps and plausibility checks.
// Plain fields (JSON-able via toJson()) plus human-readable warnings, each naming the source file
// and the record index. Filled by StreamChecker.
#pragma once

#include <cstddef>
#include <map>
#include <string>
#include <vector>

namespace rgbdi::io {

/// Timing statistics of one kind of measurement (IMU samples, RGB-D frames, wheel odometry).
struct SensorStreamStats {
  std::size_t delivered = 0;       ///< passed on to the consumer
  double first_t = 0.0;            ///< [s] first delivered stamp
  double last_t = 0.0;             ///< [s] last delivered stamp
  double duration_s = 0.0;         ///< [s] last_t - first_t
  double rate_hz = 0.0;            ///< [Hz] (delivered - 1) / duration_s
  double median_period_s = 0.0;    ///< [s] RGB-D and wheel odometry (IMU: 1 / rate_hz)
  std::size_t gaps = 0;            ///< consecutive delivered stamps further apart than the limit
  double gap_limit_s = 0.0;        ///< [s] the limit used
  double max_gap_s = 0.0;          ///< [s] largest dt between consecutive delivered stamps
  std::size_t non_monotonic = 0;   ///< arrived with a stamp older than the previous arrival
  std::size_t reordered = 0;       ///< late but within the window: delivered in order
  std::size_t duplicates = 0;      ///< same stamp as an earlier one: dropped
  std::size_t dropped_late = 0;    ///< later than the reorder window allows: dropped
  std::size_t invalid_stamps = 0;  ///< stamp zero/negative/not finite: dropped
};

struct StreamDiagnostics {
  std::string source;                          ///< file name as given
  std::string images_directory;                ///< where externally stored images are looked up
  std::size_t records = 0;                     ///< top-level rawlog entries read
  std::size_t observations = 0;                ///< observations met (inside sensory frames too)
  std::size_t actions = 0;                     ///< CActionCollection entries (ignored)
  std::map<std::string, std::size_t> skipped;  ///< ignored entries by class name
  std::size_t unusable = 0;  ///< RGB-D/IMU observations that could not be converted
  /// RGB-D frames skipped undecoded by [stream] image_rate_limit_hz (not counted in `images`).
  std::size_t frames_rate_limited = 0;

  SensorStreamStats imu;
  SensorStreamStats images;
  /// Wheel odometry (CObservationOdometry); report() and toJson() show it only when the stream
  /// has some (hasWheel()).
  SensorStreamStats wheel;
  std::size_t wheel_with_velocities = 0;  ///< readings that carry velocities
  std::size_t wheel_with_encoders = 0;    ///< readings that carry encoder ticks
  std::size_t non_finite_wheel = 0;       ///< readings with a NaN/inf value: skipped
  /// Episodes (and their total time) in which the wheels moved while the IMU was at rest
  /// ([stream] wheel_rest_*).
  std::size_t wheel_moving_at_rest = 0;
  double wheel_moving_at_rest_s = 0.0;  ///< [s]
  /// Episodes (and their total time) in which the wheels stood while the IMU moved
  /// ([stream] wheel_still_*): a blocked wheel, a robot pushed or carried.
  std::size_t wheel_still_imu_moving = 0;
  double wheel_still_imu_moving_s = 0.0;  ///< [s]
  double wheel_max_gap_t = 0.0;           ///< [s] stamp of the reading before the largest wheel dt
  /// The listed warnings of the wheel checks (gaps, the two verdicts); also in `warnings`.
  std::vector<std::string> wheel_warnings;

  std::size_t frames_with_color = 0;
  std::size_t frames_with_depth = 0;
  std::size_t frames_aligned = 0;       ///< depth registered to colour
  std::size_t size_mismatches = 0;      ///< colour/depth sizes vs alignment or intrinsics
  std::size_t missing_intrinsics = 0;   ///< frames whose colour or depth fx is 0
  std::size_t depth_unit_suspects = 0;  ///< frames whose median valid depth is implausible
  double median_depth_m = 0.0;          ///< median over frames of the per-frame median depth
  double depth_unit_m = 0.0;            ///< depth unit of the last frame with depth
  bool extrinsic_mismatch = false;      ///< sensorPose disagrees with [extrinsic]
  double mean_acc_norm_m_s2 = 0.0;      ///< mean |acc| over delivered IMU samples
  bool acc_looks_like_g_units = false;
  std::size_t non_finite_imu = 0;         ///< IMU samples with a NaN/inf value: skipped
  std::size_t constant_color_frames = 0;  ///< colour images that are black or one flat value
  double constant_color_s = 0.0;          ///< [s] time spanned by runs of such images

  /// [s] thread CPU time spent reading records (deserialisation, external-image loading and
  /// decoding, conversion, checks); of which rgbd_decode_cpu_s turned RGB-D observations into
  /// frames (PNG / compressed range-file decoding, colour-order and depth conversion). Timings
  /// only: they vary from run to run.
  double read_cpu_s = 0.0;
  double rgbd_decode_cpu_s = 0.0;

  std::vector<std::string> warnings;  ///< each names the file and the record(s)
  std::string error;                  ///< why reading stopped early; empty when it did not

  /// The whole stream was refused (e.g. accelerometer in g): nothing was delivered, `error` says
  /// why. Otherwise a non-empty `error` means damage: everything before it was delivered.
  bool refused = false;

  bool ok() const { return error.empty(); }
  /// Whether any wheel-odometry reading arrived (delivered or not).
  bool hasWheel() const {
    return wheel.delivered + wheel.duplicates + wheel.dropped_late + wheel.invalid_stamps +
               non_finite_wheel >
           0;
  }
  /// Multi-line human-readable summary (counts, rates, durations, gaps, checks, warnings).
  std::string report() const;
  /// The lines of report()'s "Wheel:" block after its first (period and gaps, content, the two
  /// verdicts, ordering), each indented by 7 spaces.
  std::string wheelReport() const;
  /// The same content as a JSON object (keys match the field names).
  std::string toJson(int indent = 2) const;
};

/// The problems of a stream as lines for a console, each "FILE record N: what": every distinct
/// warning once in the order found, then the error that stopped reading (if any, prefixed
/// "error: "). For tools that print the problems of a run (rgbdi-slam) after its progress line.
std::vector<std::string> streamProblemLines(const StreamDiagnostics& d);

}  // namespace rgbdi::io
