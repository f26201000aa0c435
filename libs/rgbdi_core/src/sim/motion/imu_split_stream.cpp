#include "rgbdi/sim/imu_split_stream.h"

#include <stdexcept>

#include "rgbdi/bag/convert_options.h"

namespace rgbdi::sim {

ImuSplitStream::ImuSplitStream(std::shared_ptr<const BodyTrajectory> trajectory,
                               const ImuSynthOptions& options, std::uint64_t seed) {
  if (!(options.accel_rate_hz > 0.0) || !(options.gyro_rate_hz > 0.0))
    throw std::invalid_argument("ImuSplitStream: accel_rate_hz and gyro_rate_hz must be positive");
  ImuSynthOptions a = options, g = options;
  a.rate_hz = options.accel_rate_hz;
  g.rate_hz = options.gyro_rate_hz;
  accel_ = std::make_unique<ImuSynthesizer>(trajectory, a, seed);
  gyro_ = std::make_unique<ImuSynthesizer>(trajectory, g, seed);

  // Both streams in time order (accelerometer first on equal stamps, as it then brackets the
  // gyro sample), through the merger rawlog-convert uses for a D435i's bag.
  const bag::ConvertOptions convert;
  bag::AccelGyroMerger merger(convert.max_accel_gap_s, convert.max_wait_s);
  merged_.reserve(gyro_->sampleCount());
  ImuSample out;
  std::size_t i = 0, j = 0;
  while (i < accel_->sampleCount() || j < gyro_->sampleCount()) {
    const bool take_accel =
        j >= gyro_->sampleCount() ||
        (i < accel_->sampleCount() && accel_->sampleTime(i) <= gyro_->sampleTime(j));
    if (take_accel) {
      merger.pushAccel(accel_->sampleTime(i), accel_->measured(i).acc);
      ++i;
    } else {
      merger.pushGyro(gyro_->sampleTime(j), gyro_->measured(j).gyr);
      ++j;
    }
    while (merger.pop(out)) merged_.push_back(out);
  }
  merger.finish();
  while (merger.pop(out)) merged_.push_back(out);
  stats_ = merger.stats();
}

ImuBias ImuSplitStream::biasAt(double t) const {
  ImuBias b;
  b.acc = accel_->biasAt(t).acc;
  b.gyr = gyro_->biasAt(t).gyr;
  return b;
}

}  // namespace rgbdi::sim
