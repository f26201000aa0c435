#include "rgbdi/io/stream_diagnostics.h"

#include <cstdio>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

namespace rgbdi::io {
namespace {

std::string num(double v, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

std::string timing(const SensorStreamStats& s, const char* what) {
  std::ostringstream os;
  os << s.delivered << " " << what;
  if (s.delivered == 0) return os.str();
  os << ", " << num(s.duration_s, 3) << " s (t = " << num(s.first_t, 6) << " .. "
     << num(s.last_t, 6) << ")";
  if (s.rate_hz > 0.0) os << ", " << num(s.rate_hz, 2) << " Hz";
  return os.str();
}

std::string ordering(const SensorStreamStats& s) {
  std::ostringstream os;
  os << "non-monotonic " << s.non_monotonic << ", reordered " << s.reordered
     << ", duplicates dropped " << s.duplicates << ", late dropped " << s.dropped_late
     << ", invalid stamps " << s.invalid_stamps;
  return os.str();
}

nlohmann::json statsJson(const SensorStreamStats& s) {
  return {{"delivered", s.delivered},
          {"first_t", s.first_t},
          {"last_t", s.last_t},
          {"duration_s", s.duration_s},
          {"rate_hz", s.rate_hz},
          {"median_period_s", s.median_period_s},
          {"gaps", s.gaps},
          {"gap_limit_s", s.gap_limit_s},
          {"max_gap_s", s.max_gap_s},
          {"non_monotonic", s.non_monotonic},
          {"reordered", s.reordered},
          {"duplicates", s.duplicates},
          {"dropped_late", s.dropped_late},
          {"invalid_stamps", s.invalid_stamps}};
}

}  // namespace

std::string StreamDiagnostics::report() const {
  std::ostringstream os;
  os << "Source: " << source << "\n";
  if (!images_directory.empty()) os << "External images directory: " << images_directory << "\n";
  os << "Records: " << records << " (observations " << observations << ", actions " << actions
     << ", unusable " << unusable << ")\n";
  if (!skipped.empty()) {
    os << "Skipped (not used):";
    for (const auto& [cls, n] : skipped) os << " " << cls << " x" << n;
    os << "\n";
  }
  os << "IMU:   " << timing(imu, "samples") << "\n";
  if (imu.delivered > 0) {
    os << "       gaps " << imu.gaps << " (limit " << num(imu.gap_limit_s, 4) << " s, largest dt "
       << num(imu.max_gap_s, 4) << " s); mean |acc| " << num(mean_acc_norm_m_s2, 3) << " m/s^2"
       << (acc_looks_like_g_units ? " (looks like g units!)" : "") << "\n";
  }
  os << "       order: " << ordering(imu) << "\n";
  os << "RGB-D: " << timing(images, "frames") << "\n";
  if (frames_rate_limited > 0)
    os << "       skipped by [stream] image_rate_limit_hz (not decoded): " << frames_rate_limited
       << "\n";
  if (images.delivered >= 2) {
    os << "       median period " << num(images.median_period_s, 4) << " s, gaps " << images.gaps
       << " (limit " << num(images.gap_limit_s, 4) << " s, largest dt " << num(images.max_gap_s, 4)
       << " s)\n";
  }
  if (images.delivered > 0) {
    os << "       with colour " << frames_with_color << ", with depth " << frames_with_depth
       << ", depth aligned to colour " << frames_aligned << "; depth unit " << depth_unit_m
       << " m, median depth " << num(median_depth_m, 3) << " m\n";
  }
  os << "       order: " << ordering(images) << "\n";
  if (hasWheel()) {
    os << "Wheel: " << timing(wheel, "readings") << "\n";
    os << wheelReport();
  }
  os << "Checks: size mismatches " << size_mismatches << ", missing intrinsics "
     << missing_intrinsics << ", depth unit suspects " << depth_unit_suspects
     << ", sensorPose vs [extrinsic] " << (extrinsic_mismatch ? "DISAGREE" : "agree or absent")
     << ", non-finite IMU samples " << non_finite_imu << ", black/constant colour images "
     << constant_color_frames << " (" << num(constant_color_s, 3) << " s)\n";
  os << "Warnings: " << warnings.size() << "\n";
  for (const auto& w : warnings) os << "  " << w << "\n";
  if (!error.empty()) os << "ERROR: " << error << "\n";
  return os.str();
}

std::string StreamDiagnostics::wheelReport() const {
  std::ostringstream os;
  if (wheel.delivered >= 2) {
    os << "       median period " << num(wheel.median_period_s, 4) << " s, gaps " << wheel.gaps
       << " (limit " << num(wheel.gap_limit_s, 4) << " s, largest dt " << num(wheel.max_gap_s, 4)
       << " s after t = " << num(wheel_max_gap_t, 6) << " s)\n";
  }
  os << "       with velocities " << wheel_with_velocities << ", with encoder ticks "
     << wheel_with_encoders << ", non-finite " << non_finite_wheel << "\n";
  os << "       moving while the IMU is at rest: " << wheel_moving_at_rest << " times ("
     << num(wheel_moving_at_rest_s, 3)
     << " s); standing while the IMU moves: " << wheel_still_imu_moving << " times ("
     << num(wheel_still_imu_moving_s, 3) << " s)\n";
  os << "       order: " << ordering(wheel) << "\n";
  return os.str();
}

std::string StreamDiagnostics::toJson(int indent) const {
  nlohmann::json j;
  j["source"] = source;
  j["images_directory"] = images_directory;
  j["records"] = records;
  j["observations"] = observations;
  j["actions"] = actions;
  j["skipped"] = skipped;
  j["unusable"] = unusable;
  j["frames_rate_limited"] = frames_rate_limited;
  j["imu"] = statsJson(imu);
  j["images"] = statsJson(images);
  if (hasWheel()) {
    j["wheel"] = statsJson(wheel);
    j["wheel"]["with_velocities"] = wheel_with_velocities;
    j["wheel"]["with_encoders"] = wheel_with_encoders;
    j["wheel"]["non_finite"] = non_finite_wheel;
    j["wheel"]["moving_at_rest"] = wheel_moving_at_rest;
    j["wheel"]["moving_at_rest_s"] = wheel_moving_at_rest_s;
    j["wheel"]["still_imu_moving"] = wheel_still_imu_moving;
    j["wheel"]["still_imu_moving_s"] = wheel_still_imu_moving_s;
    j["wheel"]["max_gap_t"] = wheel_max_gap_t;
  }
  j["frames_with_color"] = frames_with_color;
  j["frames_with_depth"] = frames_with_depth;
  j["frames_aligned"] = frames_aligned;
  j["size_mismatches"] = size_mismatches;
  j["missing_intrinsics"] = missing_intrinsics;
  j["depth_unit_suspects"] = depth_unit_suspects;
  j["median_depth_m"] = median_depth_m;
  j["depth_unit_m"] = depth_unit_m;
  j["extrinsic_mismatch"] = extrinsic_mismatch;
  j["mean_acc_norm_m_s2"] = mean_acc_norm_m_s2;
  j["acc_looks_like_g_units"] = acc_looks_like_g_units;
  j["read_cpu_s"] = read_cpu_s;
  j["rgbd_decode_cpu_s"] = rgbd_decode_cpu_s;
  j["non_finite_imu"] = non_finite_imu;
  j["constant_color_frames"] = constant_color_frames;
  j["constant_color_s"] = constant_color_s;
  j["warnings"] = warnings;
  j["error"] = error;
  j["refused"] = refused;
  j["ok"] = ok();
  return j.dump(indent);
}

std::vector<std::string> streamProblemLines(const StreamDiagnostics& d) {
  std::vector<std::string> lines;
  std::set<std::string> seen;
  for (const auto& w : d.warnings)
    if (seen.insert(w).second) lines.push_back(w);
  if (!d.error.empty()) lines.push_back("error: " + d.error);
  return lines;
}

}  // namespace rgbdi::io
