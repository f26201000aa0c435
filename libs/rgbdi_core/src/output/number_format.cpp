#include "output/number_format.h"

#include <charconv>
#include <stdexcept>

namespace rgbdi::output {
namespace {
// Enough for any double in fixed notation with up to 9 decimals (|v| < 1e300 has < 310 digits).
constexpr std::size_t kBufferSize = 400;
}  // namespace

std::string shortestRoundTrip(double v) {
  char buf[kBufferSize];
  const auto res = std::to_chars(buf, buf + kBufferSize, v);
  if (res.ec != std::errc()) throw std::logic_error("shortestRoundTrip: buffer too small");
  return std::string(buf, res.ptr);
}

std::string fixedDecimals(double v, int decimals) {
  char buf[kBufferSize];
  const auto res = std::to_chars(buf, buf + kBufferSize, v, std::chars_format::fixed, decimals);
  if (res.ec != std::errc()) throw std::logic_error("fixedDecimals: buffer too small");
  return std::string(buf, res.ptr);
}

}  // namespace rgbdi::output
