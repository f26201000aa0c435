// The point map's octree: OctoMap's key arithmetic and node storage (OcTreeBase) with a node
// type whose payload is the index of the leaf's record in the point map. Insertion and deletion
// descents are written here because OctoMap's generic ones assume occupancy nodes (deleteNode
// calls updateOccupancyChildren and leaves the child array of an emptied inner node behind).
#pragma once

#include <octomap/OcTreeBase.h>
#include <octomap/OcTreeDataNode.h>
#include <octomap/OcTreeKey.h>

#include <cstdint>
#include <limits>
#include <string>

namespace rgbdi::mapping::detail {

inline constexpr std::uint32_t kNoLeaf = std::numeric_limits<std::uint32_t>::max();

class PointLeafNode : public octomap::OcTreeDataNode<std::uint32_t> {
 public:
  PointLeafNode() : octomap::OcTreeDataNode<std::uint32_t>(kNoLeaf) {}
  /// Required by OcTreeBaseImpl's generic code; inner nodes carry no aggregate.
  void updateOccupancyChildren() {}
  /// Frees the (all-empty) child pointer array so the node can be deleted without a leak.
  void releaseEmptyChildArray();
  bool hasAnyChild() const;
};

class PointOctree : public octomap::OcTreeBase<PointLeafNode> {
 public:
  explicit PointOctree(double resolution) : octomap::OcTreeBase<PointLeafNode>(resolution) {}
  std::string getTreeType() const { return "rgbdi::PointOctree"; }

  /// The leaf node (finest depth) of `key`, created with its missing ancestors if needed.
  PointLeafNode* touchLeaf(const octomap::OcTreeKey& key);
  /// Deletes the leaf of `key` and every ancestor left without children (the root included:
  /// the tree is then empty). Returns false when there is no such leaf.
  bool eraseLeaf(const octomap::OcTreeKey& key);
  /// Bytes of nodes and child arrays (tree_size is maintained by OcTreeBaseImpl).
  std::size_t nodeBytes(std::size_t leaf_count) const;
  /// Empties the tree (and the descent cache).
  void clearAll();

 private:
  // Consecutive insertions are spatially coherent (one keyframe's points): the descent starts
  // at the ancestor block of the previous leaf when the new key lies in the same block.
  static constexpr unsigned kCachedLevel = 11;  // levels below the root: 2^5 leaves per block side
  PointLeafNode* cached_block_ = nullptr;
  octomap::OcTreeKey cached_block_key_;
};

}  // namespace rgbdi::mapping::detail
