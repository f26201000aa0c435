// Writing trajectories in the TUM format read by evo, the TUM/rpg tools and rgbdi-eval.
#pragma once

#include <string>

#include "rgbdi/common/atomic_file.h"  // IoError

#include "rgbdi/common/types.h"

namespace rgbdi::output {

/// Writes "timestamp tx ty tz qx qy qz qw" per pose after a '#' header line: timestamps with 9
/// decimals (ns), other values in the shortest form that reads back to the same double.
/// Atomic (temporary file + rename). Throws std::invalid_argument naming the file and the pose
/// index for non-finite values or timestamps that do not increase (the file could not be read
/// back), IoError when the file cannot be written.
void writeTum(const std::string& path, const Trajectory& trajectory);

}  // namespace rgbdi::output
