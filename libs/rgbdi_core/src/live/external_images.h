// Images of an observation stored as external files, as MRPT's setPathForExternalImages asks
// (rawlog-grabber passes "<rawlog>_Images"): colour in the sensor's image format, depth as MRPT's
// external range file. The rawlog then holds only the file names (relative to that directory).
#pragma once

#include <mrpt/obs/CObservation3DRangeScan.h>

#include <string>

namespace rgbdi::live {

/// Writes the colour and depth of `obs` below `dir` as "<stem>_color.<ext>" and
/// "<stem>_depth.bin" and switches the observation to external storage. Throws
/// std::runtime_error naming the file when writing fails.
void storeImagesExternally(mrpt::obs::CObservation3DRangeScan& obs, const std::string& dir,
                           const std::string& stem, const std::string& ext);

}  // namespace rgbdi::live
