// Motion building blocks and profiles: Taylor arithmetic against closed-form derivatives,
// smooth steps, ground paths, analytic derivatives against finite differences, and each
// profile's length / speed / duration / geometry as the issue specifies.
#include <gtest/gtest.h>

#include <cmath>

#include "rgbdi/common/sensor_options.h"
#include "rgbdi/common/so3.h"
#include "rgbdi/sim/motion_ground_path.h"
#include "rgbdi/sim/motion_smooth_steps.h"
#include "rgbdi/sim/motion_taylor.h"
#include "rgbdi/sim/profiles.h"

namespace rgbdi::sim {
namespace {

TEST(Taylor, ElementaryFunctionsMatchClosedFormDerivatives) {
  const double t0 = 0.7;
  const Taylor<3> t = Taylor<3>::variable(t0);
  const Taylor<3> s = sin(t), c = cos(t);
  EXPECT_NEAR(s.derivative(1), std::cos(t0), 1e-15);
  EXPECT_NEAR(s.derivative(2), -std::sin(t0), 1e-15);
  EXPECT_NEAR(s.derivative(3), -std::cos(t0), 1e-15);
  EXPECT_NEAR(c.derivative(3), std::sin(t0), 1e-15);

  const Taylor<3> a = atan(t);
  const double d = 1.0 + t0 * t0;
  EXPECT_NEAR(a.value(), std::atan(t0), 1e-15);
  EXPECT_NEAR(a.derivative(1), 1.0 / d, 1e-15);
  EXPECT_NEAR(a.derivative(2), -2.0 * t0 / (d * d), 1e-15);
  EXPECT_NEAR(a.derivative(3), (6.0 * t0 * t0 - 2.0) / (d * d * d), 1e-14);

  const Taylor<3> r = sqrt(t);
  EXPECT_NEAR(r.derivative(1), 0.5 * std::pow(t0, -0.5), 1e-15);
  EXPECT_NEAR(r.derivative(2), -0.25 * std::pow(t0, -1.5), 1e-15);
  EXPECT_NEAR(r.derivative(3), 0.375 * std::pow(t0, -2.5), 1e-14);

  const Taylor<3> inv = Taylor<3>(1.0) / t;
  EXPECT_NEAR(inv.derivative(1), -1.0 / (t0 * t0), 1e-14);
  EXPECT_NEAR(inv.derivative(2), 2.0 / std::pow(t0, 3), 1e-13);
  EXPECT_NEAR(inv.derivative(3), -6.0 / std::pow(t0, 4), 1e-12);

  // Chain and product rule: f = sin(t^2) * t; f' = 2 t^2 cos(t^2) + sin(t^2).
  const Taylor<3> f = sin(t * t) * t;
  EXPECT_NEAR(f.derivative(1), 2 * t0 * t0 * std::cos(t0 * t0) + std::sin(t0 * t0), 1e-14);
  // Differentiation / integration shift the coefficients.
  EXPECT_NEAR(f.differentiated().derivative(2), f.derivative(3), 1e-13);
  EXPECT_NEAR(f.differentiated().integrated(f.value()).derivative(3), f.derivative(3), 1e-13);
}

TEST(SmoothSteps, ValuesIntegralAndContinuity) {
  SmoothSteps f(0.5);
  f.addStep(1.0, 2.0, 3.0);  // 0.5 -> 3.5 over [1, 3]
  EXPECT_DOUBLE_EQ(f.value(0.0), 0.5);
  EXPECT_DOUBLE_EQ(f.value(2.0), 0.5 + 1.5);  // symmetric step: half-way at the middle
  EXPECT_DOUBLE_EQ(f.value(5.0), 3.5);
  // Integral: base * x + delta * (x - start - width / 2) after the step.
  EXPECT_NEAR(f.integral(5.0), 0.5 * 5.0 + 3.0 * (5.0 - 1.0 - 1.0), 1e-12);
  EXPECT_NEAR(f.integral(0.8), 0.4, 1e-15);
  // The integral's derivative is the value, and the value is C3 at the breakpoints.
  for (double x : {1.0, 1.3, 2.0, 2.9, 3.0}) {
    const Taylor<3> F = f.integral(Taylor<3>::variable(x));
    EXPECT_NEAR(F.derivative(1), f.value(x), 1e-12) << x;
    for (int k = 1; k <= 3; ++k) {
      const double left = f.value(Taylor<3>::variable(x - 1e-9)).derivative(k);
      const double right = f.value(Taylor<3>::variable(x + 1e-9)).derivative(k);
      EXPECT_NEAR(left, right, 1e-5 * (1 + std::abs(left))) << "x " << x << " order " << k;
    }
  }
  EXPECT_THROW(f.addStep(0.0, 0.0, 1.0), std::invalid_argument);
}

TEST(GroundPath, ConstantCurvatureIsAnExactCircle) {
  const double r = 2.0;
  const GroundPath path(SmoothSteps(1.0 / r), SmoothSteps(), Eigen::Vector2d(r, 0.0), 0.0,
                        0.5 * M_PI, 40.0);
  for (double s : {0.0, 0.37, 3.0, 12.566, 25.1, 39.9}) {
    const Eigen::Vector2d expect(r * std::cos(s / r), r * std::sin(s / r));
    EXPECT_LT((path.xy(s) - expect).norm(), 1e-12) << s;
  }
  // Time expansion for s(t) = 0.4 t: speed 0.4 m/s, centripetal acceleration v^2 / r.
  Taylor<3> s = 0.4 * Taylor<3>::variable(5.0);
  const GroundPoint g = path.at(s);
  const Eigen::Vector2d v(g.position[0].derivative(1), g.position[1].derivative(1));
  const Eigen::Vector2d a(g.position[0].derivative(2), g.position[1].derivative(2));
  const Eigen::Vector2d p(g.position[0].value(), g.position[1].value());
  EXPECT_NEAR(v.norm(), 0.4, 1e-14);
  EXPECT_NEAR(a.norm(), 0.16 / r, 1e-14);
  EXPECT_NEAR(a.normalized().dot(-p.normalized()), 1.0, 1e-12);  // towards the centre
}

TEST(GroundPath, HeightFollowsTheSlopeProfile) {
  SmoothSteps slope;
  slope.addStep(0.9, 0.2, 0.1);   // up at 1 m
  slope.addStep(1.9, 0.2, -0.2);  // crest at 2 m
  slope.addStep(2.9, 0.2, 0.1);   // back to flat at 3 m
  const GroundPath path(SmoothSteps(), slope, Eigen::Vector2d::Zero(), 0.0, 0.0, 5.0);
  EXPECT_NEAR(path.height(0.5), 0.0, 1e-15);
  EXPECT_NEAR(path.height(1.5), 0.05, 1e-12);
  EXPECT_NEAR(path.height(4.0), 0.0, 1e-12);
  EXPECT_NEAR(path.xy(4.0).x(), 4.0, 1e-12);
}

// ---------------------------------------------------------------- profiles
MotionProfile profile(ProfileKind kind, SpeedPreset speed = SpeedPreset::Normal) {
  ProfileOptions o;
  o.kind = kind;
  o.speed = speed;
  return makeMotionProfile(o, ExtrinsicOptions().T_body_cam);
}

/// 3-D distance travelled by the body, by fine sampling.
double travelled(const BodyTrajectory& traj) {
  double d = 0.0;
  Eigen::Vector3d prev = traj.pose(0.0).translation();
  for (double t = 0.01; t <= traj.duration(); t += 0.01) {
    const Eigen::Vector3d p = traj.pose(t).translation();
    d += (p - prev).norm();
    prev = p;
  }
  return d;
}

TEST(Profiles, WheeledCircleIsThreeLapsOfRadiusTwoAtPointFourMetresPerSecond) {
  // Without wheel vibration the geometry is exact.
  ProfileOptions o;
  o.kind = ProfileKind::WheeledCircle;
  o.wheeled_vibration_acc_rms = 0.0;
  o.wheeled_vibration_gyr_rms = 0.0;
  const Eigen::Isometry3d T_body_cam = ExtrinsicOptions().T_body_cam;
  const MotionProfile exact = makeMotionProfile(o, T_body_cam);
  EXPECT_NEAR(exact.cruise_speed_m_s, 0.4, 1e-12);
  EXPECT_NEAR(exact.path_length_m, 3 * 2 * M_PI * 2.0, 1e-9);
  for (double t = exact.cruise_start_s; t < exact.cruise_end_s; t += 0.37) {
    const KinematicState s = exact.trajectory->state(t);
    const Eigen::Vector3d pos = s.T_world_body.translation();
    EXPECT_NEAR(pos.head<2>().norm(), 2.0, 1e-12) << t;
    EXPECT_NEAR(s.v_world.norm(), 0.4, 1e-12) << t;
    EXPECT_NEAR((s.T_world_body * T_body_cam).translation().z(), 0.3, 1e-12) << t;
    // Constant centripetal acceleration v^2 / r (the scale-unobservable case of the paper).
    EXPECT_NEAR(s.a_world.norm(), 0.08, 1e-12) << t;
    EXPECT_NEAR(s.a_world.head<2>().dot(-pos.head<2>().normalized()), 0.08, 1e-12) << t;
    EXPECT_NEAR(s.omega_body.z(), 0.2, 1e-12) << t;
  }
  // Laps: the heading turns by 3 * 360 degrees.
  double turned = 0.0;
  for (double t = 0.0; t < exact.trajectory->duration(); t += 0.01)
    turned += exact.trajectory->state(t).omega_body.z() * 0.01;
  EXPECT_NEAR(turned, 3 * 2 * M_PI, 0.01);

  // The default adds wheel vibration: sub-millimetre displacement, same path.
  const MotionProfile p = profile(ProfileKind::WheeledCircle);
  for (double t = p.cruise_start_s; t < p.cruise_end_s; t += 0.37) {
    const KinematicState s = p.trajectory->state(t);
    EXPECT_NEAR(s.T_world_body.translation().head<2>().norm(), 2.0, 5e-4) << t;
    EXPECT_NEAR(s.v_world.norm(), 0.4, 5e-3) << t;
  }
  EXPECT_NEAR(travelled(*p.trajectory), p.path_length_m, 0.01 * p.path_length_m);
}

TEST(Profiles, EveryProfileStartsAtRestForTwoSecondsThenMovesAndEndsAtRest) {
  for (const std::string& name : profileNames()) {
    const MotionProfile p = profile(parseProfileKind(name));
    const BodyTrajectory& traj = *p.trajectory;
    EXPECT_DOUBLE_EQ(p.moving_start_s, 2.0) << name;
    const Eigen::Isometry3d T0 = traj.pose(0.0);
    for (double t = 0.0; t <= 2.0; t += 0.05) {
      const KinematicState s = traj.state(t);
      EXPECT_LT(s.v_world.norm(), 1e-12) << name << " t " << t;
      EXPECT_LT(s.omega_body.norm(), 1e-12) << name << " t " << t;
      EXPECT_LT((s.T_world_body.translation() - T0.translation()).norm(), 1e-12) << name;
    }
    EXPECT_GT(traj.state(p.cruise_start_s + 1.0).v_world.norm(), 0.1) << name;
    const KinematicState end = traj.state(traj.duration());
    EXPECT_LT(end.v_world.norm(), 1e-12) << name;
  }
}

TEST(Profiles, WheeledSlopesSpeedsMatchThePaperRuns) {
  struct Run {
    SpeedPreset speed;
    double length, duration;
  };
  for (const Run& run : {Run{SpeedPreset::Slow, 31.0, 148.0}, Run{SpeedPreset::Normal, 32.0, 74.0},
                         Run{SpeedPreset::Fast, 48.0, 99.0}}) {
    const MotionProfile p = profile(ProfileKind::WheeledSlopes, run.speed);
    EXPECT_DOUBLE_EQ(p.trajectory->duration(), run.duration);
    EXPECT_NEAR(p.path_length_m, run.length, 1e-9);
    // The 3-D length includes climbing the ramps (a few millimetres per ramp).
    EXPECT_NEAR(travelled(*p.trajectory), run.length, 0.01 * run.length);
    EXPECT_EQ(p.layout.ramps.size(), 2u);
    double top = 0.0;
    for (double t = 0.0; t < p.trajectory->duration(); t += 0.05)
      top = std::max(top, p.trajectory->pose(t).translation().z());
    // Camera at 0.3 m, so the body rises to about 0.3 + ramp height 0.12 at the crest.
    EXPECT_GT(top, 0.3 + 0.09);
    EXPECT_LT(top, 0.3 + 0.121);
  }
  // Fast has high-speed phases, normal does not.
  const MotionProfile fast = profile(ProfileKind::WheeledSlopes, SpeedPreset::Fast);
  double vmax = 0.0;
  for (double t = 0.0; t < fast.trajectory->duration(); t += 0.1)
    vmax = std::max(vmax, fast.trajectory->state(t).v_world.norm());
  EXPECT_GT(vmax, 1.5 * fast.cruise_speed_m_s);
}

TEST(Profiles, TrackedSlopesIsAbout65SecondsAtPointThreeWithAnEightCentimetreDrop) {
  const MotionProfile p = profile(ProfileKind::TrackedSlopes);
  EXPECT_DOUBLE_EQ(p.trajectory->duration(), 65.0);
  EXPECT_NEAR(p.cruise_speed_m_s, 0.3, 1e-12);
  ASSERT_EQ(p.layout.platforms.size(), 1u);
  EXPECT_DOUBLE_EQ(p.layout.platforms[0].height, 0.08);
  // The body falls by the platform height within about a second somewhere on the run, and
  // pitches nose-down while doing so.
  double largest_fall = 0.0, max_nose_down = 0.0;
  for (double t = 0.0; t + 1.0 < p.trajectory->duration(); t += 0.02) {
    const double z0 = p.trajectory->pose(t).translation().z();
    const double z1 = p.trajectory->pose(t + 1.0).translation().z();
    largest_fall = std::max(largest_fall, z0 - z1);
    const Eigen::Vector3d x_axis = p.trajectory->pose(t).linear().col(0);
    max_nose_down = std::max(max_nose_down, -x_axis.z());
  }
  EXPECT_GT(largest_fall, 0.075);
  EXPECT_GT(max_nose_down, std::sin(15.0 * M_PI / 180.0));
}

/// The tracked robot's jitter is real motion: it shows in the ground-truth attitude (roll is
/// not changed by the ramps, so it is the jitter alone), the wheeled robot has none.
TEST(Profiles, TrackedJitterIsInTheGroundTruthAttitude) {
  for (ProfileKind kind : {ProfileKind::TrackedSlopes, ProfileKind::WheeledSlopes}) {
    const MotionProfile p = profile(kind);
    double sum = 0.0;
    int n = 0;
    for (double t = p.cruise_start_s; t < p.cruise_end_s; t += 0.01, ++n) {
      const Eigen::Matrix3d R = p.trajectory->pose(t).linear();
      const double roll = std::atan2(R(2, 1), R(2, 2));
      sum += roll * roll;
    }
    const double rms_deg = std::sqrt(sum / n) * 180.0 / M_PI;
    if (kind == ProfileKind::TrackedSlopes)
      EXPECT_NEAR(rms_deg, 0.5, 0.1);
    else
      EXPECT_LT(rms_deg, 0.05);
  }
}

TEST(Profiles, HandheldHasRichRotationAndWalkingSpeed) {
  const MotionProfile p = profile(ProfileKind::Handheld);
  EXPECT_DOUBLE_EQ(p.trajectory->duration(), 40.0);
  Eigen::Vector3d wmax = Eigen::Vector3d::Zero();
  for (double t = p.cruise_start_s; t < p.cruise_end_s; t += 0.05)
    wmax = wmax.cwiseMax(p.trajectory->state(t).omega_body.cwiseAbs());
  // All three axes rotate noticeably (6-DOF motion, not planar).
  EXPECT_GT(wmax.minCoeff(), 0.2);
  EXPECT_NEAR(p.cruise_speed_m_s, 0.7, 1e-12);
}

TEST(Profiles, DurationAndSpeedAreConfigurable) {
  ProfileOptions o;
  o.kind = ProfileKind::WheeledCircle;
  o.duration_s = 30.0;
  o.speed_m_s = 0.5;
  const MotionProfile p = makeMotionProfile(o, ExtrinsicOptions().T_body_cam);
  EXPECT_DOUBLE_EQ(p.trajectory->duration(), 30.0);
  EXPECT_DOUBLE_EQ(p.cruise_speed_m_s, 0.5);
  // Moving 30 - 2 - 1 s, 2.5 s each accelerating and braking at half speed on average.
  EXPECT_NEAR(p.path_length_m, 0.5 * (27.0 - 2.5), 1e-9);
  o.duration_s = 5.0;
  EXPECT_THROW(makeMotionProfile(o, ExtrinsicOptions().T_body_cam), std::invalid_argument);
  EXPECT_THROW(parseProfileKind("flying"), std::invalid_argument);
}

/// Analytic velocity, acceleration and angular rate against 4th-order central differences of
/// the pose.
TEST(Profiles, AnalyticDerivativesMatchFiniteDifferences) {
  for (const std::string& name : profileNames()) {
    const MotionProfile p = profile(parseProfileKind(name));
    const BodyTrajectory& traj = *p.trajectory;
    const double h = 2e-4;
    for (double t : {1.0, 3.1, 7.77, 15.2, 33.3}) {
      const KinematicState s = traj.state(t);
      Eigen::Vector3d pm2 = traj.pose(t - 2 * h).translation(),
                      pm1 = traj.pose(t - h).translation();
      Eigen::Vector3d pp1 = traj.pose(t + h).translation(),
                      pp2 = traj.pose(t + 2 * h).translation();
      const Eigen::Vector3d p0 = traj.pose(t).translation();
      const Eigen::Vector3d v_num = (pm2 - 8 * pm1 + 8 * pp1 - pp2) / (12 * h);
      const Eigen::Vector3d a_num = (-pm2 + 16 * pm1 - 30 * p0 + 16 * pp1 - pp2) / (12 * h * h);
      EXPECT_LT((v_num - s.v_world).norm(), 1e-7) << name << " t " << t;
      EXPECT_LT((a_num - s.a_world).norm(), 2e-3) << name << " t " << t;
      // Body rate: log(R(t)^T R(t +- h)) / h, 4th-order combination.
      const Eigen::Matrix3d R0 = s.T_world_body.linear();
      auto rel = [&](double dt) { return logSO3(R0.transpose() * traj.pose(t + dt).linear()); };
      const Eigen::Vector3d w_num =
          (rel(-2 * h) - 8 * rel(-h) + 8 * rel(h) - rel(2 * h)) / (12 * h);
      EXPECT_LT((w_num - s.omega_body).norm(), 1e-6) << name << " t " << t;
      // omega_dot against differences of omega.
      const Eigen::Vector3d wd_num =
          (traj.state(t + h).omega_body - traj.state(t - h).omega_body) / (2 * h);
      EXPECT_LT((wd_num - s.omega_dot_body).norm(), 1e-3 * (1.0 + s.omega_dot_body.norm()))
          << name << " t " << t;
    }
  }
}

}  // namespace
}  // namespace rgbdi::sim
