// A synthetic loop: one set of 3-D points seen by a candidate and a query keyframe from two known
// body poses, with binary descriptors (random 32-byte strings per point, copied with a few
// flipped bits into the query), wrong correspondences and distractors, and optional pixel and
// depth noise. The true T_from_to is known exactly. Used by the verifier tests and benchmark.
#pragma once

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <random>
#include <vector>

#include "rgbdi/common/camera.h"
#include "rgbdi/loop/loop_keyframe.h"

namespace rgbdi::test {

struct SyntheticLoopPairOptions {
  int shared_points = 300;  ///< points with a keypoint in both keyframes
  /// candidate keypoints (with depth) whose descriptor reappears in the query at an unrelated
  /// pixel: wrong correspondences that only geometry can reject
  int outliers = 40;
  int distractors = 60;         ///< keypoints of each keyframe with an unrelated random descriptor
  int max_flipped_bits = 8;     ///< the query copy of a descriptor has 0..this many bits flipped
  double pixel_noise_px = 0.0;  ///< Gaussian noise on the query and candidate keypoints
  double depth_noise_coeff = 0.0;  ///< [1/m] depth noise sigma = coeff * z^2, both keyframes
  double depth_min_m = 1.0;        ///< [m] candidate-frame depth of the shared points
  double depth_max_m = 4.0;        ///< [m]
  std::uint64_t seed = 1;
  PinholeCamera camera;  ///< default: the D435i colour camera of share/config.ini
  Eigen::Isometry3d T_world_body_candidate = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d T_world_body_query = Eigen::Isometry3d::Identity();
};

struct SyntheticLoopPair {
  loop::LoopKeyframe query, candidate;  ///< T_world_body (and _odom) = the true poses
  PinholeCamera camera;
  Eigen::Isometry3d T_body_cam = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d T_from_to_true = Eigen::Isometry3d::Identity();
};

inline PinholeCamera d435Camera() {
  PinholeCamera c;
  c.width = 640;
  c.height = 480;
  c.fx = 616.5911;
  c.fy = 616.6796;
  c.cx = 324.2194;
  c.cy = 239.4270;
  return c;
}

/// Camera optical frame (x right, y down, z forward) in the body frame (x forward, y left, z up).
inline Eigen::Isometry3d bodyCamExtrinsic() {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  T.translation() = Eigen::Vector3d(0.0, 0.015, 0.0003);
  return T;
}

/// Body pose from position and yaw/pitch/roll [rad] (z-y-x, world z up).
inline Eigen::Isometry3d bodyPose(const Eigen::Vector3d& p, double yaw, double pitch = 0.0,
                                  double roll = 0.0) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  T.translation() = p;
  return T;
}

/// The default geometry of the tests: candidate at (1, 2, 0.3) heading 30 deg; query 0.4 m
/// forward-ish, 0.3 m to the side, 5 cm up, turned 15 deg, pitched 3 deg and rolled -2 deg.
inline SyntheticLoopPairOptions defaultLoopPairOptions() {
  SyntheticLoopPairOptions o;
  o.camera = d435Camera();
  const double deg = M_PI / 180.0;
  o.T_world_body_candidate = bodyPose({1.0, 2.0, 0.3}, 30 * deg);
  o.T_world_body_query = bodyPose({1.4, 1.7, 0.35}, 45 * deg, 3 * deg, -2 * deg);
  return o;
}

