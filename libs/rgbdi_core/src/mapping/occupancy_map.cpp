#include "rgbdi/mapping/occupancy_map.h"

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <utility>

#include "mapping/depth_grid_sampler.h"
#include "mapping/pose_check.h"
#include "rgbdi/common/atomic_file.h"
#include "rgbdi/mapping/occupancy_cells.h"

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
  detail::OccupancyTree tree;
  OccupancyStats stats;
  std::vector<MapPoint> scratch;
  std::vector<octomap::point3d> rays, hits_only;  ///< castRays' buffers
  detail::ScanCells cells;
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

  /// Ray casts every `ray_every`-th point (in the given order) from the camera centre; the
  /// other points only mark their endpoint cells occupied. A keyframe's kept points are the
  /// whole sampling grid less full leaves, so casting all of them carves the same free space
  /// several times over (neighbouring rays cross the same cells near the camera): a fraction of
  /// the rays carves nearly the same space at a fraction of the cost, and every point still
  /// marks its surface cell.
  void castRays(const std::vector<MapPoint>& points_cam, const Eigen::Isometry3d& T_world_cam,
                std::size_t ray_every) {
    const auto start = std::chrono::steady_clock::now();
    const Eigen::Vector3d o = T_world_cam.translation();
    const octomap::point3d origin(static_cast<float>(o.x()), static_cast<float>(o.y()),
                                  static_cast<float>(o.z()));
    rays.clear();
    hits_only.clear();
    for (std::size_t i = 0; i < points_cam.size(); ++i) {
      const Eigen::Vector3d w = T_world_cam * points_cam[i].p_cam.cast<double>();
      const octomap::point3d pw(static_cast<float>(w.x()), static_cast<float>(w.y()),
                                static_cast<float>(w.z()));
      if (i % ray_every == 0) {
        rays.push_back(pw);
      } else {
        hits_only.push_back(pw);
      }
    }
    // As OcTree::insertPointCloud: discretised endpoints (rays ending in the same voxel are cast
    // once), max range (farther readings only clear space up to the trusted depth), occupied
    // wins over free within one scan, lazy inner-node updates (refreshed once by finish()).
    // Each cell is updated once per scan (the free and occupied cells are disjoint), so the
    // order of the updates does not change the tree: in Morton order consecutive cells share
    // their path from the root.
    cells.compute(tree, origin, rays, hits_only, options.depth_max_m);
    tree.updateSorted(cells.freeCells(), tree.getProbMissLog());
    tree.updateSorted(cells.occupiedCells(), tree.getProbHitLog());
    inner_nodes_stale = true;
    ++stats.scans;
    stats.rays += rays.size();
    stats.seconds +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }

  /// Every how many kept points a ray is cast: occupancy_grid_stride in both image directions.
  std::size_t keptPointRayStep() const {
    return static_cast<std::size_t>(options.occupancy_grid_stride) *
           static_cast<std::size_t>(options.occupancy_grid_stride);
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
  m.castRays(m.scratch, T_world_cam, 1);  // the sampler already applied the stride
}

void OccupancyMap::insertPoints(const std::vector<MapPoint>& points_cam,
                                const Eigen::Isometry3d& T_world_cam) {
  if (!detail::isRigid(T_world_cam))
    throw std::invalid_argument(
        "OccupancyMap::insertPoints: T_world_cam is not a finite rigid transform");
  impl_->castRays(points_cam, T_world_cam, impl_->keptPointRayStep());
}

void OccupancyMap::rebuild(const KeyframeStore& store) {
  clear();
  for (const Keyframe& kf : store.keyframes())
    impl_->castRays(kf.points, kf.T_world_cam, impl_->keptPointRayStep());
  // A rebuild is the end-of-run pass (Mapper::finish): its work buffers (several MB for the
  // largest scan) would otherwise stay allocated while the outputs are written, the run's peak.
  impl_->cells = detail::ScanCells();
  std::vector<octomap::point3d>().swap(impl_->rays);
  std::vector<octomap::point3d>().swap(impl_->hits_only);
}

void OccupancyMap::clear() {
  impl_->tree.clear();
  impl_->stats = OccupancyStats{};
  impl_->inner_nodes_stale = false;
}

void OccupancyMap::write(const std::string& path) const {
  writeFileAtomically(path, [&](std::ostream& os) {
    // OctoMap's writeBinaryConst writes this header and the nodes, then prints " done." on
    // stderr (Debian's liboctomap is built with its debug messages on): one stray line per .bt
    // file on the console. The header of the .bt format is written here and the nodes by
    // writeBinaryData, which prints nothing; the bytes are writeBinaryConst's (test).
    const octomap::OcTree& t = impl_->finish();
    os << "# Octomap OcTree binary file\n"
       << "# (feel free to add / change comments, but leave the first line as it is!)\n#\n"
       << "id " << t.getTreeType() << "\n"
       << "size " << t.size() << "\n"
       << "res " << t.getResolution() << "\n"
       << "data\n";
    t.writeBinaryData(os);
    if (!os.good()) throw IoError(path + ": OctoMap could not write the tree");
  });
}

const octomap::OcTree& OccupancyMap::tree() const { return impl_->finish(); }
std::size_t OccupancyMap::leafCount() const { return impl_->tree.getNumLeafNodes(); }
const OccupancyStats& OccupancyMap::stats() const { return impl_->stats; }
std::size_t OccupancyMap::memoryBytes() const {
  return sizeof(OccupancyMap) + sizeof(Impl) + impl_->tree.memoryUsage() +
         impl_->scratch.capacity() * sizeof(MapPoint) +
         (impl_->rays.capacity() + impl_->hits_only.capacity()) * sizeof(octomap::point3d) +
         impl_->cells.memoryBytes();
}

}  // namespace rgbdi::mapping
