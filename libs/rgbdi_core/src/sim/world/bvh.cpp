#include "rgbdi/sim/bvh.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace rgbdi::sim {
namespace {

double halfArea(const Eigen::AlignedBox3d& b) {
  if (b.isEmpty()) return 0.0;
  const Eigen::Vector3d e = b.sizes();
  return e.x() * e.y() + e.y() * e.z() + e.z() * e.x();
}

// Float bounds that contain the double box for sure: rounded outwards plus a relative margin
// (float slab tests carry ~1e-7 relative error in the ray distances).
void storeBounds(const Eigen::AlignedBox3d& b, float lo[3], float hi[3]) {
  const double extent = b.sizes().maxCoeff();
  for (int a = 0; a < 3; ++a) {
    const double pad = 1e-5 * (extent + std::abs(b.min()[a]) + std::abs(b.max()[a])) + 1e-6;
    lo[a] =
        std::nextafter(static_cast<float>(b.min()[a] - pad), -std::numeric_limits<float>::max());
    hi[a] = std::nextafter(static_cast<float>(b.max()[a] + pad), std::numeric_limits<float>::max());
  }
}

}  // namespace

void Bvh::build(const std::vector<Eigen::AlignedBox3d>& boxes, const BuildOptions& options) {
  if (options.max_leaf_size < 1 || options.bins < 2 || options.max_depth < 1 ||
      options.max_depth >= kStackSize)
    throw std::invalid_argument("Bvh::build: invalid build options");
  nodes_.clear();
  prim_order_.resize(boxes.size());
  std::iota(prim_order_.begin(), prim_order_.end(), 0u);
  depth_ = 0;
  if (boxes.empty()) return;
  for (const auto& b : boxes)
    if (b.isEmpty() || !b.min().allFinite() || !b.max().allFinite())
      throw std::invalid_argument("Bvh::build: a primitive has empty or non-finite bounds");
  nodes_.reserve(2 * boxes.size());
  Builder builder(boxes, options, nodes_, prim_order_);
  builder.split(0, static_cast<std::uint32_t>(boxes.size()), 1);
  depth_ = builder.max_depth_reached;
}

Bvh::Builder::Builder(const std::vector<Eigen::AlignedBox3d>& boxes, const BuildOptions& options,
                      std::vector<Node>& nodes, std::vector<std::uint32_t>& order)
    : boxes_(boxes), opt_(options), nodes_(nodes), order_(order) {
  centroid_.resize(boxes.size());
  for (std::size_t i = 0; i < boxes.size(); ++i) centroid_[i] = boxes[i].center();
  bins_.resize(static_cast<std::size_t>(options.bins));
  right_area_.resize(static_cast<std::size_t>(options.bins));
  right_count_.resize(static_cast<std::size_t>(options.bins));
}

std::uint32_t Bvh::Builder::split(std::uint32_t begin, std::uint32_t end, int depth) {
  max_depth_reached = std::max(max_depth_reached, depth);
  const std::uint32_t index = static_cast<std::uint32_t>(nodes_.size());
  nodes_.push_back({});
  Eigen::AlignedBox3d bounds, cbounds;
  for (std::uint32_t i = begin; i < end; ++i) {
    bounds.extend(boxes_[order_[i]]);
    cbounds.extend(centroid_[order_[i]]);
  }
  storeBounds(bounds, nodes_[index].lo, nodes_[index].hi);
  const std::uint32_t n = end - begin;
  auto makeLeaf = [&]() {
    nodes_[index].first_or_right = begin;
    nodes_[index].count = n;
    return index;
  };
  if (n <= 1 || depth >= opt_.max_depth) return makeLeaf();

  // Binned SAH: a split costs ~ area(L)*|L| + area(R)*|R| (+ one node visit), a leaf area*n.
  const int bins = opt_.bins;
  int best_axis = -1, best_split = -1;
  double best_cost = std::numeric_limits<double>::infinity();
  const Eigen::Vector3d cext = cbounds.sizes();
  auto binOf = [&](std::uint32_t p, int axis) {
    const double scale = bins / cext[axis];
    const int k = static_cast<int>((centroid_[p][axis] - cbounds.min()[axis]) * scale);
    return std::min(std::max(k, 0), bins - 1);
  };
  for (int axis = 0; axis < 3; ++axis) {
    if (cext[axis] <= 0.0) continue;
    for (auto& b : bins_) b = Bin{};
    for (std::uint32_t i = begin; i < end; ++i) {
      Bin& b = bins_[static_cast<std::size_t>(binOf(order_[i], axis))];
      b.box.extend(boxes_[order_[i]]);
      ++b.count;
    }
    Eigen::AlignedBox3d acc;
    std::uint32_t cnt = 0;
    for (int k = bins - 1; k > 0; --k) {
      const std::size_t ks = static_cast<std::size_t>(k);
      acc.extend(bins_[ks].box);
      cnt += bins_[ks].count;
      right_area_[ks] = halfArea(acc);
      right_count_[ks] = cnt;
    }
    acc.setEmpty();
    cnt = 0;
    for (int k = 1; k < bins; ++k) {
      const std::size_t ks = static_cast<std::size_t>(k);
      acc.extend(bins_[ks - 1].box);
      cnt += bins_[ks - 1].count;
      if (cnt == 0 || right_count_[ks] == 0) continue;
      const double cost = halfArea(acc) * cnt + right_area_[ks] * right_count_[ks];
      if (cost < best_cost) {
        best_cost = cost;
        best_axis = axis;
        best_split = k;
      }
    }
  }

  const bool small = n <= static_cast<std::uint32_t>(opt_.max_leaf_size);
  std::uint32_t mid;
  if (best_axis < 0) {
    // All centroids coincide: split by count so the depth stays logarithmic.
    if (small) return makeLeaf();
    mid = begin + n / 2;
  } else {
    const double leaf_cost = halfArea(bounds) * n;
    if (small && leaf_cost <= best_cost + halfArea(bounds)) return makeLeaf();
    auto it = std::partition(order_.begin() + begin, order_.begin() + end,
                             [&](std::uint32_t p) { return binOf(p, best_axis) < best_split; });
    mid = static_cast<std::uint32_t>(it - order_.begin());
  }
  // Left child directly follows its parent (depth-first layout); the right index is stored.
  split(begin, mid, depth + 1);
  const std::uint32_t right = split(mid, end, depth + 1);
  nodes_[index].first_or_right = right;
  nodes_[index].count = 0;
  return index;
}

}  // namespace rgbdi::sim
