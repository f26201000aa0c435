// Private: locale-independent number formatting for text outputs.
#pragma once

#include <string>

namespace rgbdi::output {

/// Shortest text that reads back to exactly `v` (std::to_chars round-trip form).
std::string shortestRoundTrip(double v);
/// Fixed-point text with `decimals` digits after the point.
std::string fixedDecimals(double v, int decimals);

}  // namespace rgbdi::output
