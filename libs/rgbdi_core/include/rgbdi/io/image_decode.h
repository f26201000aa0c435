// Fast decoding of the external image files of a rawlog (the simulator's and rawlog-convert's
// layout: a colour PNG and a gzip range file per frame). Inflating them with zlib (through
// libpng and MRPT's gzip stream) was a quarter of rgbdi-slam's CPU time; libdeflate inflates the
// same data in about half the time, and the PNG is written straight into the RGB image the
// front end wants (no BGR intermediate, no conversion).
//
// Both functions decode only the common case exactly and return nullopt for any other kind of
// file (the caller then takes MRPT/OpenCV's path, which decodes the rest). Damaged files of the
// kinds they decode throw ImageDecodeError saying what is wrong: MRPT's gzip reader returns a
// truncated range file as a frame of zeros without any error, and OpenCV's PNG errors reach
// the user as a bare "MRPT exception" banner.
#pragma once

#include <cstddef>
#include <cstdint>
#include <opencv2/core.hpp>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace rgbdi::io {

/// A damaged PNG or range file (truncated, checksum mismatch, undecodable data).
struct ImageDecodeError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// True if the data start with the PNG file signature (8 bytes).
bool isPngData(const std::uint8_t* data, std::size_t size);
/// True if the data start with a JPEG start-of-image marker followed by a marker (FF D8 FF).
bool isJpegData(const std::uint8_t* data, std::size_t size);

/// An 8-bit, non-interlaced PNG of colour type grey, RGB or RGBA without a transparency (tRNS)
/// or palette chunk, decoded to CV_8UC3 R,G,B (grey replicated, alpha dropped: what OpenCV's
/// decoder followed by a conversion to RGB gives). nullopt for other PNG kinds and non-PNG data.
/// Throws ImageDecodeError for a truncated file, a critical chunk whose CRC does not match,
/// image data that does not inflate to the image's size (zlib checksum included) or an unknown
/// row filter (ancillary chunks with a bad CRC are ignored, as libpng does).
std::optional<cv::Mat> decodePngToRgb(const std::uint8_t* data, std::size_t size);

/// The range file MRPT writes for an externally stored CObservation3DRangeScan range image
/// (rangeImage_convertToExternalStorage, binary form): one gzip member holding uint32 rows,
/// uint32 cols and rows x cols uint16 values, row-major, little-endian. Returns CV_16UC1
/// rows x cols. nullopt when the file cannot be read or is not exactly that: not gzip, more
/// than one gzip member, or other content (the CMatrixF files of rawlogs older than MRPT's
/// format version 9). Throws ImageDecodeError naming the file when its gzip data are damaged
/// (truncated, CRC or size mismatch, or a trailer size above 256 MB).
std::optional<cv::Mat> readMrptRangeFile(const std::string& path);

}  // namespace rgbdi::io
