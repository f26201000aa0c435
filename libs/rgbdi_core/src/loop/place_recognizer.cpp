#include "rgbdi/loop/place_recognizer.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace rgbdi::loop {

PlaceRecognizer::PlaceRecognizer(const PlaceRecognitionOptions& options)
    : options_(options), index_((options.validate(), options.index)) {}

std::size_t PlaceRecognizer::slotOf(std::uint64_t id) const {
  const auto it = std::lower_bound(records_.begin(), records_.end(), id,
                                   [](const Record& r, std::uint64_t v) { return r.id < v; });
  return it != records_.end() && it->id == id ? static_cast<std::size_t>(it - records_.begin())
                                              : records_.size();
}

bool PlaceRecognizer::eligible(std::size_t slot, const LoopKeyframe& kf) const {
  const Record& r = records_[slot];
  return slot + static_cast<std::size_t>(options_.exclude_recent_count) < records_.size() &&
         kf.t - r.t >= options_.exclude_recent_s &&
         kf.travelled_m - r.travelled_m >= options_.exclude_recent_m;
}

std::size_t PlaceRecognizer::eligibleEnd(const LoopKeyframe& kf) const {
  // Stamps, distances travelled and slots all grow with the id (checkNewer), so the eligible
  // keyframes are the oldest ones up to a last eligible slot: a binary search finds it.
  std::size_t lo = 0, hi = records_.size();
  while (lo < hi) {
    const std::size_t mid = lo + (hi - lo) / 2;
    if (eligible(mid, kf))
      lo = mid + 1;
    else
      hi = mid;
  }
  return lo;
}

void PlaceRecognizer::checkNewer(const LoopKeyframe& kf, const char* who) const {
  if (records_.empty()) return;
  const Record& last = records_.back();
  const std::string what = std::string(who) + ": keyframe " + std::to_string(kf.id);
  if (kf.id <= last.id)
    throw std::invalid_argument(what + " is not newer than keyframe " + std::to_string(last.id));
  if (!(kf.t >= last.t) || !(kf.travelled_m >= last.travelled_m))
    throw std::invalid_argument(what + " has an earlier stamp or a shorter distance travelled " +
                                "than keyframe " + std::to_string(last.id));
}

void PlaceRecognizer::add(const LoopKeyframe& kf, const PlaceKeys& keys) {
  index_.add(kf.id, keys);
  records_.push_back({kf.id, kf.segment, kf.t, kf.travelled_m, kf.T_world_body.translation()});
}

void PlaceRecognizer::insert(const LoopKeyframe& kf) {
  checkNewer(kf, "PlaceRecognizer::insert");
  add(kf, index_.keys(kf.descriptors));  // validates the descriptors before anything is kept
  previous_streaks_.clear();             // a rebuilt map has no query history
}

