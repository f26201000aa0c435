// Fuzz target: rgbdi INI configuration text read by IniReader (line check, MRPT's parser) and
// the option loaders of the readers of outside data ([stream], [imu], [extrinsic], [camera],
// [mapping]) and the unknown-key check. Documented
// refusal: ConfigError naming the file, line or key.
#include "fuzz_target.h"
#include "rgbdi/common/ini_reader.h"
#include "rgbdi/common/sensor_options.h"
#include "rgbdi/io/stream_options.h"
#include "rgbdi/mapping/mapping_options.h"

#ifndef RGBDI_SOURCE_DIR
#error "RGBDI_SOURCE_DIR must name the source tree (seeds read share/*.ini)"
#endif

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    rgbdi::IniReader ini = rgbdi::IniReader::fromText(
        std::string(reinterpret_cast<const char*>(data), size), "fuzz.ini");
    (void)rgbdi::io::StreamConfig::load(ini);
    (void)rgbdi::CameraOptions::load(ini);
    (void)rgbdi::mapping::MappingOptions::load(ini);
    for (const char* s : {"frontend", "estimator", "loop", "output", "sim", "convert", "live"})
      ini.acceptSection(s);
    ini.checkNoUnknownKeys();
  } catch (const rgbdi::ConfigError&) {
  }
  return 0;
}

namespace rgbdi::fuzz {

std::vector<std::string> rgbdiFuzzSeeds() {
  const std::string src = RGBDI_SOURCE_DIR;
  return {readFileBytes(src + "/share/config.ini"),
          "[imu]\nrate_hz = 400 ; Hz\n[stream]\naccel_scale = 9.80665\n",
          "@define R 200\n[imu]\nrate_hz = ${R}\n[extrinsic]\nR_body_cam = 0 0 1 -1 0 0 0 -1 0\n"};
}

}  // namespace rgbdi::fuzz
