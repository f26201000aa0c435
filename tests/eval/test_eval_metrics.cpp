// Known-answer tests of association, alignment, ATE statistics, RPE and coverage on synthetic
// trajectories whose correct results follow from their construction.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "rgbdi/common/so3.h"
#include "rgbdi/eval/association.h"
#include "rgbdi/eval/coverage.h"
#include "rgbdi/eval/eval_error.h"
#include "rgbdi/eval/evaluate.h"
#include "rgbdi/eval/rpe.h"

namespace rgbdi::eval {
namespace {

StampedPose pose(double t, const Eigen::Vector3d& p = Eigen::Vector3d::Zero(),
                 const Eigen::Quaterniond& q = Eigen::Quaterniond::Identity()) {
  StampedPose s;
  s.t = t;
  s.p = p;
  s.q = q;
  return s;
}

Trajectory stamps(const std::vector<double>& ts) {
  Trajectory t;
  for (double x : ts) t.push_back(pose(x));
  return t;
}

// n + 1 poses at t = k * period, k = 0..n, on a smooth 3-D curve with varying orientation.
Trajectory curve(int n, double period) {
  Trajectory t;
  for (int k = 0; k <= n; ++k) {
    const double s = k * period;
    const Eigen::Vector3d p(std::sin(0.7 * s) + 0.3 * s, std::cos(0.5 * s),
                            0.2 * std::sin(1.3 * s));
    t.push_back(pose(s, p, expQuat(Eigen::Vector3d(0.1 * std::sin(s), 0.05 * s, 0.3 * s))));
  }
  return t;
}

TEST(Association, GreedyNearestOneToOneStrictTolerance) {
  const Trajectory gt = stamps({0.0, 0.1, 0.2, 1.0});
  // est 0.019 loses gt 0.0 to the closer est 0.005; 1.03 is too far from gt 1.0.
  const Trajectory est = stamps({0.005, 0.019, 0.2199, 1.03});
  const auto pairs = associate(gt, est, 0.02);
  ASSERT_EQ(pairs.size(), 2u);
  EXPECT_EQ(pairs[0].gt, 0u);
  EXPECT_EQ(pairs[0].est, 0u);
  EXPECT_EQ(pairs[1].gt, 2u);
  EXPECT_EQ(pairs[1].est, 2u);
  // Strict tolerance: exactly max_dt apart (both exactly representable) is not a match.
  EXPECT_TRUE(associate(stamps({1.0}), stamps({1.015625}), 0.015625).empty());
  EXPECT_EQ(associate(stamps({1.0}), stamps({1.015625}), 0.0157).size(), 1u);
}

TEST(Association, PrefersTheGloballyClosestCandidate) {
  // gt 0.03 is closer to est 0.016 (0.014) than gt 0.0 is (0.016).
  const auto pairs = associate(stamps({0.0, 0.03}), stamps({0.016}), 0.02);
  ASSERT_EQ(pairs.size(), 1u);
  EXPECT_EQ(pairs[0].gt, 1u);
}

TEST(Statistics, KnownAnswers) {
  const ErrorStatistics even = computeStatistics({4.0, 3.0});
  EXPECT_DOUBLE_EQ(even.rmse, std::sqrt(12.5));
  EXPECT_DOUBLE_EQ(even.mean, 3.5);
  EXPECT_DOUBLE_EQ(even.median, 3.5);
  EXPECT_DOUBLE_EQ(even.max, 4.0);
  EXPECT_DOUBLE_EQ(computeStatistics({1.0, 5.0, 2.0}).median, 2.0);
  EXPECT_TRUE(std::isnan(computeStatistics({}).rmse));
}

std::vector<Eigen::Vector3d> randomPoints(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-5.0, 5.0);
  std::vector<Eigen::Vector3d> pts;
  for (std::size_t k = 0; k < n; ++k) pts.emplace_back(u(rng), u(rng), u(rng));
  return pts;
}

std::vector<Eigen::Vector3d> transform(const std::vector<Eigen::Vector3d>& pts, double s,
                                       const Eigen::Matrix3d& R, const Eigen::Vector3d& t) {
  std::vector<Eigen::Vector3d> out;
  for (const auto& p : pts) out.push_back(s * R * p + t);
  return out;
}

TEST(Alignment, RecoversKnownSim3Se3AndYaw) {
  const auto est = randomPoints(50, 7);
  const Eigen::Matrix3d R = expSO3(Eigen::Vector3d(0.3, -1.2, 2.0));
  const Eigen::Vector3d t(1.0, -2.0, 0.5);

  const Alignment sim3 = alignPositions(est, transform(est, 1.7, R, t), AlignMode::Sim3);
  EXPECT_NEAR(sim3.scale, 1.7, 1e-12);
  EXPECT_LT((sim3.R - R).norm(), 1e-12);
  EXPECT_LT((sim3.t - t).norm(), 1e-12);

  const Alignment se3 = alignPositions(est, transform(est, 1.0, R, t), AlignMode::Se3);
  EXPECT_EQ(se3.scale, 1.0);
  EXPECT_LT((se3.R - R).norm(), 1e-12);
  EXPECT_LT((se3.t - t).norm(), 1e-12);

  const Eigen::Matrix3d Rz = expSO3(Eigen::Vector3d(0, 0, -2.5));
  const Alignment yaw = alignPositions(est, transform(est, 1.0, Rz, t), AlignMode::PosYaw);
  EXPECT_LT((yaw.R - Rz).norm(), 1e-12);
  EXPECT_LT((yaw.t - t).norm(), 1e-12);

  const Alignment none = alignPositions(est, est, AlignMode::None);
  EXPECT_EQ(none.R, Eigen::Matrix3d::Identity());
  EXPECT_EQ(none.t, Eigen::Vector3d::Zero());
}

TEST(Alignment, PosYawCannotAbsorbRollAndSe3NeverReflects) {
  const auto est = randomPoints(40, 11);
  const auto tilted =
      transform(est, 1.0, expSO3(Eigen::Vector3d(0.2, 0, 0)), Eigen::Vector3d::Zero());
  const Alignment yaw = alignPositions(est, tilted, AlignMode::PosYaw);
  EXPECT_NEAR(yaw.R(2, 2), 1.0, 1e-15);  // still a pure yaw

  // Mirror image: the best orthogonal matrix is a reflection; Umeyama must return a rotation.
  const auto mirrored =
      transform(est, 1.0, Eigen::Vector3d(1, 1, -1).asDiagonal(), Eigen::Vector3d::Zero());
  const Alignment se3 = alignPositions(est, mirrored, AlignMode::Se3);
  EXPECT_NEAR(se3.R.determinant(), 1.0, 1e-12);
}

TEST(Alignment, RejectsTooFewPairsAndDegenerateScale) {
  const std::vector<Eigen::Vector3d> two{Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX()};
  EXPECT_THROW(alignPositions(two, two, AlignMode::Se3), EvalError);
  EXPECT_NO_THROW(alignPositions(two, two, AlignMode::PosYaw));
  const std::vector<Eigen::Vector3d> same(3, Eigen::Vector3d::Ones());
  EXPECT_THROW(alignPositions(same, same, AlignMode::Sim3), EvalError);
  EXPECT_EQ(parseAlignMode("posyaw"), AlignMode::PosYaw);
  EXPECT_THROW(parseAlignMode("SE3x"), std::invalid_argument);
}

TEST(Evaluate, TransformedCopyGivesZeroAteForEveryMode) {
  const Trajectory gt = curve(300, 0.05);
  // The estimate lives in another world frame (and scale for sim3); stamps are shifted by 5 ms.
  const Eigen::Matrix3d R = expSO3(Eigen::Vector3d(0, 0, 0.9));
  const Eigen::Vector3d t(3, -1, 0.25);
  for (const AlignMode mode : {AlignMode::Se3, AlignMode::Sim3, AlignMode::PosYaw}) {
    const double s = mode == AlignMode::Sim3 ? 0.8 : 1.0;
    Trajectory est;
    for (const auto& g : gt) {
      // est = (1/s) R^T (gt - t): aligning est back onto gt needs exactly (s, R, t).
      est.push_back(pose(g.t + 0.005, R.transpose() * (g.p - t) / s,
                         Eigen::Quaterniond(R.transpose()) * g.q));
    }
    EvalOptions opt;
    opt.align = mode;
    const EvalResult r = evaluate(gt, est, opt);
    EXPECT_EQ(r.pairs, gt.size());
    EXPECT_LT(r.ate.rmse, 1e-12) << alignModeName(mode);
    EXPECT_LT(r.ate.max, 1e-12);
    EXPECT_NEAR(r.alignment.scale, s, 1e-12);
    EXPECT_LT((r.alignment.R - R).norm(), 1e-12);
    EXPECT_LT((r.alignment.t - t).norm(), 1e-12);
    if (mode != AlignMode::Sim3) {
      EXPECT_LT(r.rpe.trans_rmse_m, 1e-12);  // rigid change of world frame: relative motion intact
      EXPECT_LT(r.rpe.rot_rmse_deg, 1e-6);
    }
    EXPECT_NEAR(r.coverage.coverage, 1.0, 1e-12);
  }
}

TEST(Evaluate, ConstantOffsetWithoutAlignment) {
  const Trajectory gt = curve(100, 0.1);
  Trajectory est = gt;
  for (auto& p : est) p.p += Eigen::Vector3d(0.3, 0.4, 0.0);  // 0.5 m everywhere
  EvalOptions opt;
  opt.align = AlignMode::None;
  const EvalResult r = evaluate(gt, est, opt);
  EXPECT_NEAR(r.ate.rmse, 0.5, 1e-12);
  EXPECT_NEAR(r.ate.median, 0.5, 1e-12);
  opt.align = AlignMode::Se3;
  EXPECT_LT(evaluate(gt, est, opt).ate.rmse, 1e-12);
}

TEST(Evaluate, NoOverlapIsAClearError) {
  try {
    evaluate(stamps({0, 1, 2}), stamps({10, 11, 12}), EvalOptions{});
    FAIL();
  } catch (const EvalError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("no estimate stamp is within max_dt 0.02 s"), std::string::npos) << msg;
    EXPECT_NE(msg.find("[10.000, 12.000]"), std::string::npos) << msg;
  }
}

