#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "loop/synthetic_loop_pair.h"
#include "rgbdi/common/so3.h"
#include "rgbdi/loop/hamming_matcher.h"
#include "rgbdi/loop/loop_verifier.h"
#include "rgbdi/loop/rigid_fit.h"

using rgbdi::loop::LoopRejection;
using rgbdi::loop::LoopVerification;
using rgbdi::loop::LoopVerificationOptions;
using rgbdi::loop::LoopVerifier;
using rgbdi::test::SyntheticLoopPair;
using rgbdi::test::SyntheticLoopPairOptions;

namespace {

constexpr double kDeg = M_PI / 180.0;

double rotationErrorRad(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return rgbdi::logSO3(a.linear().transpose() * b.linear()).norm();
}
double translationError(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return (a.translation() - b.translation()).norm();
}

LoopVerification verifyPair(const SyntheticLoopPair& p, bool related = true,
                            const LoopVerificationOptions& o = {}) {
  const LoopVerifier verifier(o, p.camera, p.T_body_cam);
  return verifier.verify(p.query, p.candidate, related);
}

/// Relative heading [rad] of the default pair (query 45 deg, candidate 30 deg).
constexpr double kTrueYawDeg = 15.0;

}  // namespace

TEST(LoopVerifier, RecoversTheExactRelativePoseOfNoiseFreeKeyframes) {
  const SyntheticLoopPair p =
      rgbdi::test::makeSyntheticLoopPair(rgbdi::test::defaultLoopPairOptions());
  const LoopVerification v = verifyPair(p);
  ASSERT_TRUE(v.accepted) << rgbdi::loop::toString(v.reason) << ": " << v.detail;
  EXPECT_EQ(v.reason, LoopRejection::Accepted);
  EXPECT_TRUE(v.detail.empty());
  EXPECT_EQ(v.constraint.from_id, 10u);
  EXPECT_EQ(v.constraint.to_id, 250u);
  // 300 shared points and 40 wrong correspondences match; distractors never do (random 256-bit
  // strings are ~128 bits apart, 8 flipped bits at most keep the true pairs within 8).
  EXPECT_EQ(v.constraint.matches, 340);
  EXPECT_GE(v.constraint.pnp_inliers, 300);
  EXPECT_LE(v.constraint.pnp_inliers, 302);  // a wrong pair may fall near its true pixel
  EXPECT_GE(v.constraint.depth_inliers, 300);
  EXPECT_LT(translationError(v.constraint.T_from_to, p.T_from_to_true), 1e-5);
  EXPECT_LT(rotationErrorRad(v.constraint.T_from_to, p.T_from_to_true), 1e-5);
  EXPECT_LT(v.constraint.reprojection_rms_px, 1e-3);
  EXPECT_LT(v.constraint.depth_rms_m, 1e-5);
}

TEST(LoopVerifier, RecoversTheRelativePoseWithDepthAndPixelNoiseAndDistortion) {
  SyntheticLoopPairOptions o = rgbdi::test::defaultLoopPairOptions();
  o.pixel_noise_px = 0.5;
  o.depth_noise_coeff = 0.004;  // D435: 16 mm at 2 m
  o.camera.dist = {0.12, -0.25, 0.001, -0.0008, 0.1};
  o.seed = 7;
  const SyntheticLoopPair p = rgbdi::test::makeSyntheticLoopPair(o);
  const LoopVerification v = verifyPair(p);
  ASSERT_TRUE(v.accepted) << rgbdi::loop::toString(v.reason) << ": " << v.detail;
  // Far points whose candidate depth is off by more than ~2 sigma reproject outside 3 px in the
  // query (0.5 m baseline): PnP keeps about 87 % of the 300; nearly all of those agree in 3-D.
  EXPECT_GE(v.constraint.pnp_inliers, 240);
  EXPECT_GE(v.constraint.depth_inliers, 0.95 * v.constraint.pnp_inliers);
  EXPECT_LT(translationError(v.constraint.T_from_to, p.T_from_to_true), 0.01);
  EXPECT_LT(rotationErrorRad(v.constraint.T_from_to, p.T_from_to_true), 0.3 * kDeg);
  EXPECT_GT(v.constraint.reprojection_rms_px, 0.3);
  EXPECT_LT(v.constraint.reprojection_rms_px, 3.0);
  EXPECT_GT(v.constraint.depth_rms_m, 0.003);
  EXPECT_LT(v.constraint.depth_rms_m, 0.05);
}

