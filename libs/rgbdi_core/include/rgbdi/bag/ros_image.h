// Decoding ROS image messages into rgbdi's image conventions: colour CV_8UC3 in R,G,B order,
// depth CV_16UC1 in integer units with a known length per unit (0 = invalid).
//
// sensor_msgs/Image colour encodings: rgb8, bgr8, rgba8, bgra8, mono8, 8UC1, 8UC3 (taken as
// bgr8, like cv_bridge), yuv422 (UYVY) and yuv422_yuy2 / yuyv (YUYV). Depth encodings: 16UC1 and
// mono16 (integer units: `integer_unit_m`), 32FC1 (metres, converted to units of
// `float_unit_m`; NaN, infinite, non-positive and too far values become 0 and are counted).
// Big-endian data and padded rows are handled. sensor_msgs/CompressedImage: JPEG/PNG colour, PNG
// depth and the compressedDepth formats of image_transport ("16UC1; compressedDepth [png]",
// "32FC1; compressedDepth [png]" with its inverse-depth quantisation).
// Anything else is an ImageDecodeError naming the message and the encoding.
#pragma once

#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>

#include <cstddef>
#include <opencv2/core.hpp>
#include <string>

#include "rgbdi/bag/bag_writer.h"

namespace rgbdi::bag {

class ImageDecodeError : public BagError {
 public:
  using BagError::BagError;
};

struct DepthImage {
  cv::Mat depth;            ///< CV_16UC1, 0 = invalid
  double unit_m = 1e-3;     ///< metres per unit
  std::size_t clipped = 0;  ///< float depths that did not fit into 16 bits (set to 0)
};

/// `label` (e.g. "file.bag /camera/color/image_raw message 12") prefixes every error message.
cv::Mat decodeColorImage(const sensor_msgs::Image& msg, const std::string& label);
cv::Mat decodeColorImage(const sensor_msgs::CompressedImage& msg, const std::string& label);

DepthImage decodeDepthImage(const sensor_msgs::Image& msg, double integer_unit_m,
                            double float_unit_m, const std::string& label);
DepthImage decodeDepthImage(const sensor_msgs::CompressedImage& msg, double integer_unit_m,
                            double float_unit_m, const std::string& label);

/// Metres -> units of `unit_m` (rounded); 0 for NaN, inf, <= 0 and values beyond 16 bits
/// (`clipped` counts the latter).
cv::Mat metresToUnits(const cv::Mat& metres_32f, double unit_m, std::size_t& clipped);

}  // namespace rgbdi::bag
