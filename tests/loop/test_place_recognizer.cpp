// Place recognizer: exclusion of recent keyframes by time and travel, normalisation by the
// predecessor, temporal consistency, proximity candidates, and no candidate on a sequence that
// never revisits a place. Views are drawn from a synthetic corridor of landmarks with exact
// descriptors (each observation flips a few bits), so every expectation follows from geometry.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>

#include "rgbdi/loop/place_recognizer.h"

using rgbdi::loop::LoopKeyframe;
using rgbdi::loop::PlaceCandidate;
using rgbdi::loop::PlaceRecognitionOptions;
using rgbdi::loop::PlaceRecognizer;

namespace {

constexpr double kLandmarkSpacingM = 0.01;  // landmarks every cm along the corridor
constexpr double kViewHalfWidthM = 1.5;     // a view sees 300 landmarks

/// Descriptor of landmark j (a pure function of j).
std::array<std::uint8_t, 32> landmark(long j) {
  std::mt19937_64 rng(static_cast<std::uint64_t>(j) * 7919u + 17u);
  std::array<std::uint8_t, 32> d{};
  for (std::uint8_t& b : d) b = static_cast<std::uint8_t>(rng() & 0xFF);
  return d;
}

/// The view of a keyframe at corridor coordinate s: every landmark within kViewHalfWidthM, each
/// with up to 8 bits flipped (noise of this observation, seeded by the keyframe id).
rgbdi::mapping::DescriptorSet corridorView(double s, std::uint64_t id) {
  rgbdi::mapping::DescriptorSet d;
  d.type = "ORB-256";
  d.bytes_per_descriptor = 32;
  std::mt19937_64 rng(id * 104729u + 3u);
  const long lo = std::lround((s - kViewHalfWidthM) / kLandmarkSpacingM);
  const long hi = std::lround((s + kViewHalfWidthM) / kLandmarkSpacingM);
  for (long j = lo; j < hi; ++j) {
    std::array<std::uint8_t, 32> desc = landmark(j);
    const int flips = static_cast<int>(rng() % 9);
    for (int f = 0; f < flips; ++f) {
      const int bit = static_cast<int>(rng() % 256);
      desc[static_cast<std::size_t>(bit / 8)] ^= static_cast<std::uint8_t>(1u << (bit % 8));
    }
    d.keypoints_uv.emplace_back(0.0f, 0.0f);
    d.data.insert(d.data.end(), desc.begin(), desc.end());
  }
  return d;
}

LoopKeyframe keyframe(std::uint64_t id, double t, double travelled, double view_s,
                      const Eigen::Vector3d& p = Eigen::Vector3d::Zero(), int segment = 0) {
  LoopKeyframe k;
  k.id = id;
  k.t = t;
  k.travelled_m = travelled;
  k.segment = segment;
  k.T_world_body.translation() = p;
  k.T_world_body_odom = k.T_world_body;
  k.descriptors = corridorView(view_s, id);
  return k;
}

PlaceRecognitionOptions appearanceOnly() {
  PlaceRecognitionOptions o;
  o.proximity_radius_m = 0.0;
  return o;
}

std::set<std::uint64_t> appearanceIds(const std::vector<PlaceCandidate>& c) {
  std::set<std::uint64_t> ids;
  for (const PlaceCandidate& x : c)
    if (!x.by_proximity) ids.insert(x.id);
  return ids;
}

}  // namespace

