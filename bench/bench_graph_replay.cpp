// Replays the pose graph of a finished run (bench_slam --dump PREFIX writes PREFIX.graph): the
// loop keyframes with their odometry and ground-truth poses and the verified loops, solved again
// with the given [loop] graph_* options. Prints the keyframe ATE (position+yaw alignment) of the
// odometry, of the run's own result and of the replay, the error split by degree of freedom
// (horizontal, height, yaw, and the roll/pitch a 4-DOF graph cannot change), and the solve time.
// Used to study the graph's weighting without running the whole system again.
//
//   bench_graph_replay PREFIX.graph [--set key=value ...] [--quality K FLOOR_M] [--errors FILE]
// --set: a [loop] key (graph_* keys are used); --quality K FLOOR_M: loop edges with their own
// position sigma max(FLOOR_M, K * depth RMS / sqrt(depth inliers)) and the yaw sigma scaled alike
// (an experiment: LoopCloser uses the constant graph_loop_sigma_* sigmas).
// --errors writes one line per keyframe: t, travelled [m], then the aligned position error
// x y z [m] and yaw error [deg] of the odometry and of the replay.
#include <chrono>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "rgbdi/common/ini_reader.h"
#include "rgbdi/eval/evaluate.h"
#include "rgbdi/loop/four_dof.h"
#include "rgbdi/loop/pose_graph.h"

using namespace rgbdi;

namespace {

struct Node {
  std::uint64_t id = 0;
  int segment = 0;
  double t = 0, travelled = 0;
  Eigen::Isometry3d odom, run, gt;
};
struct Loop {
  std::uint64_t from = 0, to = 0;
  bool active = true;
  Eigen::Isometry3d T;
  int pnp = 0, depth = 0;
  double reproj_px = 0, depth_rms_m = 0;
};

Eigen::Isometry3d readPose(std::istream& is) {
  Eigen::Vector3d p;
  double qx, qy, qz, qw;
  is >> p.x() >> p.y() >> p.z() >> qx >> qy >> qz >> qw;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::Quaterniond(qw, qx, qy, qz).normalized().toRotationMatrix();
  T.translation() = p;
  return T;
}

Trajectory toTrajectory(const std::vector<Node>& nodes,
                        const std::vector<Eigen::Isometry3d>& poses) {
  Trajectory tr;
  for (std::size_t i = 0; i < nodes.size(); ++i)
    tr.push_back(StampedPose::fromIsometry(nodes[i].t, poses[i]));
  return tr;
}

double deg(double rad) { return rad * 180.0 / M_PI; }

struct Split {
  double ate = 0, xy = 0, z = 0, yaw_deg = 0, tilt_deg = 0;
  std::vector<Eigen::Vector4d> per_node;  ///< x, y, z [m], yaw [deg]
};

/// Aligned errors of `poses` against the ground truth of `nodes`.
Split split(const std::vector<Node>& nodes, const std::vector<Eigen::Isometry3d>& poses) {
  Trajectory gt;
  for (const Node& n : nodes) gt.push_back(StampedPose::fromIsometry(n.t, n.gt));
  eval::EvalOptions eo;
  eo.align = eval::AlignMode::PosYaw;
  const eval::EvalResult r = eval::evaluate(gt, toTrajectory(nodes, poses), eo);
  Split s;
  s.ate = r.ate.rmse;
  const Eigen::Isometry3d A = r.alignment.rigid();
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const Eigen::Isometry3d T = A * poses[i];
    const Eigen::Vector3d e = T.translation() - nodes[i].gt.translation();
    const double yaw = loop::wrapAngle(loop::yawOf(T.linear()) - loop::yawOf(nodes[i].gt.linear()));
    const Eigen::Matrix3d dt =
        loop::tiltOf(T.linear()).transpose() * loop::tiltOf(nodes[i].gt.linear());
    const double tilt = Eigen::AngleAxisd(dt).angle();
    s.xy += e.head<2>().squaredNorm();
    s.z += e.z() * e.z();
    s.yaw_deg += deg(yaw) * deg(yaw);
    s.tilt_deg += deg(tilt) * deg(tilt);
    s.per_node.emplace_back(e.x(), e.y(), e.z(), deg(yaw));
  }
  const double n = static_cast<double>(std::max<std::size_t>(1, nodes.size()));
  s.xy = std::sqrt(s.xy / n);
  s.z = std::sqrt(s.z / n);
  s.yaw_deg = std::sqrt(s.yaw_deg / n);
  s.tilt_deg = std::sqrt(s.tilt_deg / n);
  return s;
}

