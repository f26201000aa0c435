// Check of a ROS1 2.0 bag's record structure before rosbag_storage opens it. rosbag allocates
// what the size fields say (record headers, chunk sizes) and asserts when that fails, and it
// reads as many index entries as a count field says: a corrupt size would abort or exhaust the
// process. The check walks every top-level record (headers only; it seeks over the data) and
// refuses, with the file and byte offset, what rosbag could not read safely:
//  - a record header or data that runs past the end of the file, a header above the limit;
//  - a chunk whose decompressed size is above the limit (or differs from its data size when
//    uncompressed), or whose compression rosbag does not know;
//  - a file header whose index position is not a record, or whose connection and chunk counts
//    are not the records found there; a chunk info pointing at no chunk; index data or chunk
//    info whose data length is not what its count says;
//  - an index entry outside its chunk, or, for an uncompressed chunk, whose message record
//    overruns the chunk.
// Not checked: the records inside compressed chunks (that needs decompressing every chunk); bz2
// and lz4 checksums catch most damage there, and rosbag throws for what they catch.
#pragma once

#include <string>

#include "rgbdi/bag/bag_reader.h"

namespace rgbdi::bag::detail {

/// Throws BagReadError "PATH: byte N: ..." at the first record that fails a check above.
void checkBagStructure(const std::string& path, const BagLimits& limits);

}  // namespace rgbdi::bag::detail
