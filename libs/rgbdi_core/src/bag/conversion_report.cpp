#include "rgbdi/bag/conversion_report.h"

#include <algorithm>
#include <iomanip>
#include <sstream>

namespace rgbdi::bag {

void ConversionReport::addIssue(const std::string& kind, const std::string& message,
                                int max_listed) {
  IssueList& l = issues_[kind];
  ++l.count;
  if (l.listed.size() < static_cast<std::size_t>(std::max(0, max_listed)))
    l.listed.push_back(message);
}

std::size_t ConversionReport::issueCount(const std::string& kind) const {
  const auto it = issues_.find(kind);
  return it == issues_.end() ? 0 : it->second.count;
}

std::vector<std::string> ConversionReport::listedIssues(const std::string& kind) const {
  const auto it = issues_.find(kind);
  return it == issues_.end() ? std::vector<std::string>() : it->second.listed;
}

void ConversionReport::absorbWriter(const ConversionReport& w, int max_listed) {
  frames_written += w.frames_written;
  imu_written += w.imu_written;
  groundtruth_written += w.groundtruth_written;
  wheel_written += w.wheel_written;
  dropped_by_ordering += w.dropped_by_ordering;
  outputs.insert(outputs.end(), w.outputs.begin(), w.outputs.end());
  for (const auto& [kind, l] : w.issues_) {
    IssueList& mine = issues_[kind];
    mine.count += l.count;
    for (const std::string& m : l.listed)
      if (mine.listed.size() < static_cast<std::size_t>(std::max(0, max_listed)))
        mine.listed.push_back(m);
  }
}

std::string ConversionReport::text() const {
  std::ostringstream os;
  os << std::fixed;
  const auto list = [&os](const char* title, const std::vector<std::string>& lines) {
    if (lines.empty()) return;
    os << title << "\n";
    for (const std::string& l : lines) os << "  " << l << "\n";
  };
  os << "Input: " << input << " (" << format << std::setprecision(1) << ", "
     << static_cast<double>(input_bytes) / 1e6 << " MB)\n";
  list("Streams:", streams);
  list("Calibration:", calibration);

  const std::size_t depth_only = pairing.depth_alone - depth_alone_dropped;
  os << "Written: " << frames_written << " RGB-D observations (" << pairing.pairs
     << " colour+depth, " << depth_only << " depth-only), " << imu_written << " IMU observations, "
     << groundtruth_written << " ground-truth poses";
  // Only inputs with wheel odometry mention it: the line of every other input stays as it was.
  if (odometry_messages > 0 || wheel_written > 0)
    os << ", " << wheel_written << " wheel odometry observations";
  os << "\n";

  std::vector<std::string> dropped;
  std::ostringstream d;
  d << std::fixed << std::setprecision(3);
  if (pairing.color_alone) {
    d << pairing.color_alone << " colour image(s) without a depth image within " << pair_tolerance_s
      << " s";
    dropped.push_back(d.str());
    d.str("");
  }
  if (depth_alone_dropped) {
    d << depth_alone_dropped << " depth image(s) without a colour image within " << pair_tolerance_s
      << " s (--require-colour)";
    dropped.push_back(d.str());
    d.str("");
  }
  if (merge.gyro_before_accel)
    dropped.push_back(std::to_string(merge.gyro_before_accel) +
                      " gyro sample(s) before the first accelerometer sample");
  if (merge.gyro_after_accel)
    dropped.push_back(std::to_string(merge.gyro_after_accel) +
                      " gyro sample(s) after the last accelerometer sample");
  if (merge.gyro_in_accel_gap)
    dropped.push_back(std::to_string(merge.gyro_in_accel_gap) +
                      " gyro sample(s) inside an accelerometer gap");
  if (merge.out_of_order)
    dropped.push_back(std::to_string(merge.out_of_order) + " IMU sample(s) out of order");
  if (unreadable)
    dropped.push_back(std::to_string(unreadable) + " unreadable message(s)/file(s) (listed below)");
  if (dropped_by_ordering)
    dropped.push_back(std::to_string(dropped_by_ordering) +
                      " measurement(s) with a duplicate or too late stamp (listed below)");
  list("Dropped:", dropped);
  if (depth_clipped_pixels)
    os << "Depth: " << depth_clipped_pixels
       << " float depth pixel(s) beyond the 16-bit range set to 0\n";
  if (stamps_from_bag_time)
    os << "Stamps: " << stamps_from_bag_time
       << " message(s) had a zero header stamp; their bag time was used\n";
  for (const auto& [kind, l] : issues_) {
    os << "Issues (" << kind << "): " << l.count << "\n";
    for (const std::string& m : l.listed) os << "  " << m << "\n";
    if (l.count > l.listed.size())
      os << "  ... " << (l.count - l.listed.size()) << " more not listed\n";
  }
  list("Notes:", notes);
  list("Output:", outputs);
  os << std::setprecision(2) << "Time: " << wall_time_s << " s";
  if (wall_time_s > 0)
    os << std::setprecision(1) << ", " << static_cast<double>(input_bytes) / 1e6 / wall_time_s
       << " MB/s";
  os << "\n";
  if (!error.empty()) os << "ERROR: " << error << "\n";
  return os.str();
}

}  // namespace rgbdi::bag
