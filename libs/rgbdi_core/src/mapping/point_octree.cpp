#include "mapping/point_octree.h"

#include <array>

namespace rgbdi::mapping::detail {

void PointLeafNode::releaseEmptyChildArray() {
  delete[] children;
  children = nullptr;
}

bool PointLeafNode::hasAnyChild() const {
  if (children == nullptr) return false;
  for (int i = 0; i < 8; ++i)
    if (children[i] != nullptr) return true;
  return false;
}

PointLeafNode* PointOctree::touchLeaf(const octomap::OcTreeKey& key) {
  if (root == nullptr) {
    root = new PointLeafNode();
    ++tree_size;
    size_changed = true;
  }
  // Level i below the root is selected by bit (tree_depth - 1 - i) of the key (OctoMap's
  // convention, so OctoMap's keyToCoord/search agree with this tree).
  const unsigned shift = tree_depth - kCachedLevel;
  const bool same_block = cached_block_ != nullptr &&
                          (key[0] >> shift) == (cached_block_key_[0] >> shift) &&
                          (key[1] >> shift) == (cached_block_key_[1] >> shift) &&
                          (key[2] >> shift) == (cached_block_key_[2] >> shift);
  PointLeafNode* node = same_block ? cached_block_ : root;
  for (int bit = static_cast<int>(same_block ? shift : tree_depth) - 1; bit >= 0; --bit) {
    const unsigned child = octomap::computeChildIdx(key, bit);
    node = nodeChildExists(node, child) ? getNodeChild(node, child) : createNodeChild(node, child);
    if (bit == static_cast<int>(shift)) {
      cached_block_ = node;
      cached_block_key_ = key;
    }
  }
  return node;
}

bool PointOctree::eraseLeaf(const octomap::OcTreeKey& key) {
  if (root == nullptr) return false;
  cached_block_ = nullptr;  // the cached ancestor may be deleted below
  std::array<PointLeafNode*, 17> path{};  // root .. leaf (tree_depth is 16)
  std::array<unsigned, 17> child_of{};
  path[0] = root;
  for (unsigned level = 0; level < tree_depth; ++level) {
    const unsigned child = octomap::computeChildIdx(key, static_cast<int>(tree_depth - 1 - level));
    if (!nodeChildExists(path[level], child)) return false;
    child_of[level] = child;
    path[level + 1] = getNodeChild(path[level], child);
  }
  // Delete upwards while the node just emptied has no other child.
  for (int level = static_cast<int>(tree_depth); level >= 1; --level) {
    PointLeafNode* node = path[static_cast<std::size_t>(level)];
    if (node->hasAnyChild()) break;
    node->releaseEmptyChildArray();
    deleteNodeChild(path[static_cast<std::size_t>(level - 1)],
                    child_of[static_cast<std::size_t>(level - 1)]);
  }
  if (!root->hasAnyChild()) {
    root->releaseEmptyChildArray();
    delete root;
    root = nullptr;
    tree_size = 0;
    size_changed = true;
  }
  return true;
}

void PointOctree::clearAll() {
  cached_block_ = nullptr;
  clear();
}

std::size_t PointOctree::nodeBytes(std::size_t leaf_count) const {
  const std::size_t inner = tree_size > leaf_count ? tree_size - leaf_count : 0;
  return sizeof(*this) + tree_size * sizeof(PointLeafNode) + inner * 8 * sizeof(PointLeafNode*);
}

}  // namespace rgbdi::mapping::detail
