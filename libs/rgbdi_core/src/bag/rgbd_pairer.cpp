#include "rgbdi/bag/rgbd_pairer.h"

#include <algorithm>
#include <cmath>

namespace rgbdi::bag {

RgbdPairer::RgbdPairer(double tolerance_s, double max_wait_s)
    : tolerance_(tolerance_s), max_wait_(max_wait_s) {}

void RgbdPairer::pushColor(StampedImage image) { push(0, std::move(image)); }
void RgbdPairer::pushDepth(StampedImage image) { push(1, std::move(image)); }

void RgbdPairer::push(int stream, StampedImage image) {
  const double t = image.t;
  auto& q = queue_[stream];
  const auto pos = std::upper_bound(q.begin(), q.end(), t,
                                    [](double a, const StampedImage& s) { return a < s.t; });
  q.insert(pos, std::move(image));
  latest_[stream] = seen_[stream] ? std::max(latest_[stream], t) : t;
  newest_ = seen_[0] || seen_[1] ? std::max(newest_, t) : t;
  seen_[stream] = true;
  process();
}

void RgbdPairer::finish() {
  finished_ = true;
  process();
}

bool RgbdPairer::decided(int stream, double t) const {
  return finished_ || (seen_[stream] && latest_[stream] > t + tolerance_) ||
         newest_ > t + max_wait_;
}

long RgbdPairer::nearest(int stream, double t) const {
  long best = -1;
  double best_dt = tolerance_;
  const auto& q = queue_[stream];
  for (std::size_t i = 0; i < q.size(); ++i) {
    const double dt = std::abs(q[i].t - t);
    if (dt <= best_dt && (best < 0 || dt < best_dt)) {
      best = static_cast<long>(i);
      best_dt = dt;
    }
    if (q[i].t > t + tolerance_) break;
  }
  return best;
}

void RgbdPairer::emitAlone(int stream, StampedImage image) {
  PairedImages p;
  (stream == 0 ? p.color : p.depth) = std::move(image);
  ++(stream == 0 ? stats_.color_alone : stats_.depth_alone);
  ready_.push_back(std::move(p));
}

void RgbdPairer::process() {
  while (!queue_[0].empty() || !queue_[1].empty()) {
    // The oldest buffered image decides first.
    const int x = queue_[0].empty()   ? 1
                  : queue_[1].empty() ? 0
                                      : (queue_[0].front().t <= queue_[1].front().t ? 0 : 1);
    const int y = 1 - x;
    const double tx = queue_[x].front().t;
    if (!decided(y, tx)) return;
    const long iy = nearest(y, tx);
    if (iy < 0) {
      StampedImage alone = std::move(queue_[x].front());
      queue_[x].pop_front();
      emitAlone(x, std::move(alone));
      continue;
    }
    const double ty = queue_[y][static_cast<std::size_t>(iy)].t;
    if (!decided(x, ty)) return;
    if (nearest(x, ty) != 0) {
      // A later image of stream x is closer to that partner: this one stays alone.
      StampedImage alone = std::move(queue_[x].front());
      queue_[x].pop_front();
      emitAlone(x, std::move(alone));
      continue;
    }
    PairedImages p;
    (x == 0 ? p.color : p.depth) = std::move(queue_[x].front());
    (y == 0 ? p.color : p.depth) = std::move(queue_[y][static_cast<std::size_t>(iy)]);
    queue_[x].pop_front();
    ready_.push_back(std::move(p));
    ++stats_.pairs;
    // Images of y between the two are skipped over: pairs never cross.
    for (long i = 0; i < iy; ++i) {
      emitAlone(y, std::move(queue_[y].front()));
      queue_[y].pop_front();
    }
    queue_[y].pop_front();  // the partner
  }
}

bool RgbdPairer::pop(PairedImages& out) {
  if (ready_.empty()) return false;
  out = std::move(ready_.front());
  ready_.pop_front();
  return true;
}

std::optional<RgbdFrame> frameFromPair(PairedImages pair, bool require_colour,
                                       std::size_t* depth_alone_dropped) {
  if (!pair.depth) return std::nullopt;  // colour alone: counted by the pairer, dropped
  if (!pair.color && require_colour) {
    ++*depth_alone_dropped;
    return std::nullopt;
  }
  RgbdFrame f;
  f.t = pair.color ? pair.color->t : pair.depth->t;
  if (pair.color) f.rgb = pair.color->image;
  f.depth = pair.depth->image;
  f.depth_unit_m = pair.depth->unit_m;
  f.source_label = pair.color ? pair.color->label : pair.depth->label;
  return f;
}

}  // namespace rgbdi::bag
