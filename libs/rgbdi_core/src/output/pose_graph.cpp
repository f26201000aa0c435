#include "rgbdi/output/pose_graph.h"

#include <mrpt/graphs/CNetworkOfPoses.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/poses/CPose3DPDFGaussianInf.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

#include "output/number_format.h"
#include "rgbdi/common/atomic_file.h"
#include "rgbdi/output/pose_graph_information.h"

namespace rgbdi::output {
namespace {

// rgbdi annotations, written as comment lines that MRPT's parser skips:
//   "# rgbdi-node <id> <t>"
//   "# rgbdi-edge <from> <to> <kind> <21 upper-triangle entries of the rgbdi information>"
// The edge information is repeated here because MRPT 2.5's loader zeroes the yaw-pitch, yaw-roll
// and pitch-roll information entries of EDGE3 / EDGE_SE3:QUAT lines (it stores them in the lower
// triangle, then overwrites the lower triangle from the still-empty upper one).
const char* const kNodeTag = "# rgbdi-node";
const char* const kEdgeTag = "# rgbdi-edge";
constexpr int kStampDecimals = 9;  // ns, as in the TUM files

struct EdgeAnnotation {
  std::string kind;
  Matrix6d information;
};
constexpr int kDigits = std::numeric_limits<double>::max_digits10;
// Tolerances for accepting caller data (rounding, not tuning): R^T R = I and info = info^T.
constexpr double kRotationTolerance = 1e-6;
constexpr double kSymmetryTolerance = 1e-9;  // relative to the largest entry

mrpt::poses::CPose3D toMrpt(const Eigen::Isometry3d& T) {
  return mrpt::poses::CPose3D(mrpt::math::CMatrixDouble33(Eigen::Matrix3d(T.linear())),
                              mrpt::math::CVectorFixedDouble<3>(Eigen::Vector3d(T.translation())));
}

Eigen::Isometry3d fromMrpt(const mrpt::poses::CPose3D& p) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = p.getRotationMatrix().asEigen();
  T.translation() = Eigen::Vector3d(p.x(), p.y(), p.z());
  return T;
}

bool isRigid(const Eigen::Isometry3d& T) {
  return T.matrix().allFinite() &&
         (T.linear().transpose() * T.linear() - Eigen::Matrix3d::Identity()).norm() <
             kRotationTolerance &&
         T.linear().determinant() > 0.0;
}

std::string edgeName(const PoseGraphEdge& e) {
  return "edge " + std::to_string(e.from) + "->" + std::to_string(e.to);
}

void validate(const std::string& path, const std::vector<PoseGraphNode>& nodes,
              const std::vector<PoseGraphEdge>& edges) {
  const std::string where = "writePoseGraph " + path + ": ";
  std::set<std::uint64_t> ids;
  for (const auto& n : nodes) {
    const std::string name = "node " + std::to_string(n.id);
    if (!ids.insert(n.id).second) throw std::invalid_argument(where + "duplicate " + name);
    if (!std::isfinite(n.t)) throw std::invalid_argument(where + name + " has a non-finite stamp");
    if (!isRigid(n.T_world_body)) {
      throw std::invalid_argument(where + name + " pose is not a finite rigid transform");
    }
  }
  for (const auto& e : edges) {
    if (!ids.count(e.from) || !ids.count(e.to)) {
      throw std::invalid_argument(where + edgeName(e) +
                                  " refers to a node that is not in the graph");
    }
    if (e.from == e.to)
      throw std::invalid_argument(where + edgeName(e) + " connects a node to itself");
    if (e.kind != "odometry" && e.kind != "loop") {
      throw std::invalid_argument(where + edgeName(e) + " has kind '" + e.kind +
                                  "' (expected odometry or loop)");
    }
    if (!isRigid(e.T_from_to)) {
      throw std::invalid_argument(where + edgeName(e) + " pose is not a finite rigid transform");
    }
    const double scale = e.information.cwiseAbs().maxCoeff();
    if (!e.information.allFinite() ||
        (e.information - e.information.transpose()).cwiseAbs().maxCoeff() >
            kSymmetryTolerance * scale) {
      throw std::invalid_argument(where + edgeName(e) + " information is not finite and symmetric");
    }
    const double cos_pitch = std::cos(mrptYawPitchRoll(e.T_from_to.linear())(1));
    if (std::abs(cos_pitch) < kMinCosPitch) {
      throw std::invalid_argument(
          where + edgeName(e) +
          " is pitched at +-90 deg, where MRPT's yaw/pitch/roll information "
          "is singular");
    }
  }
}

// MRPT's exception text is a multi-line report; keep the line that says what went wrong.
std::string mrptReason(const std::exception& e) {
  std::istringstream lines(e.what());
  std::string line, first;
  while (std::getline(lines, line)) {
    if (line.find("Line ") != std::string::npos) return line.substr(line.find("Line "));
    if (first.empty() && line.find_first_not_of(" =") != std::string::npos) first = line;
  }
  return first;
}

}  // namespace

