// Pose graphs saved as MRPT `mrpt::graphs::CNetworkOfPoses3DInf` text files (.graph), the format
// MRPT's graph-slam tools open. MRPT 2.5 writes it as TORO-style VERTEX3 / EDGE3 lines (x y z roll
// pitch yaw, 21 upper-triangle information entries); its loader also reads VERTEX_SE3:QUAT /
// EDGE_SE3:QUAT. rgbdi adds '#' comment lines (ignored by MRPT) carrying node timestamps, edge
// kinds and the edge information in the rgbdi convention, so readPoseGraph restores everything
// writePoseGraph was given.
// MRPT 2.5 limitation: its text loader zeroes the yaw-pitch, yaw-roll and pitch-roll information
// entries; MRPT tools therefore see those three cross terms as 0 (all other entries are exact).
// readPoseGraph takes the information from the rgbdi annotation and is not affected.
//
// Information convention of PoseGraphEdge::information (6x6, order x y z rx ry rz): inverse
// covariance of the perturbation (dt, dtheta) of T_from_to where the perturbed edge is
//   translation t + dt (dt in the `from` frame),  rotation R * Exp(dtheta) (dtheta a rotation
//   vector in the `to` frame, i.e. right-multiplied).
// MRPT stores the information of the 6-vector (x, y, z, yaw, pitch, roll) instead; the conversion
// (pose_graph_information.h) is exact for the linearisation at the edge's mean.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "rgbdi/common/atomic_file.h"  // IoError

namespace rgbdi::output {

struct PoseGraphNode {
  std::uint64_t id = 0;
  double t = 0.0;  ///< [s] stamp of the keyframe; NaN after reading a file without rgbdi stamps
  Eigen::Isometry3d T_world_body = Eigen::Isometry3d::Identity();
};

struct PoseGraphEdge {
  std::uint64_t from = 0;
  std::uint64_t to = 0;
  Eigen::Isometry3d T_from_to = Eigen::Isometry3d::Identity();
  /// Information in (x, y, z, rotation vector) order, see the file comment.
  Eigen::Matrix<double, 6, 6> information = Eigen::Matrix<double, 6, 6>::Identity();
  std::string kind =
      "odometry";  ///< "odometry" or "loop" ("unknown" when read from a foreign file)
};

struct PoseGraph {
  std::vector<PoseGraphNode> nodes;  ///< ordered by id
  std::vector<PoseGraphEdge> edges;  ///< ordered by (from, to), file order among equal pairs
  std::uint64_t root = 0;            ///< node held fixed (MRPT "FIX" line)
};

/// Builds a CNetworkOfPoses3DInf (root = first node) and writes it with MRPT's own text writer at
/// full precision into a temporary file renamed over `path`. Throws std::invalid_argument (naming
/// the file and the node/edge) for duplicate node ids, edges to unknown nodes or to themselves
/// (MRPT would drop them), non-finite or non-rigid poses, non-symmetric or non-finite
/// information, an unknown kind, or an edge pitched within 0.01 deg of +-90 deg (MRPT's
/// yaw/pitch/roll information is singular there); IoError when the file cannot be written.
void writePoseGraph(const std::string& path, const std::vector<PoseGraphNode>& nodes,
                    const std::vector<PoseGraphEdge>& edges);

/// Loads a .graph text file with MRPT's loadFromTextFile (duplicate edges kept): nodes, root and
/// edge poses from MRPT; stamps, kinds and information from the rgbdi annotations when present,
/// otherwise the information is MRPT's, converted to the rgbdi convention. Throws IoError naming
/// the file (and the line) when the file is missing or malformed.
PoseGraph readPoseGraph(const std::string& path);

}  // namespace rgbdi::output