TEST(LoopVerifier, WithPreciseDepthAndNoisyPixelsTheDepthRefinementBeatsPnpAlone) {
  LoopVerificationOptions pnp_only;
  pnp_only.refine_rounds = 0;
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    SyntheticLoopPairOptions o = rgbdi::test::defaultLoopPairOptions();
    o.pixel_noise_px = 1.5;
    o.depth_noise_coeff = 0.0005;
    o.seed = seed;
    const SyntheticLoopPair p = rgbdi::test::makeSyntheticLoopPair(o);
    const LoopVerification a = verifyPair(p, true, pnp_only);
    const LoopVerification b = verifyPair(p);
    ASSERT_TRUE(a.accepted && b.accepted) << a.detail << " / " << b.detail;
    const double ta = translationError(a.constraint.T_from_to, p.T_from_to_true);
    const double tb = translationError(b.constraint.T_from_to, p.T_from_to_true);
    const double ra = rotationErrorRad(a.constraint.T_from_to, p.T_from_to_true);
    const double rb = rotationErrorRad(b.constraint.T_from_to, p.T_from_to_true);
    EXPECT_LT(tb, ta) << "seed " << seed;
    EXPECT_LT(rb, ra) << "seed " << seed;
    EXPECT_LT(b.constraint.depth_rms_m, a.constraint.depth_rms_m) << "seed " << seed;
  }
}

TEST(LoopVerifier, RejectsTooFewMatchesAndCountsThemExactly) {
  SyntheticLoopPairOptions o = rgbdi::test::defaultLoopPairOptions();
  o.shared_points = 20;
  o.outliers = 5;
  const SyntheticLoopPair p = rgbdi::test::makeSyntheticLoopPair(o);
  const LoopVerification v = verifyPair(p);
  EXPECT_FALSE(v.accepted);
  EXPECT_EQ(v.reason, LoopRejection::TooFewMatches);
  EXPECT_EQ(v.constraint.matches, 25);
  EXPECT_NE(v.detail.find("verify_min_matches 30"), std::string::npos) << v.detail;
}

TEST(LoopVerifier, MatchesNeedACandidatePointAndSurviveTheRatioTest) {
  SyntheticLoopPair p = rgbdi::test::makeSyntheticLoopPair(rgbdi::test::defaultLoopPairOptions());
  // Without depth in the candidate nothing can be used for PnP.
  SyntheticLoopPair no_depth = p;
  for (auto& q : no_depth.candidate.descriptors.keypoints_p_cam) q.z() = NAN;
  const LoopVerification v1 = verifyPair(no_depth);
  EXPECT_EQ(v1.reason, LoopRejection::TooFewMatches);
  EXPECT_EQ(v1.constraint.matches, 0);
  // Every candidate descriptor twice: the second best equals the best, no match passes.
  SyntheticLoopPair doubled = p;
  auto& d = doubled.candidate.descriptors;
  const std::size_t n = d.size();
  for (std::size_t k = 0; k < n; ++k) {
    d.keypoints_uv.push_back(d.keypoints_uv[k]);
    d.keypoints_p_cam.push_back(d.keypoints_p_cam[k]);
    d.data.insert(d.data.end(), d.data.begin() + k * 32, d.data.begin() + (k + 1) * 32);
  }
  const LoopVerification v2 = verifyPair(doubled);
  EXPECT_EQ(v2.reason, LoopRejection::TooFewMatches);
  EXPECT_EQ(v2.constraint.matches, 0);
}