Trajectory line(double t0, double t1, double period, double speed, double yaw_rate) {
  Trajectory t;
  const int n = static_cast<int>(std::lround((t1 - t0) / period));
  for (int k = 0; k <= n; ++k) {
    const double s = t0 + k * period;
    t.push_back(
        pose(s, Eigen::Vector3d(speed * s, 0, 0),
             Eigen::Quaterniond(Eigen::AngleAxisd(yaw_rate * s, Eigen::Vector3d::UnitZ()))));
  }
  return t;
}

TEST(Rpe, ScaleErrorGivesKnownTranslationError) {
  // Straight line at 1 m/s (gt) vs 1.1 m/s (estimate): every 1 s step is 0.1 m too long.
  const Trajectory gt = line(0, 10, 0.01, 1.0, 0.0);
  const Trajectory est = line(0, 10, 0.1, 1.1, 0.0);
  const RpeResult r = computeRpe(gt, est, RpeOptions{});
  // i = 0..89: from t_i = 8.95 s on the step lands on the last estimate (dropped).
  EXPECT_EQ(r.pairs, 90u);
  EXPECT_NEAR(r.trans_rmse_m, 0.1, 1e-9);
  EXPECT_NEAR(r.rot_rmse_deg, 0.0, 1e-6);
}

TEST(Rpe, YawRateErrorGivesKnownRotationError) {
  const Trajectory gt = line(0, 10, 0.01, 0.0, 0.0);
  const Trajectory est = line(0, 10, 0.1, 0.0, 0.1);  // 0.1 rad per 1 s step
  const RpeResult r = computeRpe(gt, est, RpeOptions{});
  EXPECT_EQ(r.pairs, 90u);
  EXPECT_NEAR(r.rot_rmse_deg, 0.1 * 180.0 / M_PI, 1e-9);
  EXPECT_NEAR(r.trans_rmse_m, 0.0, 1e-12);
}