void print(const char* name, const Split& s) {
  std::cout << std::fixed << std::setprecision(4) << "  " << std::left << std::setw(9) << name
            << " ATE " << s.ate << " m (xy " << s.xy << ", z " << s.z << " m; yaw "
            << std::setprecision(3) << s.yaw_deg << " deg, roll/pitch " << s.tilt_deg << " deg)\n";
}

}  // namespace

int main(int argc, char** argv) {
  try {
    if (argc < 2) throw std::invalid_argument("usage: bench_graph_replay PREFIX.graph [--set k=v]");
    std::string ini_text = "[loop]\n", errors_file;
    double quality_k = 0.0, quality_floor_m = 0.0;
    for (int i = 2; i < argc; ++i) {
      const std::string a = argv[i];
      if (a == "--set" && i + 1 < argc)
        ini_text += std::string(argv[++i]) + "\n";
      else if (a == "--quality" && i + 2 < argc) {
        quality_k = std::stod(argv[++i]);
        quality_floor_m = std::stod(argv[++i]);
      } else if (a == "--errors" && i + 1 < argc)
        errors_file = argv[++i];
      else
        throw std::invalid_argument("unknown argument " + a);
    }
    std::ifstream in(argv[1]);
    if (!in) throw std::runtime_error(std::string("cannot open ") + argv[1]);
    std::vector<Node> nodes;
    std::vector<Loop> loops;
    std::string line;
    while (std::getline(in, line)) {
      std::istringstream is(line);
      std::string tag;
      is >> tag;
      if (tag == "N") {
        Node n;
        is >> n.id >> n.segment >> n.t >> n.travelled;
        n.odom = readPose(is);
        n.run = readPose(is);
        n.gt = readPose(is);
        nodes.push_back(n);
      } else if (tag == "L") {
        Loop l;
        int active = 0;
        is >> l.from >> l.to >> active;
        l.active = active != 0;
        l.T = readPose(is);
        is >> l.pnp >> l.depth >> l.reproj_px >> l.depth_rms_m;
        loops.push_back(l);
      }
    }
    auto ini = IniReader::fromText(ini_text, "--set");
    const loop::PoseGraphOptions opt = loop::PoseGraphOptions::load(ini);

    // Loops are added when their query keyframe arrives and solved at the end (the run solved
    // in between too; to convergence, the final optimum is the same up to local minima).
    loop::PoseGraph4Dof graph(opt);
    std::multimap<std::uint64_t, const Loop*> by_query;
    for (const Loop& l : loops) by_query.emplace(l.to, &l);
    for (const Node& n : nodes) {
      graph.addNode(n.id, n.segment, n.odom);
      const auto range = by_query.equal_range(n.id);
      for (auto it = range.first; it != range.second; ++it)
        if (quality_k > 0.0) {
          const Loop& l = *it->second;
          const double sp = std::max(quality_floor_m,
                                     quality_k * l.depth_rms_m / std::sqrt(std::max(1, l.depth)));
          graph.addLoopEdge(l.from, l.to, l.T, sp,
                            opt.loop_sigma_yaw_deg * M_PI / 180.0 * sp / opt.loop_sigma_pos_m);
        } else {
          graph.addLoopEdge(it->second->from, it->second->to, it->second->T);
        }
    }
    const auto t0 = std::chrono::steady_clock::now();
    const loop::PoseGraphSolveReport rep = graph.solve();
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();

    std::vector<Eigen::Isometry3d> odom, run, replay;
    for (const Node& n : nodes) {
      odom.push_back(n.odom);
      run.push_back(n.run);
      replay.push_back(graph.pose(n.id));
    }
    std::size_t active_run = 0;
    for (const Loop& l : loops) active_run += l.active ? 1 : 0;
    std::cout << argv[1] << ": " << nodes.size() << " keyframes, " << loops.size() << " loops ("
              << active_run << " active in the run, " << rep.active_loop_edges.size()
              << " in the replay), solve " << std::setprecision(1) << std::fixed << ms << " ms, "
              << rep.iterations << " iterations\n";
    const Split so = split(nodes, odom), sr = split(nodes, run), sp = split(nodes, replay);
    print("odometry", so);
    print("run", sr);
    print("replay", sp);
    std::cout << std::setprecision(0) << "  replay / odometry " << 100.0 * sp.ate / so.ate
              << " %\n";
    if (!errors_file.empty()) {
      std::ofstream f(errors_file);
      f << std::setprecision(6);
      for (std::size_t i = 0; i < nodes.size(); ++i)
        f << nodes[i].t << " " << nodes[i].travelled << " " << so.per_node[i].transpose() << " "
          << sp.per_node[i].transpose() << "\n";
    }
  } catch (const std::exception& e) {
    std::cerr << "bench_graph_replay: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
