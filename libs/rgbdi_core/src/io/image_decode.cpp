#include "rgbdi/io/image_decode.h"

#include <libdeflate.h>

#include <cstdlib>
#include <cstring>
#include <memory>

#include "rgbdi/common/whole_file.h"

namespace rgbdi::io {
namespace {

/// One decompressor per thread (the reader thread decodes every frame; allocating its tables
/// per image would cost more than small images take to inflate).
libdeflate_decompressor* decompressor() {
  struct Free {
    void operator()(libdeflate_decompressor* d) const { libdeflate_free_decompressor(d); }
  };
  thread_local std::unique_ptr<libdeflate_decompressor, Free> d(libdeflate_alloc_decompressor());
  return d.get();
}

std::uint32_t bigEndian32(const std::uint8_t* p) {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) |
         std::uint32_t{p[3]};
}

std::uint32_t littleEndian32(const std::uint8_t* p) {
  return std::uint32_t{p[0]} | (std::uint32_t{p[1]} << 8) | (std::uint32_t{p[2]} << 16) |
         (std::uint32_t{p[3]} << 24);
}

// Largest decoded image accepted on this path [bytes]; bigger ones go to OpenCV/MRPT.
constexpr std::size_t kMaxDecodedBytes = std::size_t{1} << 28;

std::uint8_t paeth(int a, int b, int c) {
  const int p = a + b - c;
  const int pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
  if (pa <= pb && pa <= pc) return static_cast<std::uint8_t>(a);
  if (pb <= pc) return static_cast<std::uint8_t>(b);
  return static_cast<std::uint8_t>(c);
}

/// The Sub filter's inverse for B bytes per pixel: one running sum per byte of the pixel, kept in
/// registers (the byte-wise loop reads back every byte it has just stored: a store-to-load chain
/// per byte, the decoder's own cost on OpenCV's PNGs, which filter every row with Sub).
template <std::size_t B>
void unfilterSub(const std::uint8_t* in, std::uint8_t* out, std::size_t n) {
  std::uint8_t sum[B] = {};
  for (std::size_t i = 0; i + B <= n; i += B)
    for (std::size_t k = 0; k < B; ++k)
      out[i + k] = sum[k] = static_cast<std::uint8_t>(sum[k] + in[i + k]);
}

/// Reverses the PNG filter of one row: `out` = the unfiltered bytes of `in` (`prior`: the row
/// above, already unfiltered, or zeros for the first row). False for an unknown filter type.
bool unfilterRow(int type, const std::uint8_t* in, std::uint8_t* out, const std::uint8_t* prior,
                 std::size_t n, int bpp) {
  const std::size_t b = static_cast<std::size_t>(bpp);
  switch (type) {
    case 0:
      std::memcpy(out, in, n);
      return true;
    case 1:
      // bpp is 1, 3 or 4 (the IHDR check); n is a whole number of pixels
      if (b == 3) {
        unfilterSub<3>(in, out, n);
      } else if (b == 4) {
        unfilterSub<4>(in, out, n);
      } else {
        unfilterSub<1>(in, out, n);
      }
      return true;
    case 2:
      for (std::size_t i = 0; i < n; ++i) out[i] = static_cast<std::uint8_t>(in[i] + prior[i]);
      return true;
    case 3:
      for (std::size_t i = 0; i < b; ++i) out[i] = static_cast<std::uint8_t>(in[i] + prior[i] / 2);
      for (std::size_t i = b; i < n; ++i)
        out[i] = static_cast<std::uint8_t>(in[i] + (out[i - b] + prior[i]) / 2);
      return true;
    case 4:
      for (std::size_t i = 0; i < b; ++i) out[i] = static_cast<std::uint8_t>(in[i] + prior[i]);
      for (std::size_t i = b; i < n; ++i)
        out[i] = static_cast<std::uint8_t>(in[i] + paeth(out[i - b], prior[i], prior[i - b]));
      return true;
    default:
      return false;
  }
}

}  // namespace

bool isPngData(const std::uint8_t* data, std::size_t size) {
  static const std::uint8_t kSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  return size >= sizeof kSignature && std::memcmp(data, kSignature, sizeof kSignature) == 0;
}

