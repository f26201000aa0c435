#include "rgbdi/live_run/pose_latency.h"

namespace rgbdi::system {

PoseLatencyMeter::PoseLatencyMeter(double bin_s, double range_s, std::size_t max_pending)
    : max_pending_(max_pending),
      stamp_to_pose_(bin_s, range_s),
      delivery_to_pose_(bin_s, range_s) {}

void PoseLatencyMeter::delivered(double t_image, double wall_s) {
  std::lock_guard<std::mutex> lock(mutex_);
  pending_.push_back({t_image, wall_s});
  while (pending_.size() > max_pending_) pending_.pop_front();
}

void PoseLatencyMeter::posed(double t_image, double wall_s) {
  std::lock_guard<std::mutex> lock(mutex_);
  stamp_to_pose_.add(wall_s - t_image);
  // Poses come in stamp order: images before this one will never get a pose.
  while (!pending_.empty() && pending_.front().t_image < t_image) pending_.pop_front();
  if (!pending_.empty() && pending_.front().t_image == t_image) {
    delivery_to_pose_.add(wall_s - pending_.front().wall_s);
    pending_.pop_front();
  }
}

PoseLatencyMeter::Summary PoseLatencyMeter::summary() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return {stamp_to_pose_.summary(), delivery_to_pose_.summary()};
}

}  // namespace rgbdi::system