void writePoseGraph(const std::string& path, const std::vector<PoseGraphNode>& nodes,
                    const std::vector<PoseGraphEdge>& edges) {
  validate(path, nodes, edges);

  mrpt::graphs::CNetworkOfPoses3DInf graph;
  for (const auto& n : nodes) graph.nodes[n.id] = toMrpt(n.T_world_body);
  if (!nodes.empty()) graph.root = nodes.front().id;
  // Annotations in the order MRPT will write the edges: its multimap keeps insertion order among
  // equal (from, to) keys, and readPoseGraph pairs them up the same way.
  std::multimap<std::pair<std::uint64_t, std::uint64_t>, const PoseGraphEdge*> annotations;
  for (const auto& e : edges) {
    const mrpt::poses::CPose3D mean = toMrpt(e.T_from_to);
    const Matrix6d info = informationToMrpt(e.information, e.T_from_to.linear());
    graph.insertEdge(e.from, e.to,
                     mrpt::poses::CPose3DPDFGaussianInf(mean, mrpt::math::CMatrixDouble66(info)));
    annotations.emplace(std::make_pair(e.from, e.to), &e);
  }

  writeFileAtomically(path, [&](std::ostream& os) {
    os << "# rgbdi pose graph: mrpt::graphs::CNetworkOfPoses3DInf text format (VERTEX3/EDGE3:\n"
       << "# x y z roll pitch yaw; information upper triangle in that order). Node = "
          "T_world_body.\n"
       << "# Annotations: rgbdi-node id t; rgbdi-edge from to kind + information upper triangle "
          "in\n"
       << "# (x y z rotation-vector) order, rotation perturbation right-multiplied "
          "(doc/evaluation.md).\n";
    os.precision(kDigits);
    for (const auto& n : nodes)
      os << kNodeTag << ' ' << n.id << ' ' << fixedDecimals(n.t, kStampDecimals) << '\n';
    for (const auto& [ids, e] : annotations) {
      os << kEdgeTag << ' ' << ids.first << ' ' << ids.second << ' ' << e->kind;
      for (int r = 0; r < 6; ++r) {
        for (int c = r; c < 6; ++c) os << ' ' << shortestRoundTrip(e->information(r, c));
      }
      os << '\n';
    }
    graph.writeAsText(os);  // MRPT's own writer, at the stream's full precision
  });
}

PoseGraph readPoseGraph(const std::string& path) {
  if (!std::ifstream(path).good()) throw IoError(path + ": cannot open pose graph");
  mrpt::graphs::CNetworkOfPoses3DInf graph;
  try {
    graph.loadFromTextFile(path, /*collapse_dup_edges=*/false);
  } catch (const std::exception& e) {
    throw IoError(path + ": MRPT cannot load the pose graph: " + mrptReason(e));
  }

  // rgbdi annotations (stamps and kinds) from the comment lines.
  std::map<std::uint64_t, double> stamps;
  std::multimap<std::pair<std::uint64_t, std::uint64_t>, EdgeAnnotation> annotations;
  {
    std::ifstream in(path);
    std::string line;
    std::size_t line_no = 0;
    while (std::getline(in, line)) {
      ++line_no;
      const bool is_node = line.rfind(kNodeTag, 0) == 0;
      const bool is_edge = line.rfind(kEdgeTag, 0) == 0;
      if (!is_node && !is_edge) continue;
      std::istringstream is(line.substr(std::string(is_node ? kNodeTag : kEdgeTag).size()));
      std::uint64_t a = 0, b = 0;
      double t = 0.0;
      EdgeAnnotation note;
      bool ok =
          is_node ? static_cast<bool>(is >> a >> t) : static_cast<bool>(is >> a >> b >> note.kind);
      for (int r = 0; ok && !is_node && r < 6; ++r) {
        for (int c = r; ok && c < 6; ++c) {
          ok = static_cast<bool>(is >> note.information(r, c));
          note.information(c, r) = note.information(r, c);
        }
      }
      std::string rest;
      if (!ok || (is >> rest)) {
        throw IoError(path + ":" + std::to_string(line_no) + ": malformed rgbdi annotation: '" +
                      line + "'");
      }
      if (is_node)
        stamps[a] = t;
      else
        annotations.emplace(std::make_pair(a, b), note);
    }
  }

  PoseGraph g;
  g.root = graph.root;
  for (const auto& [id, pose] : graph.nodes) {
    PoseGraphNode n;
    n.id = id;
    const auto it = stamps.find(id);
    n.t = it != stamps.end() ? it->second : std::numeric_limits<double>::quiet_NaN();
    n.T_world_body = fromMrpt(pose);
    g.nodes.push_back(n);
  }
  for (const auto& [ids, pdf] : graph.edges) {
    PoseGraphEdge e;
    e.from = ids.first;
    e.to = ids.second;
    e.T_from_to = fromMrpt(pdf.mean);
    const auto note = annotations.find(ids);
    if (note != annotations.end()) {
      e.kind = note->second.kind;
      e.information = note->second.information;
      annotations.erase(note);  // the next edge with the same ids takes the next annotation
    } else {
      // Foreign file: only what MRPT loaded (see the note on MRPT 2.5 at the top).
      e.kind = "unknown";
      try {
        e.information = informationFromMrpt(pdf.cov_inv.asEigen(), e.T_from_to.linear());
      } catch (const std::domain_error& err) {
        throw IoError(path + ": " + edgeName(e) + ": " + err.what());
      }
    }
    g.edges.push_back(e);
  }
  return g;
}

}  // namespace rgbdi::output