TEST(LoopVerifier, RejectsTooFewPnpInliers) {
  SyntheticLoopPairOptions o = rgbdi::test::defaultLoopPairOptions();
  o.shared_points = 40;
  o.outliers = 60;
  const SyntheticLoopPair p = rgbdi::test::makeSyntheticLoopPair(o);
  LoopVerificationOptions opt;
  opt.min_matches = 50;
  opt.min_pnp_inliers = 45;
  const LoopVerification v = verifyPair(p, true, opt);
  EXPECT_EQ(v.reason, LoopRejection::TooFewPnpInliers) << v.detail;
  EXPECT_EQ(v.constraint.matches, 100);
  EXPECT_GE(v.constraint.pnp_inliers, 40);
  EXPECT_LT(v.constraint.pnp_inliers, 45);
  // The same pair passes with the default gate of 25.
  opt.min_pnp_inliers = 25;
  opt.min_depth_inliers = 20;
  EXPECT_TRUE(verifyPair(p, true, opt).accepted);
}

TEST(LoopVerifier, RejectsWrongDepthOnOneSideIn3dCheck) {
  SyntheticLoopPair p = rgbdi::test::makeSyntheticLoopPair(rgbdi::test::defaultLoopPairOptions());
  // The query's depth is 15 % too far (a wrong depth scale): its pixels, hence PnP, are right.
  for (auto& q : p.query.descriptors.keypoints_p_cam) q *= 1.15f;
  const LoopVerification v = verifyPair(p);
  EXPECT_FALSE(v.accepted);
  EXPECT_EQ(v.reason, LoopRejection::DepthDisagreement);
  EXPECT_GE(v.constraint.pnp_inliers, 300);
  EXPECT_LT(v.constraint.depth_inliers, 20);
  // The PnP pose is reported with the rejection (for diagnostics); it is right.
  EXPECT_LT(translationError(v.constraint.T_from_to, p.T_from_to_true), 1e-4);
  // Without depth in the query there is nothing to check against: rejected as well.
  for (auto& q : p.query.descriptors.keypoints_p_cam) q.z() = NAN;
  const LoopVerification w = verifyPair(p);
  EXPECT_EQ(w.reason, LoopRejection::DepthDisagreement);
  EXPECT_EQ(w.constraint.depth_inliers, 0);
}

TEST(LoopVerifier, RejectsARollErrorAsGravityMismatch) {
  SyntheticLoopPair p = rgbdi::test::makeSyntheticLoopPair(rgbdi::test::defaultLoopPairOptions());
  // The query's own pose rolled by 4 deg: the loop implies a different gravity direction.
  const Eigen::Isometry3d rolled =
      p.query.T_world_body * Eigen::AngleAxisd(4.0 * kDeg, Eigen::Vector3d::UnitX());
  p.query.T_world_body = rolled;
  const LoopVerification v = verifyPair(p);
  EXPECT_EQ(v.reason, LoopRejection::GravityMismatch) << v.detail;
  // The measurement is 4 deg: a gate of 4.1 deg lets it through, a gate of 3.9 deg does not.
  LoopVerificationOptions o;
  o.max_gravity_deg = 4.01;
  EXPECT_TRUE(verifyPair(p, true, o).accepted) << verifyPair(p, true, o).detail;
  o.max_gravity_deg = 3.99;
  EXPECT_EQ(verifyPair(p, true, o).reason, LoopRejection::GravityMismatch);
  // A pure heading error is not a gravity error.
  SyntheticLoopPair q = rgbdi::test::makeSyntheticLoopPair(rgbdi::test::defaultLoopPairOptions());
  q.query.T_world_body.linear() =
      Eigen::AngleAxisd(4.0 * kDeg, Eigen::Vector3d::UnitZ()) * q.query.T_world_body.linear();
  EXPECT_TRUE(verifyPair(q).accepted) << verifyPair(q).detail;
}