bool isJpegData(const std::uint8_t* data, std::size_t size) {
  return size >= 3 && data[0] == 0xFF && data[1] == 0xD8 && data[2] == 0xFF;
}

std::optional<cv::Mat> decodePngToRgb(const std::uint8_t* data, std::size_t size) {
  if (!isPngData(data, size)) return std::nullopt;
  std::uint32_t width = 0, height = 0;
  int channels = 0;
  thread_local std::vector<std::uint8_t> compressed;
  compressed.clear();
  bool have_header = false, have_end = false;
  for (std::size_t pos = 8; !have_end;) {
    if (pos + 12 > size) throw ImageDecodeError("PNG truncated (no IEND chunk)");
    const std::uint32_t length = bigEndian32(data + pos);
    if (length > size - pos - 12) throw ImageDecodeError("PNG truncated inside a chunk");
    const std::uint8_t* type = data + pos + 4;
    const std::uint8_t* body = data + pos + 8;
    pos += 12 + std::size_t{length};
    const bool critical = !(type[0] & 0x20);
    if (libdeflate_crc32(0, type, length + 4) != bigEndian32(body + length)) {
      if (critical)
        throw ImageDecodeError("PNG chunk " + std::string(reinterpret_cast<const char*>(type), 4) +
                               " has a wrong CRC (damaged file)");
      continue;  // a damaged ancillary chunk carries nothing decoded here
    }
    if (std::memcmp(type, "IHDR", 4) == 0) {
      if (have_header || length != 13) return std::nullopt;
      width = bigEndian32(body);
      height = bigEndian32(body + 4);
      const int bit_depth = body[8], colour_type = body[9];
      // compression method, filter method and interlacing: only the standard, non-interlaced.
      if (bit_depth != 8 || body[10] != 0 || body[11] != 0 || body[12] != 0) return std::nullopt;
      channels = colour_type == 0 ? 1 : colour_type == 2 ? 3 : colour_type == 6 ? 4 : 0;
      if (channels == 0 || width == 0 || height == 0) return std::nullopt;
      have_header = true;
    } else if (!have_header) {
      return std::nullopt;  // IHDR must come first
    } else if (std::memcmp(type, "IDAT", 4) == 0) {
      compressed.insert(compressed.end(), body, body + length);
    } else if (std::memcmp(type, "IEND", 4) == 0) {
      have_end = true;
    } else if (std::memcmp(type, "tRNS", 4) == 0 || std::memcmp(type, "PLTE", 4) == 0) {
      return std::nullopt;  // transparency or palette: OpenCV's conversions apply
    } else if (critical) {
      return std::nullopt;  // a critical chunk this decoder does not know
    }
  }
  if (compressed.empty()) throw ImageDecodeError("PNG has no image data (IDAT)");
  const std::size_t stride = std::size_t{width} * static_cast<std::size_t>(channels);
  if (stride + 1 > kMaxDecodedBytes / height) return std::nullopt;
  const std::size_t raw_size = (stride + 1) * height;
  thread_local std::vector<std::uint8_t> raw, zeros;
  raw.resize(raw_size);
  std::size_t in_used = 0, out_size = 0;
  if (libdeflate_zlib_decompress_ex(decompressor(), compressed.data(), compressed.size(),
                                    raw.data(), raw_size, &in_used,
                                    &out_size) != LIBDEFLATE_SUCCESS ||
      out_size != raw_size)
    throw ImageDecodeError("PNG image data are damaged (they do not inflate to " +
                           std::to_string(width) + "x" + std::to_string(height) + " pixels)");
  zeros.assign(stride, 0);
  // RGB rows are unfiltered straight into the image; grey and RGBA rows into two alternating
  // row buffers first (the filters work on the file's own bytes per pixel).
  thread_local std::vector<std::uint8_t> rows;
  if (channels != 3) rows.resize(2 * stride);
  cv::Mat rgb(static_cast<int>(height), static_cast<int>(width), CV_8UC3);
  const std::uint8_t* prior = zeros.data();
  for (std::uint32_t r = 0; r < height; ++r) {
    const std::uint8_t* in = raw.data() + std::size_t{r} * (stride + 1);
    std::uint8_t* dst = rgb.ptr<std::uint8_t>(static_cast<int>(r));
    std::uint8_t* out = channels == 3 ? dst : rows.data() + (r % 2) * stride;
    if (!unfilterRow(in[0], in + 1, out, prior, stride, channels))
      throw ImageDecodeError("PNG row " + std::to_string(r) + " has an unknown filter type " +
                             std::to_string(in[0]) + " (damaged file)");
    prior = out;
    if (channels == 1) {
      for (std::uint32_t c = 0; c < width; ++c, dst += 3) dst[0] = dst[1] = dst[2] = out[c];
    } else if (channels == 4) {
      for (std::uint32_t c = 0; c < width; ++c, dst += 3) std::memcpy(dst, out + 4 * c, 3);
    }
  }
  return rgb;
}

