// Monte-Carlo check of the propagated pre-integration covariance.
//
// Noisy IMU readings are simulated the way a real IMU delivers them: independent white noise per
// sample with variance density^2 / dt, plus biases that random-walk with variance rw^2 * dt per
// sample. Each run is pre-integrated with the initial biases as linearisation point; the sample
// covariance of the resulting residual at the true states must match Preintegration::covariance().
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "imu/synthetic_motion.h"
#include "rgbdi/common/so3.h"
#include "rgbdi/imu/preintegration.h"

using namespace rgbdi;
using namespace rgbdi::imu;

namespace {

const Eigen::Vector3d& kGravity = test::kTestGravity;
ImuNoise simNoise() { return test::simImuNoise(); }

struct MonteCarloResult {
  Matrix15d sample_cov;
  Matrix15d model_cov;
};

// Residual vector of one run w.r.t. the noise-free pre-integration (the "true" deltas):
// [dp_true - dp, Log(dq^-1 dq_true), dv_true - dv, ba_end - ba_start, bg_end - bg_start],
// the sign convention of Preintegration::residual evaluated at the true states.
MonteCarloResult runMonteCarlo(int runs, int steps, std::uint64_t seed) {
  const ImuNoise noise = simNoise();
  const double rate = 200.0, dt = 1.0 / rate;
  const test::SyntheticMotion motion(kGravity);
  const Eigen::Vector3d ba0(0.05, -0.03, 0.08), bg0(0.004, -0.002, 0.003);
  const auto clean = motion.samples(1.0, 1.0 + steps * dt, rate);

  Preintegration truth(Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), noise);
  for (const auto& s : clean) truth.push(s);

  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n01(0.0, 1.0);
  auto draw = [&](double sigma) {
    return Eigen::Vector3d(sigma * n01(rng), sigma * n01(rng), sigma * n01(rng));
  };
  const double sa = noise.acc_nd / std::sqrt(dt), sg = noise.gyr_nd / std::sqrt(dt);
  const double swa = noise.acc_rw * std::sqrt(dt), swg = noise.gyr_rw * std::sqrt(dt);

  Vector15d mean = Vector15d::Zero();
  Matrix15d second = Matrix15d::Zero();
  Matrix15d model = Matrix15d::Zero();
  for (int run = 0; run < runs; ++run) {
    Preintegration pre(ba0, bg0, noise);
    Eigen::Vector3d ba = ba0, bg = bg0;
    for (std::size_t k = 0; k < clean.size(); ++k) {
      if (k > 0) {
        ba += draw(swa);
        bg += draw(swg);
      }
      pre.push(clean[k].t, clean[k].acc + ba + draw(sa), clean[k].gyr + bg + draw(sg));
    }
    Vector15d r;
    r.segment<3>(kIdxP) = truth.deltaP() - pre.deltaP();
    r.segment<3>(kIdxR) = logSO3((pre.deltaQ().inverse() * truth.deltaQ()).toRotationMatrix());
    r.segment<3>(kIdxV) = truth.deltaV() - pre.deltaV();
    r.segment<3>(kIdxBa) = ba - ba0;
    r.segment<3>(kIdxBg) = bg - bg0;
    mean += r;
    second += r * r.transpose();
    model = pre.covariance();  // depends on the (noisy) samples only through second order
  }
  mean /= runs;
  MonteCarloResult out;
  out.sample_cov = (second - runs * mean * mean.transpose()) / (runs - 1);
  out.model_cov = model;
  return out;
}

const char* blockName(int i) {
  static const char* names[] = {"p", "theta", "v", "ba", "bg"};
  return names[i / 3];
}

double varianceRatio(const MonteCarloResult& mc, int i) {
  const double ratio = mc.sample_cov(i, i) / mc.model_cov(i, i);
  std::printf("%-5s[%d] variance sample/model = %.3f\n", blockName(i), i % 3, ratio);
  return ratio;
}

void expectCorrelationsMatch(const MonteCarloResult& mc, double corr_tol) {
  const Matrix15d& S = mc.sample_cov;
  const Matrix15d& P = mc.model_cov;
  double worst = 0.0;
  for (int i = 0; i < 15; ++i) {
    for (int j = 0; j < i; ++j) {
      const double rs = S(i, j) / std::sqrt(S(i, i) * S(j, j));
      const double rp = P(i, j) / std::sqrt(P(i, i) * P(j, j));
      worst = std::max(worst, std::abs(rs - rp));
      EXPECT_NEAR(rs, rp, corr_tol) << "correlation (" << i << ", " << j << ")";
    }
  }
  std::printf("largest correlation difference: %.3f\n", worst);
}

// Variance of the midpoint-rule integral of N steps of independent per-sample noise relative to
// the continuous-time model the pre-integration uses. A sample inside the interval enters two
// steps with weight 1/2 each, the two end samples only one: the single integral (rotation,
// velocity) gets (N - 1/2) / N, the double integral (position) the ratio computed here.
double discreteOverContinuousSingle(int n) { return (n - 0.5) / n; }
double discreteOverContinuousDouble(int n) {
  std::vector<double> weight(static_cast<std::size_t>(n) + 1, 0.0);
  for (int k = 0; k < n; ++k) {
    // A unit acceleration during step k moves the end position by (N - k - 1/2) step^2.
    const double w = 0.5 * (n - k - 0.5);
    weight[static_cast<std::size_t>(k)] += w;
    weight[static_cast<std::size_t>(k) + 1] += w;
  }
  double sum = 0.0;
  for (double w : weight) sum += w * w;
  return sum / (n * n * n / 3.0);
}

}  // namespace

// 2000 runs: the relative standard error of a sample variance is sqrt(2 / 2000) = 3.2 %, and
// that of a correlation at most 1 / sqrt(2000) = 0.022; the bounds are about 4 standard errors.
// Over 100 steps the per-sample end effects are below 1 %, so model and Monte Carlo must agree.
TEST(PreintegrationCovariance, MatchesMonteCarloOverHalfASecond) {
  const MonteCarloResult mc = runMonteCarlo(2000, 100, 12345);
  for (int i = 0; i < 15; ++i) EXPECT_NEAR(varianceRatio(mc, i), 1.0, 0.13) << blockName(i);
  expectCorrelationsMatch(mc, 0.09);
}

// Over a few steps the continuous-time model is knowingly conservative (doc/imu.md): the sample
// covariance must equal the model times the closed-form discrete/continuous ratio (3 steps:
// 0.736 for position, 0.833 for rotation and velocity; 7 steps, one 30 Hz frame interval at
// 200 Hz: 0.889 and 0.929). Bias rows have no end effect.
TEST(PreintegrationCovariance, ShortIntervalsAreConservativeByTheKnownEndEffect) {
  for (int steps : {3, 7}) {
    const MonteCarloResult mc = runMonteCarlo(2000, steps, 777 + steps);
    const double single = discreteOverContinuousSingle(steps);
    const double dbl = discreteOverContinuousDouble(steps);
    std::printf("%d steps: expected ratios position %.3f, rotation/velocity %.3f\n", steps, dbl,
                single);
    for (int i = 0; i < 15; ++i) {
      const double expected = i < kIdxR ? dbl : (i < kIdxBa ? single : 1.0);
      EXPECT_NEAR(varianceRatio(mc, i) / expected, 1.0, 0.13)
          << blockName(i) << "[" << i % 3 << "] over " << steps << " steps";
    }
    expectCorrelationsMatch(mc, 0.09);
  }
}
