// Fuzz target: serialized ROS messages as found in bags: sensor_msgs/Image and CompressedImage
// deserialised by bag::deserializeImage (length fields checked first) and decoded by
// bag::decodeColorImage / decodeDepthImage, sensor_msgs/Imu deserialized. The first
// byte selects the message kind, the rest is the ROS wire format. Documented refusals: ROS's
// serialization exception (message shorter than its fields say) and ImageDecodeError.
#include <ros/serialization.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>

#include <new>
#include <opencv2/imgcodecs.hpp>

#include "fuzz_target.h"
#include "rgbdi/bag/ros_image.h"
#include "rgbdi/bag/ros_wire.h"

namespace {

/// sensor_msgs/Imu: fixed-size arrays and one string, which ROS checks before allocating.
template <class M>
bool deserialize(const std::uint8_t* data, std::size_t size, M& out) {
  try {
    ros::serialization::IStream s(const_cast<std::uint8_t*>(data),
                                  static_cast<std::uint32_t>(size));
    ros::serialization::deserialize(s, out);
    return true;
  } catch (const ros::Exception&) {
    return false;
  }
}

/// The image path of BagConverter: lengths checked by bag::deserializeImage (ImageDecodeError),
/// then ROS's deserialiser (ros::Exception for what is short). No std::bad_alloc is expected
/// any more: a corrupt pixel length is refused before anything is allocated (finding 2).
template <class M>
bool deserializeImageAsBagConverter(const std::uint8_t* data, std::size_t size, M& out) {
  try {
    rgbdi::bag::deserializeImage(data, static_cast<std::uint32_t>(size), out, "fuzz message");
    return true;
  } catch (const rgbdi::bag::ImageDecodeError&) {
    return false;
  } catch (const ros::Exception&) {
    return false;
  }
}

template <class M>
std::string serialize(std::uint8_t kind, const M& msg) {
  const std::uint32_t n = ros::serialization::serializationLength(msg);
  std::string bytes(n + 1, '\0');
  bytes[0] = static_cast<char>(kind);
  ros::serialization::OStream s(reinterpret_cast<std::uint8_t*>(&bytes[1]), n);
  ros::serialization::serialize(s, msg);
  return bytes;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace rgbdi::bag;
  if (size < 1) return 0;
  const std::uint8_t kind = data[0] % 5;
  ++data;
  --size;
  try {
    if (kind == 0 || kind == 1) {
      sensor_msgs::Image msg;
      if (!deserializeImageAsBagConverter(data, size, msg)) return 0;
      if (kind == 0)
        (void)decodeColorImage(msg, "fuzz colour");
      else
        (void)decodeDepthImage(msg, 1e-3, 1e-3, "fuzz depth");
    } else if (kind == 2 || kind == 3) {
      sensor_msgs::CompressedImage msg;
      if (!deserializeImageAsBagConverter(data, size, msg)) return 0;
      if (kind == 2)
        (void)decodeColorImage(msg, "fuzz colour");
      else
        (void)decodeDepthImage(msg, 1e-3, 1e-3, "fuzz depth");
    } else {
      sensor_msgs::Imu msg;
      deserialize(data, size, msg);
    }
  } catch (const ImageDecodeError&) {
  }
  return 0;
}

namespace rgbdi::fuzz {

std::vector<std::string> rgbdiFuzzSeeds() {
  std::vector<std::string> seeds;
  sensor_msgs::Image img;
  img.height = 3;
  img.width = 4;
  for (const char* enc : {"rgb8", "bgra8", "mono8", "yuv422"}) {
    img.encoding = enc;
    const int bpp = img.encoding == "bgra8"    ? 4
                    : img.encoding == "mono8"  ? 1
                    : img.encoding == "yuv422" ? 2
                                               : 3;
    img.step = img.width * bpp;
    img.data.assign(img.step * img.height, 77);
    seeds.push_back(serialize(0, img));
  }
  for (const char* enc : {"16UC1", "32FC1"}) {
    img.encoding = enc;
    img.step = img.width * (img.encoding == "16UC1" ? 2 : 4);
    img.data.assign(img.step * img.height, 0x3f);
    img.is_bigendian = 0;
    seeds.push_back(serialize(1, img));
  }
  sensor_msgs::CompressedImage c;
  std::vector<std::uint8_t> png;
  cv::imencode(".png", cv::Mat(3, 4, CV_8UC3, cv::Scalar(1, 2, 3)), png);
  c.format = "png";
  c.data = png;
  seeds.push_back(serialize(2, c));
  cv::imencode(".png", cv::Mat(3, 4, CV_16UC1, cv::Scalar(1000)), png);
  c.format = "16UC1; png";
  c.data = png;
  seeds.push_back(serialize(3, c));
  std::string header(12, '\0');  // compressedDepth: 4-byte format + 2 floats, then the PNG
  c.format = "32FC1; compressedDepth png";
  c.data.assign(header.begin(), header.end());
  c.data.insert(c.data.end(), png.begin(), png.end());
  seeds.push_back(serialize(3, c));
  sensor_msgs::Imu imu;
  imu.linear_acceleration.z = 9.8;
  imu.angular_velocity.x = 0.1;
  seeds.push_back(serialize(4, imu));
  return seeds;
}

}  // namespace rgbdi::fuzz
