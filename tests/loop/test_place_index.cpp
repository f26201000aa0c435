// Place index: exact scores on a hand-made case, table keys from the drawn bit positions, the
// same view scoring highest among synthetic views, identical scores after a rebuild, the
// allowed-predicate and the errors.
#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <random>
#include <set>

#include "frontend/synthetic_scene.h"
#include "rgbdi/common/ini_reader.h"
#include "rgbdi/loop/loop_features.h"
#include "rgbdi/loop/place_index.h"

using rgbdi::loop::PlaceIndex;
using rgbdi::loop::PlaceIndexOptions;
using rgbdi::loop::PlaceMatch;
using rgbdi::mapping::DescriptorSet;

namespace {

/// One-byte descriptors: with one table of 8 bits every byte value is its own key.
DescriptorSet bytes(std::initializer_list<std::uint8_t> values) {
  DescriptorSet d;
  d.type = "TEST-8";
  d.bytes_per_descriptor = 1;
  for (std::uint8_t v : values) {
    d.keypoints_uv.emplace_back(0.0f, 0.0f);
    d.data.push_back(v);
  }
  return d;
}

PlaceIndexOptions oneByteOptions() {
  PlaceIndexOptions o;
  o.tables = 1;
  o.key_bits = 8;
  o.descriptor_bytes = 1;
  return o;
}

/// ORB features of a synthetic textured view; `shift_px` moves the view, `noise` adds grey
/// noise (another exposure of the same place).
DescriptorSet view(std::uint64_t texture_seed, int shift_px = 0, double noise = 0.0,
                   std::uint64_t noise_seed = 0) {
  const rgbdi::PinholeCamera cam = rgbdi::test::simpleCamera();
  cv::Mat tex =
      rgbdi::test::randomRectangleTexture(cam.width + 40, cam.height, texture_seed, 1000, 1.0);
  tex = tex(cv::Rect(20 + shift_px, 0, cam.width, cam.height)).clone();
  if (noise > 0.0) {
    cv::Mat n(tex.size(), CV_32FC1);
    cv::theRNG().state = noise_seed + 1;
    cv::randn(n, 0.0, noise);
    tex += n;
  }
  const rgbdi::RgbdFrame f = rgbdi::test::colourFrame(rgbdi::test::toGrey8(tex), 0.0, 0, cam);
  return rgbdi::loop::extractLoopFeatures(f, cam, rgbdi::loop::LoopFeatureOptions());
}

}  // namespace

TEST(PlaceIndex, ScoresAHandMadeCaseExactly) {
  PlaceIndex index(oneByteOptions());
  index.add(10, bytes({1, 2, 3}));
  index.add(11, bytes({1, 4}));
  index.add(12, bytes({5}));
  EXPECT_EQ(index.size(), 3u);
  // Q = {1, 2, 4, 6}, the repeated 1 counts once. N = 3; df(1) = 2, df(2) = df(4) = 1.
  const DescriptorSet q = bytes({1, 2, 4, 6, 1});
  const double idf1 = std::log(1.0 + 3.0 / 2.0), idf_single = std::log(1.0 + 3.0 / 1.0);
  const double s10 = (idf1 + idf_single) / std::sqrt(4.0 * 3.0);
  const double s11 = (idf1 + idf_single) / std::sqrt(4.0 * 2.0);
  const std::vector<PlaceMatch> m = index.query(q, 10);
  ASSERT_EQ(m.size(), 2u);  // keyframe 12 shares nothing
  EXPECT_EQ(m[0].id, 11u);
  EXPECT_DOUBLE_EQ(m[0].score, s11);
  EXPECT_EQ(m[1].id, 10u);
  EXPECT_DOUBLE_EQ(m[1].score, s10);
  EXPECT_DOUBLE_EQ(index.similarity(q, 10), s10);
  EXPECT_DOUBLE_EQ(index.similarity(q, 11), s11);
  EXPECT_EQ(index.similarity(q, 12), 0.0);
  // A perfect match as one more keyframe: N + 1 = 4 and df + 1 for each of Q's keys.
  const double self =
      (std::log(1.0 + 4.0 / 3.0) + 2.0 * std::log(1.0 + 4.0 / 2.0) + std::log(1.0 + 4.0 / 1.0)) /
      4.0;
  EXPECT_DOUBLE_EQ(index.selfSimilarity(q), self);
  // Keys computed once give the same answers.
  const rgbdi::loop::PlaceKeys qk = index.keys(q);
  EXPECT_EQ(qk.sorted(), index.keysOf(q));
  EXPECT_EQ(index.query(qk, 10).at(1).score, s10);
  EXPECT_EQ(index.similarity(qk, 11), index.similarity(q, 11));
  EXPECT_EQ(index.selfSimilarity(qk), index.selfSimilarity(q));
  // top_k cuts the list after the best.
  const std::vector<PlaceMatch> best = index.query(q, 1);
  ASSERT_EQ(best.size(), 1u);
  EXPECT_EQ(best[0].id, 11u);
}

