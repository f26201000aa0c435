#include "rgbdi/live/live_stats.h"

#include <iomanip>
#include <nlohmann/json.hpp>
#include <sstream>

namespace rgbdi::live {
namespace {

nlohmann::json latency(const LatencySummary& s) {
  return {{"count", s.count}, {"p50_s", s.p50_s}, {"p95_s", s.p95_s}, {"max_s", s.max_s}};
}

}  // namespace

std::string LiveStats::toJson(int indent) const {
  nlohmann::json j;
  j["imu_received"] = imu_received;
  j["imu_delivered"] = imu_delivered;
  j["imu_rejected"] = imu_rejected;
  j["frames_received"] = frames_received;
  j["frames_delivered"] = frames_delivered;
  j["frames_dropped"] = frames_dropped;
  j["frames_rejected"] = frames_rejected;
  j["imu_queue_high_water"] = imu_queue_high_water;
  j["frame_queue_high_water"] = frame_queue_high_water;
  j["ordering_high_water"] = ordering_high_water;
  j["imu_latency"] = latency(imu_latency);
  j["frame_latency"] = latency(frame_latency);
  j["imu_stalls"] = imu_stalls;
  j["imu_time_jumps"] = imu_time_jumps;
  j["events"] = events;
  nlohmann::json ss = nlohmann::json::array();
  for (const auto& s : sensors) {
    ss.push_back({{"section", s.section},
                  {"driver", s.driver},
                  {"imu", s.imu},
                  {"frames", s.frames},
                  {"other", s.other},
                  {"unusable", s.unusable},
                  {"ended", s.ended}});
  }
  j["sensors"] = ss;
  j["wall_duration_s"] = wall_duration_s;
  j["error"] = error;
  return j.dump(indent);
}

std::string LiveStats::line() const {
  std::ostringstream os;
  const double d = wall_duration_s > 0.0 ? wall_duration_s : 1.0;
  os << std::fixed << std::setprecision(1) << "frames " << frames_delivered << " ("
     << frames_delivered / d << " Hz, " << frames_dropped << " dropped), IMU " << imu_delivered
     << " (" << imu_delivered / d << " Hz)" << std::setprecision(1) << ", latency p50 "
     << frame_latency.p50_s * 1e3 << " ms p95 " << frame_latency.p95_s * 1e3 << " ms";
  if (imu_stalls || imu_time_jumps)
    os << ", IMU stalls " << imu_stalls << " jumps " << imu_time_jumps;
  return os.str();
}

}  // namespace rgbdi::live
