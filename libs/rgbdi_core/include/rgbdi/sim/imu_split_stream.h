// Separate accelerometer and gyroscope streams, as a D435i delivers them (accel 250 or 63 Hz,
// gyro 200 or 400 Hz, each on its own stamps), merged into combined samples on the gyro stamps
// by bag::AccelGyroMerger with rawlog-convert's default [convert] gap and wait limits: the
// acceleration is interpolated linearly between the accelerometer samples around each gyro
// stamp; gyro samples outside the accelerometer's span are dropped (counted in stats()).
// Each stream is an ImuSynthesizer at its own rate with the same seed (so the same initial bias
// and constant errors); its own white noise, random walk and bias instability.
#pragma once

#include <memory>
#include <vector>

#include "rgbdi/bag/accel_gyro_merger.h"
#include "rgbdi/common/types.h"
#include "rgbdi/sim/imu_synth.h"

namespace rgbdi::sim {

class ImuSplitStream {
 public:
  /// options.accel_rate_hz and gyro_rate_hz must both be positive (std::invalid_argument).
  ImuSplitStream(std::shared_ptr<const BodyTrajectory> trajectory, const ImuSynthOptions& options,
                 std::uint64_t seed);

  /// Merged samples in gyro-stamp order, stamped with sequence time.
  const std::vector<ImuSample>& samples() const { return merged_; }
  /// True bias at sequence time t: accelerometer part from the accelerometer stream, gyro part
  /// from the gyro stream.
  ImuBias biasAt(double t) const;
  const bag::AccelGyroMergeStats& stats() const { return stats_; }
  const ImuSynthesizer& accelStream() const { return *accel_; }
  const ImuSynthesizer& gyroStream() const { return *gyro_; }

 private:
  std::unique_ptr<ImuSynthesizer> accel_, gyro_;
  std::vector<ImuSample> merged_;
  bag::AccelGyroMergeStats stats_;
};

}  // namespace rgbdi::sim
