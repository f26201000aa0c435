// doc/configuration.md against the configuration itself: its key tables list every key of
// share/config.ini and no other, each documented default equals the shipped file's value and the
// default of the option struct that reads the key, and every documented key is one the tools read.
// A key added to share/config.ini without a row in doc/configuration.md (and an entry in
// kFields below) fails here.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "rgbdi/bag/convert_options.h"
#include "rgbdi/common/ini_reader.h"
#include "rgbdi/common/ini_text.h"
#include "rgbdi/sim/sequence.h"
#include "rgbdi/system/system_config.h"
#include "testing/fixtures.h"

using namespace rgbdi;

namespace {

using SectionKey = std::pair<std::string, std::string>;

/// A documented (or shipped) value with the line it came from, for messages.
struct Entry {
  std::string value;
  int line = 0;
};
using Table = std::map<SectionKey, Entry>;

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return {};
  return s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
}

/// The cells of a markdown table row ("| a | b \| c |"), with "\|" kept inside a cell.
std::vector<std::string> cells(const std::string& row) {
  std::vector<std::string> out;
  std::string cur;
  for (std::size_t i = 1; i < row.size(); ++i) {
    if (row[i] == '\\' && i + 1 < row.size() && row[i + 1] == '|') {
      cur += '|';
      ++i;
    } else if (row[i] == '|') {
      out.push_back(trim(cur));
      cur.clear();
    } else {
      cur += row[i];
    }
  }
  return out;
}

std::string unquote(const std::string& cell) {
  if (cell.size() >= 2 && cell.front() == '`' && cell.back() == '`')
    return cell.substr(1, cell.size() - 2);
  return cell;
}

/// The key rows of doc/configuration.md: under a heading "## [section]", rows whose first cell
/// is a `key` and whose second is its `default`. Another "## " heading ends the section.
Table readDocTables(const std::string& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << "cannot open " << path;
  Table t;
  std::string line, section;
  for (int n = 1; std::getline(in, line); ++n) {
    if (line.rfind("## ", 0) == 0) {
      const std::string h = trim(line.substr(3));
      section = (h.size() > 2 && h.front() == '[' && h.back() == ']') ? h.substr(1, h.size() - 2)
                                                                      : std::string();
      continue;
    }
    if (section.empty() || line.rfind("| `", 0) != 0) continue;
    const std::vector<std::string> c = cells(line);
    EXPECT_GE(c.size(), 4u) << path << " line " << n << ": a key row has key, default, unit, "
                            << "meaning: " << line;
    if (c.size() < 2) continue;
    const SectionKey sk{section, unquote(c[0])};
    EXPECT_EQ(t.count(sk), 0u) << path << " line " << n << ": [" << section << "] " << sk.second
                               << " documented twice";
    t[sk] = {unquote(c[1]), n};
  }
  return t;
}

/// The keys of share/config.ini with their values (inline comments stripped).
Table readIni(const std::string& path, std::vector<std::string>* sections) {
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << "cannot open " << path;
  Table t;
  std::string line, section;
  for (int n = 1; std::getline(in, line); ++n) {
    const std::string s = trim(line);
    if (s.empty() || s[0] == ';' || s[0] == '#') continue;
    if (s[0] == '[') {
      section = s.substr(1, s.find(']') - 1);
      sections->push_back(section);
      continue;
    }
    const auto eq = s.find('=');
    if (eq == std::string::npos) continue;
    std::string v = s.substr(eq + 1);
    v = trim(v.substr(0, v.find_first_of(";#")));
    t[{section, trim(s.substr(0, eq))}] = {v, n};
  }
  return t;
}

std::vector<std::string> tokens(const std::string& s) {
  std::istringstream is(s);
  std::vector<std::string> out;
  for (std::string w; is >> w;) out.push_back(w);
  return out;
}

bool isNumber(const std::string& s, double* v) {
  char* end = nullptr;
  *v = std::strtod(s.c_str(), &end);
  return !s.empty() && end != s.c_str() && *end == '\0';
}

/// Same value: the same words, numbers compared as numbers (within `abs_tol` or relative
/// tolerance `rel`; both 0: exactly).
bool sameValue(const std::string& a, const std::string& b, double rel, double abs_tol = 0.0) {
  const std::vector<std::string> x = tokens(a), y = tokens(b);
  if (x.size() != y.size()) return false;
  for (std::size_t i = 0; i < x.size(); ++i) {
    double u = 0, v = 0;
    if (isNumber(x[i], &u) && isNumber(y[i], &v)) {
      if (std::abs(u - v) > std::max(abs_tol, rel * std::max(std::abs(u), std::abs(v))))
        return false;
    } else if (x[i] != y[i]) {
      return false;
    }
  }
  return true;
}

// The value of an option struct's field as INI text.
std::string text(double v) { return iniNumber(v); }
std::string text(int v) { return std::to_string(v); }
std::string text(std::uint64_t v) { return std::to_string(v); }
std::string text(bool v) { return v ? "true" : "false"; }
std::string text(const char* v) { return v; }
std::string text(const std::string& v) { return v; }
std::string text(const std::array<double, 5>& v) {
  return iniNumbers(Eigen::Map<const Eigen::Matrix<double, 5, 1>>(v.data()));
}
std::string text(const Eigen::Matrix3d& m) {
  Eigen::Matrix<double, 9, 1> row_major;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) row_major[3 * i + j] = m(i, j);
  return iniNumbers(row_major);
}
std::string text(const Eigen::Vector3d& v) { return iniNumbers(v); }

/// The defaults of the option structs, loaded from an empty configuration as the tools do.
struct Defaults {
  system::SystemConfig system;  ///< rgbdi-slam: every section but [sim] and [convert]
  sim::SimOptions sim;          ///< rgbdi-sim: [sim] ([camera] and [extrinsic] as above)
  bag::ConvertOptions convert;  ///< rawlog-convert: [convert]
};

Defaults loadDefaults() {
  IniReader a = IniReader::empty(), b = IniReader::empty(), c = IniReader::empty();
  return {system::SystemConfig::load(a), sim::SimOptions::load(b), bag::ConvertOptions::load(c)};
}

struct Field {
  const char* section;
  const char* key;
  std::function<std::string(const Defaults&)> value;
};