TEST(PlaceIndex, KeysOfTooManyKeyframesAreStopWords) {
  PlaceIndexOptions o = oneByteOptions();
  o.max_key_keyframes = 2;
  PlaceIndex index(o);
  index.add(1, bytes({1, 2}));
  index.add(2, bytes({1, 3}));
  EXPECT_GT(index.similarity(bytes({1}), 2), 0.0);  // key 1 in two keyframes still counts
  index.add(3, bytes({1, 4}));
  // Key 1 is now in three keyframes: it adds nothing; |Q| and |K| still count it.
  const std::vector<PlaceMatch> m = index.query(bytes({1, 2}), 10);
  ASSERT_EQ(m.size(), 1u);
  EXPECT_EQ(m[0].id, 1u);
  EXPECT_DOUBLE_EQ(m[0].score, std::log(1.0 + 3.0 / 1.0) / std::sqrt(2.0 * 2.0));
  EXPECT_EQ(index.similarity(bytes({1}), 2), 0.0);
  EXPECT_DOUBLE_EQ(index.selfSimilarity(bytes({1, 2})), std::log(1.0 + 4.0 / 2.0) / 2.0);
}

TEST(PlaceIndex, EqualScoresAreOrderedById) {
  PlaceIndex index(oneByteOptions());
  for (std::uint64_t id : {3u, 8u, 20u, 21u}) index.add(id, bytes({7, 9}));
  const std::vector<PlaceMatch> m = index.query(bytes({7}), 10);
  ASSERT_EQ(m.size(), 4u);
  for (std::size_t i = 0; i < m.size(); ++i) EXPECT_EQ(m[i].score, m[0].score);
  EXPECT_EQ(m[0].id, 3u);
  EXPECT_EQ(m[1].id, 8u);
  EXPECT_EQ(m[2].id, 20u);
  EXPECT_EQ(m[3].id, 21u);
  const std::vector<PlaceMatch> two = index.query(bytes({7}), 2);
  ASSERT_EQ(two.size(), 2u);
  EXPECT_EQ(two[1].id, 8u);
}

TEST(PlaceIndex, KeysAreTheDescriptorBitsAtTheTablePositions) {
  PlaceIndexOptions o;  // 4 tables of 16 bits over 256-bit descriptors
  PlaceIndex index(o);
  std::mt19937_64 rng(4);
  DescriptorSet d;
  d.type = "ORB-256";
  d.bytes_per_descriptor = 32;
  d.keypoints_uv.resize(3);
  for (int i = 0; i < 96; ++i) d.data.push_back(static_cast<std::uint8_t>(rng() & 0xFF));
  std::set<std::uint32_t> expected;
  for (int t = 0; t < o.tables; ++t) {
    const std::vector<int>& bits = index.tableBits(t);
    ASSERT_EQ(bits.size(), 16u);
    EXPECT_EQ(std::set<int>(bits.begin(), bits.end()).size(), 16u);  // distinct positions
    for (int b : bits) {
      EXPECT_GE(b, 0);
      EXPECT_LT(b, 256);
    }
    for (std::size_t k = 0; k < 3; ++k) {
      std::uint32_t key = 0;
      for (int b : bits) key = key * 2 + ((d.data[k * 32 + b / 8] >> (b % 8)) & 1);
      expected.insert((static_cast<std::uint32_t>(t) << 16) + key);
    }
  }
  const std::vector<std::uint32_t> keys = index.keysOf(d);
  EXPECT_EQ(std::set<std::uint32_t>(keys.begin(), keys.end()), expected);
  EXPECT_TRUE(std::is_sorted(keys.begin(), keys.end()));
  // The positions are a function of the seed only.
  PlaceIndex same(o);
  o.seed = 2;
  PlaceIndex other(o);
  EXPECT_EQ(same.tableBits(2), index.tableBits(2));
  EXPECT_NE(other.tableBits(0), index.tableBits(0));
}

