// The verifier on real ORB features: a textured wall imaged from two known poses (each image an
// exact homography of the wall texture), keypoints from cv::ORB, depth from the wall plane.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <opencv2/core/eigen.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>
#include <random>

#include "loop/synthetic_loop_pair.h"
#include "rgbdi/common/so3.h"
#include "rgbdi/loop/loop_verifier.h"

namespace {

constexpr double kDeg = M_PI / 180.0;
constexpr double kTexelM = 0.005;  // [m] wall texture resolution
// The wall: plane x = 2.5 m, texture column s along -y, row t along -z, from (2.5, 3, 3).
const Eigen::Vector3d kWallOrigin(2.5, 3.0, 3.0);
const Eigen::Vector3d kWallS(0.0, -1.0, 0.0), kWallT(0.0, 0.0, -1.0);

/// Random shapes of random grey on a 1200 x 800 canvas (6 x 4 m), slightly blurred.
cv::Mat wallTexture(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int> x(0, 1199), y(0, 799), r(4, 40), g(0, 255);
  cv::Mat tex(800, 1200, CV_8UC1, cv::Scalar(128));
  for (int i = 0; i < 2500; ++i) {
    const cv::Point c(x(rng), y(rng));
    if (i % 2 == 0)
      cv::circle(tex, c, r(rng), cv::Scalar(g(rng)), cv::FILLED, cv::LINE_AA);
    else
      cv::rectangle(tex, c, c + cv::Point(r(rng), r(rng)), cv::Scalar(g(rng)), cv::FILLED);
  }
  cv::GaussianBlur(tex, tex, cv::Size(0, 0), 0.8);
  return tex;
}

/// Image of the wall seen by a camera at T_world_cam, and the wall's depth-backed keypoints.
rgbdi::mapping::DescriptorSet orbView(const cv::Mat& texture, const rgbdi::PinholeCamera& cam,
                                      const Eigen::Isometry3d& T_world_cam) {
  const Eigen::Isometry3d T_cam_world = T_world_cam.inverse();
  Eigen::Matrix3d K;
  K << cam.fx, 0, cam.cx, 0, cam.fy, cam.cy, 0, 0, 1;
  Eigen::Matrix3d A;  // texture pixel (s, t, 1) -> camera point
  A.col(0) = T_cam_world.linear() * kWallS * kTexelM;
  A.col(1) = T_cam_world.linear() * kWallT * kTexelM;
  A.col(2) = T_cam_world * kWallOrigin;
  cv::Mat H;
  cv::eigen2cv(Eigen::Matrix3d(K * A), H);
  cv::Mat image;
  cv::warpPerspective(texture, image, H, cv::Size(cam.width, cam.height), cv::INTER_LINEAR,
                      cv::BORDER_CONSTANT, cv::Scalar(0));
  std::vector<cv::KeyPoint> kps;
  cv::Mat desc;
  cv::ORB::create(400)->detectAndCompute(image, cv::noArray(), kps, desc);
  // Wall plane in the camera frame: n . X = d.
  const Eigen::Vector3d n = T_cam_world.linear() * Eigen::Vector3d::UnitX();
  const double d = n.dot(T_cam_world * kWallOrigin);
  rgbdi::mapping::DescriptorSet ds;
  ds.type = "ORB-256";
  ds.bytes_per_descriptor = 32;
  for (std::size_t k = 0; k < kps.size(); ++k) {
    const Eigen::Vector2d uv(kps[k].pt.x, kps[k].pt.y);
    const Eigen::Vector3d ray = cam.backProject(uv, 1.0);
    ds.keypoints_uv.push_back(uv.cast<float>());
    ds.keypoints_p_cam.push_back((ray * (d / n.dot(ray))).cast<float>());
    ds.data.insert(ds.data.end(), desc.ptr<std::uint8_t>(static_cast<int>(k)),
                   desc.ptr<std::uint8_t>(static_cast<int>(k)) + 32);
  }
  return ds;
}

rgbdi::loop::LoopKeyframe keyframe(std::uint64_t id, const Eigen::Isometry3d& T_world_body,
                                   double travelled, rgbdi::mapping::DescriptorSet ds) {
  rgbdi::loop::LoopKeyframe kf;
  kf.id = id;
  kf.T_world_body = kf.T_world_body_odom = T_world_body;
  kf.travelled_m = travelled;
  kf.descriptors = std::move(ds);
  return kf;
}

}  // namespace

TEST(LoopVerifierOrb, RecoversTheRelativePoseOfTwoViewsOfATexturedWall) {
  const rgbdi::PinholeCamera cam = rgbdi::test::d435Camera();
  const Eigen::Isometry3d T_body_cam = rgbdi::test::bodyCamExtrinsic();
  const Eigen::Isometry3d T_wb_cand = rgbdi::test::bodyPose({0.0, 0.0, 1.0}, 0.0);
  const Eigen::Isometry3d T_wb_query =
      rgbdi::test::bodyPose({0.35, 0.4, 1.05}, 12.0 * kDeg, 2.0 * kDeg, -1.5 * kDeg);
  const cv::Mat texture = wallTexture(1);
  const auto cand = keyframe(3, T_wb_cand, 2.0, orbView(texture, cam, T_wb_cand * T_body_cam));
  const auto query = keyframe(90, T_wb_query, 12.0, orbView(texture, cam, T_wb_query * T_body_cam));
  ASSERT_GE(cand.descriptors.size(), 300u);
  ASSERT_GE(query.descriptors.size(), 300u);
  const rgbdi::loop::LoopVerifier verifier({}, cam, T_body_cam);
  const rgbdi::loop::LoopVerification v = verifier.verify(query, cand, true);
  ASSERT_TRUE(v.accepted) << rgbdi::loop::toString(v.reason) << ": " << v.detail;
  const Eigen::Isometry3d truth = T_wb_cand.inverse() * T_wb_query;
  // Measured: 49 matches, 43 PnP inliers, all 43 agree in 3-D; 0.26 mm and 0.02 deg.
  EXPECT_GE(v.constraint.pnp_inliers, 30);
  EXPECT_EQ(v.constraint.depth_inliers, v.constraint.pnp_inliers);  // exact plane depth
  EXPECT_LT((v.constraint.T_from_to.translation() - truth.translation()).norm(), 0.005);
  EXPECT_LT(rgbdi::logSO3(v.constraint.T_from_to.linear().transpose() * truth.linear()).norm(),
            0.2 * kDeg);
  EXPECT_LT(v.constraint.reprojection_rms_px, 1.5);
}

TEST(LoopVerifierOrb, RejectsTwoViewsOfDifferentWalls) {
  const rgbdi::PinholeCamera cam = rgbdi::test::d435Camera();
  const Eigen::Isometry3d T_body_cam = rgbdi::test::bodyCamExtrinsic();
  const Eigen::Isometry3d T_wb = rgbdi::test::bodyPose({0.0, 0.0, 1.0}, 0.0);
  const auto cand = keyframe(3, T_wb, 2.0, orbView(wallTexture(1), cam, T_wb * T_body_cam));
  const auto query = keyframe(90, T_wb, 12.0, orbView(wallTexture(2), cam, T_wb * T_body_cam));
  const rgbdi::loop::LoopVerifier verifier({}, cam, T_body_cam);
  const rgbdi::loop::LoopVerification v = verifier.verify(query, cand, true);
  EXPECT_FALSE(v.accepted);
  EXPECT_EQ(v.reason, rgbdi::loop::LoopRejection::TooFewMatches) << v.detail;
}
