#include "rgbdi/convert/progress_meter.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace rgbdi::convert {

ProgressMeter::ProgressMeter(std::ostream* os, bool interactive, double interval_s,
                             std::uint64_t total_bytes, std::string prefix)
    : os_(os),
      interactive_(interactive),
      gate_(interactive, interval_s),
      total_(total_bytes),
      prefix_(std::move(prefix)),
      start_(std::chrono::steady_clock::now()) {}

std::string ProgressMeter::line(const std::string& prefix, double fraction,
                                std::uint64_t total_bytes, double elapsed_s) {
  constexpr int kBar = 20;
  fraction = std::clamp(fraction, 0.0, 1.0);
  const int filled = static_cast<int>(std::floor(fraction * kBar + 1e-9));
  const double total_mb = static_cast<double>(total_bytes) / 1e6;
  const double done_mb = fraction * total_mb;
  std::ostringstream os;
  os << prefix << ": [" << std::string(static_cast<std::size_t>(filled), '#')
     << std::string(static_cast<std::size_t>(kBar - filled), '-') << "] " << std::fixed
     << std::setprecision(1) << std::setw(5) << 100.0 * fraction << " %  " << done_mb << "/"
     << total_mb << " MB";
  if (elapsed_s > 0.0) {
    const double rate = done_mb / elapsed_s;
    os << "  " << rate << " MB/s";
    if (fraction > 0.0 && fraction < 1.0)
      os << "  ETA " << std::setprecision(0) << elapsed_s * (1.0 - fraction) / fraction << " s";
    else if (fraction >= 1.0)
      os << "  " << std::setprecision(1) << elapsed_s << " s";
  }
  return os.str();
}

void ProgressMeter::print(bool final) {
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const std::string l = line(prefix_, fraction_, total_, elapsed);
  if (interactive_)
    *os_ << "\r" << l << "\x1b[K" << (final ? "\n" : "") << std::flush;
  else
    *os_ << l << "\n" << std::flush;
  printed_fraction_ = fraction_;
}

void ProgressMeter::update(double fraction) {
  fraction_ = fraction;
  if (!os_) return;
  const double now_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  if (gate_.due(fraction, now_s)) print(false);
}

void ProgressMeter::finish() {
  if (!os_) return;
  // A log that already holds the line of this point gets no copy of it.
  if (!interactive_ && printed_fraction_ == fraction_) return;
  print(true);
}

}  // namespace rgbdi::convert