TEST(LoopVerifier, GatesTheRelativeYawAtItsThreshold) {
  const SyntheticLoopPair p =
      rgbdi::test::makeSyntheticLoopPair(rgbdi::test::defaultLoopPairOptions());
  LoopVerificationOptions o;
  o.max_yaw_deg = kTrueYawDeg - 0.05;
  const LoopVerification v = verifyPair(p, true, o);
  EXPECT_EQ(v.reason, LoopRejection::YawGate) << v.detail;
  o.max_yaw_deg = kTrueYawDeg + 0.05;
  EXPECT_TRUE(verifyPair(p, true, o).accepted);
}

TEST(LoopVerifier, RejectsALargeYawWithTheDefaultGate) {
  // 40 deg apart, both looking at the same points (30 deg is the reference's gate).
  SyntheticLoopPairOptions o = rgbdi::test::defaultLoopPairOptions();
  o.T_world_body_candidate = rgbdi::test::bodyPose({0.0, 0.0, 0.3}, 0.0);
  o.T_world_body_query = rgbdi::test::bodyPose({0.2, -1.8, 0.3}, 40.0 * kDeg);
  o.depth_min_m = 2.5;
  o.depth_max_m = 3.5;
  const SyntheticLoopPair p = rgbdi::test::makeSyntheticLoopPair(o);
  const LoopVerification v = verifyPair(p);
  EXPECT_EQ(v.reason, LoopRejection::YawGate) << v.detail;
  EXPECT_LT(translationError(v.constraint.T_from_to, p.T_from_to_true), 1e-5);
}

TEST(LoopVerifier, GatesTheRelativeTranslation) {
  const SyntheticLoopPair p =
      rgbdi::test::makeSyntheticLoopPair(rgbdi::test::defaultLoopPairOptions());
  const double d = p.T_from_to_true.translation().norm();  // ~0.5 m
  LoopVerificationOptions o;
  o.max_translation_m = d - 0.001;
  EXPECT_EQ(verifyPair(p, true, o).reason, LoopRejection::TranslationGate);
  o.max_translation_m = d + 0.001;
  EXPECT_TRUE(verifyPair(p, true, o).accepted);
  // 4.5 m straight back, same heading: rejected by the default 4 m gate.
  SyntheticLoopPairOptions g = rgbdi::test::defaultLoopPairOptions();
  g.T_world_body_candidate = rgbdi::test::bodyPose({0.0, 0.0, 0.3}, 0.0);
  g.T_world_body_query = rgbdi::test::bodyPose({-4.5, 0.0, 0.3}, 0.0);
  g.depth_min_m = 1.2;
  g.depth_max_m = 1.8;
  const SyntheticLoopPair far = rgbdi::test::makeSyntheticLoopPair(g);
  const LoopVerification v = verifyPair(far);
  EXPECT_EQ(v.reason, LoopRejection::TranslationGate) << v.detail;
}

TEST(LoopVerifier, RejectsACorrectionLargerThanTheDriftBudget) {
  SyntheticLoopPair p = rgbdi::test::makeSyntheticLoopPair(rgbdi::test::defaultLoopPairOptions());
  // The odometry puts the query 0.5 m off its true place. Budget: 0.2 m + 5 % of the distance.
  p.query.T_world_body.translation() += Eigen::Vector3d(0.3, 0.4, 0.0);
  p.candidate.travelled_m = 10.0;
  p.query.travelled_m = 15.0;  // 5 m: budget 0.45 m
  LoopVerification v = verifyPair(p);
  EXPECT_EQ(v.reason, LoopRejection::DriftBudget) << v.detail;
  EXPECT_NE(v.detail.find("position"), std::string::npos) << v.detail;
  p.query.travelled_m = 17.0;  // 7 m: budget 0.55 m
  v = verifyPair(p);
  EXPECT_TRUE(v.accepted) << v.detail;
  // The recovered loop does not depend on the odometry's error.
  EXPECT_LT(translationError(v.constraint.T_from_to, p.T_from_to_true), 1e-5);
}

