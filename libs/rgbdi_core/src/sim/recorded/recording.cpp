// The recording formats and what they share.
#include "rgbdi/sim/recording.h"

namespace rgbdi::sim {

double nanosecondsToSeconds(long long ns) {
  return static_cast<double>(ns / 1000000000LL) + static_cast<double>(ns % 1000000000LL) * 1e-9;
}

const std::vector<std::string>& recordingFormats() {
  static const std::vector<std::string> formats{"euroc"};
  return formats;
}

Recording readRecording(const std::string& dir, const std::string& format) {
  if (format == "euroc") return readEurocRecording(dir);
  std::string list;
  for (const std::string& f : recordingFormats()) list += (list.empty() ? "" : ", ") + f;
  throw std::invalid_argument("unknown recording format '" + format + "' (known: " + list + ")");
}

}  // namespace rgbdi::sim