const std::vector<Field> kFields = {
    {"camera", "width", [](const Defaults& d) { return text(d.system.camera.camera.width); }},
    {"camera", "height", [](const Defaults& d) { return text(d.system.camera.camera.height); }},
    {"camera", "fx", [](const Defaults& d) { return text(d.system.camera.camera.fx); }},
    {"camera", "fy", [](const Defaults& d) { return text(d.system.camera.camera.fy); }},
    {"camera", "cx", [](const Defaults& d) { return text(d.system.camera.camera.cx); }},
    {"camera", "cy", [](const Defaults& d) { return text(d.system.camera.camera.cy); }},
    {"camera", "distortion", [](const Defaults& d) { return text(d.system.camera.camera.dist); }},
    {"camera", "intrinsics_source", [](const Defaults& d) { return text(d.system.camera.intrinsics_source); }},
    {"camera", "rolling_shutter_readout_s", [](const Defaults& d) { return text(d.system.camera.rolling_shutter_readout_s); }},
    {"imu", "rate_hz", [](const Defaults& d) { return text(d.system.imu.rate_hz); }},
    {"imu", "acc_noise_density", [](const Defaults& d) { return text(d.system.imu.acc_noise_density); }},
    {"imu", "gyr_noise_density", [](const Defaults& d) { return text(d.system.imu.gyr_noise_density); }},
    {"imu", "acc_random_walk", [](const Defaults& d) { return text(d.system.imu.acc_random_walk); }},
    {"imu", "gyr_random_walk", [](const Defaults& d) { return text(d.system.imu.gyr_random_walk); }},
    {"imu", "gravity_m_s2", [](const Defaults& d) { return text(d.system.imu.gravity_m_s2); }},
    {"extrinsic", "R_body_cam", [](const Defaults& d) { return text(Eigen::Matrix3d(d.system.extrinsic.T_body_cam.linear())); }},
    {"extrinsic", "t_body_cam_m", [](const Defaults& d) { return text(Eigen::Vector3d(d.system.extrinsic.T_body_cam.translation())); }},
    {"extrinsic", "time_offset_s", [](const Defaults& d) { return text(d.system.extrinsic.time_offset_s); }},
    {"extrinsic", "sensor_pose_tolerance_m", [](const Defaults& d) { return text(d.system.extrinsic.sensor_pose_tolerance_m); }},
    {"extrinsic", "sensor_pose_tolerance_deg", [](const Defaults& d) { return text(d.system.extrinsic.sensor_pose_tolerance_deg); }},
    {"stream", "imu_reorder_window_s", [](const Defaults& d) { return text(d.system.stream.imu_reorder_window_s); }},
    {"stream", "image_reorder_window_s", [](const Defaults& d) { return text(d.system.stream.image_reorder_window_s); }},
    {"stream", "imu_gap_factor", [](const Defaults& d) { return text(d.system.stream.imu_gap_factor); }},
    {"stream", "image_gap_factor", [](const Defaults& d) { return text(d.system.stream.image_gap_factor); }},
    {"stream", "imu_rate_tolerance", [](const Defaults& d) { return text(d.system.stream.imu_rate_tolerance); }},
    {"stream", "g_units_min_m_s2", [](const Defaults& d) { return text(d.system.stream.g_units_min_m_s2); }},
    {"stream", "g_units_max_m_s2", [](const Defaults& d) { return text(d.system.stream.g_units_max_m_s2); }},
    {"stream", "acc_magnitude_tolerance", [](const Defaults& d) { return text(d.system.stream.acc_magnitude_tolerance); }},
    {"stream", "depth_median_min_m", [](const Defaults& d) { return text(d.system.stream.depth_median_min_m); }},
    {"stream", "depth_median_max_m", [](const Defaults& d) { return text(d.system.stream.depth_median_max_m); }},
    {"stream", "depth_check_step_px", [](const Defaults& d) { return text(d.system.stream.depth_check_step_px); }},
    {"stream", "max_listed_issues", [](const Defaults& d) { return text(d.system.stream.max_listed_issues); }},
    {"stream", "accel_scale", [](const Defaults& d) { return text(d.system.stream.accel_scale); }},
    {"stream", "accel_check_samples", [](const Defaults& d) { return text(d.system.stream.accel_check_samples); }},
    {"stream", "accel_check_max_s", [](const Defaults& d) { return text(d.system.stream.accel_check_max_s); }},
    {"stream", "time_jump_back_s", [](const Defaults& d) { return text(d.system.stream.time_jump_back_s); }},
    {"stream", "constant_image_max_range", [](const Defaults& d) { return text(d.system.stream.constant_image_max_range); }},
    {"stream", "image_check_step_px", [](const Defaults& d) { return text(d.system.stream.image_check_step_px); }},
    {"stream", "image_rate_limit_hz", [](const Defaults& d) { return text(d.system.stream.image_rate_limit_hz); }},
    {"stream", "wheel_gap_factor", [](const Defaults& d) { return text(d.system.stream.wheel_gap_factor); }},
    {"stream", "wheel_rest_window_s", [](const Defaults& d) { return text(d.system.stream.wheel_rest_window_s); }},
    {"stream", "wheel_rest_gyr_rad_s", [](const Defaults& d) { return text(d.system.stream.wheel_rest_gyr_rad_s); }},
    {"stream", "wheel_rest_acc_std_m_s2", [](const Defaults& d) { return text(d.system.stream.wheel_rest_acc_std_m_s2); }},
    {"stream", "wheel_rest_speed_m_s", [](const Defaults& d) { return text(d.system.stream.wheel_rest_speed_m_s); }},
    {"stream", "wheel_rest_yaw_rate_rad_s", [](const Defaults& d) { return text(d.system.stream.wheel_rest_yaw_rate_rad_s); }},
    {"stream", "wheel_still_gyr_rad_s", [](const Defaults& d) { return text(d.system.stream.wheel_still_gyr_rad_s); }},
    {"stream", "wheel_still_acc_m_s2", [](const Defaults& d) { return text(d.system.stream.wheel_still_acc_m_s2); }},
    {"stream", "wheel_still_block_s", [](const Defaults& d) { return text(d.system.stream.wheel_still_block_s); }},
    {"frontend", "max_features", [](const Defaults& d) { return text(d.system.frontend.max_features); }},
    {"frontend", "detect_min_missing", [](const Defaults& d) { return text(d.system.frontend.detect_min_missing); }},
    {"frontend", "min_distance_px", [](const Defaults& d) { return text(d.system.frontend.min_distance_px); }},
    {"frontend", "shi_tomasi_quality", [](const Defaults& d) { return text(d.system.frontend.shi_tomasi_quality); }},
    {"frontend", "shi_tomasi_block_size", [](const Defaults& d) { return text(d.system.frontend.shi_tomasi_block_size); }},
    {"frontend", "min_gradient_grey_per_px", [](const Defaults& d) { return text(d.system.frontend.min_gradient_grey_per_px); }},
    {"frontend", "border_px", [](const Defaults& d) { return text(d.system.frontend.border_px); }},
    {"frontend", "clahe_clip_limit", [](const Defaults& d) { return text(d.system.frontend.clahe_clip_limit); }},
    {"frontend", "klt_window_px", [](const Defaults& d) { return text(d.system.frontend.klt_window_px); }},
    {"frontend", "klt_pyramid_levels", [](const Defaults& d) { return text(d.system.frontend.klt_pyramid_levels); }},
    {"frontend", "klt_max_iterations", [](const Defaults& d) { return text(d.system.frontend.klt_max_iterations); }},
    {"frontend", "klt_epsilon_px", [](const Defaults& d) { return text(d.system.frontend.klt_epsilon_px); }},
    {"frontend", "klt_max_forward_backward_px", [](const Defaults& d) { return text(d.system.frontend.klt_max_forward_backward_px); }},
    {"frontend", "klt_predict_rotation", [](const Defaults& d) { return text(d.system.frontend.klt_predict_rotation); }},
    {"frontend", "klt_predict_translation", [](const Defaults& d) { return text(d.system.frontend.klt_predict_translation); }},
    {"frontend", "klt_predict_every_feature", [](const Defaults& d) { return text(d.system.frontend.klt_predict_every_feature); }},
    {"frontend", "ransac_threshold_px", [](const Defaults& d) { return text(d.system.frontend.ransac_threshold_px); }},
    {"frontend", "ransac_confidence", [](const Defaults& d) { return text(d.system.frontend.ransac_confidence); }},
    {"frontend", "depth_min_m", [](const Defaults& d) { return text(d.system.frontend.depth_min_m); }},
    {"frontend", "depth_max_m", [](const Defaults& d) { return text(d.system.frontend.depth_max_m); }},
    {"frontend", "depth_neighbourhood_px", [](const Defaults& d) { return text(d.system.frontend.depth_neighbourhood_px); }},
    {"frontend", "depth_max_relative_spread", [](const Defaults& d) { return text(d.system.frontend.depth_max_relative_spread); }},
    {"frontend", "depth_noise_coeff", [](const Defaults& d) { return text(d.system.frontend.depth_noise_coeff); }},
    {"frontend", "depth_max_noise_sigmas", [](const Defaults& d) { return text(d.system.frontend.depth_max_noise_sigmas); }},
    {"frontend", "registration_fill_max_relative_diff", [](const Defaults& d) { return text(d.system.frontend.registration_fill_max_relative_diff); }},
    {"frontend", "occlusion_window_px", [](const Defaults& d) { return text(d.system.frontend.occlusion_window_px); }},
    {"frontend", "occlusion_sample_step_px", [](const Defaults& d) { return text(d.system.frontend.occlusion_sample_step_px); }},
    {"frontend", "occlusion_max_residual_sigmas", [](const Defaults& d) { return text(d.system.frontend.occlusion_max_residual_sigmas); }},
    {"frontend", "occlusion_min_valid_fraction", [](const Defaults& d) { return text(d.system.frontend.occlusion_min_valid_fraction); }},
    {"frontend", "opencv_threads", [](const Defaults& d) { return text(d.system.frontend.opencv_threads); }},
    {"estimator", "window_size", [](const Defaults& d) { return text(d.system.estimator.window_size); }},
    {"estimator", "keyframe_parallax_px", [](const Defaults& d) { return text(d.system.estimator.keyframe_parallax_px); }},
    {"estimator", "keyframe_min_tracked", [](const Defaults& d) { return text(d.system.estimator.keyframe_min_tracked); }},
    {"estimator", "keyframe_parallax_without_rotation", [](const Defaults& d) { return text(d.system.estimator.keyframe_parallax_without_rotation); }},
    {"estimator", "max_iterations", [](const Defaults& d) { return text(d.system.estimator.max_iterations); }},
    {"estimator", "max_solver_time_s", [](const Defaults& d) { return text(d.system.estimator.max_solver_time_s); }},
    {"estimator", "solver_function_tolerance", [](const Defaults& d) { return text(d.system.estimator.solver_function_tolerance); }},
    {"estimator", "solver_function_tolerance_no_depth", [](const Defaults& d) { return text(d.system.estimator.solver_function_tolerance_no_depth); }},
    {"estimator", "non_keyframe_update", [](const Defaults& d) { return text(d.system.estimator.non_keyframe_update); }},
    {"estimator", "reprojection_sigma_px", [](const Defaults& d) { return text(d.system.estimator.reprojection_sigma_px); }},
    {"estimator", "cauchy_loss_sigma", [](const Defaults& d) { return text(d.system.estimator.cauchy_loss_sigma); }},
    {"estimator", "depth_verify_tolerance_px", [](const Defaults& d) { return text(d.system.estimator.depth_verify_tolerance_px); }},
    {"estimator", "depth_verify_min_m", [](const Defaults& d) { return text(d.system.estimator.depth_verify_min_m); }},
    {"estimator", "depth_verify_max_m", [](const Defaults& d) { return text(d.system.estimator.depth_verify_max_m); }},
    {"estimator", "verified_depth", [](const Defaults& d) { return text(d.system.estimator.verified_depth); }},
    {"estimator", "depth_noise_coeff", [](const Defaults& d) { return text(d.system.estimator.depth_noise_coeff); }},
    {"estimator", "init_depth_max_m", [](const Defaults& d) { return text(d.system.estimator.init_depth_max_m); }},
    {"estimator", "init_min_correspondences", [](const Defaults& d) { return text(d.system.estimator.init_min_correspondences); }},
    {"estimator", "init_min_parallax_px", [](const Defaults& d) { return text(d.system.estimator.init_min_parallax_px); }},
    {"estimator", "init_static_max_gyro_rad_s", [](const Defaults& d) { return text(d.system.estimator.init_static_max_gyro_rad_s); }},
    {"estimator", "init_static_max_acc_std_m_s2", [](const Defaults& d) { return text(d.system.estimator.init_static_max_acc_std_m_s2); }},
    {"estimator", "init_static_max_acc_dev_m_s2", [](const Defaults& d) { return text(d.system.estimator.init_static_max_acc_dev_m_s2); }},
    {"estimator", "init_static_max_motion_px", [](const Defaults& d) { return text(d.system.estimator.init_static_max_motion_px); }},
    {"estimator", "init_static_window_s", [](const Defaults& d) { return text(d.system.estimator.init_static_window_s); }},
    {"estimator", "init_min_frames", [](const Defaults& d) { return text(d.system.estimator.init_min_frames); }},
    {"estimator", "init_min_span_s", [](const Defaults& d) { return text(d.system.estimator.init_min_span_s); }},
    {"estimator", "init_allow_static", [](const Defaults& d) { return text(d.system.estimator.init_allow_static); }},
    {"estimator", "init_max_scale_rel_sigma", [](const Defaults& d) { return text(d.system.estimator.init_max_scale_rel_sigma); }},
    {"estimator", "init_max_alignment_rms", [](const Defaults& d) { return text(d.system.estimator.init_max_alignment_rms); }},
    {"estimator", "init_alignment_interval_s", [](const Defaults& d) { return text(d.system.estimator.init_alignment_interval_s); }},
    {"estimator", "init_acc_bias_sigma_m_s2", [](const Defaults& d) { return text(d.system.estimator.init_acc_bias_sigma_m_s2); }},
    {"estimator", "init_gyr_bias_sigma_rad_s", [](const Defaults& d) { return text(d.system.estimator.init_gyr_bias_sigma_rad_s); }},
    {"estimator", "init_static_velocity_sigma_m_s", [](const Defaults& d) { return text(d.system.estimator.init_static_velocity_sigma_m_s); }},
    {"estimator", "outlier_reprojection_px", [](const Defaults& d) { return text(d.system.estimator.outlier_reprojection_px); }},
    {"estimator", "repropagate_acc_bias_m_s2", [](const Defaults& d) { return text(d.system.estimator.repropagate_acc_bias_m_s2); }},
    {"estimator", "repropagate_gyr_bias_rad_s", [](const Defaults& d) { return text(d.system.estimator.repropagate_gyr_bias_rad_s); }},
    {"estimator", "estimate_time_offset", [](const Defaults& d) { return text(d.system.estimator.estimate_time_offset); }},
    {"estimator", "time_offset_velocity", [](const Defaults& d) { return text(d.system.estimator.time_offset_velocity); }},
    {"estimator", "time_offset_prior_sigma_s", [](const Defaults& d) { return text(d.system.estimator.time_offset_prior_sigma_s); }},
    {"estimator", "estimate_rolling_shutter_readout", [](const Defaults& d) { return text(d.system.estimator.estimate_rolling_shutter_readout); }},
    {"estimator", "rolling_shutter_readout_prior_sigma_s", [](const Defaults& d) { return text(d.system.estimator.rolling_shutter_readout_prior_sigma_s); }},
    {"estimator", "rolling_shutter_readout_max_s", [](const Defaults& d) { return text(d.system.estimator.rolling_shutter_readout_max_s); }},
    {"estimator", "update_rate_hz", [](const Defaults& d) { return text(d.system.estimator.update_rate_hz); }},
    {"estimator", "fail_max_acc_bias_m_s2", [](const Defaults& d) { return text(d.system.estimator.fail_max_acc_bias_m_s2); }},
    {"estimator", "fail_max_gyr_bias_rad_s", [](const Defaults& d) { return text(d.system.estimator.fail_max_gyr_bias_rad_s); }},
    {"estimator", "fail_max_speed_m_s", [](const Defaults& d) { return text(d.system.estimator.fail_max_speed_m_s); }},
    {"estimator", "fail_max_jump_m", [](const Defaults& d) { return text(d.system.estimator.fail_max_jump_m); }},
    {"estimator", "fail_max_vertical_jump_m", [](const Defaults& d) { return text(d.system.estimator.fail_max_vertical_jump_m); }},
    {"estimator", "fail_min_features", [](const Defaults& d) { return text(d.system.estimator.fail_min_features); }},
    {"estimator", "fail_max_blind_s", [](const Defaults& d) { return text(d.system.estimator.fail_max_blind_s); }},
    {"relocalise", "geometric", [](const Defaults& d) { return text(d.system.reloc.enable); }},
    {"relocalise", "grid_resolution_m", [](const Defaults& d) { return text(d.system.reloc.grid.resolution_m); }},
    {"relocalise", "band_min_m", [](const Defaults& d) { return text(d.system.reloc.grid.band_min_m); }},
    {"relocalise", "band_max_m", [](const Defaults& d) { return text(d.system.reloc.grid.band_max_m); }},
    {"relocalise", "max_range_m", [](const Defaults& d) { return text(d.system.reloc.grid.max_range_m); }},
    {"relocalise", "min_hits", [](const Defaults& d) { return text(d.system.reloc.grid.min_hits); }},
    {"relocalise", "yaw_step_deg", [](const Defaults& d) { return text(d.system.reloc.search.yaw_step_deg); }},
    {"relocalise", "pyramid_levels", [](const Defaults& d) { return text(d.system.reloc.search.pyramid_levels); }},
    {"relocalise", "candidate_margin", [](const Defaults& d) { return text(d.system.reloc.search.candidate_margin); }},
    {"relocalise", "conflict_penalty", [](const Defaults& d) { return text(d.system.reloc.search.conflict_penalty); }},
    {"relocalise", "hypothesis_margin", [](const Defaults& d) { return text(d.system.reloc.search.hypothesis_margin); }},
    {"relocalise", "place_separation_m", [](const Defaults& d) { return text(d.system.reloc.search.place_separation_m); }},
    {"relocalise", "place_separation_deg", [](const Defaults& d) { return text(d.system.reloc.search.place_separation_deg); }},
    {"relocalise", "min_overlap_fraction", [](const Defaults& d) { return text(d.system.reloc.search.min_overlap_fraction); }},
    {"relocalise", "max_conflict_fraction", [](const Defaults& d) { return text(d.system.reloc.search.max_conflict_fraction); }},
    {"relocalise", "max_hypotheses", [](const Defaults& d) { return text(d.system.reloc.search.max_hypotheses); }},
    {"relocalise", "submap_path_m", [](const Defaults& d) { return text(d.system.reloc.submap_path_m); }},
    {"relocalise", "submap_min_occupied_cells", [](const Defaults& d) { return text(d.system.reloc.submap_min_occupied_cells); }},
    {"relocalise", "submap_max_path_m", [](const Defaults& d) { return text(d.system.reloc.submap_max_path_m); }},
    {"relocalise", "attempt_interval_m", [](const Defaults& d) { return text(d.system.reloc.attempt_interval_m); }},
    {"relocalise", "result_lag_keyframes", [](const Defaults& d) { return text(d.system.reloc.result_lag_keyframes); }},
    {"relocalise", "confirm_fits", [](const Defaults& d) { return text(d.system.reloc.confirm_fits); }},
    {"relocalise", "confirm_distance_m", [](const Defaults& d) { return text(d.system.reloc.confirm_distance_m); }},
    {"relocalise", "confirm_max_disagreement_m", [](const Defaults& d) { return text(d.system.reloc.confirm_max_disagreement_m); }},
    {"relocalise", "confirm_max_disagreement_deg", [](const Defaults& d) { return text(d.system.reloc.confirm_max_disagreement_deg); }},
    {"relocalise", "confirm_join_mean", [](const Defaults& d) { return text(d.system.reloc.confirm_join_mean); }},
    {"relocalise", "refine_max_distance_m", [](const Defaults& d) { return text(d.system.reloc.refine_max_distance_m); }},
    {"relocalise", "refine_max_range_m", [](const Defaults& d) { return text(d.system.reloc.refine_max_range_m); }},
    {"relocalise", "refine_horizontal", [](const Defaults& d) { return text(d.system.reloc.refine_horizontal); }},
    {"relocalise", "refine_iterations", [](const Defaults& d) { return text(d.system.reloc.refine_iterations); }},
    {"relocalise", "refine_huber_m", [](const Defaults& d) { return text(d.system.reloc.refine_huber_m); }},
    {"relocalise", "refine_height_drift_sigma_per_m", [](const Defaults& d) { return text(d.system.reloc.refine_height_drift_sigma_per_m); }},
    {"relocalise", "refine_min_view_cos", [](const Defaults& d) { return text(d.system.reloc.refine_min_view_cos); }},
    {"relocalise", "refine_tilt_sigma_deg", [](const Defaults& d) { return text(d.system.reloc.refine_tilt_sigma_deg); }},
    {"relocalise", "refine_min_pair_fraction", [](const Defaults& d) { return text(d.system.reloc.refine_min_pair_fraction); }},
    {"relocalise", "refine_max_rms_m", [](const Defaults& d) { return text(d.system.reloc.refine_max_rms_m); }},
    {"relocalise", "refine_min_horizontal_constraint", [](const Defaults& d) { return text(d.system.reloc.refine_min_horizontal_constraint); }},
    {"relocalise", "min_floor_cells", [](const Defaults& d) { return text(d.system.reloc.min_floor_cells); }},
    {"relocalise", "join_keyframes", [](const Defaults& d) { return text(d.system.reloc.join_keyframes); }},
    {"relocalise", "join_max_distance_m", [](const Defaults& d) { return text(d.system.reloc.join_max_distance_m); }},
    {"relocalise", "track_interval_m", [](const Defaults& d) { return text(d.system.reloc.track_interval_m); }},
    {"relocalise", "track_max_correction_m", [](const Defaults& d) { return text(d.system.reloc.track_max_correction_m); }},
    {"relocalise", "track_max_correction_deg", [](const Defaults& d) { return text(d.system.reloc.track_max_correction_deg); }},
    {"relocalise", "track_keyframes", [](const Defaults& d) { return text(d.system.reloc.track_keyframes); }},
    {"relocalise", "track_sigma_pos_m", [](const Defaults& d) { return text(d.system.reloc.track_sigma_pos_m); }},
    {"relocalise", "track_sigma_yaw_deg", [](const Defaults& d) { return text(d.system.reloc.track_sigma_yaw_deg); }},
    {"wheel", "enable", [](const Defaults& d) { return text(d.system.estimator.wheel.enable); }},
    {"wheel", "time_offset_s", [](const Defaults& d) { return text(d.system.estimator.wheel.time_offset_s); }},
    {"wheel", "R_body_wheel", [](const Defaults& d) { return text(Eigen::Matrix3d(d.system.estimator.wheel.T_body_wheel.linear())); }},
    {"wheel", "t_body_wheel_m", [](const Defaults& d) { return text(Eigen::Vector3d(d.system.estimator.wheel.T_body_wheel.translation())); }},
    {"wheel", "forward_sigma_per_sqrt_m", [](const Defaults& d) { return text(d.system.estimator.wheel.noise.forward_sigma_per_sqrt_m); }},
    {"wheel", "lateral_sigma_per_sqrt_m", [](const Defaults& d) { return text(d.system.estimator.wheel.noise.lateral_sigma_per_sqrt_m); }},
    {"wheel", "vertical_sigma_per_sqrt_m", [](const Defaults& d) { return text(d.system.estimator.wheel.noise.vertical_sigma_per_sqrt_m); }},
    {"wheel", "yaw_sigma_per_sqrt_rad", [](const Defaults& d) { return text(d.system.estimator.wheel.noise.yaw_sigma_per_sqrt_rad); }},
    {"wheel", "yaw_sigma_per_sqrt_m", [](const Defaults& d) { return text(d.system.estimator.wheel.noise.yaw_sigma_per_sqrt_m); }},
    {"wheel", "tilt_sigma_per_sqrt_m", [](const Defaults& d) { return text(d.system.estimator.wheel.noise.tilt_sigma_per_sqrt_m); }},
    {"wheel", "min_sigma_m", [](const Defaults& d) { return text(d.system.estimator.wheel.noise.min_sigma_m); }},
    {"wheel", "min_sigma_rad", [](const Defaults& d) { return text(d.system.estimator.wheel.noise.min_sigma_rad); }},
    {"wheel", "estimate_scale", [](const Defaults& d) { return text(d.system.estimator.wheel.estimate_scale); }},
    {"wheel", "scale_prior_sigma", [](const Defaults& d) { return text(d.system.estimator.wheel.scale_prior_sigma); }},
    {"wheel", "estimate_extrinsic_yaw", [](const Defaults& d) { return text(d.system.estimator.wheel.estimate_extrinsic_yaw); }},
    {"wheel", "extrinsic_yaw_prior_sigma_rad", [](const Defaults& d) { return text(d.system.estimator.wheel.extrinsic_yaw_prior_sigma_rad); }},
    {"wheel", "extrinsic_yaw_max_rad", [](const Defaults& d) { return text(d.system.estimator.wheel.extrinsic_yaw_max_rad); }},
    {"wheel", "estimate_time_offset", [](const Defaults& d) { return text(d.system.estimator.wheel.estimate_time_offset); }},
    {"wheel", "time_offset_prior_sigma_s", [](const Defaults& d) { return text(d.system.estimator.wheel.time_offset_prior_sigma_s); }},
    {"wheel", "time_offset_max_change_s", [](const Defaults& d) { return text(d.system.estimator.wheel.time_offset_max_change_s); }},
    {"wheel", "gate_chi2", [](const Defaults& d) { return text(d.system.estimator.wheel.gate_chi2); }},
    {"wheel", "max_blind_s", [](const Defaults& d) { return text(d.system.estimator.wheel.max_blind_s); }},
    {"wheel", "reading_lag_s", [](const Defaults& d) { return text(d.system.estimator.wheel.reading_lag_s); }},
    {"wheel", "fault_motion_ratio", [](const Defaults& d) { return text(d.system.estimator.wheel.fault_motion_ratio); }},
    {"wheel", "direction_from_gyro", [](const Defaults& d) { return text(d.system.estimator.wheel.direction_from_gyro); }},
    {"wheel", "ground_plane_sigma_m", [](const Defaults& d) { return text(d.system.estimator.wheel.ground_plane_sigma_m); }},
    {"wheel", "ground_plane_tilt_sigma_rad", [](const Defaults& d) { return text(d.system.estimator.wheel.ground_plane_tilt_sigma_rad); }},
    {"wheel", "ground_plane_gate_chi2", [](const Defaults& d) { return text(d.system.estimator.wheel.ground_plane_gate_chi2); }},
    {"wheel", "start_from_wheels", [](const Defaults& d) { return text(d.system.estimator.wheel.start_from_wheels); }},
    {"wheel", "start_window_s", [](const Defaults& d) { return text(d.system.estimator.wheel.start_window_s); }},
    {"wheel", "start_max_gravity_dev_m_s2", [](const Defaults& d) { return text(d.system.estimator.wheel.start_max_gravity_dev_m_s2); }},
    {"wheel", "start_max_rate_dev_rad_s", [](const Defaults& d) { return text(d.system.estimator.wheel.start_max_rate_dev_rad_s); }},
    {"wheel", "start_velocity_sigma_m_s", [](const Defaults& d) { return text(d.system.estimator.wheel.start_velocity_sigma_m_s); }},
    {"loop", "enable", [](const Defaults& d) { return text(d.system.loop.enable); }},
    {"loop", "offline_lag_keyframes", [](const Defaults& d) { return text(d.system.loop.offline_lag_keyframes); }},
    {"loop", "max_verified_candidates", [](const Defaults& d) { return text(d.system.loop.max_verified_candidates); }},
    {"loop", "max_loops_per_keyframe", [](const Defaults& d) { return text(d.system.loop.max_loops_per_keyframe); }},
    {"loop", "min_keyframe_distance_m", [](const Defaults& d) { return text(d.system.loop.min_keyframe_distance_m); }},
    {"loop", "min_keyframe_angle_deg", [](const Defaults& d) { return text(d.system.loop.min_keyframe_angle_deg); }},
    {"loop", "solve_interval_keyframes", [](const Defaults& d) { return text(d.system.loop.solve_interval_keyframes); }},
    {"loop", "relocalize_min_inliers", [](const Defaults& d) { return text(d.system.loop.relocalize_min_inliers); }},
    {"loop", "relocalize_consistent_keyframes", [](const Defaults& d) { return text(d.system.loop.relocalize_consistent_keyframes); }},
    {"loop", "relocalize_max_disagreement_m", [](const Defaults& d) { return text(d.system.loop.relocalize_max_disagreement_m); }},
    {"loop", "relocalize_max_disagreement_deg", [](const Defaults& d) { return text(d.system.loop.relocalize_max_disagreement_deg); }},
    {"loop", "relocalize_window_keyframes", [](const Defaults& d) { return text(d.system.loop.relocalize_window_keyframes); }},
    {"loop", "relocalize_from_window", [](const Defaults& d) { return text(d.system.loop.relocalize_from_window); }},
    {"loop", "relocalize_check_keyframes", [](const Defaults& d) { return text(d.system.loop.relocalize_check_keyframes); }},
    {"loop", "relocalize_check_radius_m", [](const Defaults& d) { return text(d.system.loop.relocalize_check_radius_m); }},
    {"loop", "relocalize_check_max_conflict_fraction", [](const Defaults& d) { return text(d.system.loop.relocalize_check_max_conflict_fraction); }},
    {"loop", "relocalize_check_max_conflict_fraction_geometric", [](const Defaults& d) { return text(d.system.loop.relocalize_check_max_conflict_fraction_geometric); }},
    {"loop", "correction_gate_sigma", [](const Defaults& d) { return text(d.system.loop.correction.gate_sigma); }},
    {"loop", "correction_sigma_floor_m", [](const Defaults& d) { return text(d.system.loop.correction.sigma_floor_m); }},
    {"loop", "correction_yaw_sigma_deg_per_m", [](const Defaults& d) { return text(d.system.loop.correction.yaw_sigma_deg_per_m); }},
    {"loop", "feature_max_keypoints", [](const Defaults& d) { return text(d.system.loop.features.max_keypoints); }},
    {"loop", "feature_detect_candidates", [](const Defaults& d) { return text(d.system.loop.features.detect_candidates); }},
    {"loop", "feature_fast_threshold", [](const Defaults& d) { return text(d.system.loop.features.fast_threshold); }},
    {"loop", "feature_pyramid_levels", [](const Defaults& d) { return text(d.system.loop.features.pyramid_levels); }},
    {"loop", "feature_pyramid_scale", [](const Defaults& d) { return text(d.system.loop.features.pyramid_scale); }},
    {"loop", "feature_border_px", [](const Defaults& d) { return text(d.system.loop.features.border_px); }},
    {"loop", "feature_grid_cols", [](const Defaults& d) { return text(d.system.loop.features.grid_cols); }},
    {"loop", "feature_grid_rows", [](const Defaults& d) { return text(d.system.loop.features.grid_rows); }},
    {"loop", "feature_depth_min_m", [](const Defaults& d) { return text(d.system.loop.features.depth_min_m); }},
    {"loop", "feature_depth_max_m", [](const Defaults& d) { return text(d.system.loop.features.depth_max_m); }},
    {"loop", "feature_depth_window_px", [](const Defaults& d) { return text(d.system.loop.features.depth_window_px); }},
    {"loop", "feature_depth_max_relative_spread", [](const Defaults& d) { return text(d.system.loop.features.depth_max_relative_spread); }},
    {"loop", "feature_depth_noise_coeff", [](const Defaults& d) { return text(d.system.loop.features.depth_noise_coeff); }},
    {"loop", "feature_depth_max_noise_sigmas", [](const Defaults& d) { return text(d.system.loop.features.depth_max_noise_sigmas); }},
    {"loop", "feature_depth_grid_cols", [](const Defaults& d) { return text(d.system.loop.features.depth_grid_cols); }},
    {"loop", "feature_depth_grid_rows", [](const Defaults& d) { return text(d.system.loop.features.depth_grid_rows); }},
    {"loop", "place_index_tables", [](const Defaults& d) { return text(d.system.loop.place.index.tables); }},
    {"loop", "place_index_key_bits", [](const Defaults& d) { return text(d.system.loop.place.index.key_bits); }},
    {"loop", "place_index_max_key_keyframes", [](const Defaults& d) { return text(d.system.loop.place.index.max_key_keyframes); }},
    {"loop", "place_index_seed", [](const Defaults& d) { return text(d.system.loop.place.index.seed); }},
    {"loop", "place_top_k", [](const Defaults& d) { return text(d.system.loop.place.top_k); }},
    {"loop", "place_exclude_recent_s", [](const Defaults& d) { return text(d.system.loop.place.exclude_recent_s); }},
    {"loop", "place_exclude_recent_m", [](const Defaults& d) { return text(d.system.loop.place.exclude_recent_m); }},
    {"loop", "place_exclude_recent_count", [](const Defaults& d) { return text(d.system.loop.place.exclude_recent_count); }},
    {"loop", "place_min_normalised_score", [](const Defaults& d) { return text(d.system.loop.place.min_normalised_score); }},
    {"loop", "place_min_reference_ratio", [](const Defaults& d) { return text(d.system.loop.place.min_reference_ratio); }},
    {"loop", "place_consistency_keyframes", [](const Defaults& d) { return text(d.system.loop.place.consistency_keyframes); }},
    {"loop", "place_consistency_window_s", [](const Defaults& d) { return text(d.system.loop.place.consistency_window_s); }},
    {"loop", "place_proximity_radius_m", [](const Defaults& d) { return text(d.system.loop.place.proximity_radius_m); }},
    {"loop", "place_proximity_max_candidates", [](const Defaults& d) { return text(d.system.loop.place.proximity_max_candidates); }},
    {"loop", "verify_match_ratio", [](const Defaults& d) { return text(d.system.loop.verify.match_ratio); }},
    {"loop", "verify_max_hamming_bits", [](const Defaults& d) { return text(d.system.loop.verify.max_hamming_bits); }},
    {"loop", "verify_cross_check", [](const Defaults& d) { return text(d.system.loop.verify.cross_check); }},
    {"loop", "verify_min_matches", [](const Defaults& d) { return text(d.system.loop.verify.min_matches); }},
    {"loop", "verify_pnp_threshold_px", [](const Defaults& d) { return text(d.system.loop.verify.pnp_threshold_px); }},
    {"loop", "verify_pnp_iterations", [](const Defaults& d) { return text(d.system.loop.verify.pnp_iterations); }},
    {"loop", "verify_pnp_confidence", [](const Defaults& d) { return text(d.system.loop.verify.pnp_confidence); }},
    {"loop", "verify_min_pnp_inliers", [](const Defaults& d) { return text(d.system.loop.verify.min_pnp_inliers); }},
    {"loop", "verify_depth_tolerance_m", [](const Defaults& d) { return text(d.system.loop.verify.depth_tolerance_m); }},
    {"loop", "verify_depth_noise_coeff", [](const Defaults& d) { return text(d.system.loop.verify.depth_noise_coeff); }},
    {"loop", "verify_depth_tolerance_sigmas", [](const Defaults& d) { return text(d.system.loop.verify.depth_tolerance_sigmas); }},
    {"loop", "verify_min_depth_inliers", [](const Defaults& d) { return text(d.system.loop.verify.min_depth_inliers); }},
    {"loop", "verify_min_depth_inlier_fraction", [](const Defaults& d) { return text(d.system.loop.verify.min_depth_inlier_fraction); }},
    {"loop", "verify_refine_rounds", [](const Defaults& d) { return text(d.system.loop.verify.refine_rounds); }},
    {"loop", "verify_keypoint_sigma_px", [](const Defaults& d) { return text(d.system.loop.verify.keypoint_sigma_px); }},
    {"loop", "verify_max_gravity_deg", [](const Defaults& d) { return text(d.system.loop.verify.max_gravity_deg); }},
    {"loop", "verify_max_yaw_deg", [](const Defaults& d) { return text(d.system.loop.verify.max_yaw_deg); }},
    {"loop", "verify_max_translation_m", [](const Defaults& d) { return text(d.system.loop.verify.max_translation_m); }},
    {"loop", "verify_drift_base_m", [](const Defaults& d) { return text(d.system.loop.verify.drift_base_m); }},
    {"loop", "verify_drift_fraction", [](const Defaults& d) { return text(d.system.loop.verify.drift_fraction); }},
    {"loop", "verify_drift_base_deg", [](const Defaults& d) { return text(d.system.loop.verify.drift_base_deg); }},
    {"loop", "verify_drift_deg_per_m", [](const Defaults& d) { return text(d.system.loop.verify.drift_deg_per_m); }},
    {"loop", "verify_freespace_margin_m", [](const Defaults& d) { return text(d.system.loop.verify.freespace_margin_m); }},
    {"loop", "verify_freespace_margin_sigmas", [](const Defaults& d) { return text(d.system.loop.verify.freespace_margin_sigmas); }},
    {"loop", "verify_freespace_max_conflict_fraction", [](const Defaults& d) { return text(d.system.loop.verify.freespace_max_conflict_fraction); }},
    {"loop", "verify_freespace_min_samples", [](const Defaults& d) { return text(d.system.loop.verify.freespace_min_samples); }},
    {"loop", "verify_freespace_for_loops", [](const Defaults& d) { return text(d.system.loop.verify.freespace_for_loops); }},
    {"loop", "graph_sequential_edges", [](const Defaults& d) { return text(d.system.loop.graph.sequential_edges); }},
    {"loop", "graph_odom_pos_sigma_floor_m", [](const Defaults& d) { return text(d.system.loop.graph.odom_pos_sigma_floor_m); }},
    {"loop", "graph_odom_pos_sigma_per_sqrt_m", [](const Defaults& d) { return text(d.system.loop.graph.odom_pos_sigma_per_sqrt_m); }},
    {"loop", "graph_odom_yaw_sigma_floor_deg", [](const Defaults& d) { return text(d.system.loop.graph.odom_yaw_sigma_floor_deg); }},
    {"loop", "graph_odom_yaw_sigma_per_sqrt_m_deg", [](const Defaults& d) { return text(d.system.loop.graph.odom_yaw_sigma_per_sqrt_m_deg); }},
    {"loop", "graph_odom_yaw_sigma_per_sqrt_rad_deg", [](const Defaults& d) { return text(d.system.loop.graph.odom_yaw_sigma_per_sqrt_rad_deg); }},
    {"loop", "graph_odom_bridge_pos_sigma_m", [](const Defaults& d) { return text(d.system.loop.graph.odom_bridge_pos_sigma_m); }},
    {"loop", "graph_odom_bridge_yaw_sigma_deg", [](const Defaults& d) { return text(d.system.loop.graph.odom_bridge_yaw_sigma_deg); }},
    {"loop", "graph_loop_sigma_pos_m", [](const Defaults& d) { return text(d.system.loop.graph.loop_sigma_pos_m); }},
    {"loop", "graph_loop_sigma_yaw_deg", [](const Defaults& d) { return text(d.system.loop.graph.loop_sigma_yaw_deg); }},
    {"loop", "graph_loss", [](const Defaults& d) { return text(d.system.loop.graph.loss == loop::RobustLoss::kHuber ? "huber" : "cauchy"); }},
    {"loop", "graph_loss_scale_sigma", [](const Defaults& d) { return text(d.system.loop.graph.loss_scale_sigma); }},
    {"loop", "graph_max_iterations", [](const Defaults& d) { return text(d.system.loop.graph.max_iterations); }},
    {"loop", "graph_function_tolerance", [](const Defaults& d) { return text(d.system.loop.graph.function_tolerance); }},
    {"loop", "graph_gradient_tolerance", [](const Defaults& d) { return text(d.system.loop.graph.gradient_tolerance); }},
    {"loop", "graph_parameter_tolerance", [](const Defaults& d) { return text(d.system.loop.graph.parameter_tolerance); }},
    {"loop", "graph_rollback_gate_sigma", [](const Defaults& d) { return text(d.system.loop.graph.rollback_gate_sigma); }},
    {"loop", "graph_max_rollbacks", [](const Defaults& d) { return text(d.system.loop.graph.max_rollbacks_per_solve); }},
    {"navmap", "enable", [](const Defaults& d) { return text(d.system.navmap.enable); }},
    {"navmap", "cell_size_m", [](const Defaults& d) { return text(d.system.navmap.cell_size_m); }},
    {"navmap", "range_m", [](const Defaults& d) { return text(d.system.navmap.range_m); }},
    {"navmap", "min_points_per_cell", [](const Defaults& d) { return text(d.system.navmap.min_points_per_cell); }},
    {"navmap", "ground_band_m", [](const Defaults& d) { return text(d.system.navmap.ground_band_m); }},
    {"navmap", "min_obstacle_points", [](const Defaults& d) { return text(d.system.navmap.min_obstacle_points); }},
    {"navmap", "footprint_radius_m", [](const Defaults& d) { return text(d.system.navmap.footprint_radius_m); }},
    {"navmap", "max_slope_deg", [](const Defaults& d) { return text(d.system.navmap.max_slope_deg); }},
    {"navmap", "max_step_m", [](const Defaults& d) { return text(d.system.navmap.max_step_m); }},
    {"navmap", "clearance_height_m", [](const Defaults& d) { return text(d.system.navmap.clearance_height_m); }},
    {"navmap", "max_roughness_m", [](const Defaults& d) { return text(d.system.navmap.max_roughness_m); }},
    {"navmap", "path_ground_radius_m", [](const Defaults& d) { return text(d.system.navmap.path_ground_radius_m); }},
    {"navmap", "path_ground_min_fraction", [](const Defaults& d) { return text(d.system.navmap.path_ground_min_fraction); }},
    {"navmap", "max_depth_m", [](const Defaults& d) { return text(d.system.navmap.max_depth_m); }},
    {"navmap", "refresh_interval_s", [](const Defaults& d) { return text(d.system.navmap.refresh_interval_s); }},
    {"navmap", "drop_face_min_rise_m", [](const Defaults& d) { return text(d.system.navmap.drop_face_min_rise_m); }},
    {"navmap", "drop_face_min_depth_m", [](const Defaults& d) { return text(d.system.navmap.drop_face_min_depth_m); }},
    {"mapping", "grid_step_px", [](const Defaults& d) { return text(d.system.mapping.grid_step_px); }},
    {"mapping", "u_min_px", [](const Defaults& d) { return text(d.system.mapping.u_min_px); }},
    {"mapping", "u_max_px", [](const Defaults& d) { return text(d.system.mapping.u_max_px); }},
    {"mapping", "v_min_px", [](const Defaults& d) { return text(d.system.mapping.v_min_px); }},
    {"mapping", "v_max_px", [](const Defaults& d) { return text(d.system.mapping.v_max_px); }},
    {"mapping", "depth_min_m", [](const Defaults& d) { return text(d.system.mapping.depth_min_m); }},
    {"mapping", "depth_max_m", [](const Defaults& d) { return text(d.system.mapping.depth_max_m); }},
    {"mapping", "octree_resolution_m", [](const Defaults& d) { return text(d.system.mapping.octree_resolution_m); }},
    {"mapping", "max_points_per_leaf", [](const Defaults& d) { return text(d.system.mapping.max_points_per_leaf); }},
    {"mapping", "view_update_distance_m", [](const Defaults& d) { return text(d.system.mapping.view_update_distance_m); }},
    {"mapping", "view_update_angle_deg", [](const Defaults& d) { return text(d.system.mapping.view_update_angle_deg); }},
    {"mapping", "min_points_per_leaf_rebuild", [](const Defaults& d) { return text(d.system.mapping.min_points_per_leaf_rebuild); }},
    {"mapping", "correction_min_shift_m", [](const Defaults& d) { return text(d.system.mapping.correction_min_shift_m); }},
    {"mapping", "correction_min_rotation_deg", [](const Defaults& d) { return text(d.system.mapping.correction_min_rotation_deg); }},
    {"mapping", "occupancy_resolution_m", [](const Defaults& d) { return text(d.system.mapping.occupancy_resolution_m); }},
    {"mapping", "occupancy_grid_stride", [](const Defaults& d) { return text(d.system.mapping.occupancy_grid_stride); }},
    {"mapping", "occupancy_prob_hit", [](const Defaults& d) { return text(d.system.mapping.occupancy_prob_hit); }},
    {"mapping", "occupancy_prob_miss", [](const Defaults& d) { return text(d.system.mapping.occupancy_prob_miss); }},
    {"mapping", "plot_panel_px", [](const Defaults& d) { return text(d.system.mapping.plot.panel_px); }},
    {"mapping", "plot_max_time_diff_s", [](const Defaults& d) { return text(d.system.mapping.plot.max_time_diff_s); }},
    {"mapping", "scene_keyframe_axis_m", [](const Defaults& d) { return text(d.system.mapping.scene.keyframe_axis_m); }},
    {"pipeline", "queue_capacity_packets", [](const Defaults& d) { return text(d.system.pipeline.queue_capacity_packets); }},
    {"pipeline", "images_prepared_ahead", [](const Defaults& d) { return text(d.system.pipeline.images_prepared_ahead); }},
    {"output", "write_ply", [](const Defaults& d) { return text(d.system.output.write_ply); }},
    {"output", "write_octomap", [](const Defaults& d) { return text(d.system.output.write_octomap); }},
    {"output", "write_scene", [](const Defaults& d) { return text(d.system.output.write_scene); }},
    {"output", "write_plot", [](const Defaults& d) { return text(d.system.output.write_plot); }},
    {"output", "progress_interval_s", [](const Defaults& d) { return text(d.system.output.progress_interval_s); }},
    {"output", "graph_translation_sigma_m", [](const Defaults& d) { return text(d.system.output.graph_translation_sigma_m); }},
    {"output", "graph_rotation_sigma_rad", [](const Defaults& d) { return text(d.system.output.graph_rotation_sigma_rad); }},
    {"convert", "pair_tolerance_s", [](const Defaults& d) { return text(d.convert.pair_tolerance_s); }},
    {"convert", "max_wait_s", [](const Defaults& d) { return text(d.convert.max_wait_s); }},
    {"convert", "reorder_window_s", [](const Defaults& d) { return text(d.convert.reorder_window_s); }},
    {"convert", "max_accel_gap_s", [](const Defaults& d) { return text(d.convert.max_accel_gap_s); }},
    {"convert", "integer_depth_unit_m", [](const Defaults& d) { return text(d.convert.integer_depth_unit_m); }},
    {"convert", "float_depth_unit_m", [](const Defaults& d) { return text(d.convert.float_depth_unit_m); }},
    {"convert", "tum_depth_factor", [](const Defaults& d) { return text(d.convert.tum_depth_factor); }},
    {"convert", "require_colour", [](const Defaults& d) { return text(d.convert.require_colour); }},
    {"convert", "max_listed_issues", [](const Defaults& d) { return text(d.convert.max_listed_issues); }},
    {"convert", "progress_interval_s", [](const Defaults& d) { return text(d.convert.progress_interval_s); }},
    {"sim", "fps", [](const Defaults& d) { return text(d.sim.fps); }},
    {"sim", "imu_rate_hz", [](const Defaults& d) { return text(d.sim.imu.rate_hz); }},
    {"sim", "seed", [](const Defaults& d) { return text(d.sim.seed); }},
    {"sim", "gravity_m_s2", [](const Defaults& d) { return text(d.sim.imu.gravity_m_s2); }},
    {"sim", "acc_noise_density", [](const Defaults& d) { return text(d.sim.imu.acc_noise_density); }},
    {"sim", "gyr_noise_density", [](const Defaults& d) { return text(d.sim.imu.gyr_noise_density); }},
    {"sim", "acc_random_walk", [](const Defaults& d) { return text(d.sim.imu.acc_random_walk); }},
    {"sim", "gyr_random_walk", [](const Defaults& d) { return text(d.sim.imu.gyr_random_walk); }},
    {"sim", "acc_bias_max", [](const Defaults& d) { return text(d.sim.imu.acc_bias_max); }},
    {"sim", "gyr_bias_max", [](const Defaults& d) { return text(d.sim.imu.gyr_bias_max); }},
    {"sim", "imu_acc_scale_max", [](const Defaults& d) { return text(d.sim.imu.errors.acc_scale_max); }},
    {"sim", "imu_gyr_scale_max", [](const Defaults& d) { return text(d.sim.imu.errors.gyr_scale_max); }},
    {"sim", "imu_acc_misalignment_max_rad", [](const Defaults& d) { return text(d.sim.imu.errors.acc_misalignment_max_rad); }},
    {"sim", "imu_gyr_misalignment_max_rad", [](const Defaults& d) { return text(d.sim.imu.errors.gyr_misalignment_max_rad); }},
    {"sim", "imu_gyr_g_sensitivity_max", [](const Defaults& d) { return text(d.sim.imu.errors.gyr_g_sensitivity_max); }},
    {"sim", "imu_acc_bias_instability", [](const Defaults& d) { return text(d.sim.imu.errors.acc_bias_instability); }},
    {"sim", "imu_gyr_bias_instability", [](const Defaults& d) { return text(d.sim.imu.errors.gyr_bias_instability); }},
    {"sim", "imu_bias_instability_tau_s", [](const Defaults& d) { return text(d.sim.imu.errors.bias_instability_tau_s); }},
    {"sim", "imu_acc_lsb", [](const Defaults& d) { return text(d.sim.imu.errors.acc_lsb); }},
    {"sim", "imu_gyr_lsb", [](const Defaults& d) { return text(d.sim.imu.errors.gyr_lsb); }},
    {"sim", "imu_accel_rate_hz", [](const Defaults& d) { return text(d.sim.imu.accel_rate_hz); }},
    {"sim", "imu_gyro_rate_hz", [](const Defaults& d) { return text(d.sim.imu.gyro_rate_hz); }},
    {"sim", "config_noise_inflation", [](const Defaults& d) { return text(d.sim.config_noise_inflation); }},
    {"sim", "depth_sigma_coeff", [](const Defaults& d) { return text(d.sim.depth_noise.sigma_coeff); }},
    {"sim", "depth_min_m", [](const Defaults& d) { return text(d.sim.depth_noise.min_m); }},
    {"sim", "depth_max_m", [](const Defaults& d) { return text(d.sim.depth_noise.max_m); }},
    {"sim", "depth_hole_fraction", [](const Defaults& d) { return text(d.sim.depth_noise.hole_fraction); }},
    {"sim", "depth_flying_pixel_prob", [](const Defaults& d) { return text(d.sim.depth_artefacts.flying_pixel_prob); }},
    {"sim", "depth_edge_jump_m", [](const Defaults& d) { return text(d.sim.depth_artefacts.edge_jump_m); }},
    {"sim", "depth_dark_hole_prob", [](const Defaults& d) { return text(d.sim.depth_artefacts.dark_hole_prob); }},
    {"sim", "depth_dark_level", [](const Defaults& d) { return text(d.sim.depth_artefacts.dark_level); }},
    {"sim", "depth_grazing_hole_prob", [](const Defaults& d) { return text(d.sim.depth_artefacts.grazing_hole_prob); }},
    {"sim", "depth_grazing_angle_deg", [](const Defaults& d) { return text(d.sim.depth_artefacts.grazing_angle_deg); }},
    {"sim", "frame_stamp_jitter_s", [](const Defaults& d) { return text(d.sim.frame_stamp_jitter_s); }},
    {"sim", "rolling_shutter_readout_s", [](const Defaults& d) { return text(d.sim.rolling_shutter_readout_s); }},
    {"sim", "rolling_shutter_direction", [](const Defaults& d) { return text(d.sim.rolling_shutter_direction); }},
    {"sim", "rolling_shutter_reference_row", [](const Defaults& d) { return text(d.sim.rolling_shutter_reference_row); }},
    {"sim", "photometric_noise_sigma", [](const Defaults& d) { return text(d.sim.color_noise.sigma); }},
    {"sim", "time_offset_s", [](const Defaults& d) { return text(d.sim.time_offset_s); }},
    {"sim", "start_time_s", [](const Defaults& d) { return text(d.sim.start_time_s); }},
    {"sim", "world_seed", [](const Defaults& d) { return text(d.sim.scene.world_seed); }},
    {"sim", "room_margin_m", [](const Defaults& d) { return text(d.sim.scene.room_margin_m); }},
    {"sim", "furniture_density", [](const Defaults& d) { return text(d.sim.scene.furniture_density); }},
    {"sim", "furniture_lateral_max_m", [](const Defaults& d) { return text(d.sim.scene.furniture_lateral_max_m); }},
    {"sim", "texture_contrast", [](const Defaults& d) { return text(d.sim.scene.texture_contrast); }},
    {"sim", "exposure_gain_amplitude", [](const Defaults& d) { return text(d.sim.exposure.gain_amplitude); }},
    {"sim", "exposure_period_s", [](const Defaults& d) { return text(d.sim.exposure.period_s); }},
    {"sim", "aliased_walls", [](const Defaults& d) { return text(d.sim.scene.aliased_walls); }},
    {"sim", "twin_rooms", [](const Defaults& d) { return text(d.sim.scene.twin_rooms); }},
    {"sim", "nav_features", [](const Defaults& d) { return text(d.sim.scene.nav_features); }},
    {"sim", "blackout_start_s", [](const Defaults& d) { return text(d.sim.blackout_start_s); }},
    {"sim", "blackout_duration_s", [](const Defaults& d) { return text(d.sim.blackout_duration_s); }},
    {"sim", "blackout_kind", [](const Defaults& d) { return text(d.sim.blackout_kind); }},
    {"sim", "blackout_blur_px", [](const Defaults& d) { return text(d.sim.blackout_blur_px); }},
    {"sim", "spin_start_s", [](const Defaults& d) { return text(d.sim.spin_start_s); }},
    {"sim", "spin_duration_s", [](const Defaults& d) { return text(d.sim.spin_duration_s); }},
    {"sim", "spin_turns", [](const Defaults& d) { return text(d.sim.spin_turns); }},
    {"sim", "recorded_room_margin_m", [](const Defaults& d) { return text(d.sim.recorded_world.room_margin_m); }},
    {"sim", "recorded_floor_below_m", [](const Defaults& d) { return text(d.sim.recorded_world.floor_below_m); }},
    {"sim", "recorded_ceiling_above_m", [](const Defaults& d) { return text(d.sim.recorded_world.ceiling_above_m); }},
    {"sim", "recorded_path_clearance_m", [](const Defaults& d) { return text(d.sim.recorded_world.path_clearance_m); }},
    {"sim", "recorded_max_gap_s", [](const Defaults& d) { return text(d.sim.recorded_world.max_gap_s); }},
    {"sim", "duration_s", [](const Defaults& d) { return text(d.sim.profile.duration_s); }},
    {"sim", "speed", [](const Defaults& d) { return text(sim::toString(d.sim.profile.speed)); }},
    {"sim", "speed_m_s", [](const Defaults& d) { return text(d.sim.profile.speed_m_s); }},
    {"sim", "rest_start_s", [](const Defaults& d) { return text(d.sim.profile.rest_start_s); }},
    {"sim", "rest_end_s", [](const Defaults& d) { return text(d.sim.profile.rest_end_s); }},
    {"sim", "wheeled_vibration_acc_rms", [](const Defaults& d) { return text(d.sim.profile.wheeled_vibration_acc_rms); }},
    {"sim", "wheeled_vibration_gyr_rms", [](const Defaults& d) { return text(d.sim.profile.wheeled_vibration_gyr_rms); }},
    {"sim", "tracked_vibration_acc_rms", [](const Defaults& d) { return text(d.sim.profile.tracked_vibration_acc_rms); }},
    {"sim", "tracked_vibration_gyr_rms", [](const Defaults& d) { return text(d.sim.profile.tracked_vibration_gyr_rms); }},
    {"sim", "tracked_jitter_deg", [](const Defaults& d) { return text(d.sim.profile.tracked_jitter_deg); }},
    {"sim", "vibration_band_min_hz", [](const Defaults& d) { return text(d.sim.profile.vibration_band_min_hz); }},
    {"sim", "vibration_band_max_hz", [](const Defaults& d) { return text(d.sim.profile.vibration_band_max_hz); }},
    {"sim", "wheeled_camera_height_m", [](const Defaults& d) { return text(d.sim.profile.wheeled_camera_height_m); }},
    {"sim", "tracked_camera_height_m", [](const Defaults& d) { return text(d.sim.profile.tracked_camera_height_m); }},
    {"sim", "handheld_camera_height_m", [](const Defaults& d) { return text(d.sim.profile.handheld_camera_height_m); }},
    {"sim", "variant", [](const Defaults& d) { return text(d.sim.profile.variant); }},
    {"sim", "wheel_encoders", [](const Defaults& d) { return text(d.sim.wheel.mode); }},
    {"sim", "wheel_rate_hz", [](const Defaults& d) { return text(d.sim.wheel.rate_hz); }},
    {"sim", "wheel_radius_m", [](const Defaults& d) { return text(d.sim.wheel.radius_m); }},
    {"sim", "wheel_track_m", [](const Defaults& d) { return text(d.sim.wheel.track_m); }},
    {"sim", "wheel_radius_error_left", [](const Defaults& d) { return text(d.sim.wheel.radius_error_left); }},
    {"sim", "wheel_radius_error_right", [](const Defaults& d) { return text(d.sim.wheel.radius_error_right); }},
    {"sim", "wheel_track_error", [](const Defaults& d) { return text(d.sim.wheel.track_error); }},
    {"sim", "wheel_ticks_per_rev", [](const Defaults& d) { return text(d.sim.wheel.ticks_per_rev); }},
    {"sim", "wheel_time_offset_s", [](const Defaults& d) { return text(d.sim.wheel.time_offset_s); }},
    {"sim", "wheel_skid_turn_slip", [](const Defaults& d) { return text(d.sim.wheel.skid_turn_slip); }},
    {"sim", "wheel_skid_slope_gain", [](const Defaults& d) { return text(d.sim.wheel.skid_slope_gain); }},
    {"sim", "wheel_event_speed_m_s", [](const Defaults& d) { return text(d.sim.wheel.event_speed_m_s); }},
    {"sim", "wheel_events", [](const Defaults& d) { return text(sim::WheelEncoderOptions::eventsText(d.sim.wheel.events)); }},
};

