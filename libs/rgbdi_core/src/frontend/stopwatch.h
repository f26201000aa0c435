// Thread CPU milliseconds since construction or the last lap, for the per-step front-end
// timings (CPU time: on a shared machine wall time mostly measures the other processes).
#pragma once

#include "rgbdi/common/cpu_clock.h"

namespace rgbdi::frontend {

class Stopwatch {
 public:
  Stopwatch() : last_s_(threadCpuSeconds()) {}
  /// CPU milliseconds of this thread since the previous lap (or construction); starts the next.
  double lapMs() {
    const double now = threadCpuSeconds();
    const double ms = 1e3 * (now - last_s_);
    last_s_ = now;
    return ms;
  }

 private:
  double last_s_;
};

}  // namespace rgbdi::frontend
