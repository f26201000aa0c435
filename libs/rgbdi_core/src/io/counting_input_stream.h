// Private to the io stage: a pass-through input stream that counts the bytes handed to the
// MRPT archive, so that an end of file can be told apart from a record cut in the middle; it can
// also look ahead (peek) at bytes the archive reads next, and it checks the embedded images of
// every record before MRPT decodes them (cimage_guard.h).
#pragma once

#include <mrpt/io/CStream.h>

#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/cimage_guard.h"

namespace rgbdi::io {

class CountingInputStream : public mrpt::io::CStream {
 public:
  explicit CountingInputStream(mrpt::io::CStream& in) : in_(in) {}

  size_t Read(void* buffer, size_t count) override {
    guard_.beforeRead(count);
    size_t n = 0;
    auto* out = static_cast<std::uint8_t*>(buffer);
    if (ahead_pos_ < ahead_.size()) {
      n = std::min(count, ahead_.size() - ahead_pos_);
      std::memcpy(out, ahead_.data() + ahead_pos_, n);
      ahead_pos_ += n;
      if (ahead_pos_ == ahead_.size()) {
        ahead_.clear();
        ahead_pos_ = 0;
      }
    }
    if (n < count) n += in_.Read(out + n, count - n);
    bytes_ += n;
    if (n < count) short_read_ = true;
    guard_.afterRead(out, n, count);
    return n;
  }
  size_t Write(const void*, size_t) override {
    throw std::logic_error("CountingInputStream is read-only");
  }
  uint64_t Seek(int64_t, CStream::TSeekOrigin) override {
    throw std::logic_error("CountingInputStream cannot seek");
  }
  uint64_t getTotalBytesCount() const override { return in_.getTotalBytesCount(); }
  uint64_t getPosition() const override { return bytes_; }

  /// The next `count` bytes the archive will read, without consuming them (fewer at the end of
  /// the data). Valid until the next call.
  const std::vector<std::uint8_t>& peek(size_t count) {
    if (ahead_pos_ > 0) {
      ahead_.erase(ahead_.begin(), ahead_.begin() + static_cast<std::ptrdiff_t>(ahead_pos_));
      ahead_pos_ = 0;
    }
    if (ahead_.size() < count) {
      const size_t had = ahead_.size();
      ahead_.resize(count);
      ahead_.resize(had + in_.Read(ahead_.data() + had, count - had));
    }
    peeked_.assign(ahead_.begin(),
                   ahead_.begin() + static_cast<std::ptrdiff_t>(std::min(count, ahead_.size())));
    return peeked_;
  }

  /// Why the image check refused a read (empty: it did not).
  const std::string& guardError() const { return guard_.error(); }

  /// Bytes delivered so far (uncompressed).
  uint64_t bytes() const { return bytes_; }
  /// True once a read returned fewer bytes than requested (the data ended).
  bool shortRead() const { return short_read_; }

 private:
  mrpt::io::CStream& in_;
  std::vector<std::uint8_t> ahead_;   ///< read from `in_`, not yet delivered
  size_t ahead_pos_ = 0;              ///< delivered part of `ahead_`
  std::vector<std::uint8_t> peeked_;  ///< what peek() returned
  CImageGuard guard_;
  uint64_t bytes_ = 0;
  bool short_read_ = false;
};

}  // namespace rgbdi::io
