#include "rgbdi/imu/imu_noise.h"

namespace rgbdi::imu {

ImuNoise ImuNoise::fromOptions(const ImuOptions& options) {
  ImuNoise n;
  n.acc_nd = options.acc_noise_density;
  n.gyr_nd = options.gyr_noise_density;
  n.acc_rw = options.acc_random_walk;
  n.gyr_rw = options.gyr_random_walk;
  return n;
}

}  // namespace rgbdi::imu