TEST(LoopVerifier, RejectsAHeadingCorrectionLargerThanTheDriftBudget) {
  SyntheticLoopPair p = rgbdi::test::makeSyntheticLoopPair(rgbdi::test::defaultLoopPairOptions());
  // Heading off by 5 deg; budget 3 deg + 0.3 deg/m.
  p.query.T_world_body.linear() =
      Eigen::AngleAxisd(5.0 * kDeg, Eigen::Vector3d::UnitZ()) * p.query.T_world_body.linear();
  p.candidate.travelled_m = 10.0;
  p.query.travelled_m = 16.0;  // 6 m: 4.8 deg
  LoopVerification v = verifyPair(p);
  EXPECT_EQ(v.reason, LoopRejection::DriftBudget) << v.detail;
  EXPECT_NE(v.detail.find("heading"), std::string::npos) << v.detail;
  p.query.travelled_m = 17.0;  // 7 m: 5.1 deg
  EXPECT_TRUE(verifyPair(p).accepted);
}

TEST(LoopVerifier, SkipsTheDriftBudgetWhenTheFramesAreUnrelated) {
  SyntheticLoopPair p = rgbdi::test::makeSyntheticLoopPair(rgbdi::test::defaultLoopPairOptions());
  // Another segment: its frame is 10 m and 90 deg away from the candidate's.
  p.query.segment = 1;
  p.query.T_world_body = Eigen::Translation3d(10.0, -3.0, 0.0) *
                         Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()) *
                         p.query.T_world_body;
  EXPECT_EQ(verifyPair(p, true).reason, LoopRejection::DriftBudget);
  const LoopVerification v = verifyPair(p, false);
  ASSERT_TRUE(v.accepted) << v.detail;
  EXPECT_LT(translationError(v.constraint.T_from_to, p.T_from_to_true), 1e-5);
}

TEST(LoopVerifier, GivesIdenticalOutputForTheSameInput) {
  SyntheticLoopPairOptions o = rgbdi::test::defaultLoopPairOptions();
  o.pixel_noise_px = 0.7;
  o.depth_noise_coeff = 0.004;
  const SyntheticLoopPair p = rgbdi::test::makeSyntheticLoopPair(o);
  const LoopVerificationOptions opt;
  const LoopVerifier a(opt, p.camera, p.T_body_cam), b(opt, p.camera, p.T_body_cam);
  const LoopVerification v1 = a.verify(p.query, p.candidate, true);
  const LoopVerification v2 = a.verify(p.query, p.candidate, true);
  const LoopVerification v3 = b.verify(p.query, p.candidate, true);
  ASSERT_TRUE(v1.accepted);
  for (const LoopVerification* v : {&v2, &v3}) {
    EXPECT_EQ(v->accepted, v1.accepted);
    EXPECT_EQ(v->constraint.matches, v1.constraint.matches);
    EXPECT_EQ(v->constraint.pnp_inliers, v1.constraint.pnp_inliers);
    EXPECT_EQ(v->constraint.depth_inliers, v1.constraint.depth_inliers);
    EXPECT_EQ(std::memcmp(v->constraint.T_from_to.matrix().data(),
                          v1.constraint.T_from_to.matrix().data(), 16 * sizeof(double)),
              0);
    EXPECT_EQ(v->constraint.reprojection_rms_px, v1.constraint.reprojection_rms_px);
    EXPECT_EQ(v->constraint.depth_rms_m, v1.constraint.depth_rms_m);
  }
}

TEST(LoopVerifier, RejectsInconsistentDescriptorSetsNamingTheKeyframe) {
  SyntheticLoopPair p = rgbdi::test::makeSyntheticLoopPair(rgbdi::test::defaultLoopPairOptions());
  p.query.descriptors.data.pop_back();
  try {
    verifyPair(p);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("query keyframe 250"), std::string::npos) << e.what();
  }
  EXPECT_THROW(LoopVerifier(LoopVerificationOptions{}, rgbdi::PinholeCamera{}, p.T_body_cam),
               std::invalid_argument);
  LoopVerificationOptions bad;
  bad.match_ratio = 1.5;
  EXPECT_THROW(LoopVerifier(bad, p.camera, p.T_body_cam), rgbdi::ConfigError);
}

