#include "rgbdi/sim/imu_error_model.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include "sim/motion/counter_gaussian.h"

namespace rgbdi::sim {
namespace {

// Random streams of the sequence seed (ImuSynthesizer uses 1-3).
enum Stream : std::uint64_t { kConstantErrors = 4, kGaussMarkov = 5 };

/// (I + diag(scale)) (I + off-diagonal misalignment), entries from draws first .. first + 8.
Eigen::Matrix3d axisMatrix(const CounterRng& rng, std::uint64_t first, double scale_max,
                           double misalignment_max) {
  Eigen::Matrix3d s = Eigen::Matrix3d::Identity(), m = Eigen::Matrix3d::Identity();
  std::uint64_t n = first;
  for (int i = 0; i < 3; ++i) s(i, i) += rng.symmetric(n++, scale_max);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      if (r != c) m(r, c) = rng.symmetric(n++, misalignment_max);
  return s * m;
}

}  // namespace

bool ImuErrorOptions::any() const {
  return acc_scale_max != 0.0 || gyr_scale_max != 0.0 || acc_misalignment_max_rad != 0.0 ||
         gyr_misalignment_max_rad != 0.0 || gyr_g_sensitivity_max != 0.0 ||
         acc_bias_instability != 0.0 || gyr_bias_instability != 0.0 || acc_lsb != 0.0 ||
         gyr_lsb != 0.0;
}

ImuErrorOptions ImuErrorOptions::load(IniReader& ini) {
  ImuErrorOptions o;
  const std::string s = "sim";
  o.acc_scale_max = ini.getDouble(s, "imu_acc_scale_max", o.acc_scale_max, 0.0, 0.2);
  o.gyr_scale_max = ini.getDouble(s, "imu_gyr_scale_max", o.gyr_scale_max, 0.0, 0.2);
  o.acc_misalignment_max_rad =
      ini.getDouble(s, "imu_acc_misalignment_max_rad", o.acc_misalignment_max_rad, 0.0, 0.1);
  o.gyr_misalignment_max_rad =
      ini.getDouble(s, "imu_gyr_misalignment_max_rad", o.gyr_misalignment_max_rad, 0.0, 0.1);
  o.gyr_g_sensitivity_max =
      ini.getDouble(s, "imu_gyr_g_sensitivity_max", o.gyr_g_sensitivity_max, 0.0, 0.01);
  o.acc_bias_instability =
      ini.getDouble(s, "imu_acc_bias_instability", o.acc_bias_instability, 0.0, 1.0);
  o.gyr_bias_instability =
      ini.getDouble(s, "imu_gyr_bias_instability", o.gyr_bias_instability, 0.0, 0.1);
  o.bias_instability_tau_s =
      ini.getDouble(s, "imu_bias_instability_tau_s", o.bias_instability_tau_s, 0.0, 1.0e6);
  if (!(o.bias_instability_tau_s > 0.0))
    ini.fail(s, "imu_bias_instability_tau_s", "must be greater than 0");
  o.acc_lsb = ini.getDouble(s, "imu_acc_lsb", o.acc_lsb, 0.0, 1.0);
  o.gyr_lsb = ini.getDouble(s, "imu_gyr_lsb", o.gyr_lsb, 0.0, 0.1);
  return o;
}

void ImuErrorOptions::validate() const {
  for (double v :
       {acc_scale_max, gyr_scale_max, acc_misalignment_max_rad, gyr_misalignment_max_rad,
        gyr_g_sensitivity_max, acc_bias_instability, gyr_bias_instability, acc_lsb, gyr_lsb})
    if (!(v >= 0.0) || !std::isfinite(v))
      throw std::invalid_argument("ImuErrorOptions: error sizes must be finite and >= 0");
  if (!(bias_instability_tau_s > 0.0) || !std::isfinite(bias_instability_tau_s))
    throw std::invalid_argument("ImuErrorOptions: bias_instability_tau_s must be positive");
}

ImuErrorModel::ImuErrorModel(const ImuErrorOptions& options, std::uint64_t seed)
    : options_(options), seed_(seed) {
  options.validate();
  const CounterRng rng(seed, kConstantErrors);
  acc_matrix_ = axisMatrix(rng, 0, options.acc_scale_max, options.acc_misalignment_max_rad);
  gyr_matrix_ = axisMatrix(rng, 9, options.gyr_scale_max, options.gyr_misalignment_max_rad);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      g_sensitivity_(r, c) =
          rng.symmetric(18 + static_cast<std::uint64_t>(3 * r + c), options.gyr_g_sensitivity_max);
}

Eigen::Vector3d ImuErrorModel::accel(const Eigen::Vector3d& specific_force) const {
  return acc_matrix_ * specific_force;
}

Eigen::Vector3d ImuErrorModel::gyro(const Eigen::Vector3d& rate,
                                    const Eigen::Vector3d& specific_force) const {
  return gyr_matrix_ * rate + g_sensitivity_ * specific_force;
}

Eigen::Vector3d ImuErrorModel::quantise(const Eigen::Vector3d& v, double lsb) {
  if (lsb == 0.0) return v;
  return (v / lsb).array().round().matrix() * lsb;
}

void ImuErrorModel::gaussMarkov(std::size_t n, double dt, std::vector<Eigen::Vector3d>& acc,
                                std::vector<Eigen::Vector3d>& gyr) const {
  const CounterRng rng(seed_, kGaussMarkov);
  const double phi = std::exp(-dt / options_.bias_instability_tau_s);
  const double drive = std::sqrt(1.0 - phi * phi);
  acc.assign(n, Eigen::Vector3d::Zero());
  gyr.assign(n, Eigen::Vector3d::Zero());
  Eigen::Vector3d a, g;
  for (std::size_t k = 0; k < n; ++k)
    for (int i = 0; i < 3; ++i) {
      const auto ia = 6 * k + static_cast<std::uint64_t>(i), ig = ia + 3;
      // Sample 0 from the stationary distribution, then the first-order recursion.
      a[i] = k == 0 ? rng.gaussian(ia) : phi * a[i] + drive * rng.gaussian(ia);
      g[i] = k == 0 ? rng.gaussian(ig) : phi * g[i] + drive * rng.gaussian(ig);
      acc[k][i] = options_.acc_bias_instability * a[i];
      gyr[k][i] = options_.gyr_bias_instability * g[i];
    }
}

}  // namespace rgbdi::sim
