// The occupancy map's per-scan work without OctoMap's hash sets: a scan's free and occupied cells
// are collected as Morton codes in flat arrays (OctoMap's KeySet allocates a node per cell and
// visits them in hash order), then applied to the tree in Morton order along a cached path from
// the root (OcTree::updateNode searches the key and descends again from the root for every
// cell). The resulting tree is the one OctoMap's own calls give, leaf for leaf
// (test_occupancy_map).
#pragma once

#include <octomap/OcTree.h>

#include <cstdint>
#include <vector>

namespace rgbdi::mapping::detail {

/// A set of Morton codes (open addressing, linear probing) that remembers its codes in insertion
/// order. The table is kept between uses: clear() empties it without freeing.
/// Sorts Morton codes (< 2^48) ascending; `scratch` is a work buffer kept by the caller.
void sortMortonCodes(std::vector<std::uint64_t>& codes, std::vector<std::uint64_t>& scratch);

class MortonSet {
 public:
  /// Adds `code` (< 2^48); true when it was not in the set yet.
  bool insert(std::uint64_t code);
  void clear();
  /// The codes in insertion order (sortable in place: the table does not refer to them).
  std::vector<std::uint64_t>& codes() { return codes_; }
  const std::vector<std::uint64_t>& codes() const { return codes_; }
  std::size_t memoryBytes() const;

 private:
  void grow();
  std::vector<std::uint64_t> table_;  ///< kEmpty or a code; size a power of two
  std::vector<std::uint64_t> codes_;
  std::vector<std::uint32_t> slots_;  ///< table slot of each code (clear() empties only these)
};

/// One scan's cell updates, as OcTree::insertPointCloud with discretize = true computes them
/// (OcTree::computeDiscreteUpdate): ray endpoints falling into one voxel are cast once, to the
/// voxel's centre; endpoints within max_range mark their cell occupied and the cells the ray
/// crosses free; farther ones only clear the ray's first max_range metres; occupied wins over
/// free. `hits` are endpoints that only mark their cell occupied (within max_range), no ray.
class ScanCells {
 public:
  void compute(const octomap::OcTree& tree, const octomap::point3d& origin,
               const std::vector<octomap::point3d>& rays, const std::vector<octomap::point3d>& hits,
               double max_range);
  /// Morton codes, ascending, disjoint.
  const std::vector<std::uint64_t>& freeCells() const { return free_; }
  const std::vector<std::uint64_t>& occupiedCells() const { return occupied_.codes(); }
  /// Work buffers kept between scans.
  std::size_t memoryBytes() const;

 private:
  MortonSet endpoints_, free_set_, occupied_;
  std::vector<std::uint64_t> free_, sort_scratch_;
  octomap::KeyRay ray_;
};

/// OctoMap's occupancy tree with a batch update for Morton-sorted cells.
class OccupancyTree : public octomap::OcTree {
 public:
  explicit OccupancyTree(double resolution) : octomap::OcTree(resolution) {}

  /// updateNode(key, log_odds_update, lazy_eval = true) for every cell, in the given order
  /// (ascending Morton codes, each once): the same tree, leaf values and node structure, with
  /// each descent starting where the path of the previous cell branches off.
  void updateSorted(const std::vector<std::uint64_t>& codes, float log_odds_update);
};

}  // namespace rgbdi::mapping::detail
