// Private to the io stage: a pass-through input stream that counts the bytes handed to the
// MRPT archive, so that an end of file can be told apart from a record cut in the middle.
#pragma once

#include <mrpt/io/CStream.h>

#include <cstdint>
#include <stdexcept>

namespace rgbdi::io {

class CountingInputStream : public mrpt::io::CStream {
 public:
  explicit CountingInputStream(mrpt::io::CStream& in) : in_(in) {}

  size_t Read(void* buffer, size_t count) override {
    const size_t n = in_.Read(buffer, count);
    bytes_ += n;
    if (n < count) short_read_ = true;
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

  /// Bytes delivered so far (uncompressed).
  uint64_t bytes() const { return bytes_; }
  /// True once a read returned fewer bytes than requested (the data ended).
  bool shortRead() const { return short_read_; }

 private:
  mrpt::io::CStream& in_;
  uint64_t bytes_ = 0;
  bool short_read_ = false;
};

}  // namespace rgbdi::io
