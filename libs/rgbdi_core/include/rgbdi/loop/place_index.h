// Online place index over binary descriptors, built from nothing (no trained or downloaded
// vocabulary): multi-table hashing of descriptor bit subsets, in the manner of BASALT's HashBoW.
//
// Each of `tables` tables owns `key_bits` bit positions of the descriptor, drawn once from a
// seeded generator; a descriptor gives one key per table (its bits at those positions). A
// keyframe is the set K of its distinct (table, key) pairs. With N keyframes in the index and
// df(w) the number of them whose set contains w, the similarity of a query set Q to keyframe K is
//     s(Q, K) = sum over w in Q and K of idf(w) / sqrt(|Q| |K|),   idf(w) = ln(1 + N / df(w)),
// so keys that many keyframes share count little, and s(K, K) = mean idf of K's keys. Similar
// descriptors (small Hamming distance) share the key of a table with probability
// (1 - d/256)^key_bits; several tables make a match likely to share at least one key.
// Keys in more than max_key_keyframes keyframes are left out of the sums (stop words), which
// bounds the query time on large maps of repeated routes. Scores depend only on the stored sets,
// never on the order of add(): clear() and adding the stored descriptors again gives identical
// scores.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "rgbdi/mapping/keyframe.h"

namespace rgbdi::loop {

struct PlaceIndexOptions {
  int tables = 4;     ///< [count] hash tables (keys per descriptor)
  int key_bits = 16;  ///< [bit] descriptor bits per key (8-20; memory 2^key_bits * tables * 24 B)
  std::uint64_t seed = 1;               ///< draws the bit positions of the tables
  std::uint32_t descriptor_bytes = 32;  ///< [byte] size of every descriptor indexed
  /// [count] keys held by more keyframes than this are stop words: they add nothing to any
  /// score (their idf is low anyway, and their posting lists would dominate the query time)
  int max_key_keyframes = 1000;

  /// Throws ConfigError when a value is out of range or key_bits exceed the descriptor.
  void validate() const;
};

struct PlaceMatch {
  std::uint64_t id = 0;
  double score = 0.0;  ///< s(Q, K), see the file comment
};

/// The keys of one descriptor set (PlaceIndex::keys), computed once for several calls on the
/// index that made them.
class PlaceKeys {
 public:
  const std::vector<std::uint32_t>& sorted() const { return keys_; }

 private:
  friend class PlaceIndex;
  std::vector<std::uint32_t> keys_;
};

class PlaceIndex {
 public:
  /// Throws ConfigError on invalid options.
  explicit PlaceIndex(const PlaceIndexOptions& options = PlaceIndexOptions());

  /// Adds keyframe `id` (ids strictly increasing). Throws std::invalid_argument when the id is
  /// not larger than every id present, or the set is inconsistent or has another descriptor
  /// size (an empty set is accepted: it shares nothing).
  void add(std::uint64_t id, const mapping::DescriptorSet& descriptors);
  /// The best `top_k` keyframes for which `allowed(id)` is true and that share at least one key,
  /// best first (equal scores by increasing id). A null predicate allows all.
  std::vector<PlaceMatch> query(const mapping::DescriptorSet& descriptors, std::size_t top_k,
                                const std::function<bool(std::uint64_t)>& allowed = {}) const;
  /// s(Q, K) for keyframe `id`. Throws std::out_of_range naming the id when it is absent.
  double similarity(const mapping::DescriptorSet& descriptors, std::uint64_t id) const;

  /// s(Q, Q) as if Q were one more keyframe of the index (N + 1 keyframes, df(w) + 1): the
  /// score of a perfect match, the scale against which other scores of Q can be read.
  double selfSimilarity(const mapping::DescriptorSet& descriptors) const;

  /// The same four operations on keys computed once by keys() (throws like keysOf).
  PlaceKeys keys(const mapping::DescriptorSet& descriptors) const;
  void add(std::uint64_t id, const PlaceKeys& keys);
  std::vector<PlaceMatch> query(const PlaceKeys& keys, std::size_t top_k,
                                const std::function<bool(std::uint64_t)>& allowed = {}) const;
  double similarity(const PlaceKeys& keys, std::uint64_t id) const;
  double selfSimilarity(const PlaceKeys& keys) const;

  bool contains(std::uint64_t id) const;
  std::size_t size() const { return ids_.size(); }
  /// Heap + object bytes held (capacity-based).
  std::size_t memoryBytes() const;
  void clear();

  /// Sorted distinct keys (table * 2^key_bits + bits) of a descriptor set.
  std::vector<std::uint32_t> keysOf(const mapping::DescriptorSet& descriptors) const;
  /// Bit positions (0 = bit 0 of byte 0) of table t.
  const std::vector<int>& tableBits(int t) const { return bits_.at(static_cast<std::size_t>(t)); }

 private:
  std::size_t slotOf(std::uint64_t id) const;  // size() when absent
  void checkSet(const mapping::DescriptorSet& descriptors, const char* who) const;
  double idf(std::size_t df) const;
  bool stopWord(std::size_t df) const {
    return df > static_cast<std::size_t>(options_.max_key_keyframes);
  }

  PlaceIndexOptions options_;
  std::vector<std::vector<int>> bits_;  ///< per table, its bit positions
  /// Inverted index: per key, the slots of the keyframes containing it (increasing).
  std::vector<std::vector<std::uint32_t>> postings_;
  std::vector<std::uint64_t> ids_;         ///< per slot
  std::vector<std::uint32_t> key_counts_;  ///< per slot, |K|
};

}  // namespace rgbdi::loop
