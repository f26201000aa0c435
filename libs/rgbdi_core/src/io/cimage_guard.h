// Private to the io stage: checks the images embedded in rawlog records before MRPT decodes
// them, by following MRPT's reads of every mrpt::img::CImage through the input stream
// (CountingInputStream calls it around each read). Fuzzing findings 11 and 13
// (doc/robustness.md):
//  - MRPT decodes an embedded JPEG (CImage versions 1-9, colour) with libjpeg's default error
//    handler, which calls exit(1) on a damaged JPEG: rgbdi-slam ended with libjpeg's message
//    instead of its own refusal naming the file and record. The JPEG bytes are decoded here first
//    (OpenCV's decoder reports errors instead of exiting); one that does not decode, or that the
//    file ends in (MRPT decodes the short buffer anyway), makes the read throw, and the record
//    is refused as damaged.
//  - CImage version 0 reads a stored byte count into a buffer sized by the stored width, height
//    and channels, without comparing them: a count above the buffer overflowed the heap. A
//    count that does not match the pixels is refused here before the read.
//  - A CSensoryFrame or CActionCollection nested in another object (RawlogSource reads
//    top-level ones itself) is refused: MRPT resizes its element list to the stored count before
//    reading any element (a damaged count takes gigabytes, finding 1), and a version-0 frame
//    writes its stamp through every element pointer, also null ones (finding 10).
// A CImage is recognised by the reads of its object header (CArchive reads the length byte of
// the class name, then the name "CImage", then the version), wherever it is nested; the reads
// that follow are matched against MRPT 2.5's CImage::serializeFrom, and anything else (another
// layout, an externally stored or grey image) ends the check for that image.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace rgbdi::io {

/// True if a class name as stored in a rawlog names MRPT's class `cls` ("CImage"): MRPT resolves
/// it by the part after the last "::".
bool storedClassIs(const std::uint8_t* name, std::size_t size, const std::string& cls);

class CImageGuard {
 public:
  /// Before the archive reads `count` bytes: throws std::runtime_error if that read would
  /// overflow the image MRPT has allocated.
  void beforeRead(std::size_t count);
  /// After a read of `count` bytes delivered `n` at `data`: follows the image layout; throws
  /// std::runtime_error on an embedded JPEG that cannot be decoded.
  void afterRead(const std::uint8_t* data, std::size_t n, std::size_t count);

  /// The reason of the last refusal (MRPT rethrows exceptions from inside an object as its
  /// end-of-file exception, so the reader asks here for what was wrong). Empty if none.
  const std::string& error() const { return error_; }

 private:
  enum class Step {
    Idle,
    Version8,   ///< new-format header: version byte
    Version32,  ///< old-format header: int32 version
    V0Width,    ///< version 0: width, height, channels, origin, byte count, data
    V0Height,
    V0Channels,
    V0Origin,
    V0Length,
    V0Data,
    External,    ///< versions 6-9: externally stored?
    HasColor,    ///< versions 2-9: colour (JPEG) or grey
    ColorWidth,  ///< versions 7-9: width, height (>= 1: JPEG follows)
    ColorHeight,
    JpegLength,  ///< byte count of the JPEG
    JpegData,
  };
  [[noreturn]] void refuse(const std::string& why);
  void watchHeader(const std::uint8_t* data, std::size_t n, std::size_t count);
  void startPayload(int version);

  Step step_ = Step::Idle;
  int version_ = 0;
  /// "a sensory frame" or "an action collection" if the header read is one's, empty for a CImage
  std::string nested_container_;
  std::int64_t width_ = 0, height_ = 0, channels_ = 0;
  std::uint64_t length_ = 0;
  // The last two reads (for the object header): their size and first byte(s).
  std::size_t last_count_ = 0, before_last_count_ = 0;
  std::uint32_t last_bytes_ = 0, before_last_bytes_ = 0;
  std::string error_;
};

}  // namespace rgbdi::io
