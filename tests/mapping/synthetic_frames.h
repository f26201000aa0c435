// Synthetic RGB-D frames with exactly known geometry for the mapping tests.
#pragma once

#include <cstdint>
#include <opencv2/core.hpp>
#include <string>

#include "rgbdi/common/types.h"

namespace rgbdi::mapping::test {

inline PinholeCamera makeCamera(int width = 640, int height = 480, double f = 500.0) {
  PinholeCamera c;
  c.width = width;
  c.height = height;
  c.fx = c.fy = f;
  c.cx = (width - 1) / 2.0;
  c.cy = (height - 1) / 2.0;
  return c;
}

/// Colour that encodes the pixel, so a test can tell where a point's colour was sampled.
inline cv::Vec3b pixelColour(int u, int v) {
  return {static_cast<std::uint8_t>(u % 256), static_cast<std::uint8_t>(v % 256),
          static_cast<std::uint8_t>((u / 256) * 16 + (v / 256))};
}

inline cv::Mat patternImage(int width, int height) {
  cv::Mat rgb(height, width, CV_8UC3);
  for (int v = 0; v < height; ++v)
    for (int u = 0; u < width; ++u) rgb.at<cv::Vec3b>(v, u) = pixelColour(u, v);
  return rgb;
}

/// A fronto-parallel plane at depth_mm in front of an aligned colour+depth camera.
inline RgbdFrame planeFrame(std::uint16_t depth_mm, const PinholeCamera& camera = makeCamera(),
                            const std::string& label = "synthetic plane") {
  RgbdFrame f;
  f.cam_color = f.cam_depth = camera;
  f.depth = cv::Mat(camera.height, camera.width, CV_16UC1, cv::Scalar(depth_mm));
  f.rgb = patternImage(camera.width, camera.height);
  f.depth_unit_m = 1e-3;
  f.depth_aligned_to_color = true;
  f.source_label = label;
  return f;
}

}  // namespace rgbdi::mapping::test
