// A 32 x 24 RGB-D frame for the converter tests' hand-made bags: its colour and depth encode the
// index k (colour (k, 2, 3), depth 1000 + k mm), so a converted frame tells which one it was.
#pragma once

#include <opencv2/core.hpp>

#include "rgbdi/common/types.h"

namespace rgbdi::test {

inline RgbdFrame tinyFrame(double t, int k) {
  RgbdFrame f;
  f.t = t;
  f.rgb = cv::Mat(24, 32, CV_8UC3, cv::Scalar(k, 2, 3));
  f.depth = cv::Mat(24, 32, CV_16UC1, cv::Scalar(1000 + k));
  return f;
}

}  // namespace rgbdi::test
