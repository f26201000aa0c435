// Fuzz target: the external image files of a rawlog, decoded by io/image_decode.h (libdeflate):
// colour PNGs (decodePngToRgb) and MRPT's gzip range files (readMrptRangeFile). The first byte
// of an input picks the decoder (even: PNG, odd: range file), the rest is the file.
// Documented refusal: ImageDecodeError; nullopt for files of another kind.
#include <mrpt/obs/CObservation3DRangeScan.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "fuzz_target.h"
#include "rgbdi/io/image_decode.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  try {
    if (data[0] % 2 == 0) {
      (void)rgbdi::io::decodePngToRgb(data + 1, size - 1);
    } else {
      const std::string path = rgbdi::fuzz::writeScratchFile("range.bin", data + 1, size - 1);
      (void)rgbdi::io::readMrptRangeFile(path);
    }
  } catch (const rgbdi::io::ImageDecodeError&) {
  }
  return 0;
}

namespace rgbdi::fuzz {

std::vector<std::string> rgbdiFuzzSeeds() {
  std::vector<std::string> seeds;
  // PNGs as OpenCV writes them (the simulator's and rawlog-convert's colour files): RGB, grey
  // and with alpha, small and textured so that every row filter occurs.
  for (int channels : {3, 1, 4}) {
    cv::Mat img(13, 17, CV_8UC(channels));
    cv::randu(img, 0, 255);
    img(cv::Rect(0, 0, 17, 4)).setTo(cv::Scalar::all(90));
    std::vector<std::uint8_t> png;
    cv::imencode(".png", img, png);
    seeds.push_back(std::string(1, '\0') + std::string(png.begin(), png.end()));
  }
  // A range file as MRPT writes it for an externally stored range image.
  const std::string dir = scratchDir("image_decode");
  mrpt::obs::CObservation3DRangeScan obs;
  obs.hasRangeImage = true;
  obs.rangeImage_setSize(6, 9);
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 9; ++c) obs.rangeImage(r, c) = static_cast<std::uint16_t>(r * 700 + c * 3);
  obs.rangeImage_convertToExternalStorage("seed.bin", dir + "/");
  seeds.push_back(std::string(1, '\1') + readFileBytes(dir + "/seed.bin"));
  std::filesystem::remove_all(dir);
  return seeds;
}

}  // namespace rgbdi::fuzz
