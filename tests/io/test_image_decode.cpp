// Fast decoding of external rawlog images (image_decode.h): the PNG decoder against OpenCV's
// (libpng) on every filter type and colour type it accepts, refusals of everything else, and the
// MRPT range file against MRPT's own reader.
#include <gtest/gtest.h>
#include <libdeflate.h>
#include <mrpt/img/CImage.h>
#include <mrpt/obs/CObservation3DRangeScan.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <random>
#include <string>
#include <vector>

#include "rgbdi/common/whole_file.h"
#include "rgbdi/io/image_decode.h"

using namespace rgbdi::io;
namespace fs = std::filesystem;

namespace {

using Bytes = std::vector<std::uint8_t>;

void put32(Bytes& b, std::uint32_t v) {
  for (int s = 24; s >= 0; s -= 8) b.push_back(static_cast<std::uint8_t>(v >> s));
}

void chunk(Bytes& png, const char* type, const Bytes& body) {
  put32(png, static_cast<std::uint32_t>(body.size()));
  Bytes typed(type, type + 4);
  typed.insert(typed.end(), body.begin(), body.end());
  png.insert(png.end(), typed.begin(), typed.end());
  put32(png, libdeflate_crc32(0, typed.data(), typed.size()));
}

int predictor(int filter, int a, int b, int c) {
  switch (filter) {
    case 1:
      return a;
    case 2:
      return b;
    case 3:
      return (a + b) / 2;
    case 4: {
      const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
      return pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
    }
    default:
      return 0;
  }
}

/// A PNG written independently of the decoder: forward filters (row r uses filters[r % n]),
/// zlib stream from libdeflate, the IDAT split in two chunks, plus optional extra chunks.
Bytes encodePng(const cv::Mat& img, int colour_type, const std::vector<int>& filters,
                const std::vector<std::pair<std::string, Bytes>>& extra = {}, int interlace = 0,
                int bit_depth = 8) {
  const int ch = img.channels();
  const std::size_t stride = static_cast<std::size_t>(img.cols) * ch;
  Bytes raw;
  Bytes zero(stride, 0);
  for (int r = 0; r < img.rows; ++r) {
    const int f = filters[static_cast<std::size_t>(r) % filters.size()];
    raw.push_back(static_cast<std::uint8_t>(f));
    const std::uint8_t* x = img.ptr<std::uint8_t>(r);
    const std::uint8_t* up = r > 0 ? img.ptr<std::uint8_t>(r - 1) : zero.data();
    for (std::size_t i = 0; i < stride; ++i) {
      const int a = i >= static_cast<std::size_t>(ch) ? x[i - ch] : 0;
      const int c = i >= static_cast<std::size_t>(ch) ? up[i - ch] : 0;
      raw.push_back(static_cast<std::uint8_t>(x[i] - predictor(f, a, up[i], c)));
    }
  }
  libdeflate_compressor* comp = libdeflate_alloc_compressor(6);
  Bytes z(libdeflate_zlib_compress_bound(comp, raw.size()));
  z.resize(libdeflate_zlib_compress(comp, raw.data(), raw.size(), z.data(), z.size()));
  libdeflate_free_compressor(comp);

  Bytes png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  Bytes ihdr;
  put32(ihdr, static_cast<std::uint32_t>(img.cols));
  put32(ihdr, static_cast<std::uint32_t>(img.rows));
  ihdr.insert(ihdr.end(),
              {static_cast<std::uint8_t>(bit_depth), static_cast<std::uint8_t>(colour_type), 0, 0,
               static_cast<std::uint8_t>(interlace)});
  chunk(png, "IHDR", ihdr);
  for (const auto& [type, body] : extra) chunk(png, type.c_str(), body);
  const std::size_t half = z.size() / 2;
  chunk(png, "IDAT", Bytes(z.begin(), z.begin() + static_cast<std::ptrdiff_t>(half)));
  chunk(png, "IDAT", Bytes(z.begin() + static_cast<std::ptrdiff_t>(half), z.end()));
  chunk(png, "IEND", {});
  return png;
}

/// Textured test image: smooth gradients plus noise, so every filter has work to do.
cv::Mat testImage(int channels, unsigned seed) {
  cv::Mat img(37, 53, CV_8UC(channels));
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> noise(0, 40);
  for (int r = 0; r < img.rows; ++r)
    for (int c = 0; c < img.cols; ++c)
      for (int k = 0; k < channels; ++k)
        img.ptr<std::uint8_t>(r)[c * channels + k] =
            static_cast<std::uint8_t>(3 * r + 5 * c + 60 * k + noise(rng));
  return img;
}

/// OpenCV's decoding (libpng) of the same bytes, converted to RGB as the rawlog reader does.
cv::Mat openCvRgb(const Bytes& png) {
  const cv::Mat m = cv::imdecode(png, cv::IMREAD_UNCHANGED);
  cv::Mat rgb;
  const int code = m.channels() == 1   ? cv::COLOR_GRAY2RGB
                   : m.channels() == 3 ? cv::COLOR_BGR2RGB
                                       : cv::COLOR_BGRA2RGB;
  cv::cvtColor(m, rgb, code);
  return rgb;
}

bool identical(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() && cv::norm(a, b, cv::NORM_INF) == 0.0;
}

std::string tempDir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d.string();
}

}  // namespace