TEST(LoopRejection, EveryReasonHasItsOwnName) {
  std::vector<std::string> names;
  for (LoopRejection r : rgbdi::loop::kAllLoopRejections) names.push_back(rgbdi::loop::toString(r));
  EXPECT_EQ(names.front(), "accepted");
  EXPECT_EQ(std::string(rgbdi::loop::toString(LoopRejection::DriftBudget)), "drift_budget");
  for (std::size_t i = 0; i < names.size(); ++i)
    for (std::size_t j = i + 1; j < names.size(); ++j) EXPECT_NE(names[i], names[j]);
}

TEST(HammingMatcher, CountsDifferingBits) {
  std::vector<std::uint8_t> a(32, 0), b(32, 0);
  EXPECT_EQ(rgbdi::loop::hammingDistance(a.data(), b.data(), 32), 0);
  b[0] = 0xff;
  b[31] = 0x01;
  b[13] = 0x30;
  EXPECT_EQ(rgbdi::loop::hammingDistance(a.data(), b.data(), 32), 11);
  EXPECT_EQ(rgbdi::loop::hammingDistance(a.data() + 1, b.data() + 1, 31), 3);  // unaligned tail
}

TEST(HammingMatcher, AppliesTheRatioTestTheDistanceCapAndTheMutualCheck) {
  // 1-byte descriptors. Train: 0x00, 0x0f, 0xff. Queries:
  //  q0 = 0x01: best t0 (1), second t1 (3): ratio 1/3 passes.
  //  q1 = 0x07: t1 (1) vs t0 (3): passes.
  //  q2 = 0x03: t0 (2) vs t1 (2): equal distances, fails the ratio test.
  //  q3 = 0x0e: t1 (1): but t1's nearest query is q1 (1, lower index) -> mutual check drops it.
  //  q4 = 0xf0: t2 (4) vs t0 (4): fails the ratio.
  const std::vector<std::uint8_t> train = {0x00, 0x0f, 0xff};
  const std::vector<std::uint8_t> query = {0x01, 0x07, 0x03, 0x0e, 0xf0};
  rgbdi::loop::HammingMatchOptions o;
  o.ratio = 0.8;
  o.max_distance_bits = 8;
  o.cross_check = true;
  auto m = rgbdi::loop::matchDescriptors(query.data(), 5, train.data(), 3, 1, o);
  ASSERT_EQ(m.size(), 2u);
  EXPECT_EQ(m[0].query, 0);
  EXPECT_EQ(m[0].train, 0);
  EXPECT_EQ(m[0].distance_bits, 1);
  EXPECT_EQ(m[1].query, 1);
  EXPECT_EQ(m[1].train, 1);
  o.cross_check = false;
  m = rgbdi::loop::matchDescriptors(query.data(), 5, train.data(), 3, 1, o);
  ASSERT_EQ(m.size(), 3u);
  EXPECT_EQ(m[2].query, 3);
  EXPECT_EQ(m[2].train, 1);
  o.max_distance_bits = 0;
  EXPECT_TRUE(rgbdi::loop::matchDescriptors(query.data(), 5, train.data(), 3, 1, o).empty());
}

