#include "rgbdi/mapping/occupancy_cells.h"

#include <algorithm>
#include <iterator>

#include "rgbdi/mapping/morton_code.h"

namespace rgbdi::mapping::detail {
namespace {
// Morton codes use 48 bits: all ones marks an empty slot.
constexpr std::uint64_t kEmpty = ~std::uint64_t{0};
constexpr std::size_t kInitialSlots = std::size_t{1} << 12;

std::size_t slotOf(std::uint64_t code, std::size_t mask) {
  // Fibonacci hashing: neighbouring cells (codes differing in low bits) spread over the table.
  return static_cast<std::size_t>((code * 0x9E3779B97F4A7C15ull) >> 20) & mask;
}
}  // namespace

void sortMortonCodes(std::vector<std::uint64_t>& codes, std::vector<std::uint64_t>& scratch) {
  // LSD radix sort, 8 bits per pass over the 48 code bits. A scan's cells lie close together,
  // so the high digits are mostly one value: passes whose digit is the same for every code are
  // skipped (all six histograms come from one read).
  constexpr int kPasses = 6;
  const std::size_t n = codes.size();
  if (n < 2) return;
  std::uint32_t count[kPasses][256] = {};
  for (std::uint64_t c : codes)
    for (int p = 0; p < kPasses; ++p) ++count[p][(c >> (8 * p)) & 0xFF];
  scratch.resize(n);
  std::uint64_t* from = codes.data();
  std::uint64_t* to = scratch.data();
  for (int p = 0; p < kPasses; ++p) {
    std::uint32_t* bucket = count[p];
    if (bucket[(from[0] >> (8 * p)) & 0xFF] == n) continue;  // one digit value: already in order
    std::uint32_t offset = 0;
    for (int d = 0; d < 256; ++d) {
      const std::uint32_t c = bucket[d];
      bucket[d] = offset;
      offset += c;
    }
    for (std::size_t i = 0; i < n; ++i) to[bucket[(from[i] >> (8 * p)) & 0xFF]++] = from[i];
    std::swap(from, to);
  }
  if (from != codes.data()) std::copy(from, from + n, codes.data());
}

bool MortonSet::insert(std::uint64_t code) {
  if (2 * (codes_.size() + 1) > table_.size()) grow();  // load factor <= 1/2
  const std::size_t mask = table_.size() - 1;
  for (std::size_t s = slotOf(code, mask);; s = (s + 1) & mask) {
    if (table_[s] == code) return false;
    if (table_[s] == kEmpty) {
      table_[s] = code;
      codes_.push_back(code);
      slots_.push_back(static_cast<std::uint32_t>(s));
      return true;
    }
  }
}

void MortonSet::clear() {
  for (std::uint32_t s : slots_) table_[s] = kEmpty;
  codes_.clear();
  slots_.clear();
}

std::size_t MortonSet::memoryBytes() const {
  return (table_.capacity() + codes_.capacity()) * sizeof(std::uint64_t) +
         slots_.capacity() * sizeof(std::uint32_t);
}

void MortonSet::grow() {
  table_.assign(std::max(kInitialSlots, 2 * table_.size()), kEmpty);
  const std::size_t mask = table_.size() - 1;
  // The codes keep their list (a caller may have reordered it); only their slots change.
  slots_.clear();
  for (std::uint64_t code : codes_) {
    std::size_t s = slotOf(code, mask);
    while (table_[s] != kEmpty) s = (s + 1) & mask;
    table_[s] = code;
    slots_.push_back(static_cast<std::uint32_t>(s));
  }
}

void ScanCells::compute(const octomap::OcTree& tree, const octomap::point3d& origin,
                        const std::vector<octomap::point3d>& rays,
                        const std::vector<octomap::point3d>& hits, double max_range) {
  endpoints_.clear();
  free_set_.clear();
  occupied_.clear();
  // Endpoints discretised to their voxels, each voxel cast once to its centre (unchecked
  // conversion, as OctoMap's computeDiscreteUpdate).
  for (const octomap::point3d& p : rays) endpoints_.insert(mortonCode(tree.coordToKey(p)));
  for (std::uint64_t code : endpoints_.codes()) {
    const octomap::point3d p = tree.keyToCoord(keyOfMortonCode(code));
    if (max_range < 0.0 || (p - origin).norm() <= max_range) {
      if (tree.computeRayKeys(origin, p, ray_))
        for (const octomap::OcTreeKey& k : ray_) free_set_.insert(mortonCode(k));
      octomap::OcTreeKey key;
      if (tree.coordToKeyChecked(p, key)) occupied_.insert(mortonCode(key));
    } else {
      // A reading beyond the trusted range clears the first max_range metres of its ray.
      const octomap::point3d end =
          origin + (p - origin).normalized() * static_cast<float>(max_range);
      if (tree.computeRayKeys(origin, end, ray_))
        for (const octomap::OcTreeKey& k : ray_) free_set_.insert(mortonCode(k));
    }
  }
  for (const octomap::point3d& p : hits) {
    octomap::OcTreeKey key;
    if ((p - origin).norm() <= max_range && tree.coordToKeyChecked(p, key))
      occupied_.insert(mortonCode(key));
  }
  std::vector<std::uint64_t>& free_codes = free_set_.codes();
  std::vector<std::uint64_t>& occupied_codes = occupied_.codes();
  sortMortonCodes(free_codes, sort_scratch_);
  sortMortonCodes(occupied_codes, sort_scratch_);
  // Occupied wins over free within one scan.
  free_.clear();
  std::set_difference(free_codes.begin(), free_codes.end(), occupied_codes.begin(),
                      occupied_codes.end(), std::back_inserter(free_));
}

std::size_t ScanCells::memoryBytes() const {
  return endpoints_.memoryBytes() + free_set_.memoryBytes() + occupied_.memoryBytes() +
         (free_.capacity() + sort_scratch_.capacity()) * sizeof(std::uint64_t) +
         ray_.sizeMax() * sizeof(octomap::OcTreeKey);
}

void OccupancyTree::updateSorted(const std::vector<std::uint64_t>& codes, float log_odds_update) {
  if (codes.empty()) return;
  const unsigned leaf_depth = tree_depth;  // 16
  // path[d]: the node at depth d on the previous cell's path, valid for d <= valid; created[d]:
  // made during the descent that reached it (OctoMap's node_just_created).
  octomap::OcTreeNode* path[17];
  bool created[17] = {};
  if (root == nullptr) {
    root = new octomap::OcTreeNode();
    ++tree_size;
    created[0] = true;
  }
  path[0] = root;
  unsigned valid = 0;
  std::uint64_t previous = codes.front();
  const bool raises = log_odds_update >= 0.0f, lowers = log_odds_update <= 0.0f;
  for (std::uint64_t code : codes) {
    // The two paths share the nodes above the highest level at which the codes differ.
    unsigned d = valid;
    if (code != previous) {
      const unsigned level = static_cast<unsigned>(63 - __builtin_clzll(code ^ previous)) / 3;
      d = std::min(d, leaf_depth - 1 - level);
    }
    previous = code;
    octomap::OcTreeNode* node = path[d];
    bool clamped_pruned = false;
    for (; d < leaf_depth; ++d) {
      const unsigned pos = static_cast<unsigned>(code >> (3 * (leaf_depth - 1 - d))) & 7u;
      bool made = false;
      if (!nodeChildExists(node, pos)) {
        if (!nodeHasChildren(node) && !created[d]) {
          // A pruned node: OctoMap's updateNode finds it by its search and leaves it alone when
          // it is already clamped in the update's direction; otherwise it is expanded.
          if ((raises && node->getLogOdds() >= getClampingThresMaxLog()) ||
              (lowers && node->getLogOdds() <= getClampingThresMinLog())) {
            clamped_pruned = true;
            break;
          }
          expandNode(node);
        } else {
          createNodeChild(node, pos);
          made = true;
        }
      }
      node = getNodeChild(node, pos);
      path[d + 1] = node;
      created[d + 1] = made;
    }
    valid = d;
    // A leaf at the clamp stays there either way (OctoMap's early abort, or the clamping).
    if (!clamped_pruned) updateNodeLogOdds(node, log_odds_update);
  }
}

}  // namespace rgbdi::mapping::detail
