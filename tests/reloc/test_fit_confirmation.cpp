// FitConfirmation: a fit is trusted only when a second one, far enough along the path, agrees.
#include <gtest/gtest.h>

#include <cmath>

#include "rgbdi/reloc/fit_confirmation.h"

using namespace rgbdi::reloc;

namespace {
RelocOptions options() {
  RelocOptions o;
  o.confirm_fits = 2;
  o.confirm_distance_m = 1.5;
  o.confirm_max_disagreement_m = 0.10;
  o.confirm_max_disagreement_deg = 2.0;
  return o;
}
RelocFit fitAt(double travelled, double x, double yaw_deg, FitOutcome outcome = FitOutcome::kFit,
               int segment = 1) {
  RelocFit f;
  f.segment = segment;
  f.anchor_id = static_cast<std::uint64_t>(travelled * 10);
  f.travelled_m = travelled;
  f.outcome = outcome;
  f.T_map_part.linear() =
      Eigen::AngleAxisd(yaw_deg * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  f.T_map_part.translation() = Eigen::Vector3d(x, 0, 0);
  return f;
}
// Anchors never moved since their fit.
const auto unchanged = [](std::uint64_t) { return Eigen::Isometry3d::Identity(); };
}  // namespace

TEST(FitConfirmation, ASecondAgreeingFitFarEnoughAlongConfirms) {
  FitConfirmation c(options());
  const Eigen::Vector3d p(1, 0, 0);
  EXPECT_FALSE(c.add(fitAt(0.0, 2.0, 30), p, unchanged));
  EXPECT_TRUE(c.waiting());
  EXPECT_FALSE(c.add(fitAt(1.0, 2.05, 30), p, unchanged));   // agrees, only 1 m later
  const auto A = c.add(fitAt(1.5, 2.05, 31), p, unchanged);  // agrees, 1.5 m after the first
  ASSERT_TRUE(A);
  EXPECT_NEAR(A->translation().x(), 2.05, 1e-12);
  EXPECT_FALSE(c.waiting());
}

TEST(FitConfirmation, ADisagreeingFitReplacesTheProposal) {
  FitConfirmation c(options());
  const Eigen::Vector3d p(1, 0, 0);
  EXPECT_FALSE(c.add(fitAt(0.0, 2.0, 30), p, unchanged));
  EXPECT_FALSE(c.add(fitAt(2.0, 2.2, 30), p, unchanged));  // 20 cm off: a new proposal
  EXPECT_EQ(c.disagreements(), 1);
  EXPECT_FALSE(c.add(fitAt(3.0, 2.2, 33), p, unchanged));  // 3 deg off the new one
  EXPECT_EQ(c.disagreements(), 2);
  EXPECT_FALSE(c.add(fitAt(4.0, 2.2, 33.5), p, unchanged));  // agrees, 1 m after
  EXPECT_TRUE(c.add(fitAt(4.5, 2.2, 33.5), p, unchanged));
}

TEST(FitConfirmation, AmbiguousAttemptsDropTheProposalFailedOnesLeaveItWaiting) {
  FitConfirmation c(options());
  const Eigen::Vector3d p(0, 0, 0);
  EXPECT_FALSE(c.add(fitAt(0.0, 2.0, 0), p, unchanged));
  EXPECT_FALSE(c.add(fitAt(0.5, 9.0, 0, FitOutcome::kUnrefined), p, unchanged));
  EXPECT_TRUE(c.waiting());
  EXPECT_FALSE(c.add(fitAt(1.0, 9.0, 0, FitOutcome::kAmbiguous), p, unchanged));
  EXPECT_FALSE(c.waiting());
  EXPECT_EQ(c.lastOutcome(), FitOutcome::kAmbiguous);
  // The agreeing fit 1.5 m after the first starts a new proposal instead of confirming it.
  EXPECT_FALSE(c.add(fitAt(1.5, 2.0, 0), p, unchanged));
  EXPECT_TRUE(c.waiting());
  EXPECT_TRUE(c.add(fitAt(3.0, 2.0, 0), p, unchanged));
}

TEST(FitConfirmation, SegmentsStartOver) {
  FitConfirmation c(options());
  const Eigen::Vector3d p(0, 0, 0);
  EXPECT_FALSE(c.add(fitAt(0.0, 2.0, 0), p, unchanged));
  EXPECT_FALSE(c.add(fitAt(2.0, 2.0, 0, FitOutcome::kFit, 2), p, unchanged));  // another segment
  EXPECT_FALSE(c.add(fitAt(3.0, 2.0, 0, FitOutcome::kFit, 2), p, unchanged));  // 1 m only
  EXPECT_TRUE(c.add(fitAt(3.5, 2.0, 0, FitOutcome::kFit, 2), p, unchanged));
}

TEST(FitConfirmation, AlignmentsFollowTheAnchorsCurrentPose) {
  RelocFit f = fitAt(0.0, 2.0, 0);
  f.T_anchor.translation() = Eigen::Vector3d(1, 0, 0);
  Eigen::Isometry3d now = Eigen::Isometry3d::Identity();
  now.translation() = Eigen::Vector3d(1.5, 0, 0);  // the part's own correction moved it
  const Eigen::Isometry3d A = FitConfirmation::alignmentNow(f, now);
  // The anchor stays where the fit put it: map x = 2 + 1 = 3.
  EXPECT_NEAR((A * now.translation()).x(), 3.0, 1e-12);
}

TEST(FitConfirmation, ThreeFitsMustAgreeWhenAsked) {
  RelocOptions o = options();
  o.confirm_fits = 3;
  FitConfirmation c(o);
  const Eigen::Vector3d p(1, 0, 0);
  EXPECT_FALSE(c.add(fitAt(0.0, 2.0, 30), p, unchanged));
  EXPECT_FALSE(c.add(fitAt(2.0, 2.05, 30), p, unchanged));  // far enough, but only the second
  EXPECT_FALSE(c.add(fitAt(2.5, 5.0, 30), p, unchanged));   // disagrees: starts over
  EXPECT_FALSE(c.add(fitAt(3.0, 5.0, 30), p, unchanged));
  EXPECT_FALSE(c.add(fitAt(3.25, 5.0, 30), p, unchanged));  // three, but 0.75 m < 1.5 m
  EXPECT_TRUE(c.add(fitAt(4.0, 5.0, 30), p, unchanged));
}

TEST(FitConfirmation, TheJoinCanUseTheMeanOfTheAgreeingFits) {
  // The same three fits as above: the last one (2.05 m, 31 deg) by default, their mean
  // (2.0333 m, 30.333 deg) with confirm_join_mean; a disagreeing fit before them is not in it.
  RelocOptions o = options();
  o.confirm_join_mean = true;
  FitConfirmation c(o);
  const Eigen::Vector3d p(1, 0, 0);
  EXPECT_FALSE(c.add(fitAt(0.0, 3.0, 30), p, unchanged));  // replaced by the next
  EXPECT_FALSE(c.add(fitAt(0.0, 2.0, 30), p, unchanged));
  EXPECT_FALSE(c.add(fitAt(1.0, 2.05, 30), p, unchanged));
  const auto A = c.add(fitAt(1.5, 2.05, 31), p, unchanged);
  ASSERT_TRUE(A);
  EXPECT_NEAR(A->translation().x(), (2.0 + 2.05 + 2.05) / 3.0, 1e-12);
  const double yaw = std::atan2(A->linear()(1, 0), A->linear()(0, 0)) * 180.0 / M_PI;
  // The circular mean of 30, 30, 31 deg: atan2 of the summed sines and cosines.
  const double a = 30 * M_PI / 180, b = 31 * M_PI / 180;
  EXPECT_NEAR(
      yaw, std::atan2(2 * std::sin(a) + std::sin(b), 2 * std::cos(a) + std::cos(b)) * 180.0 / M_PI,
      1e-12);
  EXPECT_NEAR(yaw, 30.333, 1e-3);
}
