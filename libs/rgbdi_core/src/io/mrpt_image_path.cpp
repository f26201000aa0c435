#include "rgbdi/io/mrpt_image_path.h"

namespace rgbdi::io {

std::mutex& mrptImagePathMutex() {
  // Guards state that MRPT itself makes global; there is nothing per-object to lock instead.
  static std::mutex m;
  return m;
}

}  // namespace rgbdi::io