TEST(PlaceRecognizer, ExcludesRecentKeyframesByTimeAndByTravelAndTheLastFew) {
  PlaceRecognitionOptions o = appearanceOnly();
  o.top_k = 1000;
  o.min_normalised_score = 0.0;
  o.consistency_keyframes = 1;  // every match that passes the exclusion is returned
  o.exclude_recent_s = 10.0;
  o.exclude_recent_m = 2.0;
  o.exclude_recent_count = 5;
  PlaceRecognizer rec(o);
  // The same view all along, with irregular steps: sometimes time passes without travel
  // (standing), sometimes travel without much time (fast), so each rule is the binding one.
  std::vector<double> t{0.0}, travel{0.0};
  for (int i = 1; i < 60; ++i) {
    const int phase = (i / 10) % 3;
    t.push_back(t.back() + (phase == 0 ? 2.0 : phase == 1 ? 0.2 : 1.0));
    travel.push_back(travel.back() + (phase == 0 ? 0.0 : phase == 1 ? 0.6 : 0.3));
  }
  int with_candidates = 0;
  for (std::size_t i = 0; i < t.size(); ++i) {
    const std::set<std::uint64_t> got =
        appearanceIds(rec.process(keyframe(i, t[i], travel[i], 0.0)));
    std::set<std::uint64_t> expected;
    for (std::size_t j = 0; j + 5 < i; ++j)
      if (t[i] - t[j] >= 10.0 && travel[i] - travel[j] >= 2.0) expected.insert(j);
    EXPECT_EQ(got, expected) << "keyframe " << i;
    if (!got.empty()) ++with_candidates;
  }
  EXPECT_GT(with_candidates, 20);
  EXPECT_EQ(rec.size(), t.size());
  EXPECT_EQ(rec.stats().queried, t.size() - 1);
}

TEST(PlaceRecognizer, NormalisesScoresByTheScoreWithThePredecessor) {
  PlaceRecognitionOptions o = appearanceOnly();
  o.consistency_keyframes = 1;
  o.min_normalised_score = 0.5;
  o.exclude_recent_count = 0;
  o.exclude_recent_s = 0.0;
  o.exclude_recent_m = 0.0;
  o.top_k = 50;
  PlaceRecognizer rec(o);
  // Stored views at 0, 1 and 2 m, then a query at 2.4 m whose predecessor was at 2.2 m.
  std::uint64_t id = 0;
  for (double s = 0.0; s < 2.1; s += 1.0, ++id) {
    const double t = static_cast<double>(id);
    rec.process(keyframe(id, t, t, s));
  }
  rec.process(keyframe(id++, 10.0, 10.0, 2.2));
  const LoopKeyframe q = keyframe(id, 20.0, 20.0, 2.4);
  const double reference = rec.index().similarity(q.descriptors, id - 1);
  std::vector<std::pair<std::uint64_t, double>> expected;  // every stored view >= 0.5 x reference
  for (std::uint64_t j = 0; j < id; ++j) {
    const double s = rec.index().similarity(q.descriptors, j);
    if (s / reference >= 0.5) expected.emplace_back(j, s);
  }
  std::sort(expected.begin(), expected.end(),
            [](const auto& a, const auto& b) { return a.second > b.second; });
  const std::vector<PlaceCandidate> c = rec.process(q);
  ASSERT_EQ(c.size(), expected.size());
  ASSERT_GE(c.size(), 2u);
  ASSERT_LT(c.size(), id);  // the threshold removed some stored views
  for (std::size_t i = 0; i < c.size(); ++i) {
    EXPECT_EQ(c[i].id, expected[i].first);
    EXPECT_EQ(c[i].score, expected[i].second);
    EXPECT_DOUBLE_EQ(c[i].normalised_score, expected[i].second / reference);
    EXPECT_FALSE(c[i].by_proximity);
  }
  // The predecessor overlaps the query most and ranks best; the view at 0 m (20 % overlap) is
  // below half of its score.
  EXPECT_EQ(c[0].id, id - 1);
  EXPECT_TRUE(std::none_of(c.begin(), c.end(), [](const PlaceCandidate& x) { return x.id == 0; }));
}

