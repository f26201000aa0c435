// A growable array in fixed chunks of kChunk elements: elements never move and growth wastes at
// most one partly filled chunk, where std::vector's doubling leaves up to half of a large block
// table unused (34 of 24 MiB for the leaf blocks of a 0.9 M-point map). Internal to the mapping
// stage.
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

namespace rgbdi::mapping::detail {

template <typename T, std::size_t kChunk>
class ChunkedVector {
 public:
  std::size_t size() const { return size_; }
  T& operator[](std::size_t i) { return chunks_[i / kChunk][i % kChunk]; }
  const T& operator[](std::size_t i) const { return chunks_[i / kChunk][i % kChunk]; }
  /// Appends a value-initialised element and returns it.
  T& emplaceBack() {
    if (size_ == chunks_.size() * kChunk) chunks_.push_back(std::make_unique<T[]>(kChunk));
    T& e = (*this)[size_++];
    e = T{};
    return e;
  }
  T& back() { return (*this)[size_ - 1]; }
  void clear() {
    chunks_.clear();
    size_ = 0;
  }
  std::size_t bytes() const {
    return chunks_.size() * kChunk * sizeof(T) + chunks_.capacity() * sizeof(std::unique_ptr<T[]>);
  }

 private:
  std::vector<std::unique_ptr<T[]>> chunks_;
  std::size_t size_ = 0;
};

}  // namespace rgbdi::mapping::detail
