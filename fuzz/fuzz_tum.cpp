// Fuzz target: TUM trajectory files read by eval::readTum (ground truth and estimates given to
// rgbdi-eval / rgbdi-slam --gt). Documented refusal: EvalError naming "path:line".
#include "fuzz_target.h"
#include "rgbdi/eval/eval_error.h"
#include "rgbdi/eval/tum_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = rgbdi::fuzz::writeScratchFile("traj.tum", data, size);
  try {
    (void)rgbdi::eval::readTum(path);
  } catch (const rgbdi::eval::EvalError&) {
  }
  return 0;
}

namespace rgbdi::fuzz {

std::vector<std::string> rgbdiFuzzSeeds() {
  return {
      "# timestamp tx ty tz qx qy qz qw\n"
      "1305031102.175304 1.3405 0.6266 1.6575 0.6574 0.6126 -0.2949 -0.3248\n"
      "1305031102.211214 1.3303 0.6256 1.6464 0.6579 0.6161 -0.2932 -0.3189\n",
      "0.0 0 0 0 0 0 0 1\n0.1 0.1 0 0 0 0 0.0499792 0.99875\n\n0.2 0.2 0 0 0 0 0.0998 0.995\n",
      "1e3,1,2,3,0,0,0,1\n1001.5,1,2,3,0,0,1,0\n",
  };
}

}  // namespace rgbdi::fuzz
