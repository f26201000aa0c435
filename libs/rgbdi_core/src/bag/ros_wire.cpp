#include "rgbdi/bag/ros_wire.h"

#include <ros/serialization.h>

#include "rgbdi/bag/ros_image.h"

namespace rgbdi::bag {
namespace {

/// Walks the wire layout of a message without allocating: fixed fields are skipped, length
/// fields are checked against the bytes left.
class WireCheck {
 public:
  WireCheck(const std::uint8_t* data, std::uint32_t size, const std::string& label)
      : data_(data), size_(size), label_(label) {}

  void fixed(std::uint32_t bytes, const char* name) {
    if (bytes > left()) refuse(name, bytes);
    pos_ += bytes;
  }
  /// A string or a uint8[] array: u32 length, then that many bytes.
  void sized(const char* name) {
    fixed(4, name);
    const std::uint32_t len = static_cast<std::uint32_t>(data_[pos_ - 4]) |
                              static_cast<std::uint32_t>(data_[pos_ - 3]) << 8 |
                              static_cast<std::uint32_t>(data_[pos_ - 2]) << 16 |
                              static_cast<std::uint32_t>(data_[pos_ - 1]) << 24;
    fixed(len, name);
  }
  void header() {
    fixed(4 + 8, "header.seq/stamp");  // u32 seq, time (u32 sec, u32 nsec)
    sized("header.frame_id");
  }

 private:
  std::uint32_t left() const { return size_ - pos_; }
  [[noreturn]] void refuse(const char* name, std::uint32_t bytes) const {
    throw ImageDecodeError(label_ + ": corrupt message: " + name + " needs " +
                           std::to_string(bytes) + " bytes at offset " + std::to_string(pos_) +
                           ", the message has " + std::to_string(left()) + " left (of " +
                           std::to_string(size_) + ")");
  }

  const std::uint8_t* data_;
  std::uint32_t size_, pos_ = 0;
  const std::string& label_;
};

template <typename M>
void deserializeRos(const std::uint8_t* data, std::uint32_t size, M& out) {
  ros::serialization::IStream s(const_cast<std::uint8_t*>(data), size);
  ros::serialization::deserialize(s, out);
}

}  // namespace

void deserializeImage(const std::uint8_t* data, std::uint32_t size, sensor_msgs::Image& out,
                      const std::string& label) {
  WireCheck w(data, size, label);
  w.header();
  w.fixed(4 + 4, "height/width");
  w.sized("encoding");
  w.fixed(1 + 4, "is_bigendian/step");
  w.sized("data");
  deserializeRos(data, size, out);
}

void deserializeImage(const std::uint8_t* data, std::uint32_t size,
                      sensor_msgs::CompressedImage& out, const std::string& label) {
  WireCheck w(data, size, label);
  w.header();
  w.sized("format");
  w.sized("data");
  deserializeRos(data, size, out);
}

}  // namespace rgbdi::bag