TEST(ImageSignature, PngAndJpegAreRecognisedByTheirFirstBytesAsOpenCvWritesThem) {
  std::vector<std::uint8_t> png, jpg;
  const cv::Mat img(4, 4, CV_8UC3, cv::Scalar(10, 20, 30));
  ASSERT_TRUE(cv::imencode(".png", img, png));
  ASSERT_TRUE(cv::imencode(".jpg", img, jpg));
  EXPECT_TRUE(isPngData(png.data(), png.size()));
  EXPECT_FALSE(isJpegData(png.data(), png.size()));
  EXPECT_TRUE(isJpegData(jpg.data(), jpg.size()));
  EXPECT_FALSE(isPngData(jpg.data(), jpg.size()));
  // Shorter than the signature, or one byte off: neither.
  EXPECT_FALSE(isPngData(png.data(), 7));
  EXPECT_FALSE(isJpegData(jpg.data(), 2));
  png[7] ^= 1;
  jpg[2] = 0x00;
  EXPECT_FALSE(isPngData(png.data(), png.size()));
  EXPECT_FALSE(isJpegData(jpg.data(), jpg.size()));
  // OpenEXR's magic (fuzzing finding 20).
  const std::uint8_t exr[] = {0x76, 0x2f, 0x31, 0x01, 0x02, 0x00, 0x00, 0x00};
  EXPECT_FALSE(isPngData(exr, sizeof exr));
  EXPECT_FALSE(isJpegData(exr, sizeof exr));
}

TEST(DecodePng, EveryFilterAndColourTypeEqualsOpenCvsDecoding) {
  const std::vector<std::vector<int>> filter_sets = {{0}, {1}, {2}, {3}, {4}, {0, 1, 2, 3, 4}};
  const std::pair<int, int> kinds[] = {{0, 1}, {2, 3}, {6, 4}};  // colour type, channels
  for (const auto& [colour_type, channels] : kinds) {
    for (std::size_t s = 0; s < filter_sets.size(); ++s) {
      // The encoder takes the image in PNG order (R,G,B[,A]); OpenCV returns B,G,R[,A].
      const cv::Mat img = testImage(channels, static_cast<unsigned>(10 * colour_type + s));
      const Bytes png = encodePng(img, colour_type, filter_sets[s]);
      const auto ours = decodePngToRgb(png.data(), png.size());
      ASSERT_TRUE(ours.has_value()) << "colour type " << colour_type << ", filters " << s;
      EXPECT_TRUE(identical(*ours, openCvRgb(png)))
          << "colour type " << colour_type << ", set " << s;
      // And the pixels themselves: R,G,B of the source (grey replicated, alpha dropped).
      const cv::Vec3b px = ours->at<cv::Vec3b>(20, 30);
      const std::uint8_t* src = img.ptr<std::uint8_t>(20) + 30 * channels;
      EXPECT_EQ(px, channels == 1 ? cv::Vec3b(src[0], src[0], src[0])
                                  : cv::Vec3b(src[0], src[1], src[2]));
    }
  }
}

TEST(DecodePng, OpenCvsOwnPngsAreDecodedIdentically) {
  cv::Mat bgr = testImage(3, 5);
  for (int level : {0, 1, 3, 9}) {
    std::vector<std::uint8_t> png;
    ASSERT_TRUE(cv::imencode(".png", bgr, png, {cv::IMWRITE_PNG_COMPRESSION, level}));
    const auto ours = decodePngToRgb(png.data(), png.size());
    ASSERT_TRUE(ours.has_value()) << "level " << level;
    EXPECT_TRUE(identical(*ours, openCvRgb(png))) << "level " << level;
  }
}

