// Benchmark of the 4-DOF pose graph (PoseGraph4Dof): a multi-lap racetrack driven with realistic
// odometry drift (yaw random walk and bias, scale error, position noise, height drift), a loop
// to the previous lap every 24 keyframes, loop measurements with noise. For 1 000 and 5 000
// keyframes it prints the time of a full solve from the odometry, the time of one more solve
// after adding a loop to the solved graph, the ATE of odometry and graph, and the heap memory
// per node.
//
//   bench_pose_graph [--seed N] [--sizes N,N,...]
#include <malloc.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "rgbdi/loop/four_dof.h"
#include "rgbdi/loop/pose_graph.h"
#include "rgbdi/loop/yaw_manifold.h"

using namespace rgbdi::loop;
using Eigen::Isometry3d;
using Eigen::Vector3d;

namespace {

constexpr double kDeg = M_PI / 180.0;
constexpr int kPerLap = 240;         // keyframes per lap; keyframe k revisits k - kPerLap
constexpr double kStraightM = 20.0;  // racetrack: two straights joined by half circles
constexpr double kRadiusM = 5.0;
constexpr int kLoopEvery = 24;  // keyframes between two loops to the previous lap

double processCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

Isometry3d poseOf(const Vector3d& p, double yaw, double pitch, double roll) {
  Isometry3d T = Isometry3d::Identity();
  T.linear() =
      (Eigen::AngleAxisd(yaw, Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Vector3d::UnitY()) *
       Eigen::AngleAxisd(roll, Vector3d::UnitX()))
          .toRotationMatrix();
  T.translation() = p;
  return T;
}

/// True pose at arc length s along the racetrack (counter-clockwise, gentle hills).
Isometry3d trackPose(double s) {
  const double arc = M_PI * kRadiusM;
  const double lap = 2.0 * kStraightM + 2.0 * arc;
  const double u = std::fmod(s, lap);
  Vector3d p;
  double yaw;
  if (u < kStraightM) {
    p << u, 0.0, 0.0;
    yaw = 0.0;
  } else if (u < kStraightM + arc) {
    const double a = (u - kStraightM) / kRadiusM;
    p << kStraightM + kRadiusM * std::sin(a), kRadiusM - kRadiusM * std::cos(a), 0.0;
    yaw = a;
  } else if (u < 2.0 * kStraightM + arc) {
    p << kStraightM - (u - kStraightM - arc), 2.0 * kRadiusM, 0.0;
    yaw = M_PI;
  } else {
    const double a = (u - 2.0 * kStraightM - arc) / kRadiusM;
    p << -kRadiusM * std::sin(a), kRadiusM + kRadiusM * std::cos(a), 0.0;
    yaw = M_PI + a;
  }
  p.z() = 0.3 * std::sin(2.0 * M_PI * u / lap);
  return poseOf(p, wrapAngle(yaw), 0.02 * std::sin(0.37 * s), 0.015 * std::cos(0.23 * s));
}

struct Route {
  std::vector<Isometry3d> truth, odom;
};

Route makeRoute(int n, std::uint64_t seed) {
  const double lap = 2.0 * kStraightM + 2.0 * M_PI * kRadiusM;
  Route r;
  for (int k = 0; k < n; ++k) r.truth.push_back(trackPose(lap * k / kPerLap));
  // Odometry drift of a good VIO: ~0.7 deg per lap of yaw bias plus a random walk, 0.5 % scale,
  // 3 mm per keyframe of position noise, 0.5 mm per keyframe of height drift.
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> yaw_noise(0.0, 0.02 * kDeg), pos_noise(0.0, 0.003);
  const double yaw_bias = 0.003 * kDeg, scale = 1.005, z_drift = 0.0005;
  double yaw = yawOf(r.truth[0].linear());
  Vector3d p = r.truth[0].translation();
  r.odom.push_back(r.truth[0]);
  for (int k = 0; k + 1 < n; ++k) {
    const double yaw_t = yawOf(r.truth[k].linear());
    const Vector3d dp =
        rotZ(yaw_t).transpose() * (r.truth[k + 1].translation() - r.truth[k].translation());
    const double dyaw = wrapAngle(yawOf(r.truth[k + 1].linear()) - yaw_t);
    p += rotZ(yaw) * (dp * scale + Vector3d(pos_noise(rng), pos_noise(rng), pos_noise(rng))) +
         Vector3d(0, 0, z_drift);
    yaw = wrapAngle(yaw + dyaw + yaw_bias + yaw_noise(rng));
    Isometry3d T = Isometry3d::Identity();
    T.linear() = rotZ(yaw) * tiltOf(r.truth[k + 1].linear());
    T.translation() = p;
    r.odom.push_back(T);
  }
  return r;
}

/// Loop measurement from the truth with the noise of a depth-verified loop (2 cm, 0.3 deg).
Isometry3d loopMeasurement(const Route& r, int from, int to, std::mt19937_64& rng) {
  std::normal_distribution<double> pos(0.0, 0.02), rot(0.0, 0.3 * kDeg);
  Isometry3d T =
      r.truth[static_cast<std::size_t>(from)].inverse() * r.truth[static_cast<std::size_t>(to)];
  T.translation() += Vector3d(pos(rng), pos(rng), pos(rng));
  T.linear() = T.linear() * rotZ(rot(rng));
  return T;
}

double ate(const PoseGraph4Dof* g, const Route& r) {
  double sq = 0.0;
  for (std::size_t k = 0; k < r.truth.size(); ++k) {
    const Vector3d p = g ? Vector3d(g->pose(k).translation()) : Vector3d(r.odom[k].translation());
    sq += (p - r.truth[k].translation()).squaredNorm();
  }
  return std::sqrt(sq / static_cast<double>(r.truth.size()));
}

/// Heap bytes in use, small blocks and mmapped large ones (glibc).
std::size_t heapInUse() {
  const struct mallinfo2 m = mallinfo2();
  return m.uordblks + m.hblkhd;
}

struct Row {
  int nodes = 0;
  std::size_t loops = 0;
  PoseGraphSolveReport full, again, wrong;
  double full_cpu_s = 0.0, again_cpu_s = 0.0, wrong_cpu_s = 0.0;
  double ate_after_wrong = 0.0;
  double ate_odom = 0.0, ate_graph = 0.0;
  double heap_per_node = 0.0;   ///< [B] measured heap growth while building the graph
  double graph_per_node = 0.0;  ///< [B] PoseGraph4Dof::memoryBytes()
};

Row run(int n, std::uint64_t seed) {
  Row row;
  row.nodes = n;
  const Route route = makeRoute(n, seed);
  std::mt19937_64 rng(seed + 1);

  const std::size_t heap0 = heapInUse();
  auto graph = std::make_unique<PoseGraph4Dof>();
  for (int k = 0; k < n; ++k) graph->addNode(static_cast<std::uint64_t>(k), 0, route.odom[k]);
  // Loops every lap: every kLoopEdge-th keyframe of a lap to the same place one lap earlier;
  // the last one is kept for the "one more loop" solve.
  std::vector<int> loop_from;
  for (int k = kPerLap; k < n; k += kLoopEvery) loop_from.push_back(k);
  const int last = loop_from.back();
  loop_from.pop_back();
  for (int k : loop_from)
    graph->addLoopEdge(static_cast<std::uint64_t>(k), static_cast<std::uint64_t>(k - kPerLap),
                       loopMeasurement(route, k, k - kPerLap, rng));
  row.heap_per_node = static_cast<double>(heapInUse() - heap0) / n;
  row.graph_per_node = static_cast<double>(graph->memoryBytes()) / n;
  row.loops = loop_from.size() + 1;

  double t0 = processCpuSeconds();
  row.full = graph->solve();
  row.full_cpu_s = processCpuSeconds() - t0;

  graph->addLoopEdge(static_cast<std::uint64_t>(last), static_cast<std::uint64_t>(last - kPerLap),
                     loopMeasurement(route, last, last - kPerLap, rng));
  t0 = processCpuSeconds();
  row.again = graph->solve();
  row.again_cpu_s = processCpuSeconds() - t0;
  row.ate_graph = ate(graph.get(), route);

  // A wrong loop (perceptual aliasing: the newest keyframe "recognises" the keyframe half a lap
  // back as seen from 0.3 m) must be rolled back, leaving the solution as it was.
  Isometry3d alias = Isometry3d::Identity();
  alias.translation() << 0.3, 0.0, 0.0;
  graph->addLoopEdge(static_cast<std::uint64_t>(n - 1),
                     static_cast<std::uint64_t>(n - 1 - kPerLap / 2), alias);
  t0 = processCpuSeconds();
  row.wrong = graph->solve();
  row.wrong_cpu_s = processCpuSeconds() - t0;
  row.ate_after_wrong = ate(graph.get(), route);

  row.ate_odom = ate(nullptr, route);
  return row;
}

std::vector<int> parseSizes(const std::string& s) {
  std::vector<int> out;
  std::stringstream ss(s);
  std::string tok;
  while (std::getline(ss, tok, ',')) out.push_back(std::stoi(tok));
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  std::uint64_t seed = 1;
  std::vector<int> sizes = {1000, 5000};
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--seed" && i + 1 < argc) {
      seed = std::stoull(argv[++i]);
    } else if (a == "--sizes" && i + 1 < argc) {
      sizes = parseSizes(argv[++i]);
    } else {
      std::fprintf(stderr, "usage: bench_pose_graph [--seed N] [--sizes N,N,...]\n");
      return 2;
    }
  }
  for (int n : sizes)
    if (n < 2 * kPerLap) {
      std::fprintf(stderr, "bench_pose_graph: %d keyframes is less than two laps (%d)\n", n,
                   2 * kPerLap);
      return 2;
    }

  std::printf(
      "4-DOF pose graph: racetrack %.1f m per lap, %d keyframes per lap, a loop every %d "
      "keyframes, default [loop] graph_* options, seed %llu\n",
      2.0 * kStraightM + 2.0 * M_PI * kRadiusM, kPerLap, kLoopEvery,
      static_cast<unsigned long long>(seed));
  std::printf("%9s %6s | %9s %8s %4s | %9s %8s %4s | %8s %4s %6s | %9s %8s %8s | %9s %9s\n",
              "keyframes", "loops", "solve[ms]", "cpu[ms]", "iter", "again[ms]", "cpu[ms]", "iter",
              "wrong[ms]", "runs", "rolled", "ATEodo[m]", "ATEpg[m]", "+wrong", "heap/node",
              "graph/node");
  for (int n : sizes) {
    const Row r = run(n, seed);
    std::printf(
        "%9d %6zu | %9.1f %8.1f %4d | %9.1f %8.1f %4d | %8.1f %4d %6zu | %9.3f %8.3f %8.3f | "
        "%7.0f B %8.0f B\n",
        r.nodes, r.loops, 1e3 * r.full.solver_time_s, 1e3 * r.full_cpu_s, r.full.iterations,
        1e3 * r.again.solver_time_s, 1e3 * r.again_cpu_s, r.again.iterations, 1e3 * r.wrong_cpu_s,
        r.wrong.solver_runs, r.wrong.rolled_back_loop_edges.size(), r.ate_odom, r.ate_graph,
        r.ate_after_wrong, r.heap_per_node, r.graph_per_node);
    if (!r.full.rolled_back_loop_edges.empty() || !r.again.rolled_back_loop_edges.empty())
      std::printf("  (a good loop was rolled back)\n");
    if (!r.full.converged || !r.again.converged || !r.wrong.converged)
      std::printf("  (a solve stopped on max_iterations before converging)\n");
  }
  std::printf(
      "solve = wall-clock time in Ceres of solve() from the odometry; cpu = process CPU time of "
      "the whole solve() call (problem set-up and rollback checks included; steadier than wall "
      "clock on a loaded machine); again = one more solve() after adding one loop to the solved "
      "graph; wrong = CPU time of the solve() after adding a wrong loop (runs = Ceres runs, "
      "rolled = loops rolled back); ATE = RMS position error against the truth (odometry, "
      "graph, graph after the wrong loop); heap/node = heap growth while building the graph "
      "(nodes, odometry and loop edges) per keyframe; graph/node = PoseGraph4Dof::memoryBytes() "
      "per keyframe.\n");
  return 0;
}