const std::string kDoc = "doc/configuration.md";

Table docTable() { return readDocTables(test::sourceDir() + "/" + kDoc); }
Table shippedTable(std::vector<std::string>* sections) {
  return readIni(test::sourceDir() + "/share/config.ini", sections);
}

std::string name(const SectionKey& k) { return "[" + k.first + "] " + k.second; }

/// INI text of the documented defaults of the given sections (all when `only` is empty).
std::string docIni(const Table& doc, const std::set<std::string>& only,
                   const std::set<std::string>& except) {
  std::map<std::string, std::string> by_section;
  for (const auto& [k, e] : doc) {
    if ((!only.empty() && !only.count(k.first)) || except.count(k.first)) continue;
    by_section[k.first] += k.second + " = " + e.value + "\n";
  }
  std::string out;
  for (const auto& [s, body] : by_section) out += "[" + s + "]\n" + body;
  return out;
}

}  // namespace

TEST(ConfigurationDoc, DocumentsEveryShippedKeyAndNoOther) {
  std::vector<std::string> sections;
  const Table shipped = shippedTable(&sections);
  const Table doc = docTable();
  ASSERT_GT(shipped.size(), 100u);
  for (const auto& [k, e] : shipped)
    EXPECT_EQ(doc.count(k), 1u) << "share/config.ini line " << e.line << ": " << name(k)
                                << " has no row in " << kDoc;
  for (const auto& [k, e] : doc)
    EXPECT_EQ(shipped.count(k), 1u)
        << kDoc << " line " << e.line << ": " << name(k) << " is not a key of share/config.ini";
  EXPECT_EQ(sections, kConfigSections);
}

