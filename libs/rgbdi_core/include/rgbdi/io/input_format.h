// Recognising dataset files and inspecting them: what `rawlog-convert --info` runs. Each input
// format has one inspection function in the library; the app only dispatches on the format.
#pragma once

#include <string>

#include "rgbdi/io/stream_diagnostics.h"
#include "rgbdi/io/stream_options.h"

namespace rgbdi::io {

enum class InputFormat {
  Rawlog,   ///< MRPT rawlog (plain or gzip)
  Ros1Bag,  ///< ROS1 bag ("#ROSBAG V2.0" header)
  TumRgbd,  ///< TUM RGB-D dataset directory (rgb.txt, depth.txt)
  Unknown,
};

/// Decides from the content (magic bytes) and, for gzip data, the extension. Throws IoError when
/// the path cannot be read.
InputFormat detectInputFormat(const std::string& path);
std::string formatName(InputFormat f);

/// Reads the whole rawlog through RawlogSource and returns its diagnostics. A corrupt record
/// does not throw: it is reported in StreamDiagnostics::error (everything before it counted).
/// Throws RawlogError when the file cannot be opened. `quiet` silences the source's logger.
StreamDiagnostics inspectRawlog(const std::string& path, const StreamConfig& cfg,
                                bool quiet = true);

}  // namespace rgbdi::io
