// manifest.json of a map directory: every MapManifest field, the counts of what the data files
// hold, and the size and FNV-1a 64 checksum of every file of the directory (doc/maps.md).
#pragma once

#include <cstdint>
#include <map>
#include <string>

#include "map/file_io.h"
#include "rgbdi/map/map_data.h"

namespace rgbdi::map::detail {

/// What the data files hold; loadMap checks the parsed files against these.
struct MapCounts {
  std::uint64_t places = 0;
  std::uint64_t place_keypoints = 0;  ///< over all places
  std::uint64_t loops = 0;            ///< all loop edges, rolled back included
  std::uint64_t keyframes = 0;        ///< keyframe store
  std::uint64_t keyframe_points = 0;  ///< kept points over all store keyframes
};

struct ManifestContent {
  MapManifest manifest;
  MapCounts counts;
  std::map<std::string, FileDigest> files;  ///< file name -> size and checksum
};

/// The JSON text (indented, ends with a newline). Doubles round-trip exactly.
std::string manifestToJson(const ManifestContent& content);

/// Parses the text of `path`. Throws MapError naming the file: not JSON, not an rgbdi map
/// manifest, another format version (checked first), a missing or mistyped key.
ManifestContent parseManifest(const std::string& text, const std::string& path);

MapCounts countsOf(const MapView& map);

}  // namespace rgbdi::map::detail
