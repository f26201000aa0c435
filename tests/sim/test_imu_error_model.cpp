// IMU errors beyond white noise and random walk (ImuErrorModel) and separate accelerometer /
// gyroscope streams merged as rawlog-convert merges a D435i's (ImuSplitStream).
#include <gtest/gtest.h>

#include <cmath>

#include "rgbdi/sim/imu_error_model.h"
#include "rgbdi/sim/imu_split_stream.h"
#include "rgbdi/sim/imu_synth.h"
#include "rgbdi/sim/profiles.h"
#include "rgbdi/sim/sequence.h"

namespace rgbdi::sim {
namespace {

std::shared_ptr<const BodyTrajectory> handheldTrajectory() {
  ProfileOptions o;
  o.kind = ProfileKind::Handheld;
  o.duration_s = 12.0;
  return makeMotionProfile(o, Eigen::Isometry3d::Identity()).trajectory;
}

IniReader iniOf(const std::string& sim_lines) {
  return IniReader::fromText("[sim]\n" + sim_lines, "imu.ini");
}

TEST(ImuErrorModel, ScaleMisalignmentAndGSensitivityAreDrawnOnceWithinTheirBounds) {
  ImuErrorOptions o;
  o.acc_scale_max = 0.02;
  o.gyr_scale_max = 0.03;
  o.acc_misalignment_max_rad = 0.01;
  o.gyr_misalignment_max_rad = 0.005;
  o.gyr_g_sensitivity_max = 3e-4;
  const ImuErrorModel m(o, 5), same(o, 5), other(o, 6);
  EXPECT_EQ(m.accMatrix(), same.accMatrix());
  EXPECT_EQ(m.gyrMatrix(), same.gyrMatrix());
  EXPECT_EQ(m.gSensitivity(), same.gSensitivity());
  EXPECT_NE(m.accMatrix(), other.accMatrix());
  // (I + S)(I + M): row r of M scaled by 1 + s_r; the diagonal is 1 + s_r exactly.
  for (const auto& [T, s_max, m_max] :
       {std::tuple{m.accMatrix(), 0.02, 0.01}, std::tuple{m.gyrMatrix(), 0.03, 0.005}})
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) {
        if (r == c) {
          EXPECT_LE(std::abs(T(r, r) - 1.0), s_max);
        } else {
          EXPECT_LE(std::abs(T(r, c)), (1.0 + s_max) * m_max);
          EXPECT_NE(T(r, c), 0.0);
        }
      }
  EXPECT_LE(m.gSensitivity().cwiseAbs().maxCoeff(), 3e-4);
  EXPECT_GT(m.gSensitivity().cwiseAbs().maxCoeff(), 1e-4);

