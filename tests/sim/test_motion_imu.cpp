// IMU synthesis: consistency with the ground truth (integration), static readings, noise
// statistics, determinism, and the tracked robot's vibration band.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdio>

#include "rgbdi/common/sensor_options.h"
#include "rgbdi/common/so3.h"
#include "rgbdi/sim/imu_synth.h"
#include "rgbdi/sim/profiles.h"

namespace rgbdi::sim {
namespace {

MotionProfile profile(ProfileKind kind) {
  ProfileOptions o;
  o.kind = kind;
  return makeMotionProfile(o, ExtrinsicOptions().T_body_cam);
}

struct IntegrationError {
  double position_m = 0, velocity_m_s = 0, rotation_deg = 0;
};

/// Strapdown integration of IMU samples k0..k1 from the true state at k0: rotation by the
/// mean rate over each interval (exponential map), velocity and position by the trapezoidal
/// rule on the world acceleration R f + g.
IntegrationError integrate(const ImuSynthesizer& imu, std::size_t k0, std::size_t k1) {
  const BodyTrajectory& traj = imu.trajectory();
  const double dt = 1.0 / imu.options().rate_hz;
  const Eigen::Vector3d g(0, 0, -imu.options().gravity_m_s2);
  const KinematicState s0 = traj.state(imu.sampleTime(k0));
  Eigen::Matrix3d R = s0.T_world_body.linear();
  Eigen::Vector3d v = s0.v_world, p = s0.T_world_body.translation();
  ImuSample m0 = imu.ideal(k0);
  for (std::size_t k = k0; k < k1; ++k) {
    const ImuSample m1 = imu.ideal(k + 1);
    const Eigen::Matrix3d R1 = R * expSO3(0.5 * (m0.gyr + m1.gyr) * dt);
    const Eigen::Vector3d a0 = R * m0.acc + g, a1 = R1 * m1.acc + g;
    p += v * dt + (2.0 * a0 + a1) / 6.0 * dt * dt;
    v += 0.5 * (a0 + a1) * dt;
    R = R1;
    m0 = m1;
  }
  const KinematicState s1 = traj.state(imu.sampleTime(k1));
  IntegrationError e;
  e.position_m = (p - s1.T_world_body.translation()).norm();
  e.velocity_m_s = (v - s1.v_world).norm();
  e.rotation_deg = logSO3(s1.T_world_body.linear().transpose() * R).norm() * 180.0 / M_PI;
  return e;
}

TEST(ImuSynth, IntegratingTheNoiseFreeImuReproducesTheGroundTruth) {
  for (const std::string& name : profileNames()) {
    const ProfileKind kind = parseProfileKind(name);
    const MotionProfile prof = profile(kind);
    // The tracked robot's 10-30 Hz vibration and 1-6 Hz jitter are sampled coarsely at 200 Hz,
    // so a second-order strapdown integrator drifts by ~5 mm in 10 s there (the error falls
    // with dt^2). Sampling the same motion at 1 kHz shows the IMU itself is exact.
    for (double rate : {200.0, 1000.0}) {
      ImuSynthOptions ideal = ImuSynthOptions().noiseFree();
      ideal.rate_hz = rate;
      const ImuSynthesizer imu(prof.trajectory, ideal, 1);
      const std::size_t n10 = static_cast<std::size_t>(10.0 * rate);
      const std::size_t mid = static_cast<std::size_t>((prof.cruise_start_s + 2.0) * rate);
      for (std::size_t k0 : {std::size_t{0}, mid}) {
        const IntegrationError e = integrate(imu, k0, k0 + n10);
        std::printf(
            "%-15s %4.0f Hz, 10 s from t=%5.2f s: position %.2e m, velocity %.2e m/s, "
            "rotation %.2e deg\n",
            name.c_str(), rate, imu.sampleTime(k0), e.position_m, e.velocity_m_s, e.rotation_deg);
        if (kind == ProfileKind::TrackedSlopes && rate < 1000.0) {
          EXPECT_LT(e.position_m, 0.01) << name;
          continue;
        }
        // Millimetres after 10 s.
        EXPECT_LT(e.position_m, 2e-3) << name << " from " << imu.sampleTime(k0);
        EXPECT_LT(e.velocity_m_s, 5e-4) << name;
        EXPECT_LT(e.rotation_deg, 1e-3) << name;
      }
    }
  }
}

TEST(ImuSynth, StaticSegmentsMeasureGravityOnly) {
  const MotionProfile prof = profile(ProfileKind::Handheld);
  const ImuSynthOptions opt;  // default (noisy) options
  const ImuSynthesizer imu(prof.trajectory, opt, 7);
  const ImuSynthesizer ideal(prof.trajectory, opt.noiseFree(), 7);
  Eigen::Vector3d mean_acc = Eigen::Vector3d::Zero(), mean_gyr = Eigen::Vector3d::Zero();
  const std::size_t n = static_cast<std::size_t>(prof.moving_start_s * opt.rate_hz);
  for (std::size_t k = 0; k < n; ++k) {
    const ImuSample s = ideal.ideal(k);
    EXPECT_NEAR(s.acc.norm(), 9.81, 1e-12);
    EXPECT_LT(s.gyr.norm(), 1e-15);
    const ImuSample m = imu.measured(k);
    mean_acc += (m.acc - imu.biasAtSample(k).acc) / n;
    mean_gyr += (m.gyr - imu.biasAtSample(k).gyr) / n;
  }
  // White noise averages down: sigma_d / sqrt(n) = 0.02 * sqrt(200) / 20 = 0.014 m/s^2.
  EXPECT_NEAR(mean_acc.norm(), 9.81, 0.05);
  EXPECT_LT(mean_gyr.norm(), 0.005);
}

TEST(ImuSynth, NoiseAndBiasStatisticsFollowTheDensities) {
  const MotionProfile prof = profile(ProfileKind::WheeledCircle);
  ImuSynthOptions opt;
  const ImuSynthesizer imu(prof.trajectory, opt, 3);
  const std::size_t n = imu.sampleCount();
  double sa = 0, sg = 0, wa = 0, wg = 0;
  for (std::size_t k = 0; k + 1 < n; ++k) {
    const ImuSample m = imu.measured(k), i = imu.ideal(k);
    const ImuBias& b = imu.biasAtSample(k);
    sa += (m.acc - i.acc - b.acc).squaredNorm();
    sg += (m.gyr - i.gyr - b.gyr).squaredNorm();
    wa += (imu.biasAtSample(k + 1).acc - b.acc).squaredNorm();
    wg += (imu.biasAtSample(k + 1).gyr - b.gyr).squaredNorm();
  }
  const double count = 3.0 * static_cast<double>(n - 1);
  // Discrete sigma = density * sqrt(rate); random-walk step = density * sqrt(dt). With ~60000
  // values per statistic the sample std is within 1.5 %.
  EXPECT_NEAR(std::sqrt(sa / count), 0.02 * std::sqrt(200.0), 0.015 * 0.02 * std::sqrt(200.0));
  EXPECT_NEAR(std::sqrt(sg / count), 0.002 * std::sqrt(200.0), 0.015 * 0.002 * std::sqrt(200.0));
  EXPECT_NEAR(std::sqrt(wa / count), 4e-4 / std::sqrt(200.0), 0.015 * 4e-4 / std::sqrt(200.0));
  EXPECT_NEAR(std::sqrt(wg / count), 2e-5 / std::sqrt(200.0), 0.015 * 2e-5 / std::sqrt(200.0));
  const ImuBias& b0 = imu.biasAtSample(0);
  EXPECT_LE(b0.acc.cwiseAbs().maxCoeff(), 0.1);
  EXPECT_LE(b0.gyr.cwiseAbs().maxCoeff(), 0.005);
  EXPECT_GT(b0.acc.norm(), 1e-3);  // an initial bias is really drawn
  // biasAt interpolates between samples.
  const ImuBias mid = imu.biasAt(imu.sampleTime(10) + 0.5 / opt.rate_hz);
  EXPECT_LT((mid.acc - 0.5 * (imu.biasAtSample(10).acc + imu.biasAtSample(11).acc)).norm(), 1e-15);
}

TEST(ImuSynth, SameSeedSameSamplesDifferentSeedDifferentNoise) {
  const MotionProfile prof = profile(ProfileKind::TrackedSlopes);
  const ImuSynthesizer a(prof.trajectory, ImuSynthOptions(), 42),
      b(prof.trajectory, ImuSynthOptions(), 42), c(prof.trajectory, ImuSynthOptions(), 43);
  int differing = 0;
  for (std::size_t k = 0; k < a.sampleCount(); k += 97) {
    const ImuSample sa = a.measured(k), sb = b.measured(k), sc = c.measured(k);
    EXPECT_EQ(sa.acc, sb.acc);
    EXPECT_EQ(sa.gyr, sb.gyr);
    if ((sa.acc - sc.acc).norm() > 1e-6) ++differing;
  }
  EXPECT_EQ(differing, static_cast<int>((a.sampleCount() + 96) / 97));
  // Random access gives the same numbers as sequential access.
  EXPECT_EQ(a.measured(1234).acc, b.measured(1234).acc);
}

/// RMS (vector norm over the three axes) of the part of `x` between f_lo and f_hi, by a
/// Hann-windowed DFT (the window keeps tones from leaking far out of their band).
double bandRms(const std::vector<Eigen::Vector3d>& x, double rate, double f_lo, double f_hi) {
  const std::size_t n = x.size();
  std::vector<double> w(n);
  double w2 = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    w[i] = 0.5 - 0.5 * std::cos(2.0 * M_PI * i / n);
    w2 += w[i] * w[i] / n;
  }
  double power = 0.0;
  for (int axis = 0; axis < 3; ++axis) {
    for (std::size_t f = 1; f < n / 2; ++f) {
      const double hz = f * rate / n;
      if (hz < f_lo || hz > f_hi) continue;
      std::complex<double> sum = 0.0;
      for (std::size_t i = 0; i < n; ++i)
        sum += w[i] * x[i][axis] * std::polar(1.0, -2.0 * M_PI * f * i / n);
      power += 2.0 * std::norm(sum) / (static_cast<double>(n) * n * w2);
    }
  }
  return std::sqrt(power);
}

TEST(ImuSynth, TrackedRobotVibratesInTheTenToThirtyHertzBand) {
  const MotionProfile prof = profile(ProfileKind::TrackedSlopes);
  const ImuSynthOptions opt;
  const ImuSynthesizer imu(prof.trajectory, opt, 1);
  // 5 s while cruising.
  std::vector<Eigen::Vector3d> acc, gyr, acc_ideal;
  const auto k0 = static_cast<std::size_t>((prof.cruise_start_s + 1.0) * opt.rate_hz);
  for (std::size_t k = k0; k < k0 + 1000; ++k) {
    acc.push_back(imu.measured(k).acc);
    gyr.push_back(imu.measured(k).gyr);
    acc_ideal.push_back(imu.ideal(k).acc);
  }
  const double acc_band = bandRms(acc, opt.rate_hz, 10.0, 30.0);
  const double gyr_band = bandRms(gyr, opt.rate_hz, 10.0, 30.0);
  std::printf("tracked vibration 10-30 Hz: acc %.3f m/s^2 RMS, gyro %.4f rad/s RMS\n", acc_band,
              gyr_band);
  EXPECT_GE(acc_band, 1.5);
  EXPECT_GE(gyr_band, 0.05);
  // The motion itself has almost nothing above the band (only the white noise is there).
  EXPECT_LT(bandRms(acc_ideal, opt.rate_hz, 31.0, 100.0), 0.05);
  // And the wheeled robot vibrates much less.
  const MotionProfile wheeled = profile(ProfileKind::WheeledCircle);
  const ImuSynthesizer wimu(wheeled.trajectory, opt.noiseFree(), 1);
  std::vector<Eigen::Vector3d> wacc;
  for (std::size_t k = k0; k < k0 + 1000; ++k) wacc.push_back(wimu.ideal(k).acc);
  EXPECT_LT(bandRms(wacc, opt.rate_hz, 10.0, 30.0), 0.5);
}

}  // namespace
}  // namespace rgbdi::sim
