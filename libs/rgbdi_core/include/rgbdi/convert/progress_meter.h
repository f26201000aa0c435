// Progress line of a conversion on a stream (stderr): fraction done, megabytes, throughput and
// estimated time left, e.g.
//   rawlog-convert: [########------------]  41.0 %  533.1/1300.0 MB  38.2 MB/s  ETA 20 s
// On a terminal the line is redrawn in place ('\r') once per interval; in a log one line per
// tenth of the input at most (ProgressGate).
#pragma once

#include <chrono>
#include <cstdint>
#include <ostream>
#include <string>

#include "rgbdi/common/progress_gate.h"

namespace rgbdi::convert {

class ProgressMeter {
 public:
  /// `os` may be nullptr (silent). `total_bytes`: size of the input.
  ProgressMeter(std::ostream* os, bool interactive, double interval_s, std::uint64_t total_bytes,
                std::string prefix = "rawlog-convert");
  /// Reports progress (fraction of the input in [0, 1]); prints when ProgressGate says so.
  void update(double fraction);
  /// Prints the final line (100 % or where it stopped).
  void finish();

  /// The line for a given state (used by update/finish; exposed for tests).
  static std::string line(const std::string& prefix, double fraction, std::uint64_t total_bytes,
                          double elapsed_s);

 private:
  void print(bool final);
  std::ostream* os_;
  bool interactive_;
  ProgressGate gate_;
  std::uint64_t total_;
  std::string prefix_;
  double fraction_ = 0.0;
  std::chrono::steady_clock::time_point start_;
  double printed_fraction_ = -1.0;  ///< of the last line printed (-1: none)
};

}  // namespace rgbdi::convert