TEST(ConfigurationDoc, DocumentedDefaultsEqualTheShippedFile) {
  std::vector<std::string> sections;
  const Table shipped = shippedTable(&sections);
  for (const auto& [k, e] : docTable()) {
    const auto it = shipped.find(k);
    if (it == shipped.end()) continue;  // reported by DocumentsEveryShippedKeyAndNoOther
    EXPECT_TRUE(sameValue(e.value, it->second.value, 0.0))
        << kDoc << " line " << e.line << ": " << name(k) << " documented as '" << e.value
        << "', share/config.ini line " << it->second.line << " has '" << it->second.value << "'";
  }
}

TEST(ConfigurationDoc, DocumentedDefaultsEqualTheOptionStructs) {
  const Defaults d = loadDefaults();
  const Table doc = docTable();
  std::set<SectionKey> with_field;
  for (const Field& f : kFields) {
    const SectionKey k{f.section, f.key};
    EXPECT_TRUE(with_field.insert(k).second) << name(k) << " twice in kFields";
    const auto it = doc.find(k);
    if (it == doc.end()) {
      ADD_FAILURE() << name(k) << " is read by the option structs but has no row in " << kDoc;
      continue;
    }
    // R_body_cam is re-orthonormalised on loading: its entries, given to 7 decimals, agree to
    // 1e-7. Every other default is exact up to the printing of doubles.
    const double abs_tol = k.second == "R_body_cam" ? 1e-7 : 0.0;
    const std::string actual = f.value(d);
    EXPECT_TRUE(sameValue(it->second.value, actual, 1e-15, abs_tol))
        << kDoc << " line " << it->second.line << ": " << name(k) << " documented as '"
        << it->second.value << "', the option struct's default is '" << actual << "'";
  }
  for (const auto& [k, e] : doc)
    EXPECT_TRUE(with_field.count(k)) << kDoc << " line " << e.line << ": " << name(k)
                                     << " has no entry in kFields of this test (add the option "
                                     << "struct field that holds it)";
}

