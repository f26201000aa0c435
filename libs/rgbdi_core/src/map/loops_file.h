// loops.txt: the loop edges of the pose graph, one per line, readable by people and scripts.
//
//   # rgbdi map loop edges, version 1
//   # from_id to_id active r00 r01 r02 tx r10 r11 r12 ty r20 r21 r22 tz
//   # T_from_to maps points of the `to` body frame into the `from` body frame [m];
//   # active 0 = rolled back (kept for the record, not used)
//   12 840 1 0.99... (12 numbers, %.17g: a round trip is bit-exact)
// Lines starting with '#' are comments; the version line must be the first.
#pragma once

#include <string>
#include <vector>

#include "rgbdi/map/map_data.h"

namespace rgbdi::map::detail {

inline constexpr int kLoopsFileVersion = 1;

/// Writes a new file durably (fsync). Throws MapError.
void writeLoopsFile(const std::string& path, const std::vector<MapLoopEdge>& loops);

/// Throws MapError naming the file and the line when the version line is missing or another,
/// a line has not 15 fields, a number does not parse, or a transform is not rigid.
std::vector<MapLoopEdge> readLoopsFile(const std::string& path);

}  // namespace rgbdi::map::detail
