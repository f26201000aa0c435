// Timings of trajectory evaluation and result writing on the shared fixtures (EuRoC V1_02:
// 16702 ground-truth poses) and on a synthetic 10000-node pose graph.
// Usage: bench_eval [SHARED_DATA_DIR]   (default ../shared/data relative to the working directory)
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "rgbdi/eval/evaluate.h"
#include "rgbdi/eval/tum_reader.h"
#include "rgbdi/output/pose_graph.h"
#include "rgbdi/output/tum_writer.h"

namespace {

template <class F>
double millis(F&& f) {
  const auto t0 = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

int main(int argc, char** argv) {
  const std::string data = argc > 1 ? argv[1] : "../shared/data";
  const std::string gt_path = data + "/eval/euroc_v102_stamped_groundtruth.txt";
  const std::string est_path = data + "/eval/euroc_v102_stamped_estimate0.txt";
  if (!std::filesystem::exists(gt_path)) {
    std::fprintf(stderr, "bench_eval: %s not found (pass the shared data directory)\n",
                 gt_path.c_str());
    return 1;
  }
  rgbdi::Trajectory gt, est;
  std::printf("readTum ground truth          %8.2f ms\n",
              millis([&] { gt = rgbdi::eval::readTum(gt_path); }));
  std::printf("readTum estimate             %8.2f ms\n",
              millis([&] { est = rgbdi::eval::readTum(est_path); }));
  for (const auto mode : {rgbdi::eval::AlignMode::Se3, rgbdi::eval::AlignMode::Sim3,
                          rgbdi::eval::AlignMode::PosYaw}) {
    rgbdi::eval::EvalOptions opt;
    opt.align = mode;
    rgbdi::eval::EvalResult r;
    const double ms = millis([&] { r = rgbdi::eval::evaluate(gt, est, opt); });
    std::printf("evaluate %-6s               %8.2f ms  (ATE rmse %.6f m, %zu pairs)\n",
                rgbdi::eval::alignModeName(mode).c_str(), ms, r.ate.rmse, r.pairs);
  }

  const std::string dir = std::filesystem::temp_directory_path().string();
  std::printf("writeTum %zu poses         %8.2f ms\n", gt.size(),
              millis([&] { rgbdi::output::writeTum(dir + "/bench_eval.tum", gt); }));

  std::vector<rgbdi::output::PoseGraphNode> nodes;
  std::vector<rgbdi::output::PoseGraphEdge> edges;
  constexpr int kNodes = 10000;
  for (int k = 0; k < kNodes; ++k) {
    rgbdi::output::PoseGraphNode n;
    n.id = static_cast<std::uint64_t>(k);
    n.t = 0.1 * k;
    n.T_world_body.translate(Eigen::Vector3d(std::cos(0.01 * k), std::sin(0.01 * k), 0.0));
    n.T_world_body.rotate(Eigen::AngleAxisd(0.01 * k, Eigen::Vector3d::UnitZ()));
    nodes.push_back(n);
    if (k > 0) {
      rgbdi::output::PoseGraphEdge e;
      e.from = static_cast<std::uint64_t>(k - 1);
      e.to = static_cast<std::uint64_t>(k);
      e.T_from_to = nodes[k - 1].T_world_body.inverse() * n.T_world_body;
      edges.push_back(e);
    }
  }
  const std::string graph = dir + "/bench_eval.graph";
  std::printf("writePoseGraph %d nodes    %8.2f ms\n", kNodes,
              millis([&] { rgbdi::output::writePoseGraph(graph, nodes, edges); }));
  std::printf("readPoseGraph  %d nodes    %8.2f ms\n", kNodes,
              millis([&] { (void)rgbdi::output::readPoseGraph(graph); }));
  std::filesystem::remove(dir + "/bench_eval.tum");
  std::filesystem::remove(graph);
  return 0;
}