TEST(RigidFit, RecoversAKnownTransformAndWeightsThePoints) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = rgbdi::expSO3(Eigen::Vector3d(0.3, -0.5, 1.1));
  T.translation() = Eigen::Vector3d(1.0, -2.0, 0.5);
  std::vector<Eigen::Vector3d> src, dst;
  std::vector<double> w;
  for (int i = 0; i < 20; ++i) {
    src.emplace_back(u(rng), u(rng), u(rng));
    dst.push_back(T * src.back());
    w.push_back(1.0 + i);
  }
  Eigen::Isometry3d fit;
  ASSERT_TRUE(rgbdi::loop::fitRigidWeighted(src, dst, w, fit));
  EXPECT_LT((fit.matrix() - T.matrix()).norm(), 1e-12);
  // One point moved 1 m: with a tiny weight it hardly matters, with a large weight it does.
  dst[0] += Eigen::Vector3d(1.0, 0.0, 0.0);
  w[0] = 1e-9;
  ASSERT_TRUE(rgbdi::loop::fitRigidWeighted(src, dst, w, fit));
  EXPECT_LT((fit.matrix() - T.matrix()).norm(), 1e-8);
  w[0] = 1e3;
  ASSERT_TRUE(rgbdi::loop::fitRigidWeighted(src, dst, w, fit));
  EXPECT_GT((fit.matrix() - T.matrix()).norm(), 1e-2);
  // Planar points are enough (no reflection); collinear or too few are not.
  std::vector<Eigen::Vector3d> plane = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  std::vector<Eigen::Vector3d> plane_dst;
  for (const auto& p : plane) plane_dst.push_back(T * p);
  ASSERT_TRUE(rgbdi::loop::fitRigidWeighted(plane, plane_dst, {1, 1, 1, 1}, fit));
  EXPECT_LT((fit.matrix() - T.matrix()).norm(), 1e-12);
  std::vector<Eigen::Vector3d> line = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  EXPECT_FALSE(rgbdi::loop::fitRigidWeighted(line, line, {1, 1, 1}, fit));
  EXPECT_FALSE(
      rgbdi::loop::fitRigidWeighted({{0, 0, 0}, {1, 0, 0}}, {{0, 0, 0}, {1, 0, 0}}, {1, 1}, fit));
}

namespace {

/// Depth grids of the pair's two keyframes seeing one wall, fronto-parallel to the candidate
/// camera at `wall_m` [m]: exact depths along each camera's optical axis.
void addWallGrids(SyntheticLoopPair& p, double wall_m) {
  const Eigen::Isometry3d T_cc_qc =
      p.T_body_cam.inverse() * p.T_from_to_true * p.T_body_cam;  // query cam -> candidate cam
  for (rgbdi::loop::DepthGrid* g : {&p.query.depth_grid, &p.candidate.depth_grid}) {
    g->cols = 32;
    g->rows = 24;
    g->depth_m.assign(32 * 24, 0.0f);
  }
  for (int r = 0; r < 24; ++r)
    for (int c = 0; c < 32; ++c) {
      const Eigen::Vector2d uv =
          p.candidate.depth_grid.pixel(c, r, p.camera.width, p.camera.height);
      p.candidate.depth_grid.depth_m[r * 32 + c] = static_cast<float>(wall_m);
      const Eigen::Vector3d d = p.camera.backProject(uv, 1.0);  // query ray, unit depth
      const double s = (wall_m - T_cc_qc.translation().z()) / (T_cc_qc.linear() * d).z();
      if (s > 0.0) p.query.depth_grid.depth_m[r * 32 + c] = static_cast<float>(s);
    }
}

}  // namespace

TEST(LoopVerifier, AcceptsAJoinWhoseDepthGridsSeeTheSameWall) {
  SyntheticLoopPair p = rgbdi::test::makeSyntheticLoopPair(rgbdi::test::defaultLoopPairOptions());
  addWallGrids(p, 4.0);
  const LoopVerification v = verifyPair(p, /*related=*/false);
  ASSERT_TRUE(v.accepted) << rgbdi::loop::toString(v.reason) << ": " << v.detail;
  EXPECT_GT(v.constraint.freespace_compared, 300);
  EXPECT_EQ(v.constraint.freespace_conflicts, 0);
}

