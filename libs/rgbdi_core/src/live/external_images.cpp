#include "live/external_images.h"

#include <filesystem>
#include <mutex>
#include <stdexcept>

#include "rgbdi/io/mrpt_image_path.h"

namespace rgbdi::live {

void storeImagesExternally(mrpt::obs::CObservation3DRangeScan& obs, const std::string& dir,
                           const std::string& stem, const std::string& ext) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (obs.hasIntensityImage) {
    const std::string name = stem + "_color." + ext;
    if (!obs.intensityImage.saveToFile(dir + "/" + name))
      throw std::runtime_error(dir + "/" + name + ": cannot write the colour image");
    obs.intensityImage.setExternalStorage(name);
  }
  if (obs.hasRangeImage) {
    // MRPT swaps its process-wide image directory while it writes the depth file.
    std::lock_guard<std::mutex> lock(io::mrptImagePathMutex());
    obs.rangeImage_convertToExternalStorage(stem + "_depth.bin", dir);
  }
}

}  // namespace rgbdi::live