inline SyntheticLoopPair makeSyntheticLoopPair(const SyntheticLoopPairOptions& o) {
  SyntheticLoopPair pair;
  pair.camera = o.camera;
  pair.T_body_cam = bodyCamExtrinsic();
  const PinholeCamera& cam = o.camera;
  const Eigen::Isometry3d T_world_cc = o.T_world_body_candidate * pair.T_body_cam;
  const Eigen::Isometry3d T_world_qc = o.T_world_body_query * pair.T_body_cam;
  const Eigen::Isometry3d T_qc_world = T_world_qc.inverse();
  pair.T_from_to_true = o.T_world_body_candidate.inverse() * o.T_world_body_query;

  std::mt19937_64 rng(o.seed);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  std::normal_distribution<double> n01(0.0, 1.0);
  auto randomDescriptor = [&rng]() {
    std::vector<std::uint8_t> d(32);
    for (auto& b : d) b = static_cast<std::uint8_t>(rng() & 0xff);
    return d;
  };
  auto flipped = [&](std::vector<std::uint8_t> d) {
    const int k = static_cast<int>(rng() % static_cast<std::uint64_t>(o.max_flipped_bits + 1));
    std::vector<int> bits(256);
    std::iota(bits.begin(), bits.end(), 0);
    for (int i = 0; i < k; ++i) {  // k distinct bits (partial Fisher-Yates)
      const int j = i + static_cast<int>(rng() % static_cast<std::uint64_t>(256 - i));
      std::swap(bits[i], bits[j]);
      d[bits[i] / 8] ^= static_cast<std::uint8_t>(1u << (bits[i] % 8));
    }
    return d;
  };
  auto randomPixel = [&]() {
    return Eigen::Vector2d(2.0 + u01(rng) * (cam.width - 5), 2.0 + u01(rng) * (cam.height - 5));
  };
  auto noisyDepthPoint = [&](const Eigen::Vector3d& p) {
    const double z = p.z();
    const double zn = z + o.depth_noise_coeff * z * z * n01(rng);
    return Eigen::Vector3d(p * (zn / z));  // depth noise moves the point along its ray
  };

  struct Kp {
    Eigen::Vector2d uv;
    Eigen::Vector3d p;
    bool has_point;
    std::vector<std::uint8_t> desc;
  };
  std::vector<Kp> cand, query;
  // Shared points: uniform in the candidate image and depth range, kept when the query sees them.
  while (static_cast<int>(cand.size()) < o.shared_points) {
    const Eigen::Vector2d uv = randomPixel();
    const double z = o.depth_min_m + u01(rng) * (o.depth_max_m - o.depth_min_m);
    const Eigen::Vector3d p_cc = cam.backProject(uv, z);
    const Eigen::Vector3d p_qc = T_qc_world * (T_world_cc * p_cc);
    Eigen::Vector2d uv_q;
    if (p_qc.z() < 0.2 || !cam.project(p_qc, uv_q) || !cam.inImage(uv_q, 2.0)) continue;
    const std::vector<std::uint8_t> d = randomDescriptor();
    const Eigen::Vector2d nc(n01(rng), n01(rng)), nq(n01(rng), n01(rng));
    cand.push_back({uv + o.pixel_noise_px * nc, noisyDepthPoint(p_cc), true, d});
    query.push_back({uv_q + o.pixel_noise_px * nq, noisyDepthPoint(p_qc), true, flipped(d)});
  }
  // Candidate distractors with depth; the first `outliers` of them reappear in the query at an
  // unrelated pixel with unrelated depth.
  for (int i = 0; i < o.distractors + o.outliers; ++i) {
    const Eigen::Vector2d uv = randomPixel();
    const std::vector<std::uint8_t> d = randomDescriptor();
    cand.push_back({uv, cam.backProject(uv, 1.0 + 3.0 * u01(rng)), true, d});
    if (i < o.outliers) {
      const Eigen::Vector2d uv_q = randomPixel();
      query.push_back({uv_q, cam.backProject(uv_q, 1.0 + 3.0 * u01(rng)), true, flipped(d)});
    }
  }
  for (int i = 0; i < o.distractors; ++i) {
    const Eigen::Vector2d uv = randomPixel();
    query.push_back({uv, cam.backProject(uv, 1.0 + 3.0 * u01(rng)), true, randomDescriptor()});
  }
  // The query lists its keypoints in another order than the candidate.
  std::shuffle(query.begin(), query.end(), rng);

  auto fill = [](const std::vector<Kp>& kps, mapping::DescriptorSet& ds) {
    ds.type = "ORB-256";
    ds.bytes_per_descriptor = 32;
    for (const Kp& k : kps) {
      ds.keypoints_uv.push_back(k.uv.cast<float>());
      ds.keypoints_p_cam.push_back(k.has_point ? Eigen::Vector3f(k.p.cast<float>())
                                               : Eigen::Vector3f::Constant(NAN));
      ds.data.insert(ds.data.end(), k.desc.begin(), k.desc.end());
    }
  };
  fill(cand, pair.candidate.descriptors);
  fill(query, pair.query.descriptors);
  pair.candidate.id = 10;
  pair.candidate.t = 100.0;
  pair.candidate.T_world_body = pair.candidate.T_world_body_odom = o.T_world_body_candidate;
  pair.candidate.travelled_m = 5.0;
  pair.query.id = 250;
  pair.query.t = 160.0;
  pair.query.T_world_body = pair.query.T_world_body_odom = o.T_world_body_query;
  pair.query.travelled_m = 25.0;
  return pair;
}

}  // namespace rgbdi::test
