// Reading TUM-format trajectories: one pose per line, "t tx ty tz qx qy qz qw" (seconds, metres,
// Hamilton quaternion with w last). '#' starts a comment line; blank lines are skipped; fields may
// be separated by whitespace or commas.
#pragma once

#include <string>

#include "rgbdi/common/types.h"

namespace rgbdi::eval {

struct TumReadOptions {
  /// A quaternion whose norm differs from 1 by more than this is an error (the line is probably
  /// not a quaternion at all); smaller deviations (rounded files) are normalised.
  double quaternion_norm_tolerance = 0.01;
};

/// Reads a TUM trajectory. Throws EvalError naming "path:line" and the offending text for: a file
/// that cannot be opened, a wrong number of fields, a field that is not a number, NaN/inf, a
/// quaternion far from unit norm, a timestamp not larger than the previous one, and a file with
/// no pose at all.
Trajectory readTum(const std::string& path, const TumReadOptions& options = {});

}  // namespace rgbdi::eval