std::optional<cv::Mat> readMrptRangeFile(const std::string& path) {
  thread_local std::vector<std::uint8_t> file;
  if (readWholeFile(path, file) != FileReadError::kNone || file.size() < 2 || file[0] != 0x1F ||
      file[1] != 0x8B)
    return std::nullopt;  // unreadable (MRPT reports it) or not gzip
  const auto damaged = [&](const std::string& what) {
    return ImageDecodeError("range file " + path + " is damaged: " + what);
  };
  // gzip header (10 bytes) and trailer: CRC32, then the uncompressed size modulo 2^32.
  if (file.size() < 18) throw damaged("truncated gzip file");
  const std::size_t raw_size = littleEndian32(file.data() + file.size() - 4);
  // A truncated file's last four bytes are deflate data: mostly a size beyond any depth image.
  if (raw_size > kMaxDecodedBytes)
    throw damaged("its gzip trailer gives " + std::to_string(raw_size) +
                  " bytes of data, more than any range image (truncated or corrupt)");
  // Inflated straight into the image's own buffer: the 8-byte size header is 4 uint16 values
  // before the pixels, which then start at column 4 of a one-row image (no copy of the image).
  const int raw_values = static_cast<int>((raw_size + 1) / 2);
  cv::Mat raw(1, std::max(raw_values, 4), CV_16UC1);
  std::size_t in_used = 0, out_size = 0;
  const libdeflate_result result = libdeflate_gzip_decompress_ex(
      decompressor(), file.data(), file.size(), raw.data, raw_size, &in_used, &out_size);
  if (result != LIBDEFLATE_SUCCESS || out_size != raw_size)
    throw damaged("its gzip data do not inflate to the size in its trailer (truncated or corrupt)");
  if (in_used != file.size()) return std::nullopt;  // more gzip members follow: MRPT reads them
  // The older CMatrixF files start with MRPT's object header (0x88 "CMatrixF"), which read as
  // rows and cols is far too large: refused here, read by MRPT.
  if (raw_size < 8) return std::nullopt;
  const std::uint32_t rows = littleEndian32(raw.data), cols = littleEndian32(raw.data + 4);
  if (rows == 0 || cols == 0 || rows > kMaxDecodedBytes / cols ||
      8 + 2 * std::size_t{rows} * cols != raw_size)
    return std::nullopt;
  const int n = static_cast<int>(std::size_t{rows} * cols);
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
  // A one-row ROI is continuous, so it reshapes to rows x cols sharing the buffer.
  cv::Mat range = raw.colRange(4, 4 + n).reshape(1, static_cast<int>(rows));
#else
  cv::Mat range(static_cast<int>(rows), static_cast<int>(cols), CV_16UC1);
  for (std::uint32_t r = 0; r < rows; ++r) {
    auto* dst = range.ptr<std::uint16_t>(static_cast<int>(r));
    const std::uint8_t* src = raw.data + 8 + 2 * std::size_t{r} * cols;
    for (std::uint32_t c = 0; c < cols; ++c)
      dst[c] = static_cast<std::uint16_t>(src[2 * c] | (src[2 * c + 1] << 8));
  }
#endif
  return range;
}

}  // namespace rgbdi::io
