// Monocular SfM initialisation and visual-inertial scale alignment on the analytic world: known
// answers with exact data, accuracy bounds with noise and outliers, and rejection of degenerate
// windows.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>

#include "rgbdi/common/sensor_options.h"
#include "rgbdi/common/so3.h"
#include "rgbdi/estimator/scale_alignment.h"
#include "rgbdi/estimator/visual_sfm.h"
#include "rgbdi/imu/preintegration.h"
#include "synthetic_world.h"

using namespace rgbdi;
using namespace rgbdi::estimator;
using Frames = std::vector<std::vector<frontend::FeatureObservation>>;

namespace {

constexpr double kFocal = 600.0;  // the synthetic 640x480 camera

/// Landmarks seen by camera T_w_c, with optional pixel noise and a fraction of gross outliers
/// (displaced by 15-45 px in a random direction).
std::vector<frontend::FeatureObservation> observe(const Eigen::Isometry3d& T_w_c,
                                                  const std::vector<Eigen::Vector3d>& landmarks,
                                                  std::mt19937_64& rng, double pixel_sigma,
                                                  double outlier_fraction) {
  std::normal_distribution<double> n(0.0, 1.0);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<frontend::FeatureObservation> out;
  const Eigen::Isometry3d T_c_w = T_w_c.inverse();
  for (std::size_t i = 0; i < landmarks.size(); ++i) {
    const Eigen::Vector3d p = T_c_w * landmarks[i];
    if (p.z() < 0.3 || p.z() > 8.0) continue;
    Eigen::Vector2d xn = p.head<2>() / p.z();
    const Eigen::Vector2d uv = kFocal * xn + Eigen::Vector2d(320, 240);
    if (uv.x() < 0 || uv.x() > 639 || uv.y() < 0 || uv.y() > 479) continue;
    xn += Eigen::Vector2d(n(rng), n(rng)) * (pixel_sigma / kFocal);
    if (u(rng) < outlier_fraction) {
      const double a = 2 * M_PI * u(rng), r = 15.0 + 30.0 * u(rng);
      xn += Eigen::Vector2d(std::cos(a), std::sin(a)) * (r / kFocal);
    }
    frontend::FeatureObservation o;
    o.id = i;
    o.xn = xn;
    out.push_back(o);
  }
  return out;
}

/// The analytic world at a brisk pace: 1.6 m/s on the 2 m circle once up to speed, so one second
/// of frames gives ample parallax.
test::SyntheticWorld makeWorld() {
  test::SyntheticWorld w;
  w.omega = 0.8;
  w.T_bc = ExtrinsicOptions().T_body_cam;
  w.makeLandmarks(5, 1500);
  return w;
}

struct Window {
  std::vector<double> t;
  std::vector<Eigen::Isometry3d> T_w_c;
  Frames frames;
  /// True T_c0_ck and the factor that makes |t_c0_cnewest| = 1.
  Eigen::Isometry3d T_c0(std::size_t k) const { return T_w_c[0].inverse() * T_w_c[k]; }
  double unitScale() const { return 1.0 / T_c0(T_w_c.size() - 1).translation().norm(); }
};

Window makeWindow(const test::SyntheticWorld& w, double t0, int n, double dt, double pixel_sigma,
                  double outlier_fraction, std::uint64_t seed = 3) {
  std::mt19937_64 rng(seed);
  Window win;
  for (int k = 0; k < n; ++k) {
    win.t.push_back(t0 + k * dt);
    win.T_w_c.push_back(w.pose(win.t.back()) * w.T_bc);
    win.frames.push_back(
        observe(win.T_w_c.back(), w.landmarks, rng, pixel_sigma, outlier_fraction));
  }
  return win;
}

double angleBetween(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

/// Pre-integrations between consecutive frame times (preint[0] is null, as the API allows).
struct ImuWindow {
  std::vector<std::unique_ptr<imu::Preintegration>> owned;
  std::vector<imu::Preintegration*> ptrs;
};

/// sample(t) gives the IMU reading at t; 200 Hz, both interval ends included.
template <typename SampleFn>
ImuWindow integrate(const std::vector<double>& t, const SampleFn& sample) {
  const imu::ImuNoise noise = imu::ImuNoise::fromOptions(ImuOptions());
  ImuWindow out;
  out.ptrs.push_back(nullptr);
  for (std::size_t k = 1; k < t.size(); ++k) {
    out.owned.push_back(std::make_unique<imu::Preintegration>(Eigen::Vector3d::Zero(),
                                                              Eigen::Vector3d::Zero(), noise));
    const int steps = static_cast<int>(std::lround((t[k] - t[k - 1]) * 200.0));
    for (int i = 0; i <= steps; ++i)
      out.owned.back()->push(sample(t[k - 1] + (t[k] - t[k - 1]) * i / steps));
    out.ptrs.push_back(out.owned.back().get());
  }
  return out;
}

const Eigen::Vector3d kGyroBias(0.012, -0.02, 0.008);  // [rad/s]

/// Exact IMU of the world plus the gyro bias kGyroBias.
ImuWindow worldImu(const test::SyntheticWorld& w, const std::vector<double>& t) {
  return integrate(t, [&](double s) {
    ImuSample m = w.imu(s);
    m.gyr += kGyroBias;
    return m;
  });
}

}  // namespace

TEST(VisualSfm, ExactObservationsGiveExactPosesAndPoints) {
  const test::SyntheticWorld w = makeWorld();
  const Window win = makeWindow(w, 3.0, 10, 0.1, 0.0, 0.0);
  const auto res = solveVisualSfm(win.frames, SfmOptions());
  ASSERT_TRUE(res.has_value());
  EXPECT_EQ(res->base_frame, 0);
  ASSERT_EQ(res->T_c0_c.size(), win.frames.size());
  EXPECT_LT(res->reprojection_rms_norm, 1e-9);
  EXPECT_EQ(res->n_outlier_observations, 0);
  const double s = win.unitScale();
  for (std::size_t k = 0; k < win.frames.size(); ++k) {
    const Eigen::Isometry3d T = win.T_c0(k);
    EXPECT_LT(logSO3(T.rotation().transpose() * res->T_c0_c[k].rotation()).norm(), 1e-6) << k;
    // Translations are in units of the newest baseline, so this is a relative error.
    EXPECT_LT((res->T_c0_c[k].translation() - s * T.translation()).norm(), 1e-6) << k;
  }
  ASSERT_GT(res->n_points, 100);
  EXPECT_EQ(res->n_points, static_cast<int>(res->points_c0.size()));
  const Eigen::Isometry3d T_c0_w = win.T_w_c[0].inverse();
  for (const auto& [id, p] : res->points_c0) {
    const Eigen::Vector3d p_true = s * (T_c0_w * w.landmarks[id]);
    EXPECT_LT((p - p_true).norm(), 1e-6 * p_true.norm()) << id;
  }
}

TEST(VisualSfm, NoiseAndOutliersStayAccurateAndDeterministic) {
  const test::SyntheticWorld w = makeWorld();
  const Window win = makeWindow(w, 3.0, 10, 0.1, 0.5, 0.1);
  const auto res = solveVisualSfm(win.frames, SfmOptions());
  ASSERT_TRUE(res.has_value());
  EXPECT_GT(res->n_outlier_observations, 0);
  EXPECT_LT(res->reprojection_rms_norm, 1.0 / kFocal);  // 0.5 px noise: RMS of norm ~0.7 px
  for (std::size_t k = 1; k < win.frames.size(); ++k) {
    const Eigen::Isometry3d T = win.T_c0(k);
    EXPECT_LT(logSO3(T.rotation().transpose() * res->T_c0_c[k].rotation()).norm(), 0.5 * M_PI / 180)
        << k;
    EXPECT_LT(angleBetween(T.translation(), res->T_c0_c[k].translation()), 2.0 * M_PI / 180) << k;
  }
  const auto again = solveVisualSfm(win.frames, SfmOptions());
  ASSERT_TRUE(again.has_value());
  for (std::size_t k = 0; k < win.frames.size(); ++k)
    EXPECT_TRUE(again->T_c0_c[k].matrix() == res->T_c0_c[k].matrix()) << k;
  ASSERT_EQ(again->points_c0.size(), res->points_c0.size());
  for (const auto& [id, p] : res->points_c0) EXPECT_TRUE(again->points_c0.at(id) == p) << id;
  EXPECT_EQ(again->reprojection_rms_norm, res->reprojection_rms_norm);
}

TEST(VisualSfm, RejectsPureRotationNoMotionAndTooLittleData) {
  const test::SyntheticWorld w = makeWorld();
  std::mt19937_64 rng(7);
  // Pure rotation from the centre of the landmark cylinder: the raw feature motion is large
  // (0.36 rad of yaw), yet nothing can be triangulated.
  Frames rotation, still;
  for (int k = 0; k < 10; ++k) {
    Eigen::Isometry3d T_w_b = Eigen::Isometry3d::Identity();
    T_w_b.linear() = expSO3(Eigen::Vector3d(0.01, -0.02, 0.04 * k));
    T_w_b.translation() << 0.0, 0.0, 0.7;
    rotation.push_back(observe(T_w_b * w.T_bc, w.landmarks, rng, 0.5, 0.0));
    T_w_b.linear().setIdentity();
    still.push_back(observe(T_w_b * w.T_bc, w.landmarks, rng, 0.0, 0.0));
  }
  ASSERT_GT(rotation.back().size(), 100u);
  EXPECT_FALSE(solveVisualSfm(rotation, SfmOptions()).has_value());
  EXPECT_FALSE(solveVisualSfm(still, SfmOptions()).has_value());

  const Window win = makeWindow(w, 3.0, 10, 0.1, 0.0, 0.0);
  ASSERT_TRUE(solveVisualSfm(win.frames, SfmOptions()).has_value());
  EXPECT_FALSE(
      solveVisualSfm(Frames(win.frames.begin(), win.frames.begin() + 2), SfmOptions()).has_value());
  // The newest frame shares only 15 features with the others: no base pair.
  Frames few = win.frames;
  few.back().resize(15);
  EXPECT_FALSE(solveVisualSfm(few, SfmOptions()).has_value());
  // A middle frame with only 15 features cannot be registered by PnP.
  few = win.frames;
  few[4].resize(15);
  EXPECT_FALSE(solveVisualSfm(few, SfmOptions()).has_value());
}

TEST(ScaleAlignment, ExactImuRecoversScaleGravityVelocitiesAndGyroBias) {
  const test::SyntheticWorld w = makeWorld();
  std::vector<double> t;
  std::vector<Eigen::Isometry3d> T_c0_c;
  const double sfm_scale = 0.37;  // SfM units per metre
  const Eigen::Isometry3d T_c0_w = (w.pose(3.0) * w.T_bc).inverse();
  for (int k = 0; k < 10; ++k) {
    t.push_back(3.0 + 0.1 * k);
    Eigen::Isometry3d T = T_c0_w * w.pose(t.back()) * w.T_bc;
    T.translation() *= sfm_scale;
    T_c0_c.push_back(T);
  }
  ImuWindow imu_win = worldImu(w, t);
  const auto res = alignWithScale(T_c0_c, w.T_bc, imu_win.ptrs, w.gravity);
  ASSERT_TRUE(res.has_value());
  EXPECT_NEAR(res->scale * sfm_scale, 1.0, 1e-4);
  EXPECT_NEAR(res->g_ref.norm(), w.gravity, 1e-9);
  EXPECT_LT(angleBetween(res->g_ref, T_c0_w.rotation() * Eigen::Vector3d(0, 0, -w.gravity)), 1e-3);
  ASSERT_EQ(res->v_ref.size(), t.size());
  for (std::size_t k = 0; k < t.size(); ++k)
    EXPECT_LT((res->v_ref[k] - T_c0_w.rotation() * w.velocity(t[k])).norm(), 1e-3) << k;
  EXPECT_LT((res->bg_correction - kGyroBias).norm(), 1e-4);
  for (std::size_t k = 1; k < t.size(); ++k)
    EXPECT_TRUE(imu_win.ptrs[k]->biasGyr() == res->bg_correction) << k;
  // Exact data: only the IMU noise model is left in the predicted scale uncertainty.
  EXPECT_GT(res->scale_rel_sigma, 0.0);
  EXPECT_LT(res->scale_rel_sigma, 0.05);
  EXPECT_EQ(res->camera_position_sigma_m, 0.0);
}

TEST(ScaleAlignment, RejectsTooFewFramesAndUnobservableScale) {
  const test::SyntheticWorld w = makeWorld();
  const Eigen::Isometry3d T_bc = w.T_bc;
  std::vector<double> t;
  for (int k = 0; k < 10; ++k) t.push_back(0.1 * k);
  const Eigen::Matrix3d R_w_b = expSO3(Eigen::Vector3d(0.1, -0.05, 0.7));
  auto imuAt = [&](double s) {
    ImuSample m;
    m.t = s;
    m.acc = R_w_b.transpose() * Eigen::Vector3d(0, 0, w.gravity);  // no acceleration at all
    m.gyr = kGyroBias;
    return m;
  };
  // Static: SfM on an (almost) still camera returns translations made of noise, normalised so
  // that the newest is 1; the IMU says nothing moved, so the scale is zero / unobservable.
  std::mt19937_64 rng(5);
  std::normal_distribution<double> n(0.0, 1.0);
  std::vector<Eigen::Isometry3d> T_static;
  for (std::size_t k = 0; k < t.size(); ++k) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    if (k > 0) T.translation() << n(rng), n(rng), n(rng);
    T_static.push_back(T);
  }
  for (auto& T : T_static) T.translation() /= T_static.back().translation().norm();
  {
    ImuWindow imu_win = integrate(t, imuAt);
    EXPECT_FALSE(alignWithScale(T_static, T_bc, imu_win.ptrs, w.gravity).has_value());
  }
  // Constant velocity: any scale is explained by a matching velocity (rank-deficient system).
  std::vector<Eigen::Isometry3d> T_const;
  for (double s : t) {
    Eigen::Isometry3d T_w_b = Eigen::Isometry3d::Identity();
    T_w_b.linear() = R_w_b;
    T_w_b.translation() = Eigen::Vector3d(0.4, -0.3, 0.1) * s;
    T_const.push_back(T_w_b * T_bc);
  }
  const Eigen::Isometry3d T_c0_w = T_const.front().inverse();
  for (auto& T : T_const) T = T_c0_w * T;
  {
    ImuWindow imu_win = integrate(t, imuAt);
    EXPECT_FALSE(alignWithScale(T_const, T_bc, imu_win.ptrs, w.gravity).has_value());
  }
  // Too few frames: three give 12 equations for 13 unknowns even with exact, moving data; four
  // are enough. Mismatched sizes are rejected.
  {
    std::vector<double> tm;
    std::vector<Eigen::Isometry3d> T_moving;
    const Eigen::Isometry3d T_m0_w = (w.pose(3.0) * T_bc).inverse();
    for (int k = 0; k < 4; ++k) {
      tm.push_back(3.0 + 0.1 * k);
      T_moving.push_back(T_m0_w * w.pose(tm.back()) * T_bc);
    }
    ImuWindow imu4 = worldImu(w, tm);
    const auto four = alignWithScale(T_moving, T_bc, imu4.ptrs, w.gravity);
    ASSERT_TRUE(four.has_value());
    EXPECT_NEAR(four->scale, 1.0, 1e-3);
    T_moving.pop_back();
    imu4.ptrs.pop_back();
    EXPECT_FALSE(alignWithScale(T_moving, T_bc, imu4.ptrs, w.gravity).has_value());
    imu4.ptrs.pop_back();
    EXPECT_FALSE(alignWithScale(T_moving, T_bc, imu4.ptrs, w.gravity).has_value());
  }
}