TEST(DecodePng, EverythingElseIsLeftToOpenCv) {
  const cv::Mat rgb = testImage(3, 1);
  const Bytes good = encodePng(rgb, 2, {4});
  ASSERT_TRUE(decodePngToRgb(good.data(), good.size()).has_value());
  // Not a PNG (no signature): someone else's format.
  EXPECT_FALSE(decodePngToRgb(good.data() + 1, good.size() - 1).has_value());
  // Kinds it does not decode: interlaced, transparency, palette, grey + alpha, 16 bit.
  const Bytes interlaced = encodePng(rgb, 2, {0}, {}, 1);
  EXPECT_FALSE(decodePngToRgb(interlaced.data(), interlaced.size()).has_value());
  const Bytes trns = encodePng(rgb, 2, {0}, {{"tRNS", {0, 1, 0, 2, 0, 3}}});
  EXPECT_FALSE(decodePngToRgb(trns.data(), trns.size()).has_value());
  const Bytes grey_alpha = encodePng(testImage(2, 3), 4, {0});
  EXPECT_FALSE(decodePngToRgb(grey_alpha.data(), grey_alpha.size()).has_value());
  const Bytes deep = encodePng(testImage(2, 3), 0, {0}, {}, 0, 16);  // 2 bytes per grey pixel
  EXPECT_FALSE(decodePngToRgb(deep.data(), deep.size()).has_value());
  const Bytes plte = encodePng(testImage(1, 4), 3, {0}, {{"PLTE", Bytes(768, 7)}});
  EXPECT_FALSE(decodePngToRgb(plte.data(), plte.size()).has_value());
}

TEST(DecodePng, DamagedFilesAreErrorsThatSayWhatIsWrong) {
  const Bytes good = encodePng(testImage(3, 1), 2, {4}, {{"tEXt", {'a', 0, 'b'}}});
  ASSERT_TRUE(decodePngToRgb(good.data(), good.size()).has_value());
  const auto error = [](const Bytes& png) -> std::string {
    try {
      decodePngToRgb(png.data(), png.size());
    } catch (const ImageDecodeError& e) {
      return e.what();
    }
    return "no error";
  };
  Bytes flipped = good;
  flipped[flipped.size() / 2] ^= 0x10;  // inside the image data
  EXPECT_EQ(error(flipped), "PNG chunk IDAT has a wrong CRC (damaged file)");
  EXPECT_EQ(error(Bytes(good.begin(), good.end() - 20)), "PNG truncated inside a chunk");
  EXPECT_EQ(error(Bytes(good.begin(), good.end() - 12)), "PNG truncated (no IEND chunk)");
  // A damaged ancillary chunk is ignored (libpng warns and goes on).
  Bytes ancillary = good;
  ancillary[8 + 25 + 8] ^= 0x01;  // first byte of the tEXt chunk's data, after IHDR
  const auto decoded = decodePngToRgb(ancillary.data(), ancillary.size());
  ASSERT_TRUE(decoded.has_value());
  EXPECT_TRUE(identical(*decoded, openCvRgb(good)));
  // An unknown row filter type (5), and image data of the wrong size (IHDR says 2 more rows).
  EXPECT_EQ(error(encodePng(testImage(1, 6), 0, {5})),
            "PNG row 0 has an unknown filter type 5 (damaged file)");
  Bytes taller = good;
  taller[8 + 8 + 7] = static_cast<std::uint8_t>(taller[8 + 8 + 7] + 2);  // height, low byte
  const std::uint32_t crc = libdeflate_crc32(0, &taller[8 + 4], 17);
  for (int k = 0; k < 4; ++k)
    taller[8 + 8 + 13 + k] = static_cast<std::uint8_t>(crc >> (24 - 8 * k));
  EXPECT_EQ(error(taller), "PNG image data are damaged (they do not inflate to 53x39 pixels)");
}