std::vector<PlaceCandidate> PlaceRecognizer::process(const LoopKeyframe& kf,
                                                     const std::function<bool(int)>& unrelated) {
  checkNewer(kf, "PlaceRecognizer::process");
  const PlaceKeys keys = index_.keys(kf.descriptors);  // validates before anything changes
  const std::size_t end = eligibleEnd(kf);
  std::vector<PlaceCandidate> out;
  std::vector<Streak> streaks;
  double reference = 0.0;
  if (!records_.empty()) {
    // The predecessor shows nearly the same view: its score is what "same place" scores now.
    // Only a predecessor of kf's own segment can serve: another segment's last keyframe shows
    // another place (a loaded map's last keyframe, the view before a reset).
    const bool own_predecessor = records_.back().segment == kf.segment;
    reference = own_predecessor ? index_.similarity(keys, records_.back().id) : 0.0;
    const double self = index_.selfSimilarity(keys);
    ++stats_.queried;
    const bool no_reference = !(reference > 0.0) || reference < options_.min_reference_ratio * self;
    if (no_reference) {
      ++stats_.no_reference;
      reference = 0.0;
    }
    // Joining candidates (parts not related to kf's: a loaded map, a segment before a reset)
    // are proposed by score rank alone, without the reference: joining is confirmed by several
    // verified matches with more inliers, and the reference fails exactly when relocalisation
    // matters most: at rest the predecessor is the same image and outscores every other view;
    // the first keyframe of a part has no predecessor of its own.
    const bool may_join = static_cast<bool>(unrelated);  // the caller passes it only then
    if (!no_reference || may_join) {
      const std::uint64_t last_id = end > 0 ? records_[end - 1].id : 0;
      const std::vector<PlaceMatch> matches =
          end == 0 ? std::vector<PlaceMatch>()
                   : index_.query(keys, static_cast<std::size_t>(options_.top_k),
                                  [last_id](std::uint64_t id) { return id <= last_id; });
      for (const PlaceMatch& m : matches) {
        const bool joining = unrelated && unrelated(records_[slotOf(m.id)].segment);
        const double normalised = reference > 0.0 ? m.score / reference : 0.0;
        if (!joining && !(reference > 0.0 && normalised >= options_.min_normalised_score)) continue;
        ++stats_.above_threshold;
        const double t = records_[slotOf(m.id)].t;
        int length = 1;
        for (const Streak& s : previous_streaks_)
          if (std::abs(s.t - t) <= options_.consistency_window_s)
            length = std::max(length, s.length + 1);
        length = std::min(length, options_.consistency_keyframes);
        streaks.push_back({t, length});
        if (joining || length >= options_.consistency_keyframes)
          out.push_back({m.id, m.score, normalised, false});
      }
    }
  }
  previous_streaks_ = std::move(streaks);
  // query() is best first by score; the reference is common, so this is best normalised first.
  stats_.temporally_consistent += out.size();

  if (options_.proximity_radius_m > 0.0 && options_.proximity_max_candidates > 0) {
    const Eigen::Vector3d p = kf.T_world_body.translation();
    std::vector<std::pair<double, std::size_t>> near;  // (squared distance, slot)
    const double r2 = options_.proximity_radius_m * options_.proximity_radius_m;
    for (std::size_t s = 0; s < end; ++s) {
      if (records_[s].segment != kf.segment) continue;
      const double d2 = (records_[s].p_world_body - p).squaredNorm();
      if (d2 <= r2) near.emplace_back(d2, s);
    }
    std::sort(near.begin(), near.end());  // nearest first, equal distances by slot (= id)
    std::size_t added = 0;
    for (const auto& [d2, s] : near) {
      if (added == static_cast<std::size_t>(options_.proximity_max_candidates)) break;
      const std::uint64_t id = records_[s].id;
      if (std::any_of(out.begin(), out.end(), [&](const PlaceCandidate& c) { return c.id == id; }))
        continue;
      const double score = index_.similarity(keys, id);
      out.push_back({id, score, reference > 0.0 ? score / reference : 0.0, true});
      ++added;
    }
    stats_.proximity += added;
  }

  add(kf, keys);
  return out;
}

void PlaceRecognizer::updatePoses(
    const std::vector<std::pair<std::uint64_t, Eigen::Isometry3d>>& T_world_body) {
  std::vector<std::size_t> slots;
  slots.reserve(T_world_body.size());
  for (const auto& [id, T] : T_world_body) {
    const std::size_t s = slotOf(id);
    if (s == records_.size())
      throw std::out_of_range("PlaceRecognizer::updatePoses: keyframe " + std::to_string(id) +
                              " was never processed");
    slots.push_back(s);
  }
  for (std::size_t i = 0; i < slots.size(); ++i)
    records_[slots[i]].p_world_body = T_world_body[i].second.translation();
}

Eigen::Vector3d PlaceRecognizer::position(std::uint64_t id) const {
  const std::size_t s = slotOf(id);
  if (s == records_.size())
    throw std::out_of_range("PlaceRecognizer::position: keyframe " + std::to_string(id) +
                            " was never processed");
  return records_[s].p_world_body;
}

void PlaceRecognizer::clear() {
  index_.clear();
  records_.clear();
  previous_streaks_.clear();
  stats_ = PlaceRecognitionStats();
}

std::size_t PlaceRecognizer::memoryBytes() const {
  return sizeof(*this) - sizeof(index_) + index_.memoryBytes() +
         records_.capacity() * sizeof(Record) + previous_streaks_.capacity() * sizeof(Streak);
}

}  // namespace rgbdi::loop
