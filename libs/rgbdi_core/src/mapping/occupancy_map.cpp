#include "rgbdi/mapping/occupancy_map.h"

#include <chrono>
#include <limits>
#include <stdexcept>

#include "mapping/depth_grid_sampler.h"
#include "mapping/pose_check.h"
#include "rgbdi/common/atomic_file.h"

namespace rgbdi::mapping {

struct OccupancyMap::Impl {
  explicit Impl(const MappingOptions& o)
      : options(o),
        sampler(detail::GridRect{o.grid_step_px, o.u_min_px, o.u_max_px, o.v_min_px, o.v_max_px}),
        tree(o.occupancy_resolution_m) {
    tree.setProbHit(o.occupancy_prob_hit);
    tree.setProbMiss(o.occupancy_prob_miss);
  }

  MappingOptions options;
  detail::DepthGridSampler sampler;
  octomap::OcTree tree;
  OccupancyStats stats;
  std::vector<MapPoint> scratch;
  bool inner_nodes_stale = false;

  /// Brings the inner nodes up to date with the leaves (needed by pruning, queries at coarse
  /// depth, the max-likelihood file and octovis).
  const octomap::OcTree& finish() {
    if (inner_nodes_stale) {
      tree.updateInnerOccupancy();
      inner_nodes_stale = false;
    }
    return tree;
  }

  void castRays(const std::vector<MapPoint>& points_cam, const Eigen::Isometry3d& T_world_cam) {
    const auto start = std::chrono::steady_clock::now();
    octomap::Pointcloud cloud;
    cloud.reserve(points_cam.size());
    for (const MapPoint& p : points_cam) {
      const Eigen::Vector3d w = T_world_cam * p.p_cam.cast<double>();
      cloud.push_back(static_cast<float>(w.x()), static_cast<float>(w.y()),
                      static_cast<float>(w.z()));
    }
    const Eigen::Vector3d o = T_world_cam.translation();
    // Max range: far readings only clear space up to the trusted depth. Discretize: rays
    // ending in the same voxel are cast once. Lazy evaluation: inner nodes are refreshed once
    // before the tree is read (finish()), not after every cell update (about 5x faster).
    tree.insertPointCloud(cloud, octomap::point3d(static_cast<float>(o.x()), static_cast<float>(o.y()),
                                                  static_cast<float>(o.z())),
                          options.depth_max_m, /*lazy_eval=*/true, /*discretize=*/true);
    inner_nodes_stale = true;
    ++stats.scans;
    stats.rays += points_cam.size();
    stats.seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
};

OccupancyMap::OccupancyMap(const MappingOptions& options) {
  options.validate();
  impl_ = std::make_unique<Impl>(options);
}

OccupancyMap::~OccupancyMap() = default;
OccupancyMap::OccupancyMap(OccupancyMap&&) noexcept = default;
OccupancyMap& OccupancyMap::operator=(OccupancyMap&&) noexcept = default;

void OccupancyMap::insert(const RgbdFrame& frame, const Eigen::Isometry3d& T_world_cam) {
  if (!detail::isRigid(T_world_cam))
    throw std::invalid_argument("OccupancyMap::insert: " + detail::frameLabel(frame) +
                                ": T_world_cam is not a finite rigid transform");
  Impl& m = *impl_;
  detail::GridSampleCounts counts;
  m.scratch.clear();
  m.sampler.sample(frame, m.options.occupancy_grid_stride, m.options.depth_min_m,
                   std::numeric_limits<double>::infinity(), m.scratch, counts);
  m.castRays(m.scratch, T_world_cam);
}

void OccupancyMap::insertPoints(const std::vector<MapPoint>& points_cam,
                                const Eigen::Isometry3d& T_world_cam) {
  if (!detail::isRigid(T_world_cam))
    throw std::invalid_argument("OccupancyMap::insertPoints: T_world_cam is not a finite rigid transform");
  impl_->castRays(points_cam, T_world_cam);
}

void OccupancyMap::rebuild(const KeyframeStore& store) {
  clear();
  for (const Keyframe& kf : store.keyframes()) impl_->castRays(kf.points, kf.T_world_cam);
}

void OccupancyMap::clear() {
  impl_->tree.clear();
  impl_->stats = OccupancyStats{};
  impl_->inner_nodes_stale = false;
}

void OccupancyMap::write(const std::string& path) const {
  writeFileAtomically(path, [&](std::ostream& os) {
    if (!impl_->finish().writeBinaryConst(os)) throw IoError(path + ": OctoMap could not write the tree");
  });
}

const octomap::OcTree& OccupancyMap::tree() const { return impl_->finish(); }
std::size_t OccupancyMap::leafCount() const { return impl_->tree.getNumLeafNodes(); }
const OccupancyStats& OccupancyMap::stats() const { return impl_->stats; }
std::size_t OccupancyMap::memoryBytes() const {
  return sizeof(OccupancyMap) + sizeof(Impl) + impl_->tree.memoryUsage() +
         impl_->scratch.capacity() * sizeof(MapPoint);
}

}  // namespace rgbdi::mapping
