#include "rgbdi/io/input_format.h"

#include <filesystem>
#include <fstream>

#include "rgbdi/common/atomic_file.h"
#include "rgbdi/io/rawlog_source.h"

namespace rgbdi::io {

InputFormat detectInputFormat(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::is_directory(path, ec)) {
    return fs::exists(fs::path(path) / "rgb.txt") && fs::exists(fs::path(path) / "depth.txt")
               ? InputFormat::TumRgbd
               : InputFormat::Unknown;
  }
  if (!fs::exists(path, ec)) throw IoError(path + ": no such file or directory");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path + ": cannot open for reading");
  char head[13] = {};
  in.read(head, sizeof head);
  const std::string magic(head, static_cast<size_t>(in.gcount()));
  if (magic.rfind("#ROSBAG V2.0", 0) == 0) return InputFormat::Ros1Bag;
  const std::string ext = fs::path(path).extension().string();
  // Rawlogs are MRPT archives (no magic) or gzip files; anything named .rawlog is tried as one.
  if (ext == ".rawlog") return InputFormat::Rawlog;
  const bool gzip = magic.size() >= 2 && static_cast<unsigned char>(magic[0]) == 0x1f &&
                    static_cast<unsigned char>(magic[1]) == 0x8b;
  if (gzip && fs::path(path).stem().extension() == ".rawlog") return InputFormat::Rawlog;
  return InputFormat::Unknown;
}

std::string formatName(InputFormat f) {
  switch (f) {
    case InputFormat::Rawlog:
      return "MRPT rawlog";
    case InputFormat::Ros1Bag:
      return "ROS1 bag";
    case InputFormat::TumRgbd:
      return "TUM RGB-D directory";
    case InputFormat::Unknown:
      break;
  }
  return "unknown";
}

StreamDiagnostics inspectRawlog(const std::string& path, const StreamConfig& cfg, bool quiet) {
  StreamConfig inspect = cfg;
  inspect.report_only = true;  // report a wrong accelerometer unit, read to the end
  RawlogSource src(path, inspect);
  if (quiet) src.logging_enable_console_output = false;
  Measurement m;
  try {
    while (src.next(m)) {
    }
  } catch (const RawlogError&) {
    // Recorded in diagnostics().error; everything before the bad record has been counted.
  }
  return src.diagnostics();
}

}  // namespace rgbdi::io
