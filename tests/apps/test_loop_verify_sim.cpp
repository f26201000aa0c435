// Geometric verification on rendered images of the simulator's handheld room with aliased end
// walls: ORB keypoints of a view of the -x wall match those of the half-turned view of the +x
// wall (the aliasing works), yet the verifier rejects that loop by the drift budget, while a true
// revisit of the first view is accepted with the right relative pose.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>

#include "rgbdi/common/sensor_options.h"
#include "rgbdi/common/so3.h"
#include "rgbdi/loop/loop_verifier.h"
#include "rgbdi/sim/profile_scene.h"
#include "rgbdi/sim/renderer.h"

namespace {

constexpr double kDeg = M_PI / 180.0;

Eigen::Isometry3d bodyPose(const Eigen::Vector3d& p, double yaw) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = p;
  return T;
}

rgbdi::loop::LoopKeyframe renderKeyframe(const rgbdi::sim::Renderer& renderer,
                                         const rgbdi::PinholeCamera& cam,
                                         const Eigen::Isometry3d& T_body_cam,
                                         const Eigen::Isometry3d& T_world_body, std::uint64_t id,
                                         double travelled) {
  cv::Mat rgb, depth, grey;
  renderer.render(T_world_body * T_body_cam, rgb, depth);
  cv::cvtColor(rgb, grey, cv::COLOR_RGB2GRAY);
  std::vector<cv::KeyPoint> kps;
  cv::Mat desc;
  cv::ORB::create(400)->detectAndCompute(grey, cv::noArray(), kps, desc);
  rgbdi::loop::LoopKeyframe kf;
  kf.id = id;
  kf.T_world_body = kf.T_world_body_odom = T_world_body;
  kf.travelled_m = travelled;
  auto& ds = kf.descriptors;
  ds.type = "ORB-256";
  ds.bytes_per_descriptor = 32;
  for (std::size_t k = 0; k < kps.size(); ++k) {
    const Eigen::Vector2d uv(kps[k].pt.x, kps[k].pt.y);
    const float z = depth.at<float>(cvRound(uv.y()), cvRound(uv.x()));
    ds.keypoints_uv.push_back(uv.cast<float>());
    ds.keypoints_p_cam.push_back(z > 0.0f ? Eigen::Vector3f(cam.backProject(uv, z).cast<float>())
                                          : Eigen::Vector3f(Eigen::Vector3f::Constant(NAN)));
    ds.data.insert(ds.data.end(), desc.ptr<std::uint8_t>(static_cast<int>(k)),
                   desc.ptr<std::uint8_t>(static_cast<int>(k)) + 32);
  }
  return kf;
}

}  // namespace

TEST(LoopVerifySim, AnAliasedWallIsRejectedByTheDriftBudgetAndATrueRevisitAccepted) {
  rgbdi::sim::ProfileOptions po;
  po.kind = rgbdi::sim::ProfileKind::Handheld;
  const Eigen::Isometry3d T_body_cam = rgbdi::ExtrinsicOptions().T_body_cam;
  const rgbdi::sim::MotionProfile prof = rgbdi::sim::makeMotionProfile(po, T_body_cam);
  rgbdi::sim::ProfileSceneOptions so;
  so.aliased_walls = true;
  const rgbdi::sim::Scene scene = rgbdi::sim::buildProfileScene(prof, 1, so);
  rgbdi::sim::RenderOptions ro;
  ro.light_dir_world.x() = 0.0;  // as SimulatedSequence does with aliased walls
  const rgbdi::PinholeCamera cam = rgbdi::CameraOptions().camera;
  const rgbdi::sim::Renderer renderer(scene, cam, ro);
  const Eigen::Vector3d lo = prof.layout.room_min, hi = prof.layout.room_max;
  const double cx = 0.5 * (lo.x() + hi.x()), cy = 0.5 * (lo.y() + hi.y());

  // A: 1.4 m from the -x wall facing it. B: A turned by half a turn about the room centre (faces
  // the +x wall). C: a true revisit of A, 20 cm and 8 deg away.
  const Eigen::Isometry3d T_a = bodyPose({lo.x() + 1.4, cy + 0.3, 1.35}, M_PI);
  const Eigen::Isometry3d T_b = bodyPose({2.0 * cx - (lo.x() + 1.4), cy - 0.3, 1.35}, 0.0);
  const Eigen::Isometry3d T_c = bodyPose({lo.x() + 1.55, cy + 0.18, 1.37}, M_PI + 8.0 * kDeg);
  const auto a = renderKeyframe(renderer, cam, T_body_cam, T_a, 1, 1.0);
  const auto b = renderKeyframe(renderer, cam, T_body_cam, T_b, 2, 9.0);
  const auto c = renderKeyframe(renderer, cam, T_body_cam, T_c, 3, 16.0);

  const rgbdi::loop::LoopVerifier verifier({}, cam, T_body_cam);
  const rgbdi::loop::LoopVerification wrong = verifier.verify(b, a, true);
  // The two walls look alike: the wrong loop passes matching, PnP and the 3-D/3-D check ...
  EXPECT_GE(wrong.constraint.matches, 30) << wrong.detail;
  EXPECT_FALSE(wrong.accepted);
  // ... and is caught because it would move the query by ~2 * 1.6 m: far beyond 0.2 + 5 % of 8 m.
  EXPECT_EQ(wrong.reason, rgbdi::loop::LoopRejection::DriftBudget) << wrong.detail;

  std::fprintf(stderr, "wrong: %d matches %d pnp %d depth: %s\n", wrong.constraint.matches,
               wrong.constraint.pnp_inliers, wrong.constraint.depth_inliers, wrong.detail.c_str());

  // Without the option the +x wall looks different: the same pair does not even match.
  const rgbdi::sim::Scene plain = rgbdi::sim::buildProfileScene(prof, 1);
  const rgbdi::sim::Renderer plain_renderer(plain, cam, ro);
  const auto a0 = renderKeyframe(plain_renderer, cam, T_body_cam, T_a, 1, 1.0);
  const auto b0 = renderKeyframe(plain_renderer, cam, T_body_cam, T_b, 2, 9.0);
  const rgbdi::loop::LoopVerification unaliased = verifier.verify(b0, a0, true);
  EXPECT_EQ(unaliased.reason, rgbdi::loop::LoopRejection::TooFewMatches) << unaliased.detail;
  std::fprintf(stderr, "unaliased: %s\n", unaliased.detail.c_str());

  const rgbdi::loop::LoopVerification right = verifier.verify(c, a, true);
  ASSERT_TRUE(right.accepted) << rgbdi::loop::toString(right.reason) << ": " << right.detail;
  const Eigen::Isometry3d truth = T_a.inverse() * T_c;
  EXPECT_LT((right.constraint.T_from_to.translation() - truth.translation()).norm(), 0.02);
  EXPECT_LT(rgbdi::logSO3(right.constraint.T_from_to.linear().transpose() * truth.linear()).norm(),
            0.5 * kDeg);
  std::fprintf(
      stderr, "right: %d matches %d pnp %d depth, %g m %g deg\n", right.constraint.matches,
      right.constraint.pnp_inliers, right.constraint.depth_inliers,
      (right.constraint.T_from_to.translation() - truth.translation()).norm(),
      rgbdi::logSO3(right.constraint.T_from_to.linear().transpose() * truth.linear()).norm() /
          kDeg);
}