TEST(ReadMrptRangeFile, EqualsMrptsOwnReader) {
  const std::string dir = tempDir("rgbdi_range_file");
  mrpt::obs::CObservation3DRangeScan obs;
  obs.hasRangeImage = true;
  obs.rangeImage_setSize(7, 11);
  for (int r = 0; r < 7; ++r)
    for (int c = 0; c < 11; ++c)
      obs.rangeImage(r, c) = static_cast<std::uint16_t>(r * 1000 + c * 7 + 1);
  obs.rangeImage(3, 4) = 65535;
  obs.rangeImage_convertToExternalStorage("r.bin", dir + "/");
  const std::string file = dir + "/r.bin";
  ASSERT_TRUE(fs::exists(file));

  const auto ours = readMrptRangeFile(file);
  ASSERT_TRUE(ours.has_value());
  ASSERT_EQ(ours->type(), CV_16UC1);
  ASSERT_EQ(ours->rows, 7);
  ASSERT_EQ(ours->cols, 11);
  const std::string saved = mrpt::img::CImage::getImagesPathBase();
  mrpt::img::CImage::setImagesPathBase(dir);
  obs.load();
  mrpt::img::CImage::setImagesPathBase(saved);
  ASSERT_EQ(obs.rangeImage.rows(), 7);
  for (int r = 0; r < 7; ++r)
    for (int c = 0; c < 11; ++c) ASSERT_EQ(ours->at<std::uint16_t>(r, c), obs.rangeImage(r, c));
  EXPECT_EQ(ours->at<std::uint16_t>(3, 4), 65535);

  // Not that format, or damaged: left to MRPT.
  std::vector<std::uint8_t> bytes;
  ASSERT_EQ(rgbdi::readWholeFile(file, bytes), rgbdi::FileReadError::kNone);
  auto write = [&](const std::string& name, const std::vector<std::uint8_t>& b) {
    std::ofstream(dir + "/" + name, std::ios::binary)
        .write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
    return dir + "/" + name;
  };
  EXPECT_FALSE(readMrptRangeFile(dir + "/missing.bin").has_value());
  std::vector<std::uint8_t> twice = bytes;
  twice.insert(twice.end(), bytes.begin(), bytes.end());  // two gzip members
  EXPECT_FALSE(readMrptRangeFile(write("twice.bin", twice)).has_value());
  EXPECT_FALSE(readMrptRangeFile(write("plain.bin", {1, 0, 0, 0, 1, 0, 0, 0, 5, 0})).has_value());
  const auto error = [](const std::string& f) -> std::string {
    try {
      readMrptRangeFile(f);
    } catch (const ImageDecodeError& e) {
      return e.what();
    }
    return "no error";
  };
  const std::string what =
      " is damaged: its gzip data do not inflate to the size in its trailer (truncated or corrupt)";
  // Truncated: the last four bytes, read as the trailer's size, are deflate data.
  std::vector<std::uint8_t> cut(bytes.begin(), bytes.end() - 9);
  cut.insert(cut.end() - 4, {0x00, 0x00});
  std::copy_n(std::vector<std::uint8_t>{0x10, 0x00, 0x00, 0x00}.begin(), 4, cut.end() - 4);
  const std::string short_file = write("short.bin", cut);  // size 16: too small for 7 x 11
  EXPECT_EQ(error(short_file), "range file " + short_file + what);
  cut.back() = 0x70;  // 0x70000010 bytes
  const std::string huge_file = write("huge.bin", cut);
  EXPECT_EQ(error(huge_file), "range file " + huge_file +
                                  " is damaged: its gzip trailer gives 1879048208 bytes of data, "
                                  "more than any range image (truncated or corrupt)");
  std::vector<std::uint8_t> flipped = bytes;
  flipped[flipped.size() - 6] ^= 0x01;  // the CRC32 of the data
  const std::string flipped_file = write("flipped.bin", flipped);
  EXPECT_EQ(error(flipped_file), "range file " + flipped_file + what);
  const std::string tiny = write("tiny.bin", {0x1F, 0x8B, 8, 0});
  EXPECT_EQ(error(tiny), "range file " + tiny + " is damaged: truncated gzip file");
  // A gzip file whose header does not describe its size (rows x cols != the data).
  libdeflate_compressor* comp = libdeflate_alloc_compressor(1);
  std::vector<std::uint8_t> payload = {7, 0, 0, 0, 11, 0, 0, 0, 1, 2, 3, 4};
  std::vector<std::uint8_t> gz(libdeflate_gzip_compress_bound(comp, payload.size()));
  gz.resize(libdeflate_gzip_compress(comp, payload.data(), payload.size(), gz.data(), gz.size()));
  libdeflate_free_compressor(comp);
  EXPECT_FALSE(readMrptRangeFile(write("size.bin", gz)).has_value());
}