  // Without noise the synthesised IMU is exactly T f and T w + G f.
  ImuSynthOptions so = ImuSynthOptions().noiseFree();
  so.errors = o;
  const ImuSynthesizer imu(handheldTrajectory(), so, 5);
  for (std::size_t k = 0; k < imu.sampleCount(); k += 37) {
    const ImuSample ideal = imu.ideal(k), meas = imu.measured(k);
    EXPECT_LT((meas.acc - m.accMatrix() * ideal.acc).norm(), 1e-12);
    EXPECT_LT((meas.gyr - m.gyrMatrix() * ideal.gyr - m.gSensitivity() * ideal.acc).norm(), 1e-12);
  }
  // At rest (the first 2 s) the gyro reads G f with |f| = g: up to 3 * 3e-4 * 9.81 rad/s.
  const ImuSample rest = imu.measured(10);
  EXPECT_LT((rest.gyr - m.gSensitivity() * imu.ideal(10).acc).norm(), 1e-15);
  EXPECT_GT(rest.gyr.norm(), 1e-4);
}

TEST(ImuErrorModel, BiasInstabilityIsAStationaryGaussMarkovProcess) {
  ImuErrorOptions o;
  o.acc_bias_instability = 0.02;
  o.gyr_bias_instability = 0.001;
  o.bias_instability_tau_s = 1.0;
  const double dt = 0.01;
  const std::size_t lag = 100;  // one time constant
  // Over 2000 seeds: standard deviation sigma at every sample, correlation exp(-1) after tau.
  double s0 = 0.0, s1 = 0.0, c01 = 0.0, g0 = 0.0;
  const int seeds = 2000;
  std::vector<Eigen::Vector3d> acc, gyr;
  for (int seed = 0; seed < seeds; ++seed) {
    ImuErrorModel(o, static_cast<std::uint64_t>(seed)).gaussMarkov(2 * lag + 1, dt, acc, gyr);
    s0 += acc[lag].squaredNorm() / 3.0;
    s1 += acc[2 * lag].squaredNorm() / 3.0;
    c01 += acc[lag].dot(acc[2 * lag]) / 3.0;
    g0 += gyr[0].squaredNorm() / 3.0;
  }
  EXPECT_NEAR(std::sqrt(s0 / seeds), 0.02, 0.02 * 0.04);
  EXPECT_NEAR(std::sqrt(s1 / seeds), 0.02, 0.02 * 0.04);
  EXPECT_NEAR(std::sqrt(g0 / seeds), 0.001, 0.001 * 0.04);  // stationary from sample 0
  EXPECT_NEAR(c01 / std::sqrt(s0 * s1), std::exp(-1.0), 0.05);

  // It is part of the true bias: without random walk and initial bias, the bias is the process.
  ImuSynthOptions so = ImuSynthOptions().noiseFree();
  so.rate_hz = 100.0;
  so.errors = o;
  const ImuSynthesizer imu(handheldTrajectory(), so, 11);
  ImuErrorModel(o, 11).gaussMarkov(imu.sampleCount(), dt, acc, gyr);
  for (std::size_t k = 0; k < imu.sampleCount(); k += 50) {
    EXPECT_EQ(imu.biasAtSample(k).acc, acc[k]);
    EXPECT_EQ(imu.biasAtSample(k).gyr, gyr[k]);
    EXPECT_LT((imu.measured(k).acc - imu.ideal(k).acc - acc[k]).norm(), 1e-12);
  }
}

TEST(ImuErrorModel, QuantisationRoundsToTheLsb) {
  ImuSynthOptions plain;
  ImuSynthOptions q = plain;
  q.errors.acc_lsb = 0.0191;    // BMI055 at +-4 g: 1.95 mg
  q.errors.gyr_lsb = 1.065e-3;  // 16 bits over +-2000 deg/s
  const auto traj = handheldTrajectory();
  const ImuSynthesizer a(traj, plain, 3), b(traj, q, 3);
  for (std::size_t k = 0; k < a.sampleCount(); k += 13) {
    const ImuSample x = a.measured(k), y = b.measured(k);
    for (int i = 0; i < 3; ++i) {
      EXPECT_NEAR(y.acc[i] / 0.0191, std::round(y.acc[i] / 0.0191), 1e-9);
      EXPECT_NEAR(y.gyr[i] / 1.065e-3, std::round(y.gyr[i] / 1.065e-3), 1e-9);
      EXPECT_LE(std::abs(y.acc[i] - x.acc[i]), 0.5 * 0.0191 + 1e-12);
      EXPECT_LE(std::abs(y.gyr[i] - x.gyr[i]), 0.5 * 1.065e-3 + 1e-12);
    }
  }
  EXPECT_EQ(ImuErrorModel::quantise(Eigen::Vector3d(0.26, -0.26, 0.24), 0.5),
            Eigen::Vector3d(0.5, -0.5, 0.0));
}

TEST(ImuSplitStream, AccelAndGyroAtTheirOwnRatesAreMergedOnTheGyroStamps) {
  const auto traj = handheldTrajectory();
  for (double accel_rate : {250.0, 63.0}) {  // the D435i's two accelerometer rates
    SCOPED_TRACE(accel_rate);
    ImuSynthOptions o = ImuSynthOptions().noiseFree();
    o.accel_rate_hz = accel_rate;
    o.gyro_rate_hz = 200.0;
    const ImuSplitStream split(traj, o, 1);
    const std::vector<ImuSample>& s = split.samples();
    // Every gyro sample inside the accelerometer's span (12 s, both ends at whole rates).
    ASSERT_EQ(s.size(), 2401u);
    EXPECT_EQ(split.stats().dropped(), 0u);
    EXPECT_EQ(split.stats().accel_in, static_cast<std::size_t>(12 * accel_rate) + 1);
    for (std::size_t k = 0; k < s.size(); k += 7) {
      EXPECT_NEAR(s[k].t, k / 200.0, 1e-12);
      EXPECT_EQ(s[k].gyr, split.gyroStream().ideal(k).gyr);
      // The accelerometer interpolated linearly between its samples around the gyro stamp.
      const double x = s[k].t * accel_rate;
      const auto i = static_cast<std::size_t>(std::floor(x + 1e-9));
      const double w = std::max(0.0, x - static_cast<double>(i));
      const Eigen::Vector3d a0 = split.accelStream().ideal(i).acc;
      const Eigen::Vector3d expected =
          w < 1e-9 ? a0 : Eigen::Vector3d((1 - w) * a0 + w * split.accelStream().ideal(i + 1).acc);
      EXPECT_LT((s[k].acc - expected).norm(), 1e-9) << k;
    }
  }
}

TEST(ImuSplitStream, ASequenceStreamsTheMergedSamplesWithTheirTrueBiases) {
  SimOptions o;
  o.profile.kind = ProfileKind::WheeledCircle;
  o.profile.duration_s = 9.0;
  o.fps = 5.0;
  o.prefetch_frames = false;
  o.imu.accel_rate_hz = 250.0;
  o.imu.gyro_rate_hz = 400.0;
  const SimulatedSequence seq(o);
  ASSERT_NE(seq.imuSplitStream(), nullptr);
  EXPECT_EQ(seq.options().imu.rate_hz, 400.0);  // the combined samples' rate
  EXPECT_EQ(seq.imuCount(), 3601u);
  for (std::size_t k = 0; k < seq.imuCount(); k += 101) {
    EXPECT_NEAR(seq.imuSample(k).t, 1000.0 + k / 400.0, 1e-9);
    const ImuBias b = seq.imuSplitStream()->biasAt(k / 400.0);
    // (1000 + t) - 1000 differs from t in the last bits: biases linear in t agree to 1e-9.
    EXPECT_LT((seq.groundTruth(1000.0 + k / 400.0).bias.acc - b.acc).norm(), 1e-9);
    EXPECT_LT((seq.groundTruth(1000.0 + k / 400.0).bias.gyr - b.gyr).norm(), 1e-9);
  }
  EXPECT_EQ(seq.bodyTrajectory().size(), seq.imuCount());
}

TEST(ImuErrorModel, OptionsLoadAndRangeErrorsNameTheKey) {
  IniReader ini = iniOf(
      "imu_acc_scale_max = 0.01\nimu_gyr_scale_max = 0.02\nimu_acc_misalignment_max_rad = 0.003\n"
      "imu_gyr_misalignment_max_rad = 0.004\nimu_gyr_g_sensitivity_max = 2e-4\n"
      "imu_acc_bias_instability = 0.005\nimu_gyr_bias_instability = 1e-4\n"
      "imu_bias_instability_tau_s = 50\nimu_acc_lsb = 0.0191\nimu_gyr_lsb = 0.001\n"
      "imu_accel_rate_hz = 63\nimu_gyro_rate_hz = 200\n");
  const ImuSynthOptions o = ImuSynthOptions::load(ini);
  EXPECT_EQ(o.errors.acc_scale_max, 0.01);
  EXPECT_EQ(o.errors.gyr_scale_max, 0.02);
  EXPECT_EQ(o.errors.acc_misalignment_max_rad, 0.003);
  EXPECT_EQ(o.errors.gyr_misalignment_max_rad, 0.004);
  EXPECT_EQ(o.errors.gyr_g_sensitivity_max, 2e-4);
  EXPECT_EQ(o.errors.acc_bias_instability, 0.005);
  EXPECT_EQ(o.errors.gyr_bias_instability, 1e-4);
  EXPECT_EQ(o.errors.bias_instability_tau_s, 50.0);
  EXPECT_EQ(o.errors.acc_lsb, 0.0191);
  EXPECT_EQ(o.errors.gyr_lsb, 0.001);
  EXPECT_EQ(o.accel_rate_hz, 63.0);
  EXPECT_EQ(o.gyro_rate_hz, 200.0);
  EXPECT_FALSE(ImuErrorOptions().any());
  for (const std::string bad :
       {"imu_acc_scale_max = -0.1", "imu_gyr_misalignment_max_rad = 0.5",
        "imu_bias_instability_tau_s = 0", "imu_acc_lsb = -1", "imu_gyro_rate_hz = 200",
        "imu_accel_rate_hz = 5\nimu_gyro_rate_hz = 200"}) {
    IniReader b = iniOf(bad + "\n");
    const std::string key = bad.rfind("imu_accel_rate_hz = 5", 0) == 0
                                ? "imu_accel_rate_hz"
                                : bad.substr(0, bad.find(' '));
    try {
      ImuSynthOptions::load(b);
      ADD_FAILURE() << bad;
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace rgbdi::sim
