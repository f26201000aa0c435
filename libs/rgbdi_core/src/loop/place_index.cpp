#include "rgbdi/loop/place_index.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

#include "rgbdi/common/ini_reader.h"

namespace rgbdi::loop {
namespace {

[[noreturn]] void failKey(const std::string& key, const std::string& what) {
  throw ConfigError("PlaceIndexOptions [loop] " + key + ": " + what);
}

/// Bit positions of every table: a partial Fisher-Yates shuffle of 0..bits-1 per table driven
/// by std::mt19937_64, whose output sequence the standard fixes (the standard distributions are
/// implementation-defined, so they are not used: the index is the same on every platform).
std::vector<std::vector<int>> drawTableBits(const PlaceIndexOptions& o) {
  std::mt19937_64 rng(o.seed);
  const int total = static_cast<int>(o.descriptor_bytes * 8);
  std::vector<std::vector<int>> bits(static_cast<std::size_t>(o.tables));
  for (std::vector<int>& table : bits) {
    std::vector<int> pool(static_cast<std::size_t>(total));
    for (int i = 0; i < total; ++i) pool[static_cast<std::size_t>(i)] = i;
    for (int i = 0; i < o.key_bits; ++i) {
      const std::uint64_t span = static_cast<std::uint64_t>(total - i);
      const int j = i + static_cast<int>(rng() % span);
      std::swap(pool[static_cast<std::size_t>(i)], pool[static_cast<std::size_t>(j)]);
    }
    table.assign(pool.begin(), pool.begin() + o.key_bits);
  }
  return bits;
}

}  // namespace

void PlaceIndexOptions::validate() const {
  if (tables < 1 || tables > 16) failKey("place_index_tables", "must be in [1, 16]");
  if (key_bits < 8 || key_bits > 20) failKey("place_index_key_bits", "must be in [8, 20]");
  if (max_key_keyframes < 1) failKey("place_index_max_key_keyframes", "must be at least 1");
  if (descriptor_bytes == 0 || static_cast<long>(descriptor_bytes) * 8 < key_bits)
    failKey("place_index_key_bits",
            "exceeds the " + std::to_string(descriptor_bytes * 8) + " bits of a descriptor");
}

PlaceIndex::PlaceIndex(const PlaceIndexOptions& options) : options_(options) {
  options_.validate();
  bits_ = drawTableBits(options_);
  postings_.resize(static_cast<std::size_t>(options_.tables) << options_.key_bits);
}

void PlaceIndex::checkSet(const mapping::DescriptorSet& d, const char* who) const {
  if (!d.consistent())
    throw std::invalid_argument(std::string(who) + ": descriptor data holds " +
                                std::to_string(d.data.size()) + " bytes for " +
                                std::to_string(d.size()) + " keypoints of " +
                                std::to_string(d.bytes_per_descriptor) + " bytes");
  if (d.size() > 0 && d.bytes_per_descriptor != options_.descriptor_bytes)
    throw std::invalid_argument(std::string(who) + ": descriptors of " +
                                std::to_string(d.bytes_per_descriptor) +
                                " bytes, the index holds " +
                                std::to_string(options_.descriptor_bytes) + "-byte descriptors");
}

std::vector<std::uint32_t> PlaceIndex::keysOf(const mapping::DescriptorSet& d) const {
  checkSet(d, "PlaceIndex::keysOf");
  std::vector<std::uint32_t> keys;
  keys.reserve(d.size() * bits_.size());
  for (std::size_t k = 0; k < d.size(); ++k) {
    const std::uint8_t* desc = d.data.data() + k * d.bytes_per_descriptor;
    for (std::size_t t = 0; t < bits_.size(); ++t) {
      std::uint32_t key = 0;
      for (int b : bits_[t]) key = (key << 1) | ((desc[b >> 3] >> (b & 7)) & 1u);
      keys.push_back(static_cast<std::uint32_t>(t << options_.key_bits) | key);
    }
  }
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  return keys;
}

double PlaceIndex::idf(std::size_t df) const {
  return std::log(1.0 + static_cast<double>(ids_.size()) / static_cast<double>(df));
}

std::size_t PlaceIndex::slotOf(std::uint64_t id) const {
  const auto it = std::lower_bound(ids_.begin(), ids_.end(), id);
  return it != ids_.end() && *it == id ? static_cast<std::size_t>(it - ids_.begin()) : ids_.size();
}

bool PlaceIndex::contains(std::uint64_t id) const { return slotOf(id) < ids_.size(); }

PlaceKeys PlaceIndex::keys(const mapping::DescriptorSet& descriptors) const {
  PlaceKeys k;
  k.keys_ = keysOf(descriptors);
  return k;
}

void PlaceIndex::add(std::uint64_t id, const mapping::DescriptorSet& descriptors) {
  add(id, keys(descriptors));
}

std::vector<PlaceMatch> PlaceIndex::query(const mapping::DescriptorSet& descriptors,
                                          std::size_t top_k,
                                          const std::function<bool(std::uint64_t)>& allowed) const {
  return query(keys(descriptors), top_k, allowed);
}

double PlaceIndex::similarity(const mapping::DescriptorSet& descriptors, std::uint64_t id) const {
  return similarity(keys(descriptors), id);
}

double PlaceIndex::selfSimilarity(const mapping::DescriptorSet& descriptors) const {
  return selfSimilarity(keys(descriptors));
}

void PlaceIndex::add(std::uint64_t id, const PlaceKeys& place_keys) {
  if (!ids_.empty() && id <= ids_.back())
    throw std::invalid_argument("PlaceIndex::add: keyframe " + std::to_string(id) +
                                " is not newer than keyframe " + std::to_string(ids_.back()) +
                                " (ids must increase)");
  const std::vector<std::uint32_t>& keys = place_keys.sorted();
  const auto slot = static_cast<std::uint32_t>(ids_.size());
  for (std::uint32_t w : keys) postings_[w].push_back(slot);
  ids_.push_back(id);
  key_counts_.push_back(static_cast<std::uint32_t>(keys.size()));
}

std::vector<PlaceMatch> PlaceIndex::query(const PlaceKeys& place_keys, std::size_t top_k,
                                          const std::function<bool(std::uint64_t)>& allowed) const {
  const std::vector<std::uint32_t>& keys = place_keys.sorted();
  std::vector<PlaceMatch> out;
  if (keys.empty() || ids_.empty() || top_k == 0) return out;
  std::vector<double> sum(ids_.size(), 0.0);
  std::vector<std::uint32_t> touched;
  for (std::uint32_t w : keys) {  // increasing keys: the same summation order on every run
    const std::vector<std::uint32_t>& list = postings_[w];
    if (list.empty() || stopWord(list.size())) continue;
    const double weight = idf(list.size());
    for (std::uint32_t slot : list) {
      if (sum[slot] == 0.0) touched.push_back(slot);
      sum[slot] += weight;
    }
  }
  const double nq = static_cast<double>(keys.size());
  out.reserve(touched.size());
  for (std::uint32_t slot : touched) {
    const std::uint64_t id = ids_[slot];
    if (allowed && !allowed(id)) continue;
    out.push_back({id, sum[slot] / std::sqrt(nq * key_counts_[slot])});
  }
  const auto better = [](const PlaceMatch& a, const PlaceMatch& b) {
    return a.score != b.score ? a.score > b.score : a.id < b.id;
  };
  if (out.size() > top_k) {
    std::partial_sort(out.begin(), out.begin() + static_cast<std::ptrdiff_t>(top_k), out.end(),
                      better);
    out.resize(top_k);
  } else {
    std::sort(out.begin(), out.end(), better);
  }
  return out;
}

double PlaceIndex::similarity(const PlaceKeys& place_keys, std::uint64_t id) const {
  const std::size_t slot = slotOf(id);
  if (slot == ids_.size())
    throw std::out_of_range("PlaceIndex::similarity: keyframe " + std::to_string(id) +
                            " is not in the index");
  const std::vector<std::uint32_t>& keys = place_keys.sorted();
  if (keys.empty() || key_counts_[slot] == 0) return 0.0;
  double sum = 0.0;
  for (std::uint32_t w : keys) {
    const std::vector<std::uint32_t>& list = postings_[w];
    if (!stopWord(list.size()) &&
        std::binary_search(list.begin(), list.end(), static_cast<std::uint32_t>(slot)))
      sum += idf(list.size());
  }
  return sum / std::sqrt(static_cast<double>(keys.size()) * key_counts_[slot]);
}

double PlaceIndex::selfSimilarity(const PlaceKeys& place_keys) const {
  const std::vector<std::uint32_t>& keys = place_keys.sorted();
  if (keys.empty()) return 0.0;
  const double n = static_cast<double>(ids_.size() + 1);
  double sum = 0.0;
  for (std::uint32_t w : keys) {
    const std::size_t df = postings_[w].size() + 1;
    if (!stopWord(df)) sum += std::log(1.0 + n / static_cast<double>(df));
  }
  return sum / static_cast<double>(keys.size());
}

std::size_t PlaceIndex::memoryBytes() const {
  std::size_t bytes = sizeof(*this) + postings_.capacity() * sizeof(std::vector<std::uint32_t>) +
                      ids_.capacity() * sizeof(std::uint64_t) +
                      key_counts_.capacity() * sizeof(std::uint32_t);
  for (const std::vector<int>& b : bits_) bytes += sizeof(b) + b.capacity() * sizeof(int);
  for (const std::vector<std::uint32_t>& list : postings_)
    bytes += list.capacity() * sizeof(std::uint32_t);
  return bytes;
}

void PlaceIndex::clear() {
  for (std::vector<std::uint32_t>& list : postings_) std::vector<std::uint32_t>().swap(list);
  ids_.clear();
  key_counts_.clear();
}

}  // namespace rgbdi::loop
