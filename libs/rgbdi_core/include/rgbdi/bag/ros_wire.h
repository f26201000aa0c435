// Deserialising ROS image messages (ROS1 wire format) with their length fields checked first.
// ROS's own deserialiser resizes a message's pixel vector to the length it reads and only then
// checks that the bytes are there, so one corrupt length field zero-fills up to 4 GiB before the
// message is refused. These check every length field (strings and the pixel data) against the
// bytes left in the message before anything is allocated; strings ROS checks itself, but a
// length past the end also means the pixel length that follows cannot be trusted.
#pragma once

#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>

#include <cstdint>
#include <string>

namespace rgbdi::bag {

/// `data`/`size`: one serialized message as stored in a bag. Throws ImageDecodeError (ros_image.h)
/// naming `label`, the field, the bytes it needs, its offset and the bytes left when a field runs
/// past the end of the message.
void deserializeImage(const std::uint8_t* data, std::uint32_t size, sensor_msgs::Image& out,
                      const std::string& label);
void deserializeImage(const std::uint8_t* data, std::uint32_t size,
                      sensor_msgs::CompressedImage& out, const std::string& label);

}  // namespace rgbdi::bag