TEST(PlaceIndex, TheSameViewScoresHighest) {
  PlaceIndex index;
  for (std::uint64_t place = 0; place < 12; ++place) index.add(place * 10, view(100 + place));
  // Another exposure of place 7, moved by 6 px.
  const DescriptorSet q = view(107, 6, 4.0, 1);
  const std::vector<PlaceMatch> m = index.query(q, 5);
  ASSERT_FALSE(m.empty());
  EXPECT_EQ(m[0].id, 70u);
  ASSERT_GE(m.size(), 2u);
  EXPECT_GT(m[0].score, 3.0 * m[1].score);  // well separated from the other places
  EXPECT_EQ(index.similarity(q, 70), m[0].score);
}

TEST(PlaceIndex, RebuildingFromTheStoredDescriptorsGivesIdenticalScores) {
  std::vector<DescriptorSet> stored;
  for (std::uint64_t place = 0; place < 8; ++place)
    stored.push_back(view(200 + place, static_cast<int>(3 * (place % 6))));
  PlaceIndex index;
  for (std::size_t i = 0; i < stored.size(); ++i) index.add(i + 1, stored[i]);
  std::vector<std::vector<PlaceMatch>> before;
  for (std::uint64_t s : {203u, 206u, 999u}) before.push_back(index.query(view(s, 2, 3.0, s), 8));
  const std::size_t memory = index.memoryBytes();
  EXPECT_GT(memory, index.size() * 400u * 4u);  // the postings of every key

  index.clear();
  EXPECT_EQ(index.size(), 0u);
  EXPECT_TRUE(index.query(stored[0], 8).empty());
  EXPECT_LT(index.memoryBytes(), memory);
  for (std::size_t i = 0; i < stored.size(); ++i) index.add(i + 1, stored[i]);
  std::size_t n = 0;
  for (std::uint64_t s : {203u, 206u, 999u}) {
    const std::vector<PlaceMatch> after = index.query(view(s, 2, 3.0, s), 8);
    ASSERT_EQ(after.size(), before[n].size());
    for (std::size_t i = 0; i < after.size(); ++i) {
      EXPECT_EQ(after[i].id, before[n][i].id);
      EXPECT_EQ(after[i].score, before[n][i].score);  // bit-identical
    }
    ++n;
  }
}

TEST(PlaceIndex, TheAllowedPredicateIsHonoured) {
  PlaceIndex index;
  for (std::uint64_t place = 0; place < 6; ++place) index.add(place, view(300 + place));
  const DescriptorSet q = view(302, 4, 3.0, 7);
  ASSERT_EQ(index.query(q, 1).at(0).id, 2u);
  const std::vector<PlaceMatch> m =
      index.query(q, 10, [](std::uint64_t id) { return id != 2 && id != 4; });
  for (const PlaceMatch& x : m) {
    EXPECT_NE(x.id, 2u);
    EXPECT_NE(x.id, 4u);
  }
  EXPECT_FALSE(m.empty());
  EXPECT_TRUE(index.query(q, 10, [](std::uint64_t) { return false; }).empty());
}

TEST(PlaceIndex, RejectsOutOfOrderIdsForeignDescriptorsAndUnknownIds) {
  PlaceIndex index(oneByteOptions());
  index.add(5, bytes({1}));
  EXPECT_THROW(index.add(5, bytes({2})), std::invalid_argument);
  EXPECT_THROW(index.add(4, bytes({2})), std::invalid_argument);
  DescriptorSet wide = bytes({1});
  wide.bytes_per_descriptor = 2;
  wide.data.push_back(0);
  EXPECT_THROW(index.add(6, wide), std::invalid_argument);
  DescriptorSet broken = bytes({1, 2});
  broken.data.pop_back();
  EXPECT_THROW(index.add(6, broken), std::invalid_argument);
  EXPECT_EQ(index.size(), 1u);
  index.add(6, DescriptorSet());  // an empty set is accepted and shares nothing
  EXPECT_EQ(index.similarity(bytes({1}), 6), 0.0);
  try {
    index.similarity(bytes({1}), 9);
    FAIL() << "expected std::out_of_range";
  } catch (const std::out_of_range& e) {
    EXPECT_NE(std::string(e.what()).find("keyframe 9"), std::string::npos) << e.what();
  }
  PlaceIndexOptions bad;
  bad.key_bits = 30;
  EXPECT_THROW(PlaceIndex{bad}, rgbdi::ConfigError);
  bad = PlaceIndexOptions();
  bad.tables = 0;
  EXPECT_THROW(PlaceIndex{bad}, rgbdi::ConfigError);
}
