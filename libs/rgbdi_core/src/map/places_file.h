// places.bin: the keyframes of loop closing (place recognition is rebuilt from them).
//
// Layout (all little-endian, ByteWriter encoding of the keyframe file):
//   "RGBDIPLC" | u32 version (kPlacesFileVersion) | u64 place count | records...
//   record: u32 'PLCE' | u64 id | i32 segment | f64 t | 12 x f64 T_world_body_odom (rows of
//           [R | t]) | 12 x f64 T_world_body | f64 travelled_m | descriptor block
//           (mapping/descriptor_codec.h, shared with the keyframe file)
// Poses are stored as full matrices so that a round trip is bit-exact.
#pragma once

#include <string>
#include <vector>

#include "rgbdi/loop/loop_keyframe.h"
#include "rgbdi/map/map_data.h"

namespace rgbdi::map::detail {

/// Writes a new file durably (fsync); each place with its T_world_body. Throws MapError.
void writePlacesFile(const std::string& path, const std::vector<MapView::Place>& places);

/// Reads a file written by writePlacesFile. Throws MapError naming the file, the record and what
/// is wrong (truncated, bad signature or version, ids not increasing, non-rigid pose, ...).
std::vector<loop::LoopKeyframe> readPlacesFile(const std::string& path);

}  // namespace rgbdi::map::detail