TEST(PlaceRecognizer, TemporalConsistencyNeedsNConsecutiveAgreeingKeyframes) {
  for (int n : {2, 3}) {
    PlaceRecognitionOptions o = appearanceOnly();
    o.consistency_keyframes = n;
    PlaceRecognizer rec(o);
    std::uint64_t id = 0;
    double t = 0.0, travel = 0.0;
    // First pass along corridor 0..30 m, then along an unrelated part 100..130 m.
    for (double s = 0.0; s <= 30.0; s += 0.3, t += 0.5, travel += 0.3)
      rec.process(keyframe(id++, t, travel, s));
    for (double s = 100.0; s <= 130.0; s += 0.3, t += 0.5, travel += 0.3)
      EXPECT_TRUE(appearanceIds(rec.process(keyframe(id++, t, travel, s))).empty());
    // Revisit 10 m ... : the first revisiting keyframe is not queried (its predecessor shows
    // another place, so it has no reference score); candidates appear when n queried keyframes
    // agree, i.e. at revisit n, and they are near the place.
    const std::uint64_t skipped = rec.stats().no_reference;
    std::vector<bool> has;
    for (int r = 0; r < 6; ++r, t += 0.5, travel += 0.3) {
      const double s = 10.0 + 0.3 * r;
      const std::vector<PlaceCandidate> c = rec.process(keyframe(id++, t, travel, s));
      has.push_back(!c.empty());
      for (const PlaceCandidate& x : c) {
        const double stored_s = 0.3 * static_cast<double>(x.id);  // first pass: s = 0.3 id
        EXPECT_LT(std::abs(stored_s - s), 2.0) << "n " << n << " revisit " << r;
      }
    }
    EXPECT_EQ(rec.stats().no_reference, skipped + 1);
    for (int r = 0; r < 6; ++r) EXPECT_EQ(has[r], r >= n) << "n " << n << " revisit " << r;
  }
}

TEST(PlaceRecognizer, AStreakBrokenByAnUnrelatedViewStartsAgain) {
  PlaceRecognitionOptions o = appearanceOnly();
  o.consistency_keyframes = 2;
  PlaceRecognizer rec(o);
  std::uint64_t id = 0;
  double t = 0.0, travel = 0.0;
  for (double s = 0.0; s <= 20.0; s += 0.3, t += 0.5, travel += 0.3)
    rec.process(keyframe(id++, t, travel, s));
  const auto next = [&](double s) {
    t += 0.5;
    travel += 0.3;
    return rec.process(keyframe(id++, t, travel, s));
  };
  next(60.0);
  EXPECT_TRUE(next(5.0).empty());   // first revisit: no streak yet
  EXPECT_TRUE(next(70.0).empty());  // unrelated view: its predecessor is no reference
  const std::uint64_t skipped = rec.stats().no_reference;
  EXPECT_TRUE(next(5.3).empty());  // predecessor unrelated: not queried
  EXPECT_EQ(rec.stats().no_reference, skipped + 1);
  EXPECT_TRUE(next(5.6).empty());   // a new streak of one
  EXPECT_FALSE(next(5.9).empty());  // two consecutive agreeing keyframes
  EXPECT_GE(rec.stats().temporally_consistent, 1u);
  EXPECT_GT(rec.stats().above_threshold, rec.stats().temporally_consistent);
}

TEST(PlaceRecognizer, ProximityAddsNearStoredKeyframesOfTheSameSegment) {
  PlaceRecognitionOptions o;
  o.proximity_radius_m = 1.0;
  o.proximity_max_candidates = 2;
  PlaceRecognizer rec(o);
  // Stored keyframes (views of unrelated places, so appearance proposes nothing).
  rec.process(keyframe(0, 0.0, 0.0, 100.0, {0.5, 0, 0}));
  rec.process(keyframe(1, 1.0, 1.0, 200.0, {0.3, 0, 0}));
  rec.process(keyframe(2, 2.0, 2.0, 300.0, {0.2, 0, 0}, 1));  // other segment
  rec.process(keyframe(3, 3.0, 3.0, 400.0, {0.8, 0, 0}));
  rec.process(keyframe(4, 4.0, 4.0, 500.0, {5.0, 0, 0}));  // far
  for (std::uint64_t id = 5; id < 12; ++id)  // recent keyframes (< 10 s) near the query
    rec.process(keyframe(id, 32.0 + static_cast<double>(id), 32.0 + static_cast<double>(id),
                         600.0 + 10.0 * static_cast<double>(id), {0.1, 0, 0}));
  const std::uint64_t before = rec.stats().proximity;
  const std::vector<PlaceCandidate> c = rec.process(keyframe(12, 45.0, 45.0, 900.0, {0, 0, 0}));
  ASSERT_EQ(c.size(), 2u);  // the two nearest of 0, 1 and 3
  EXPECT_EQ(c[0].id, 1u);
  EXPECT_EQ(c[1].id, 0u);
  EXPECT_TRUE(c[0].by_proximity && c[1].by_proximity);
  EXPECT_EQ(rec.stats().proximity, before + 2);

  // After a pose-graph correction keyframe 4 is the nearest.
  Eigen::Isometry3d moved = Eigen::Isometry3d::Identity();
  moved.translation() = Eigen::Vector3d(0.05, 0.0, 0.0);
  rec.updatePoses({{4, moved}});
  EXPECT_EQ(rec.position(4), moved.translation());
  const std::vector<PlaceCandidate> c2 = rec.process(keyframe(13, 46.0, 46.0, 950.0, {0, 0, 0}));
  ASSERT_EQ(c2.size(), 2u);
  EXPECT_EQ(c2[0].id, 4u);
  EXPECT_EQ(c2[1].id, 1u);
  EXPECT_THROW(rec.updatePoses({{99, moved}}), std::out_of_range);
}

