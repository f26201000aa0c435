// Summary statistics of a list of non-negative errors, as reported by the TUM/rpg tools.
#pragma once

#include <cstddef>
#include <vector>

namespace rgbdi::eval {

struct ErrorStatistics {
  std::size_t count = 0;
  double rmse = 0.0;
  double mean = 0.0;
  double median = 0.0;  ///< mean of the two middle values for an even count (numpy convention)
  double max = 0.0;
};

/// Statistics of `errors`; all fields are NaN when it is empty.
ErrorStatistics computeStatistics(std::vector<double> errors);

}  // namespace rgbdi::eval