TEST(Rpe, DropsPairsWithoutNearbyGroundTruth) {
  Trajectory gt;
  for (const auto& p : line(0, 10, 0.01, 1.0, 0.0)) {
    if (!(p.t > 3.0 + 1e-9 && p.t < 5.0 - 1e-9)) gt.push_back(p);  // gt hole (3, 5)
  }
  const RpeResult r = computeRpe(gt, line(0, 10, 0.1, 1.0, 0.0), RpeOptions{});
  // Pairs with t_i in [2.1, 4.9] touch the hole at one end: 29 of the 90 are dropped.
  EXPECT_EQ(r.pairs, 61u);
  EXPECT_NEAR(r.trans_rmse_m, 0.0, 1e-9);
  RpeOptions longer;
  longer.delta_s = 20.0;
  EXPECT_EQ(computeRpe(gt, line(0, 10, 0.1, 1.0, 0.0), longer).pairs, 0u);
  EXPECT_TRUE(std::isnan(computeRpe(gt, line(0, 10, 0.1, 1.0, 0.0), longer).trans_rmse_m));
}

TEST(Coverage, GapsAndLateStartAreNotCovered) {
  const Trajectory gt = line(0, 10, 0.01, 1.0, 0.0);
  Trajectory est;
  for (const auto& p : line(0, 10, 0.1, 1.0, 0.0)) {
    if (!(p.t > 4.0 + 1e-9 && p.t < 6.0 - 1e-9)) est.push_back(p);  // lost track for 2 s
  }
  const auto c = computeCoverage(gt, est, associate(gt, est, 0.02), 2.0);
  EXPECT_NEAR(c.image_period_s, 0.1, 1e-12);
  EXPECT_NEAR(c.gt_duration_s, 10.0, 1e-12);
  EXPECT_NEAR(c.covered_s, 8.0, 1e-9);
  EXPECT_NEAR(c.coverage, 0.8, 1e-10);

  const Trajectory late = line(2, 10, 0.1, 1.0, 0.0);
  EXPECT_NEAR(computeCoverage(gt, late, associate(gt, late, 0.02), 2.0).coverage, 0.8, 1e-10);
  // A single dropped frame (0.2 s = 2 periods) still counts as tracking.
  Trajectory one_drop = line(0, 10, 0.1, 1.0, 0.0);
  one_drop.erase(one_drop.begin() + 50);
  EXPECT_NEAR(computeCoverage(gt, one_drop, associate(gt, one_drop, 0.02), 2.0).coverage, 1.0,
              1e-10);
}

