// CPU time of the calling thread, for stage timings that stay meaningful on a shared machine
// (wall-clock stage times grow with the load of other processes; CPU time does not).
#pragma once

#include <ctime>

namespace rgbdi {

/// CPU seconds consumed so far by the calling thread (user + system).
inline double threadCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

/// Accumulates the thread CPU time of a scope into a counter [s].
class ScopedCpuTimer {
 public:
  explicit ScopedCpuTimer(double& total_s) : total_s_(total_s), start_s_(threadCpuSeconds()) {}
  ~ScopedCpuTimer() { total_s_ += threadCpuSeconds() - start_s_; }
  ScopedCpuTimer(const ScopedCpuTimer&) = delete;
  ScopedCpuTimer& operator=(const ScopedCpuTimer&) = delete;

 private:
  double& total_s_;
  double start_s_;
};

}  // namespace rgbdi
