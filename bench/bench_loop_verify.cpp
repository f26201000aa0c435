// Timings of loop verification (LoopVerifier::verify) per candidate for keyframes of 400 ORB
// keypoints: an accepted loop, an unrelated candidate (rejected by the match count: the common
// case), a correct match rejected by the drift budget (the whole pipeline runs), and a wrong
// depth rejected by the 3-D/3-D check. Synthetic keyframes (tests/loop/synthetic_loop_pair.h)
// with D435-like depth noise and 0.5 px keypoint noise.
#include <algorithm>
#include <cstdio>
#include <ctime>
#include <vector>

#include "../tests/loop/synthetic_loop_pair.h"
#include "rgbdi/loop/hamming_matcher.h"
#include "rgbdi/loop/loop_verifier.h"

using namespace rgbdi;

namespace {

// Thread CPU time: the development machine is shared, wall time would measure the others.
double cpuMs() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return 1e3 * static_cast<double>(ts.tv_sec) + 1e-6 * static_cast<double>(ts.tv_nsec);
}

struct Case {
  const char* name;
  test::SyntheticLoopPair pair;
  bool related = true;
};

test::SyntheticLoopPairOptions pairOptions(int shared, int outliers, std::uint64_t seed) {
  test::SyntheticLoopPairOptions o = test::defaultLoopPairOptions();
  o.shared_points = shared;
  o.outliers = outliers;
  o.distractors = 400 - shared - outliers;  // 400 keypoints in each keyframe
  o.pixel_noise_px = 0.5;
  o.depth_noise_coeff = 0.004;
  o.seed = seed;
  return o;
}

}  // namespace

int main() {
  const int repetitions = 200;
  std::vector<Case> cases;
  cases.push_back(
      {"accepted (250 shared, 30 wrong)", test::makeSyntheticLoopPair(pairOptions(250, 30, 1))});
  cases.push_back({"unrelated (0 shared)", test::makeSyntheticLoopPair(pairOptions(0, 0, 2))});
  {
    test::SyntheticLoopPair p = test::makeSyntheticLoopPair(pairOptions(250, 30, 3));
    p.query.T_world_body.translation() += Eigen::Vector3d(2.0, 0.0, 0.0);
    cases.push_back({"drift budget (2 m off)", p});
  }
  {
    test::SyntheticLoopPair p = test::makeSyntheticLoopPair(pairOptions(250, 30, 4));
    for (auto& q : p.query.descriptors.keypoints_p_cam) q *= 1.15f;
    cases.push_back({"3-D/3-D disagreement", p});
  }
  {
    test::SyntheticLoopPair p = test::makeSyntheticLoopPair(pairOptions(60, 100, 5));
    cases.push_back({"weak (60 shared, 100 wrong)", p});
  }
  const loop::LoopVerificationOptions options;
  std::printf(
      "loop verification, 400 keypoints per keyframe, %d repetitions per case, thread CPU time\n",
      repetitions);
  std::printf("%-34s %-20s %8s %8s %8s %10s %10s\n", "case", "result", "matches", "pnp_inl",
              "depth_in", "median_ms", "mean_ms");
  for (const Case& c : cases) {
    const loop::LoopVerifier verifier(options, c.pair.camera, c.pair.T_body_cam);
    std::vector<double> ms;
    loop::LoopVerification v;
    for (int r = 0; r < repetitions; ++r) {
      const double t0 = cpuMs();
      v = verifier.verify(c.pair.query, c.pair.candidate, c.related);
      ms.push_back(cpuMs() - t0);
    }
    double sum = 0.0;
    for (double x : ms) sum += x;
    std::sort(ms.begin(), ms.end());
    std::printf("%-34s %-20s %8d %8d %8d %10.3f %10.3f\n", c.name, loop::toString(v.reason),
                v.constraint.matches, v.constraint.pnp_inliers, v.constraint.depth_inliers,
                ms[ms.size() / 2], sum / ms.size());
  }
  // The matching alone (400 x 400 Hamming distances, mutual check), for reference.
  const test::SyntheticLoopPair& p = cases[0].pair;
  std::vector<double> ms;
  for (int r = 0; r < repetitions; ++r) {
    const double t0 = cpuMs();
    const auto m = loop::matchDescriptors(
        p.query.descriptors.data.data(), static_cast<int>(p.query.descriptors.size()),
        p.candidate.descriptors.data.data(), static_cast<int>(p.candidate.descriptors.size()), 32,
        {options.match_ratio, options.max_hamming_bits, options.cross_check});
    ms.push_back(cpuMs() - t0);
    if (m.empty()) return 1;
  }
  std::sort(ms.begin(), ms.end());
  std::printf("%-34s %-20s %8s %8s %8s %10.3f\n", "descriptor matching only", "", "", "", "",
              ms[ms.size() / 2]);
  return 0;
}
