// Depth samples thinned to one point per voxel (the mean of the samples in it) with a hash of
// cells for nearest-neighbour queries within a radius: the 3-D side of geometric
// relocalisation (ICP refinement of a plan fit).
#pragma once

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace rgbdi::reloc {

class PointIndex {
 public:
  PointIndex() = default;
  /// `voxel_m`: thinning; `cell_m`: the hash cell (queries look in the 27 cells around a point,
  /// so a query radius up to cell_m is exact).
  PointIndex(const std::vector<Eigen::Vector3d>& points, double voxel_m, double cell_m);
  /// The same with, per point, the unit direction from it towards the camera that saw it:
  /// averaged per voxel (views()), and each normal turned to face that side (n . view >= 0),
  /// so that a surface seen from its other side can be told apart (ICP pairs only faces both
  /// sides saw).
  PointIndex(const std::vector<Eigen::Vector3d>& points,
             const std::vector<Eigen::Vector3d>& view_directions, double voxel_m, double cell_m);
  const std::vector<Eigen::Vector3d>& points() const { return points_; }
  /// Unit surface normal of each point from its neighbours within cell_m (principal axis of
  /// least spread); zero where fewer than 5 neighbours or no clear surface.
  const std::vector<Eigen::Vector3d>& normals() const { return normals_; }
  /// Unit mean direction towards the cameras that saw each point (empty when built without).
  const std::vector<Eigen::Vector3d>& views() const { return views_; }
  /// Index of the nearest thinned point within max_distance_m (<= cell_m) of p; -1 when none.
  long nearest(const Eigen::Vector3d& p, double max_distance_m) const;
  /// The points thinned to one mean per voxel (deterministic order: first seen first).
  static std::vector<Eigen::Vector3d> thin(const std::vector<Eigen::Vector3d>& points,
                                           double voxel_m);
  /// The same, with a value per point (e.g. its keyframe's path from the anchor) averaged per
  /// voxel into *values_out (one per thinned point).
  static std::vector<Eigen::Vector3d> thin(const std::vector<Eigen::Vector3d>& points,
                                           const std::vector<double>& values, double voxel_m,
                                           std::vector<double>* values_out);
  /// The same with a vector per point (e.g. its direction towards its camera), summed per
  /// voxel and normalised into *values_out (zero where they cancel).
  static std::vector<Eigen::Vector3d> thinDirections(const std::vector<Eigen::Vector3d>& points,
                                                     const std::vector<Eigen::Vector3d>& directions,
                                                     double voxel_m,
                                                     std::vector<Eigen::Vector3d>* directions_out);

 private:
  static std::int64_t key(const Eigen::Vector3i& c);
  Eigen::Vector3i cellOf(const Eigen::Vector3d& p) const;
  void index();
  double cell_m_ = 0.1;
  std::vector<Eigen::Vector3d> points_, normals_, views_;
  std::unordered_map<std::int64_t, std::vector<std::uint32_t>> cells_;
};

}  // namespace rgbdi::reloc