TEST(PlaceRecognizer, ProximityCandidatesAreNotRepeatedWhenAppearanceFoundThem) {
  PlaceRecognitionOptions o;
  o.consistency_keyframes = 1;
  o.proximity_radius_m = 1.0;
  o.proximity_max_candidates = 5;
  o.top_k = 2;  // appearance finds two of the five stored keyframes within 1 m
  PlaceRecognizer rec(o);
  std::uint64_t id = 0;
  for (double s = 0.0; s <= 6.0; s += 0.3, ++id)
    rec.process(keyframe(id, static_cast<double>(id), s, s, {s, 0, 0}));
  for (double s = 40.0; s <= 46.0; s += 0.3, ++id)
    rec.process(keyframe(id, static_cast<double>(id), s, s, {s, 0, 0}));
  // Back at the start, with a position estimate there too (the first keyframe back has no
  // reference: its predecessor shows another place).
  rec.process(keyframe(id, id, 50.0, 0.0, {0.0, 0, 0}));
  ++id;
  const std::vector<PlaceCandidate> c = rec.process(keyframe(id, id, 50.3, 0.3, {0.3, 0, 0}));
  std::set<std::uint64_t> seen;
  bool appearance = false, proximity = false;
  for (const PlaceCandidate& x : c) {
    EXPECT_TRUE(seen.insert(x.id).second) << "id " << x.id << " twice";
    (x.by_proximity ? proximity : appearance) = true;
    EXPECT_LE(std::abs(rec.position(x.id).x() - 0.3), 1.0 + 1.5);
  }
  EXPECT_TRUE(appearance);
  EXPECT_TRUE(proximity);
  EXPECT_EQ(c.size(), 5u);  // each of the five once
  // Appearance first (best normalised first), proximity after.
  for (std::size_t i = 1; i < c.size(); ++i) {
    if (c[i - 1].by_proximity) {
      EXPECT_TRUE(c[i].by_proximity);
    }
    if (!c[i - 1].by_proximity && !c[i].by_proximity) {
      EXPECT_GE(c[i - 1].normalised_score, c[i].normalised_score);
    }
  }
}

TEST(PlaceRecognizer, ASequenceThatNeverRevisitsGivesNoConsistentCandidate) {
  PlaceRecognizer rec(PlaceRecognitionOptions{});
  std::uint64_t id = 0;
  double t = 0.0;
  for (double s = 0.0; s <= 90.0; s += 0.3, t += 0.5)
    EXPECT_TRUE(rec.process(keyframe(id++, t, s, s, {s, 0, 0})).empty()) << "s " << s;
  EXPECT_EQ(rec.stats().temporally_consistent, 0u);
  EXPECT_EQ(rec.stats().proximity, 0u);
  EXPECT_EQ(rec.stats().queried, id - 1);
  EXPECT_EQ(rec.stats().no_reference, 0u);  // every view overlaps its predecessor
}

