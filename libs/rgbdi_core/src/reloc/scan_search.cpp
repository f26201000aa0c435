#include "rgbdi/reloc/scan_search.h"

#include <algorithm>
#include <cmath>
#include <tuple>
#include <utility>

namespace rgbdi::reloc {
namespace {
constexpr std::size_t kMaxLeaves = 200000;  // near-best alignments listed at most

struct Leaf {
  int score;
  int yaw_index, ox, oy;
};

double wrapAngle(double a) { return std::atan2(std::sin(a), std::cos(a)); }
}  // namespace

Eigen::Vector2d PlanAlignment::apply(const Eigen::Vector2d& p) const {
  const double c = std::cos(yaw), s = std::sin(yaw);
  const Eigen::Vector2d q = p - pivot;
  return Eigen::Vector2d(c * q.x() - s * q.y(), s * q.x() + c * q.y()) + t;
}

ScanSearch::ScanSearch(PlanGrid map, const ScanSearchOptions& options)
    : map_(std::move(map)), options_(options) {
  const int w = map_.width(), h = map_.height();
  const std::size_t n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  std::vector<std::uint8_t> score(n, 0);
  for (int iy = 0; iy < h; ++iy)
    for (int ix = 0; ix < w; ++ix) {
      if (map_.state(ix, iy) != CellState::kOccupied) continue;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          if (!map_.inside(ix + dx, iy + dy)) continue;
          std::uint8_t& s = score[static_cast<std::size_t>(iy + dy) * w + (ix + dx)];
          s = std::max<std::uint8_t>(s, dx == 0 && dy == 0 ? 2 : 1);
        }
    }
  pyramid_.push_back(std::move(score));
  for (int level = 1; level <= options_.pyramid_levels; ++level) {
    const std::vector<std::uint8_t>& below = pyramid_.back();
    const int half = 1 << (level - 1);
    std::vector<std::uint8_t> up(n, 0);
    for (int iy = 0; iy < h; ++iy)
      for (int ix = 0; ix < w; ++ix) {
        std::uint8_t m = below[static_cast<std::size_t>(iy) * w + ix];
        if (ix + half < w) m = std::max(m, below[static_cast<std::size_t>(iy) * w + ix + half]);
        if (iy + half < h) {
          m = std::max(m, below[static_cast<std::size_t>(iy + half) * w + ix]);
          if (ix + half < w)
            m = std::max(m, below[static_cast<std::size_t>(iy + half) * w + ix + half]);
        }
        up[static_cast<std::size_t>(iy) * w + ix] = m;
      }
    pyramid_.push_back(std::move(up));
  }
}

int ScanSearch::bound(int level, int ix, int iy) const {
  const int size = 1 << level;
  const int w = map_.width(), h = map_.height();
  if (ix >= w || iy >= h || ix + size <= 0 || iy + size <= 0) return 0;
  // A window reaching past the lower edge: the window from the edge covers its inside part.
  ix = std::max(ix, 0);
  iy = std::max(iy, 0);
  return pyramid_[static_cast<std::size_t>(level)][static_cast<std::size_t>(iy) * w + ix];
}

PlanHypothesis ScanSearch::evaluate(const PlanGrid& local, const PlanAlignment& a) const {
  PlanHypothesis hyp;
  hyp.alignment = a;
  int obstacles = 0;
  for (int iy = 0; iy < local.height(); ++iy)
    for (int ix = 0; ix < local.width(); ++ix) {
      const CellState s = local.state(ix, iy);
      if (s == CellState::kUnknown) continue;
      const Eigen::Vector2i m = map_.cellOf(a.apply(local.centre(ix, iy)));
      const CellState ms = map_.state(m.x(), m.y());
      if (s == CellState::kOccupied) {
        ++obstacles;
        hyp.score += bound(0, m.x(), m.y()) * (map_.inside(m.x(), m.y()) ? 1 : 0);
      }
      if (ms == CellState::kUnknown) continue;
      ++hyp.compared;
      const bool conflict = (s == CellState::kOccupied && map_.freeInterior(m.x(), m.y())) ||
                            (ms == CellState::kOccupied && local.freeInterior(ix, iy));
      if (conflict) ++hyp.conflicts;
    }
  hyp.overlap = obstacles > 0 ? hyp.score / (2.0 * obstacles) : 0.0;
  hyp.conflict_fraction = hyp.compared > 0 ? static_cast<double>(hyp.conflicts) / hyp.compared : 0;
  hyp.agreement = hyp.score - options_.conflict_penalty * hyp.conflicts;
  return hyp;
}

