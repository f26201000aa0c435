#include "rgbdi/output/tum_writer.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "output/number_format.h"
#include "rgbdi/common/atomic_file.h"

namespace rgbdi::output {
namespace {
constexpr int kStampDecimals = 9;  // nanoseconds, the resolution of ROS and MRPT stamps
}  // namespace

void writeTum(const std::string& path, const Trajectory& trajectory,
              const std::string& frame_and_clock) {
  for (std::size_t k = 0; k < trajectory.size(); ++k) {
    const StampedPose& s = trajectory[k];
    const bool finite =
        std::isfinite(s.t) && s.p.allFinite() && s.q.coeffs().allFinite() && s.q.norm() > 0.0;
    if (!finite) {
      throw std::invalid_argument("writeTum " + path + ": pose " + std::to_string(k) +
                                  " has a non-finite value or a zero quaternion");
    }
    if (k > 0 && !(s.t > trajectory[k - 1].t)) {
      throw std::invalid_argument("writeTum " + path + ": pose " + std::to_string(k) + " stamp " +
                                  fixedDecimals(s.t, kStampDecimals) +
                                  " does not increase (previous " +
                                  fixedDecimals(trajectory[k - 1].t, kStampDecimals) + ")");
    }
  }
  writeFileAtomically(path, [&](std::ostream& os) {
    if (!frame_and_clock.empty()) {
      std::istringstream lines(frame_and_clock);
      for (std::string line; std::getline(lines, line);) os << "# " << line << '\n';
    }
    os << "# timestamp tx ty tz qx qy qz qw\n";
    for (const StampedPose& s : trajectory) {
      const Eigen::Quaterniond q = s.q.normalized();
      os << fixedDecimals(s.t, kStampDecimals) << ' ' << shortestRoundTrip(s.p.x()) << ' '
         << shortestRoundTrip(s.p.y()) << ' ' << shortestRoundTrip(s.p.z()) << ' '
         << shortestRoundTrip(q.x()) << ' ' << shortestRoundTrip(q.y()) << ' '
         << shortestRoundTrip(q.z()) << ' ' << shortestRoundTrip(q.w()) << '\n';
    }
  });
}

}  // namespace rgbdi::output
