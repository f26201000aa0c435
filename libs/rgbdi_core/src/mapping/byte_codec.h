// Little-endian encoding of fixed-size values for the keyframe file, independent of the host's
// byte order, with bounds-checked reading (a truncated file reports what it was reading).
#pragma once

#include <cstdint>
#include <cstring>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace rgbdi::mapping::detail {

class ByteWriter {
 public:
  void u8(std::uint8_t v) { bytes_.push_back(static_cast<char>(v)); }
  void u32(std::uint32_t v) {
    for (int i = 0; i < 4; ++i) u8(static_cast<std::uint8_t>(v >> (8 * i)));
  }
  void u64(std::uint64_t v) {
    for (int i = 0; i < 8; ++i) u8(static_cast<std::uint8_t>(v >> (8 * i)));
  }
  void f32(float v) {
    std::uint32_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    u32(bits);
  }
  void f64(double v) {
    std::uint64_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    u64(bits);
  }
  void raw(const void* data, std::size_t n) { bytes_.append(static_cast<const char*>(data), n); }
  const std::string& bytes() const { return bytes_; }

 private:
  std::string bytes_;
};

/// Reads from a byte buffer; every read names what it reads so that running off the end
/// produces "truncated while reading <what>" through the caller's error function.
class ByteReader {
 public:
  using Fail = std::function<void(const std::string& what)>;  // must throw

  ByteReader(const std::vector<char>& data, Fail fail) : data_(data), fail_(std::move(fail)) {}

  std::size_t offset() const { return offset_; }
  std::size_t remaining() const { return data_.size() - offset_; }

  std::uint8_t u8(const char* what) {
    need(1, what);
    return static_cast<std::uint8_t>(data_[offset_++]);
  }
  std::uint32_t u32(const char* what) {
    need(4, what);
    std::uint32_t v = 0;
    for (int i = 0; i < 4; ++i)
      v |= static_cast<std::uint32_t>(static_cast<std::uint8_t>(data_[offset_++])) << (8 * i);
    return v;
  }
  std::uint64_t u64(const char* what) {
    need(8, what);
    std::uint64_t v = 0;
    for (int i = 0; i < 8; ++i)
      v |= static_cast<std::uint64_t>(static_cast<std::uint8_t>(data_[offset_++])) << (8 * i);
    return v;
  }
  float f32(const char* what) {
    const std::uint32_t bits = u32(what);
    float v;
    std::memcpy(&v, &bits, sizeof v);
    return v;
  }
  double f64(const char* what) {
    const std::uint64_t bits = u64(what);
    double v;
    std::memcpy(&v, &bits, sizeof v);
    return v;
  }
  void raw(void* out, std::size_t n, const char* what) {
    need(n, what);
    if (n == 0) return;  // `out` may be the null data() of an empty container (memcpy: UB)
    std::memcpy(out, data_.data() + offset_, n);
    offset_ += n;
  }
  /// Checks that `count` records of `bytes_each` can still follow before anything is allocated
  /// for them (a corrupt count must not trigger a huge allocation).
  void needRecords(std::uint64_t count, std::size_t bytes_each, const char* what) {
    if (bytes_each > 0 && count > remaining() / bytes_each) {
      fail_(std::string("truncated or corrupt: ") + std::to_string(count) + " " + what +
            " announced but only " + std::to_string(remaining()) + " bytes remain");
      failed();
    }
  }

 private:
  void need(std::size_t n, const char* what) {
    if (remaining() < n) {
      fail_(std::string("truncated while reading ") + what);
      failed();
    }
  }
  [[noreturn]] static void failed() {
    throw std::logic_error("ByteReader: the failure handler returned instead of throwing");
  }

  const std::vector<char>& data_;
  Fail fail_;
  std::size_t offset_ = 0;
};

}  // namespace rgbdi::mapping::detail