TEST(LoopVerifier, RejectsAJoinWhoseSurfacesLieInTheOtherKeyframesFreeSpace) {
  SyntheticLoopPair p = rgbdi::test::makeSyntheticLoopPair(rgbdi::test::defaultLoopPairOptions());
  addWallGrids(p, 4.0);
  // The query sees a surface at half the distance everywhere: where the candidate saw the wall
  // at 4 m, the query's samples float in its free space. The candidate's wall lies behind the
  // query's surface (hidden from the query), which says nothing.
  for (float& d : p.query.depth_grid.depth_m) d *= 0.5f;
  const LoopVerification v = verifyPair(p, /*related=*/false);
  EXPECT_FALSE(v.accepted);
  EXPECT_EQ(v.reason, LoopRejection::FreeSpaceConflict);
  EXPECT_GT(v.constraint.freespace_compared, 300);
  EXPECT_EQ(v.constraint.freespace_conflicts, v.constraint.freespace_compared);
  EXPECT_NE(v.detail.find("verify_freespace_max_conflict_fraction"), std::string::npos) << v.detail;

  // Loops within one frame are not checked by default; with verify_freespace_for_loops they are.
  const LoopVerification loop = verifyPair(p, /*related=*/true);
  EXPECT_TRUE(loop.accepted) << loop.detail;
  EXPECT_EQ(loop.constraint.freespace_compared, 0);
  LoopVerificationOptions o;
  o.freespace_for_loops = true;
  EXPECT_EQ(verifyPair(p, true, o).reason, LoopRejection::FreeSpaceConflict);
  // A share of 1 switches the check off.
  o.freespace_max_conflict_fraction = 1.0;
  EXPECT_TRUE(verifyPair(p, false, o).accepted);
}

TEST(LoopVerifier, ComparesTheFreeSpaceOfTwoKeyframesPlacedAtGivenPoses) {
  // The comparison a join's neighbourhood check makes (LoopCloser): the same counts as the
  // verification's step 7 under the same relative pose, in both argument orders.
  SyntheticLoopPair p = rgbdi::test::makeSyntheticLoopPair(rgbdi::test::defaultLoopPairOptions());
  addWallGrids(p, 4.0);
  const LoopVerifier verifier({}, p.camera, p.T_body_cam);
  const Eigen::Isometry3d T_c = p.candidate.T_world_body, T_q = p.query.T_world_body;
  const rgbdi::loop::FreeSpaceTally t = verifier.compareFreeSpace(p.query, T_q, p.candidate, T_c);
  EXPECT_GT(t.compared, 300);
  EXPECT_EQ(t.conflicts, 0);
  const rgbdi::loop::FreeSpaceTally back =
      verifier.compareFreeSpace(p.candidate, T_c, p.query, T_q);
  EXPECT_EQ(back.compared, t.compared);
  EXPECT_EQ(back.conflicts, t.conflicts);
  const LoopVerification v = verifier.verify(p.query, p.candidate, /*related=*/false);
  ASSERT_TRUE(v.accepted) << v.detail;
  EXPECT_EQ(v.constraint.freespace_compared, t.compared);

  // Only the relative pose counts: both moved by the same rigid motion give the same tally.
  Eigen::Isometry3d M = Eigen::Isometry3d::Identity();
  M.linear() = Eigen::AngleAxisd(1.1, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  M.translation() = Eigen::Vector3d(-7.0, 3.0, 0.5);
  const rgbdi::loop::FreeSpaceTally moved =
      verifier.compareFreeSpace(p.query, M * T_q, p.candidate, M * T_c);
  EXPECT_EQ(moved.compared, t.compared);
  EXPECT_EQ(moved.conflicts, 0);

  // The query placed 2 m nearer the wall along the candidate's optical axis: its wall samples
  // land 2 m beyond the candidate's wall (hidden from the candidate: no evidence), and the
  // candidate's wall samples lie 2 m in front of the query's wall, in the query's free space:
  // every compared sample conflicts (fewer overlap than before).
  const Eigen::Vector3d forward = (T_c * p.T_body_cam).linear().col(2);
  Eigen::Isometry3d T_q_near = T_q;
  T_q_near.translation() += 2.0 * forward;
  const rgbdi::loop::FreeSpaceTally near =
      verifier.compareFreeSpace(p.query, T_q_near, p.candidate, T_c);
  EXPECT_GT(near.compared, 100);
  EXPECT_EQ(near.conflicts, near.compared);

  // A keyframe without depth says nothing.
  p.candidate.depth_grid = {};
  const rgbdi::loop::FreeSpaceTally none =
      verifier.compareFreeSpace(p.query, T_q, p.candidate, T_c);
  EXPECT_EQ(none.compared, 0);
  EXPECT_EQ(none.conflicts, 0);
}
