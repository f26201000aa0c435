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
/// `frame_and_clock` (when not empty) is written first as "# " comment line(s): which frame the
/// poses are of, in which frame, and which clock the stamps are (e.g. "body (IMU) frame in the
/// world frame; IMU clock; optimised poses"), so that a file says what it holds.
void writeTum(const std::string& path, const Trajectory& trajectory,
              const std::string& frame_and_clock = "");

}  // namespace rgbdi::output