TEST(EvaluateJson, HasTheKeysOtherToolsRead) {
  const Trajectory gt = line(0, 3, 0.01, 1.0, 0.2);
  const Trajectory est = line(0, 3, 0.1, 1.0, 0.2);
  EvalOptions opt;
  opt.rpe.delta_s = 5.0;  // longer than the run: no RPE pairs
  const EvalResult r = evaluate(gt, est, opt);
  const nlohmann::json j = toJson(r);
  for (const char* key :
       {"pairs", "ate_rmse", "ate_mean", "ate_median", "ate_max", "scale", "rpe_trans_rmse",
        "rpe_rot_rmse_deg", "coverage", "align", "max_dt", "rpe_delta", "rpe_pairs"}) {
    EXPECT_TRUE(j.contains(key)) << key;
  }
  EXPECT_EQ(j["pairs"].get<int>(), 31);
  EXPECT_EQ(j["align"], "se3");
  EXPECT_EQ(j["rpe_pairs"].get<int>(), 0);
  EXPECT_TRUE(j["rpe_trans_rmse"].is_null());
  EXPECT_DOUBLE_EQ(j["max_dt"].get<double>(), 0.02);
  EXPECT_NE(formatReport(r).find("no RPE"), std::string::npos);
}

}  // namespace
}  // namespace rgbdi::eval
