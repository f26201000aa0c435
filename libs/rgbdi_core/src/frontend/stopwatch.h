// Milliseconds since construction or the last lap, for the per-step front-end timings.
#pragma once

#include <chrono>

namespace rgbdi::frontend {

class Stopwatch {
 public:
  Stopwatch() : last_(std::chrono::steady_clock::now()) {}
  /// Milliseconds since the previous lap (or construction); starts the next lap.
  double lapMs() {
    const auto now = std::chrono::steady_clock::now();
    const double ms = std::chrono::duration<double, std::milli>(now - last_).count();
    last_ = now;
    return ms;
  }

 private:
  std::chrono::steady_clock::time_point last_;
};

}  // namespace rgbdi::frontend
