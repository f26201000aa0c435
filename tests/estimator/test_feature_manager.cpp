// FeatureManager::addFrame: tracks continue or start, and the keyframe parallax between the two
// slots before the new one, raw (VINS) and without the part the camera's rotation explains.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <utility>
#include <vector>

#include "rgbdi/estimator/feature_manager.h"

namespace rgbdi::estimator {
namespace {

using Frame = std::vector<std::pair<std::uint64_t, TrackObservation>>;

TrackObservation observation(const Eigen::Vector3d& p_cam) {
  TrackObservation o;
  o.meas.xn = p_cam / p_cam.z();
  return o;
}

/// Points seen from camera poses T_c0_ci (camera i in camera 0's frame).
Frame view(const std::vector<Eigen::Vector3d>& points_c0, const Eigen::Isometry3d& T_c0_ci) {
  Frame f;
  for (std::size_t k = 0; k < points_c0.size(); ++k)
    f.emplace_back(k, observation(T_c0_ci.inverse() * points_c0[k]));
  return f;
}

std::vector<Eigen::Vector3d> points() {
  std::vector<Eigen::Vector3d> p;
  for (int i = -2; i <= 2; ++i)
    for (int j = -2; j <= 2; ++j) p.emplace_back(0.3 * i, 0.2 * j, 2.0 + 0.1 * (i + j));
  return p;
}

TEST(FeatureManager, KeyframeParallaxWithoutRotationLeavesOutWhatTheTurnExplains) {
  const std::vector<Eigen::Vector3d> p = points();
  Eigen::Isometry3d T1 = Eigen::Isometry3d::Identity();  // camera 1 in camera 0: a pure turn
  T1.linear() = Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const Frame f0 = view(p, Eigen::Isometry3d::Identity()), f1 = view(p, T1), f2 = view(p, T1);

  // Raw: the turn moves every feature by about 0.05 in normalised units.
  FeatureManager raw;
  raw.addFrame(0, f0);
  EXPECT_EQ(raw.addFrame(1, f1).n_tracked, 25);
  const FeatureManager::FrameLinks r = raw.addFrame(2, f2);
  EXPECT_EQ(r.n_parallax, 25);
  EXPECT_EQ(r.n_tracked, 25);
  EXPECT_GT(r.parallax, 0.05);

  // Without rotation (R_c2_c1 = camera 1 -> camera 0): nothing is left of a pure turn.
  FeatureManager comp;
  comp.addFrame(0, f0);
  comp.addFrame(1, f1);
  const Eigen::Matrix3d R = T1.linear();
  const FeatureManager::FrameLinks c = comp.addFrame(2, f2, &R);
  EXPECT_EQ(c.n_parallax, 25);
  EXPECT_NEAR(c.parallax, 0.0, 1e-12);

  // A sideways step of 0.1 m on top of the turn: what remains is the step's parallax, the same
  // as the raw parallax of the step alone (known answer: x / z changes by 0.1 / z per point).
  Eigen::Isometry3d T1s = T1;
  T1s.translation() = Eigen::Vector3d(0.1, 0.0, 0.0);
  Eigen::Isometry3d step = Eigen::Isometry3d::Identity();
  step.translation() = Eigen::Vector3d(0.1, 0.0, 0.0);
  FeatureManager a, b;
  a.addFrame(0, f0);
  a.addFrame(1, view(p, T1s));
  const double with_turn = a.addFrame(2, f2, &R).parallax;
  b.addFrame(0, f0);
  b.addFrame(1, view(p, step));
  const double step_only = b.addFrame(2, f2).parallax;
  double expected = 0.0;
  for (const Eigen::Vector3d& q : p) expected += 0.1 / q.z();
  expected /= static_cast<double>(p.size());
  EXPECT_NEAR(step_only, expected, 1e-12);
  // Rotating the stepped observations back does not restore the depth-scaled geometry exactly:
  // the remaining parallax is the step's, to first order.
  EXPECT_NEAR(with_turn, step_only, 0.1 * step_only);
}

TEST(FeatureManager, ABrokenTrackStartsAgain) {
  const std::vector<Eigen::Vector3d> p = points();
  FeatureManager m;
  m.addFrame(0, view(p, Eigen::Isometry3d::Identity()));
  m.addFrame(1, Frame{});  // nothing seen
  const FeatureManager::FrameLinks l = m.addFrame(2, view(p, Eigen::Isometry3d::Identity()));
  EXPECT_EQ(l.n_tracked, 0);
  EXPECT_EQ(l.n_parallax, 0);
}

}  // namespace
}  // namespace rgbdi::estimator
