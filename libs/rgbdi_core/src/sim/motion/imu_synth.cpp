#include "rgbdi/sim/imu_synth.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "sim/motion/counter_gaussian.h"

namespace rgbdi::sim {
namespace {

// Independent random streams of one seed.
enum Stream : std::uint64_t { kInitialBias = 1, kBiasWalk = 2, kWhiteNoise = 3 };

}  // namespace

ImuSynthOptions ImuSynthOptions::load(IniReader& ini) {
  ImuSynthOptions o;
  const std::string s = "sim";
  o.rate_hz = ini.getDouble(s, "imu_rate_hz", o.rate_hz, 10.0, 10000.0);
  o.gravity_m_s2 = ini.getDouble(s, "gravity_m_s2", o.gravity_m_s2, 9.7, 9.9);
  o.acc_noise_density = ini.getDouble(s, "acc_noise_density", o.acc_noise_density, 0.0, 10.0);
  o.gyr_noise_density = ini.getDouble(s, "gyr_noise_density", o.gyr_noise_density, 0.0, 1.0);
  o.acc_random_walk = ini.getDouble(s, "acc_random_walk", o.acc_random_walk, 0.0, 1.0);
  o.gyr_random_walk = ini.getDouble(s, "gyr_random_walk", o.gyr_random_walk, 0.0, 0.1);
  o.acc_bias_max = ini.getDouble(s, "acc_bias_max", o.acc_bias_max, 0.0, 2.0);
  o.gyr_bias_max = ini.getDouble(s, "gyr_bias_max", o.gyr_bias_max, 0.0, 0.5);
  o.errors = ImuErrorOptions::load(ini);
  o.accel_rate_hz = ini.getDouble(s, "imu_accel_rate_hz", o.accel_rate_hz, 0.0, 10000.0);
  o.gyro_rate_hz = ini.getDouble(s, "imu_gyro_rate_hz", o.gyro_rate_hz, 0.0, 10000.0);
  if ((o.accel_rate_hz > 0.0) != (o.gyro_rate_hz > 0.0))
    ini.fail(s, o.accel_rate_hz > 0.0 ? "imu_gyro_rate_hz" : "imu_accel_rate_hz",
             "imu_accel_rate_hz and imu_gyro_rate_hz are set together (both 0: combined samples)");
  if (o.accel_rate_hz != 0.0 && o.accel_rate_hz < 10.0)
    ini.fail(s, "imu_accel_rate_hz", "must be 0 (off) or at least 10 Hz");
  if (o.gyro_rate_hz != 0.0 && o.gyro_rate_hz < 10.0)
    ini.fail(s, "imu_gyro_rate_hz", "must be 0 (off) or at least 10 Hz");
  return o;
}

ImuSynthOptions ImuSynthOptions::noiseFree() const {
  ImuSynthOptions o;
  o.rate_hz = rate_hz;
  o.gravity_m_s2 = gravity_m_s2;
  o.acc_noise_density = o.gyr_noise_density = 0.0;
  o.acc_random_walk = o.gyr_random_walk = 0.0;
  o.acc_bias_max = o.gyr_bias_max = 0.0;
  return o;
}

ImuSynthesizer::ImuSynthesizer(std::shared_ptr<const BodyTrajectory> trajectory,
                               const ImuSynthOptions& options, std::uint64_t seed)
    : trajectory_(std::move(trajectory)), options_(options), seed_(seed) {
  if (!trajectory_) throw std::invalid_argument("ImuSynthesizer: no trajectory");
  if (!(options.rate_hz > 0.0) || !std::isfinite(options.rate_hz))
    throw std::invalid_argument("ImuSynthesizer: rate_hz must be positive (got " +
                                std::to_string(options.rate_hz) + ")");
  for (double v : {options.acc_noise_density, options.gyr_noise_density, options.acc_random_walk,
                   options.gyr_random_walk, options.acc_bias_max, options.gyr_bias_max})
    if (!(v >= 0.0) || !std::isfinite(v))
      throw std::invalid_argument("ImuSynthesizer: noise parameters must be finite and >= 0");

  if (options.errors.any()) errors_ = std::make_unique<ImuErrorModel>(options.errors, seed);
  const auto n =
      static_cast<std::size_t>(std::floor(trajectory_->duration() * options.rate_hz + 1e-9)) + 1;
  biases_.resize(n);
  const CounterRng init(seed, kInitialBias), walk(seed, kBiasWalk);
  ImuBias b;
  for (int i = 0; i < 3; ++i) {
    b.acc[i] = init.symmetric(static_cast<std::uint64_t>(i), options.acc_bias_max);
    b.gyr[i] = init.symmetric(static_cast<std::uint64_t>(3 + i), options.gyr_bias_max);
  }
  const double sqrt_dt = std::sqrt(1.0 / options.rate_hz);
  const double sa = options.acc_random_walk * sqrt_dt, sg = options.gyr_random_walk * sqrt_dt;
  for (std::size_t k = 0; k < n; ++k) {
    biases_[k] = b;
    for (int i = 0; i < 3; ++i) {
      b.acc[i] += sa * walk.gaussian(6 * k + static_cast<std::uint64_t>(i));
      b.gyr[i] += sg * walk.gaussian(6 * k + 3 + static_cast<std::uint64_t>(i));
    }
  }
  if (errors_ &&
      (options.errors.acc_bias_instability > 0.0 || options.errors.gyr_bias_instability > 0.0)) {
    // The bias instability is part of the true bias.
    std::vector<Eigen::Vector3d> gm_acc, gm_gyr;
    errors_->gaussMarkov(n, 1.0 / options.rate_hz, gm_acc, gm_gyr);
    for (std::size_t k = 0; k < n; ++k) {
      biases_[k].acc += gm_acc[k];
      biases_[k].gyr += gm_gyr[k];
    }
  }
}

ImuSample ImuSynthesizer::idealAt(double t) const {
  const KinematicState s = trajectory_->state(t);
  ImuSample m;
  m.t = t;
  m.acc = s.specificForce(options_.gravity_m_s2);
  m.gyr = s.omega_body;
  return m;
}

ImuSample ImuSynthesizer::ideal(std::size_t k) const { return idealAt(sampleTime(k)); }

ImuSample ImuSynthesizer::measured(std::size_t k) const {
  ImuSample m = ideal(k);
  if (errors_) {
    const Eigen::Vector3d f = m.acc;
    m.acc = errors_->accel(f);
    m.gyr = errors_->gyro(m.gyr, f);
  }
  const ImuBias& b = biases_.at(k);
  const CounterRng white(seed_, kWhiteNoise);
  const double sqrt_rate = std::sqrt(options_.rate_hz);
  const double sa = options_.acc_noise_density * sqrt_rate;
  const double sg = options_.gyr_noise_density * sqrt_rate;
  for (int i = 0; i < 3; ++i) {
    m.acc[i] += b.acc[i] + sa * white.gaussian(6 * k + static_cast<std::uint64_t>(i));
    m.gyr[i] += b.gyr[i] + sg * white.gaussian(6 * k + 3 + static_cast<std::uint64_t>(i));
  }
  if (errors_) {
    m.acc = ImuErrorModel::quantise(m.acc, options_.errors.acc_lsb);
    m.gyr = ImuErrorModel::quantise(m.gyr, options_.errors.gyr_lsb);
  }
  return m;
}

ImuBias ImuSynthesizer::biasAt(double t) const {
  const double x = std::clamp(t * options_.rate_hz, 0.0, static_cast<double>(biases_.size() - 1));
  const auto k = static_cast<std::size_t>(std::floor(x));
  if (k + 1 >= biases_.size()) return biases_.back();
  const double w = x - static_cast<double>(k);
  ImuBias b;
  b.acc = (1.0 - w) * biases_[k].acc + w * biases_[k + 1].acc;
  b.gyr = (1.0 - w) * biases_[k].gyr + w * biases_[k + 1].gyr;
  return b;
}

}  // namespace rgbdi::sim
