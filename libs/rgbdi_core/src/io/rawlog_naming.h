// Private to the io stage: the name MRPT derives a rawlog's image directory from.
#pragma once

#include <filesystem>
#include <string>

namespace rgbdi::io {

/// File name without ".gz" and ".rawlog": "seq.rawlog.gz" -> "seq".
inline std::string rawlogBaseName(const std::filesystem::path& p) {
  std::string name = p.filename().string();
  for (const std::string ext : {".gz", ".rawlog"}) {
    if (name.size() > ext.size() && name.compare(name.size() - ext.size(), ext.size(), ext) == 0)
      name.resize(name.size() - ext.size());
  }
  return name;
}

}  // namespace rgbdi::io