TEST(ConfigurationDoc, EveryDocumentedKeyIsReadByTheTools) {
  // The documented defaults as a configuration, loaded as each tool loads its sections: any
  // documented key no option struct asks for is an unknown-key error naming it.
  const Table doc = docTable();
  try {
    IniReader slam = IniReader::fromText(docIni(doc, {}, {"sim", "convert"}), kDoc);
    system::SystemConfig::load(slam);  // checks for unknown keys itself
    IniReader sim = IniReader::fromText(docIni(doc, {"sim", "camera", "extrinsic"}, {}), kDoc);
    sim::SimOptions::load(sim);
    sim.checkNoUnknownKeys();
    IniReader convert = IniReader::fromText(docIni(doc, {"convert"}, {}), kDoc);
    bag::ConvertOptions::load(convert);
    convert.checkNoUnknownKeys();
  } catch (const ConfigError& e) {
    FAIL() << e.what();
  }
}

TEST(ConfigurationDoc, ValueComparisonTellsValuesApart) {
  EXPECT_TRUE(sameValue("0.10", "0.1", 0.0));
  EXPECT_TRUE(sameValue("1.4142e-5", "1.4142e-05", 0.0));
  EXPECT_TRUE(sameValue("0 0  0", "0 0 0", 0.0));
  EXPECT_FALSE(sameValue("0.1", "0.11", 0.0));
  EXPECT_FALSE(sameValue("0 0", "0 0 0", 0.0));
  EXPECT_FALSE(sameValue("huber", "cauchy", 0.0));
  EXPECT_TRUE(sameValue("0.0008371", "0.00083710984", 0.0, 1e-7));
  EXPECT_FALSE(sameValue("0.0008371", "0.0008373", 0.0, 1e-7));
  EXPECT_EQ(cells("| `a` | `b` | one of x\\|y | c |"),
            (std::vector<std::string>{"`a`", "`b`", "one of x|y", "c"}));
}
