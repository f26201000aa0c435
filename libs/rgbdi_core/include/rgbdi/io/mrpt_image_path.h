// MRPT keeps ONE process-wide directory for externally stored images
// (mrpt::img::CImage::setImagesPathBase): RawlogSource sets it to resolve the images it loads, and
// CObservation3DRangeScan::rangeImage_convertToExternalStorage swaps it while it writes a depth
// file. Code that reads or writes external images while other threads may do the same (a replay
// sensor reading while the live recorder or a rawlog-grabber sensor writes) holds this lock
// around the read or the write, so that no thread resolves its images in another's directory.
#pragma once

#include <mutex>

namespace rgbdi::io {

/// The one lock guarding MRPT's process-wide image directory.
std::mutex& mrptImagePathMutex();

}  // namespace rgbdi::io
