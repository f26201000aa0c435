#include "rgbdi/bag/ros_wire.h"

#include <ros/serialization.h>

#include "rgbdi/bag/ros_image.h"
#include "wire_check.h"

namespace rgbdi::bag {
namespace {

using WireCheck = detail::WireCheck<ImageDecodeError>;

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
