#include "rgbdi/estimator/estimator_options.h"

namespace rgbdi::estimator {

EstimatorOptions EstimatorOptions::load(IniReader& ini) {
  EstimatorOptions o;
  const std::string s = "estimator";
  o.window_size = ini.getInt(s, "window_size", o.window_size, 4, 50);
  o.keyframe_parallax_px =
      ini.getDouble(s, "keyframe_parallax_px", o.keyframe_parallax_px, 0.5, 200);
  o.keyframe_min_tracked = ini.getInt(s, "keyframe_min_tracked", o.keyframe_min_tracked, 0, 10000);
  o.keyframe_parallax_without_rotation =
      ini.getBool(s, "keyframe_parallax_without_rotation", o.keyframe_parallax_without_rotation);
  o.max_iterations = ini.getInt(s, "max_iterations", o.max_iterations, 1, 1000);
  o.max_solver_time_s = ini.getDouble(s, "max_solver_time_s", o.max_solver_time_s, 0.0, 10.0);
  o.solver_function_tolerance =
      ini.getDouble(s, "solver_function_tolerance", o.solver_function_tolerance, 1e-12, 0.1);
  o.solver_function_tolerance_no_depth = ini.getDouble(
      s, "solver_function_tolerance_no_depth", o.solver_function_tolerance_no_depth, 1e-12, 0.1);
  o.non_keyframe_update =
      ini.getEnum(s, "non_keyframe_update", o.non_keyframe_update, {"full", "single_step"});
  o.reprojection_sigma_px =
      ini.getDouble(s, "reprojection_sigma_px", o.reprojection_sigma_px, 0.05, 50);
  o.cauchy_loss_sigma = ini.getDouble(s, "cauchy_loss_sigma", o.cauchy_loss_sigma, 0.01, 100);
  o.depth_verify_tolerance_px =
      ini.getDouble(s, "depth_verify_tolerance_px", o.depth_verify_tolerance_px, 0.1, 200);
  o.depth_verify_min_m = ini.getDouble(s, "depth_verify_min_m", o.depth_verify_min_m, 0.0, 100);
  o.depth_verify_max_m = ini.getDouble(s, "depth_verify_max_m", o.depth_verify_max_m, 0.05, 100);
  if (o.depth_verify_max_m <= o.depth_verify_min_m)
    ini.fail(s, "depth_verify_max_m", "must be larger than depth_verify_min_m");
  o.verified_depth = ini.getEnum(s, "verified_depth", o.verified_depth, {"constant", "prior"});
  o.depth_noise_coeff = ini.getDouble(s, "depth_noise_coeff", o.depth_noise_coeff, 1e-5, 1.0);
  o.init_depth_max_m = ini.getDouble(s, "init_depth_max_m", o.init_depth_max_m, 0.2, 100);
  o.init_min_correspondences =
      ini.getInt(s, "init_min_correspondences", o.init_min_correspondences, 6, 10000);
  o.init_min_parallax_px = ini.getDouble(s, "init_min_parallax_px", o.init_min_parallax_px, 0, 500);
  o.init_static_max_gyro_rad_s =
      ini.getDouble(s, "init_static_max_gyro_rad_s", o.init_static_max_gyro_rad_s, 0.0, 1.0);
  o.init_static_max_acc_std_m_s2 =
      ini.getDouble(s, "init_static_max_acc_std_m_s2", o.init_static_max_acc_std_m_s2, 0.0, 5.0);
  o.init_static_window_s =
      ini.getDouble(s, "init_static_window_s", o.init_static_window_s, 0.05, 5.0);
  o.init_static_max_acc_dev_m_s2 =
      ini.getDouble(s, "init_static_max_acc_dev_m_s2", o.init_static_max_acc_dev_m_s2, 0.0, 5.0);
  o.init_static_max_motion_px =
      ini.getDouble(s, "init_static_max_motion_px", o.init_static_max_motion_px, 0.0, 50.0);
  o.init_min_frames = ini.getInt(s, "init_min_frames", o.init_min_frames, 3, 100);
  o.init_min_span_s = ini.getDouble(s, "init_min_span_s", o.init_min_span_s, 0.0, 10.0);
  o.init_acc_bias_sigma_m_s2 =
      ini.getDouble(s, "init_acc_bias_sigma_m_s2", o.init_acc_bias_sigma_m_s2, 1e-4, 10.0);
  o.init_gyr_bias_sigma_rad_s =
      ini.getDouble(s, "init_gyr_bias_sigma_rad_s", o.init_gyr_bias_sigma_rad_s, 1e-5, 1.0);
  o.init_static_velocity_sigma_m_s = ini.getDouble(s, "init_static_velocity_sigma_m_s",
                                                   o.init_static_velocity_sigma_m_s, 1e-4, 10.0);
  o.outlier_reprojection_px =
      ini.getDouble(s, "outlier_reprojection_px", o.outlier_reprojection_px, 0.1, 1000);
  o.repropagate_acc_bias_m_s2 =
      ini.getDouble(s, "repropagate_acc_bias_m_s2", o.repropagate_acc_bias_m_s2, 1e-4, 10.0);
  o.repropagate_gyr_bias_rad_s =
      ini.getDouble(s, "repropagate_gyr_bias_rad_s", o.repropagate_gyr_bias_rad_s, 1e-5, 1.0);
  if (o.window_size < o.init_min_frames)
    ini.fail(s, "init_min_frames", "must not exceed window_size");
  o.estimate_time_offset = ini.getBool(s, "estimate_time_offset", o.estimate_time_offset);
  o.time_offset_velocity =
      ini.getEnum(s, "time_offset_velocity", o.time_offset_velocity, {"motion_field", "tracked"});
  o.time_offset_prior_sigma_s =
      ini.getDouble(s, "time_offset_prior_sigma_s", o.time_offset_prior_sigma_s, 1e-5, 1.0);
  o.estimate_rolling_shutter_readout =
      ini.getBool(s, "estimate_rolling_shutter_readout", o.estimate_rolling_shutter_readout);
  o.rolling_shutter_readout_prior_sigma_s =
      ini.getDouble(s, "rolling_shutter_readout_prior_sigma_s",
                    o.rolling_shutter_readout_prior_sigma_s, 1e-5, 1.0);
  o.rolling_shutter_readout_max_s =
      ini.getDouble(s, "rolling_shutter_readout_max_s", o.rolling_shutter_readout_max_s, 1e-3, 1.0);
  o.update_rate_hz = ini.getDouble(s, "update_rate_hz", o.update_rate_hz, 0.0, 1000.0);
  o.fail_max_acc_bias_m_s2 =
      ini.getDouble(s, "fail_max_acc_bias_m_s2", o.fail_max_acc_bias_m_s2, 0.01, 100);
  o.fail_max_gyr_bias_rad_s =
      ini.getDouble(s, "fail_max_gyr_bias_rad_s", o.fail_max_gyr_bias_rad_s, 0.001, 100);
  o.init_allow_static = ini.getBool(s, "init_allow_static", o.init_allow_static);
  o.init_max_scale_rel_sigma =
      ini.getDouble(s, "init_max_scale_rel_sigma", o.init_max_scale_rel_sigma, 1e-4, 1.0);
  o.init_max_alignment_rms =
      ini.getDouble(s, "init_max_alignment_rms", o.init_max_alignment_rms, 1e-6, 10.0);
  o.init_alignment_interval_s =
      ini.getDouble(s, "init_alignment_interval_s", o.init_alignment_interval_s, 1e-3, 10.0);
  o.fail_max_speed_m_s = ini.getDouble(s, "fail_max_speed_m_s", o.fail_max_speed_m_s, 0.1, 1000);
  o.fail_max_jump_m = ini.getDouble(s, "fail_max_jump_m", o.fail_max_jump_m, 0.01, 1000);
  o.fail_max_vertical_jump_m =
      ini.getDouble(s, "fail_max_vertical_jump_m", o.fail_max_vertical_jump_m, 0.01, 1000);
  o.fail_min_features = ini.getInt(s, "fail_min_features", o.fail_min_features, 0, 100000);
  o.fail_max_blind_s = ini.getDouble(s, "fail_max_blind_s", o.fail_max_blind_s, 0.0, 3600.0);
  o.wheel = WheelOptions::load(ini);
  return o;
}

}  // namespace rgbdi::estimator
