// Streaming reader of MRPT rawlogs: yields a time-ordered stream of IMU samples and RGB-D frames
// with bounded memory (one record at a time plus the re-ordering window).
//
// * Both rawlog layouts: a plain sequence of observations, and CActionCollection/CSensoryFrame
//   pairs (actions are ignored, every observation of a sensory frame is used).
// * Plain or gzip-compressed files (detected automatically).
// * Externally stored images and range matrices are read from the rawlog's image directory
//   (rawlogImagesDirectory(): "<dir>/<name>_Images", MRPT's convention). MRPT keeps
//   that directory in ONE process-wide setting (CImage::setImagesPathBase); the source sets it
//   before every record it reads, so several sources may be used one after the other or
//   interleaved in one thread, but not concurrently from several threads.
// * Observations of other types are skipped and counted; RGB-D/IMU observations that cannot be
//   converted are skipped, counted and reported.
// * Ordering and checks: see TimeOrderingBuffer and StreamChecker; diagnostics() holds the result.
// * A corrupt or truncated record ends the stream: everything read before it is still delivered,
//   then next() throws RawlogError naming the file and the record (diagnostics().error too).
// Messages are also logged through mrpt::system::COutputLogger (warnings at LVL_WARN).
#pragma once

#include <mrpt/system/COutputLogger.h>

#include <memory>
#include <stdexcept>
#include <string>

#include "rgbdi/io/measurement_source.h"
#include "rgbdi/io/stream_options.h"

namespace rgbdi::io {

/// Directory of externally stored images of a rawlog: "<dir>/<name>_Images" (also "_images",
/// "_IMAGES") where <name> is the file name without ".gz" and ".rawlog"; when none exists,
/// "<dir>/Images". (MRPT's CRawlog::detectImagesDirectory in 2.5 drops the path separator.)
std::string rawlogImagesDirectory(const std::string& rawlog_path);

/// The rawlog cannot be opened or a record cannot be read.
class RawlogError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class RawlogSource : public MeasurementSource, public mrpt::system::COutputLogger {
 public:
  /// Opens `path`; throws RawlogError when it does not exist or cannot be opened.
  explicit RawlogSource(const std::string& path, const StreamConfig& cfg = StreamConfig());
  ~RawlogSource() override;
  RawlogSource(const RawlogSource&) = delete;
  RawlogSource& operator=(const RawlogSource&) = delete;

  bool next(Measurement& out) override;
  void stopReading() override;
  const StreamDiagnostics& diagnostics() const override;

  const std::string& path() const;
  /// Directory used for externally stored images of this rawlog.
  const std::string& imagesDirectory() const;
  /// Fraction of the rawlog file read so far, in [0, 1] (compressed bytes for gz files); for
  /// progress reporting only.
  double progress() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rgbdi::io