ScanSearchResult ScanSearch::search(const PlanGrid& local, const Eigen::Vector2d& pivot) const {
  ScanSearchResult out;
  std::vector<Eigen::Vector2d> pts;
  for (const Eigen::Vector2i& c : local.cells(CellState::kOccupied))
    pts.push_back(local.centre(c.x(), c.y()) - pivot);
  out.local_obstacles = static_cast<int>(pts.size());
  if (pts.empty() || map_.width() == 0) return out;
  const double r = map_.resolution();
  const int n_yaw = std::max(1, static_cast<int>(std::lround(360.0 / options_.yaw_step_deg)));
  const double yaw_step = 2.0 * M_PI / n_yaw;
  const int top = options_.pyramid_levels;
  const int min_score = static_cast<int>(
      std::ceil(options_.min_overlap_fraction * 2.0 * static_cast<double>(pts.size())));
  int best = 0;
  const auto threshold = [&] {
    return std::max(min_score,
                    static_cast<int>(std::ceil(best * (1.0 - options_.candidate_margin))));
  };
  std::vector<Leaf> leaves;

  // Offsets of the local obstacle cells from the pivot's cell, per rotation.
  std::vector<std::vector<Eigen::Vector2i>> offsets(static_cast<std::size_t>(n_yaw));
  for (int k = 0; k < n_yaw; ++k) {
    const double c = std::cos(k * yaw_step), s = std::sin(k * yaw_step);
    auto& o = offsets[static_cast<std::size_t>(k)];
    o.reserve(pts.size());
    for (const Eigen::Vector2d& p : pts)
      o.emplace_back(static_cast<int>(std::lround((c * p.x() - s * p.y()) / r)),
                     static_cast<int>(std::lround((s * p.x() + c * p.y()) / r)));
  }
  const auto score = [&](int level, int k, int ox, int oy) {
    int sum = 0;
    for (const Eigen::Vector2i& d : offsets[static_cast<std::size_t>(k)])
      sum += bound(level, ox + d.x(), oy + d.y());
    ++out.nodes_scored;
    return sum;
  };

  // Top-level nodes of every rotation, best bound first.
  struct Node {
    int bound, level, k, ox, oy;
  };
  const auto better = [](const Node& a, const Node& b) {
    return std::tie(b.bound, a.k, a.ox, a.oy) < std::tie(a.bound, b.k, b.ox, b.oy);
  };
  std::vector<Node> roots;
  const int size = 1 << top;
  for (int k = 0; k < n_yaw; ++k)
    for (int oy = 0; oy < map_.height(); oy += size)
      for (int ox = 0; ox < map_.width(); ox += size) {
        const int b = score(top, k, ox, oy);
        if (b >= min_score) roots.push_back({b, top, k, ox, oy});
      }
  std::sort(roots.begin(), roots.end(), better);
  std::vector<Node> stack;
  for (const Node& root : roots) {
    if (root.bound < threshold()) break;
    stack.push_back(root);
    while (!stack.empty()) {
      const Node n = stack.back();
      stack.pop_back();
      if (n.bound < threshold()) continue;
      if (n.level == 0) {
        best = std::max(best, n.bound);
        if (leaves.size() < kMaxLeaves)
          leaves.push_back({n.bound, n.k, n.ox, n.oy});
        else
          out.truncated = true;
        continue;
      }
      const int half = 1 << (n.level - 1);
      std::vector<Node> children;
      for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx) {
          const int ox = n.ox + dx * half, oy = n.oy + dy * half;
          if (ox >= map_.width() || oy >= map_.height()) continue;
          const int b = score(n.level - 1, n.k, ox, oy);
          if (b >= threshold()) children.push_back({b, n.level - 1, n.k, ox, oy});
        }
      // Best child on top of the stack (searched first: raises the threshold early).
      std::sort(children.begin(), children.end(), better);
      for (auto it = children.rbegin(); it != children.rend(); ++it) stack.push_back(*it);
    }
  }

  // Near-best alignments grouped into distinct places (best first, ties in search order).
  const int keep = threshold();
  std::stable_sort(leaves.begin(), leaves.end(), [](const Leaf& a, const Leaf& b) {
    return std::tie(b.score, a.yaw_index, a.ox, a.oy) < std::tie(a.score, b.yaw_index, b.ox, b.oy);
  });
  const double sep_yaw = options_.place_separation_deg * M_PI / 180.0;
  int left_out_score = -1;  // the highest obstacle score of a place not listed
  for (const Leaf& l : leaves) {
    if (l.score < keep) break;
    PlanAlignment a;
    a.yaw = wrapAngle(l.yaw_index * yaw_step);
    a.t = map_.centre(l.ox, l.oy);
    a.pivot = pivot;
    const bool known =
        std::any_of(out.candidates.begin(), out.candidates.end(), [&](const PlanHypothesis& h) {
          return (h.alignment.t - a.t).norm() <= options_.place_separation_m &&
                 std::abs(wrapAngle(h.alignment.yaw - a.yaw)) <= sep_yaw;
        });
    if (known) continue;
    if (static_cast<int>(out.candidates.size()) >= options_.max_hypotheses) {
      left_out_score = l.score;
      break;
    }
    out.candidates.push_back(evaluate(local, a));
  }
  for (const PlanHypothesis& h : out.candidates)
    if (h.conflict_fraction <= options_.max_conflict_fraction && h.agreement > 0.0)
      out.places.push_back(h);
  std::stable_sort(
      out.places.begin(), out.places.end(),
      [](const PlanHypothesis& a, const PlanHypothesis& b) { return a.agreement > b.agreement; });
  // Only the places within the margin of the best agreement remain.
  if (!out.places.empty()) {
    const double floor = (1.0 - options_.hypothesis_margin) * out.places.front().agreement;
    out.places.erase(std::remove_if(out.places.begin(), out.places.end(),
                                    [&](const PlanHypothesis& h) { return h.agreement < floor; }),
                     out.places.end());
  }
  // A place left out has an agreement of at most its obstacle score: it cannot matter when
  // that is below the margin of the best agreement.
  if (left_out_score >= 0 &&
      (out.places.empty() ||
       left_out_score >= (1.0 - options_.hypothesis_margin) * out.places.front().agreement))
    out.truncated = true;
  return out;
}

}  // namespace rgbdi::reloc