TEST(VisualSfmAndScaleAlignment, NoisyImagesGiveMetricScaleAndGravity) {
  const test::SyntheticWorld w = makeWorld();
  // 1.35 s during the speed-up: the acceleration changes in direction and size. A nearly
  // constant acceleration (steady circling) is hard to tell from a gravity tilt, which leaves the
  // scale poorly observable once the SfM poses carry noise.
  const Window win = makeWindow(w, 1.5, 10, 0.15, 0.5, 0.1);
  const auto sfm = solveVisualSfm(win.frames, SfmOptions());
  ASSERT_TRUE(sfm.has_value());
  ImuWindow imu_win = worldImu(w, win.t);
  const auto res = alignWithScale(sfm->T_c0_c, w.T_bc, imu_win.ptrs, w.gravity);
  ASSERT_TRUE(res.has_value());
  EXPECT_NEAR(res->scale * win.unitScale(), 1.0, 0.05);
  EXPECT_LT(res->scale_rel_sigma, 0.05);
  EXPECT_GT(res->camera_position_sigma_m, 0.0);  // the SfM noise was noticed
  const Eigen::Vector3d g_true = win.T_w_c[0].rotation().transpose() * Eigen::Vector3d(0, 0, -1);
  EXPECT_LT(angleBetween(res->g_ref, g_true), 2.0 * M_PI / 180);
}
