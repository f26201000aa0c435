// Walks the ROS1 wire layout of a message without allocating: fixed fields are skipped, length
// fields are checked against the bytes left, so that a corrupt length is refused before ROS's
// deserialiser resizes a vector or string to it. Throws `Error` naming the label, the field, the
// bytes it needs, its offset and the bytes left.
#pragma once

#include <cstdint>
#include <string>

namespace rgbdi::bag::detail {

template <typename Error>
class WireCheck {
 public:
  WireCheck(const std::uint8_t* data, std::uint32_t size, const std::string& label)
      : data_(data), size_(size), label_(label) {}

  void fixed(std::uint32_t bytes, const char* name) {
    if (bytes > left()) refuse(name, bytes);
    pos_ += bytes;
  }
  /// A little-endian u32 (a length or an element count).
  std::uint32_t u32(const char* name) {
    fixed(4, name);
    return static_cast<std::uint32_t>(data_[pos_ - 4]) |
           static_cast<std::uint32_t>(data_[pos_ - 3]) << 8 |
           static_cast<std::uint32_t>(data_[pos_ - 2]) << 16 |
           static_cast<std::uint32_t>(data_[pos_ - 1]) << 24;
  }
  /// A string or a uint8[] array: u32 length, then that many bytes.
  void sized(const char* name) { fixed(u32(name), name); }
  void header() {
    fixed(4 + 8, "header.seq/stamp");  // u32 seq, time (u32 sec, u32 nsec)
    sized("header.frame_id");
  }
  std::uint32_t position() const { return pos_; }
  std::uint32_t left() const { return size_ - pos_; }

 private:
  [[noreturn]] void refuse(const char* name, std::uint32_t bytes) const {
    throw Error(label_ + ": corrupt message: " + name + " needs " + std::to_string(bytes) +
                " bytes at offset " + std::to_string(pos_) + ", the message has " +
                std::to_string(left()) + " left (of " + std::to_string(size_) + ")");
  }

  const std::uint8_t* data_;
  std::uint32_t size_, pos_ = 0;
  const std::string& label_;
};

}  // namespace rgbdi::bag::detail
