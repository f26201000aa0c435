// Fuzz target: VINS-RGBD calibration yaml (OpenCV FileStorage) read by convert::readVinsYaml and
// turned into an rgbdi configuration by rgbdiConfigFromVins. Documented refusal: ConfigError.
#include <fstream>
#include <sstream>

#include "fuzz_target.h"
#include "rgbdi/common/ini_reader.h"
#include "rgbdi/convert/vins_yaml.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = rgbdi::fuzz::writeScratchFile("vins.yaml", data, size);
  try {
    const rgbdi::convert::VinsCalibration v = rgbdi::convert::readVinsYaml(path);
    (void)rgbdi::convert::rgbdiConfigFromVins(v, 200.0, "fuzz");
  } catch (const rgbdi::ConfigError&) {
  }
  return 0;
}

namespace rgbdi::fuzz {

/// The yaml texts embedded in tests/convert/test_vins_yaml.cpp (raw string literals starting
/// with %YAML), so that the seeds follow the test data.
std::vector<std::string> rgbdiFuzzSeeds() {
  const std::string text =
      readFileBytes(std::string(RGBDI_SOURCE_DIR) + "/tests/convert/test_vins_yaml.cpp");
  std::vector<std::string> seeds;
  for (std::size_t at = text.find("R\"(%YAML"); at != std::string::npos;
       at = text.find("R\"(%YAML", at + 1)) {
    const std::size_t end = text.find(")\"", at);
    if (end == std::string::npos) break;
    seeds.push_back(text.substr(at + 3, end - at - 3));
  }
  if (seeds.empty()) throw std::runtime_error("no %YAML text found in test_vins_yaml.cpp");
  return seeds;
}

}  // namespace rgbdi::fuzz
