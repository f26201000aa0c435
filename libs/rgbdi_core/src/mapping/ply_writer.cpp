#include <cstring>
#include <ostream>
#include <string>

#include "rgbdi/common/atomic_file.h"
#include "rgbdi/mapping/map_export.h"

namespace rgbdi::mapping {
namespace {

void putFloatLe(std::string& buf, float v) {
  std::uint32_t bits;
  std::memcpy(&bits, &v, sizeof bits);
  for (int i = 0; i < 4; ++i) buf.push_back(static_cast<char>((bits >> (8 * i)) & 0xFFu));
}

}  // namespace

void writePly(const std::string& path, const std::vector<WorldPoint>& points) {
  writeFileAtomically(path, [&](std::ostream& os) {
    os << "ply\n"
       << "format binary_little_endian 1.0\n"
       << "comment rgbdi point map (world frame, metres)\n"
       << "element vertex " << points.size() << "\n"
       << "property float x\nproperty float y\nproperty float z\n"
       << "property uchar red\nproperty uchar green\nproperty uchar blue\n"
       << "end_header\n";
    // Encoded explicitly as little-endian so the file is the same on any host.
    constexpr std::size_t kVertexBytes = 3 * 4 + 3;
    constexpr std::size_t kChunk = 1 << 14;
    std::string buf;
    buf.reserve(kChunk * kVertexBytes);
    for (std::size_t i = 0; i < points.size(); ++i) {
      const WorldPoint& p = points[i];
      for (int k = 0; k < 3; ++k) putFloatLe(buf, p.p_world[k]);
      for (int k = 0; k < 3; ++k) buf.push_back(static_cast<char>(p.rgb[k]));
      if (buf.size() >= kChunk * kVertexBytes || i + 1 == points.size()) {
        os.write(buf.data(), static_cast<std::streamsize>(buf.size()));
        buf.clear();
      }
    }
  });
}

void writePly(const std::string& path, const PointMap& map) { writePly(path, map.points()); }

}  // namespace rgbdi::mapping