TEST(PlaceRecognizer, InsertRebuildsWithoutQueryingAndIdsMustIncrease) {
  PlaceRecognizer a(appearanceOnly()), b(appearanceOnly());
  std::vector<LoopKeyframe> kfs;
  for (std::uint64_t i = 0; i < 40; ++i) kfs.push_back(keyframe(i, 0.5 * i, 0.3 * i, 0.3 * i));
  for (const LoopKeyframe& k : kfs) a.process(k);
  for (const LoopKeyframe& k : kfs) b.insert(k);
  EXPECT_EQ(b.stats().queried, 0u);
  EXPECT_EQ(a.size(), b.size());
  const LoopKeyframe q = keyframe(100, 60.0, 30.0, 4.0);
  EXPECT_EQ(a.index().query(q.descriptors, 5).at(0).id, b.index().query(q.descriptors, 5).at(0).id);
  EXPECT_EQ(a.index().similarity(q.descriptors, 13), b.index().similarity(q.descriptors, 13));
  EXPECT_THROW(a.process(keyframe(39, 100.0, 100.0, 0.0)), std::invalid_argument);
  EXPECT_THROW(b.insert(keyframe(3, 100.0, 100.0, 0.0)), std::invalid_argument);
  // Stamps and distances travelled may not go back (the exclusion relies on it).
  EXPECT_THROW(a.process(keyframe(40, 1.0, 100.0, 0.0)), std::invalid_argument);
  EXPECT_THROW(a.process(keyframe(40, 100.0, 1.0, 0.0)), std::invalid_argument);
  EXPECT_EQ(a.size(), 40u);
  EXPECT_GT(a.memoryBytes(), a.index().memoryBytes());
  a.clear();
  EXPECT_EQ(a.size(), 0u);
  EXPECT_EQ(a.stats().queried, 0u);
}

TEST(PlaceRecognizer, TheSameInputGivesTheSameCandidates) {
  const auto run = [] {
    PlaceRecognizer rec(PlaceRecognitionOptions{});
    std::vector<std::vector<PlaceCandidate>> all;
    std::uint64_t id = 0;
    // Two laps of a 12 m loop of the corridor (the view wraps around).
    for (int k = 0; k < 80; ++k, ++id) {
      const double s = std::fmod(0.3 * k, 12.0);
      all.push_back(rec.process(keyframe(id, 0.5 * k, 0.3 * k, s, {s, 0, 0})));
    }
    return all;
  };
  const auto a = run(), b = run();
  ASSERT_EQ(a.size(), b.size());
  std::size_t total = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a[i].size(), b[i].size()) << "keyframe " << i;
    total += a[i].size();
    for (std::size_t j = 0; j < a[i].size(); ++j) {
      EXPECT_EQ(a[i][j].id, b[i][j].id);
      EXPECT_EQ(a[i][j].score, b[i][j].score);
      EXPECT_EQ(a[i][j].normalised_score, b[i][j].normalised_score);
      EXPECT_EQ(a[i][j].by_proximity, b[i][j].by_proximity);
    }
  }
  EXPECT_GT(total, 20u);  // the second lap found the first
}

TEST(PlaceRecognizer, CandidatesOfAnUnrelatedPartSkipTheConsistencyCheck) {
  // A map (segment 0) along 0..30 m; a new part (segment 1) starts at 10 m. With consistency 3,
  // its candidates in the unrelated segment 0 come from its first keyframe on; without the
  // predicate only from the fourth (first queried at the second, consistent at the fourth).
  for (bool with_predicate : {false, true}) {
    PlaceRecognitionOptions o = appearanceOnly();
    o.consistency_keyframes = 3;
    PlaceRecognizer rec(o);
    std::uint64_t id = 0;
    double t = 0.0, travel = 0.0;
    for (double s = 0.0; s <= 30.0; s += 0.3, t += 0.5, travel += 0.3)
      rec.insert(keyframe(id++, t, travel, s));
    t += 20.0;
    travel += 5.0;
    std::vector<bool> has;
    for (int r = 0; r < 4; ++r, t += 0.5, travel += 0.3) {
      const auto unrelated = [](int segment) { return segment == 0; };
      const LoopKeyframe k = keyframe(id++, t, travel, 10.0 + 0.3 * r, {0, 0, 0}, 1);
      const std::vector<PlaceCandidate> c =
          with_predicate ? rec.process(k, unrelated) : rec.process(k);
      has.push_back(!appearanceIds(c).empty());
    }
    // Keyframe 0 of the part has no predecessor of its own: without the predicate it is not
    // queried (no reference score); with it, it proposes the unrelated part's best matches.
    const std::vector<bool> expected = with_predicate
                                           ? std::vector<bool>{true, true, true, true}
                                           : std::vector<bool>{false, false, false, true};
    EXPECT_EQ(has, expected) << "predicate " << with_predicate;
  }
}
