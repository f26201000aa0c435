// Bounding-volume hierarchy over axis-aligned boxes (binned surface-area heuristic).
//
// Nodes are stored depth-first in one array (left child right after its parent), with float
// bounds slightly inflated at build time so that float slab tests never miss a primitive the
// exact double-precision test would hit. Traversal is front-to-back with an explicit stack and
// no allocation, and lets the caller shrink the search range as closer hits are found.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace rgbdi::sim {

class Bvh {
 public:
  struct BuildOptions {
    int max_leaf_size = 2;  ///< primitives per leaf when the SAH does not prefer a split
    int bins = 16;          ///< SAH candidate split positions per axis
    int max_depth = 48;     ///< deeper nodes become leaves (bounds the traversal stack)
  };

  /// Builds the tree over the given primitive bounds (index i refers to boxes[i]).
  void build(const std::vector<Eigen::AlignedBox3d>& boxes, const BuildOptions& options);
  void build(const std::vector<Eigen::AlignedBox3d>& boxes) { build(boxes, BuildOptions{}); }

  bool empty() const { return nodes_.empty(); }
  std::size_t nodeCount() const { return nodes_.size(); }
  int depth() const { return depth_; }

  /// Calls visit(primitive_index, t_max) for every primitive whose leaf box the ray
  /// origin + t*dir (t in [0, t_max]) crosses, nearest boxes first. visit may lower t_max (a
  /// double&) when it finds a closer hit; boxes beyond the new t_max are then skipped.
  template <class Visit>
  void traverse(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, double t_max,
                Visit&& visit) const;

 private:
  struct Node {
    float lo[3];
    std::uint32_t first_or_right;  ///< leaf: first entry of prim_order_; interior: right child
    float hi[3];
    std::uint32_t count;  ///< leaf: number of primitives (> 0); interior: 0
  };
  static_assert(sizeof(Node) == 32, "BVH node should fill half a cache line");
  static constexpr int kStackSize = 64;

  struct Ray {
    float o[3], inv[3];
  };
  static bool slab(const Node& n, const Ray& r, float t_max, float& t_near) {
    float t0 = 0.0f, t1 = t_max;
    for (int a = 0; a < 3; ++a) {
      const float ta = (n.lo[a] - r.o[a]) * r.inv[a];
      const float tb = (n.hi[a] - r.o[a]) * r.inv[a];
      t0 = ta < tb ? (ta > t0 ? ta : t0) : (tb > t0 ? tb : t0);
      t1 = ta < tb ? (tb < t1 ? tb : t1) : (ta < t1 ? ta : t1);
    }
    t_near = t0;
    return t0 <= t1;
  }

  /// Recursive binned-SAH construction (defined in bvh.cpp).
  class Builder {
   public:
    Builder(const std::vector<Eigen::AlignedBox3d>& boxes, const BuildOptions& options,
            std::vector<Node>& nodes, std::vector<std::uint32_t>& order);
    /// Builds the subtree over order[begin, end) and returns its node index.
    std::uint32_t split(std::uint32_t begin, std::uint32_t end, int depth);
    int max_depth_reached = 0;

   private:
    struct Bin {
      Eigen::AlignedBox3d box;
      std::uint32_t count = 0;
    };
    const std::vector<Eigen::AlignedBox3d>& boxes_;
    const BuildOptions& opt_;
    std::vector<Node>& nodes_;
    std::vector<std::uint32_t>& order_;
    std::vector<Eigen::Vector3d> centroid_;
    std::vector<Bin> bins_;
    std::vector<double> right_area_;
    std::vector<std::uint32_t> right_count_;
  };

  std::vector<Node> nodes_;
  std::vector<std::uint32_t> prim_order_;
  int depth_ = 0;
};

template <class Visit>
void Bvh::traverse(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, double t_max,
                   Visit&& visit) const {
  if (nodes_.empty()) return;
  // A huge finite inverse instead of infinity keeps (bound - origin) * inv free of NaN when the
  // ray lies exactly in a slab plane; the inflated bounds make that case conservative.
  constexpr float kHugeInverse = 1e30f;
  Ray r;
  for (int a = 0; a < 3; ++a) {
    r.o[a] = static_cast<float>(origin[a]);
    const double d = dir[a];
    r.inv[a] =
        std::abs(d) < 1e-30 ? (d < 0 ? -kHugeInverse : kHugeInverse) : static_cast<float>(1.0 / d);
  }
  // Float distances are compared with a small relative margin so that rounding never culls a
  // box holding a hit at (almost) the current best distance.
  constexpr float kMargin = 1.0f + 1e-5f;
  auto limit = [&t_max]() {
    return t_max >= static_cast<double>(std::numeric_limits<float>::max())
               ? std::numeric_limits<float>::max()
               : static_cast<float>(t_max) * kMargin;
  };

  struct Entry {
    std::uint32_t node;
    float t_near;
  };
  Entry stack[kStackSize];
  int sp = 0;
  float t_near = 0.0f;
  if (!slab(nodes_[0], r, limit(), t_near)) return;
  std::uint32_t idx = 0;
  for (;;) {
    const Node& n = nodes_[idx];
    if (n.count > 0) {
      for (std::uint32_t i = n.first_or_right; i < n.first_or_right + n.count; ++i)
        visit(prim_order_[i], t_max);
    } else {
      const std::uint32_t left = idx + 1, right = n.first_or_right;
      float tl = 0.0f, tr = 0.0f;
      const float lim = limit();
      const bool hl = slab(nodes_[left], r, lim, tl);
      const bool hr = slab(nodes_[right], r, lim, tr);
      if (hl && hr) {
        if (tl <= tr) {
          stack[sp++] = {right, tr};
          idx = left;
        } else {
          stack[sp++] = {left, tl};
          idx = right;
        }
        continue;
      }
      if (hl || hr) {
        idx = hl ? left : right;
        continue;
      }
    }
    // Pop the next box still closer than the best hit so far.
    bool found = false;
    while (sp > 0) {
      const Entry e = stack[--sp];
      if (e.t_near <= limit()) {
        idx = e.node;
        found = true;
        break;
      }
    }
    if (!found) return;
  }
}

}  // namespace rgbdi::sim
