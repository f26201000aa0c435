#include "sim/sequence/optional_settings.h"

#include <string>

#include "rgbdi/common/ini_text.h"

namespace rgbdi::sim {
namespace {

/// One "key = value ; comment" line when value differs from def.
void numberLine(std::ostream& os, const char* key, double value, double def, const char* comment) {
  if (value != def) iniLine(os, key, iniNumber(value), comment);
}

}  // namespace

void writeOptionalSimSettings(std::ostream& os, const SimOptions& o) {
  const SimOptions d;
  const ProfileSceneOptions& w = o.scene;
  if (w.world_seed != d.scene.world_seed)
    iniLine(os, "world_seed", std::to_string(w.world_seed), "[integer] furniture layout seed");
  numberLine(os, "room_margin_m", w.room_margin_m, d.scene.room_margin_m,
             "[m] extra room around the path");
  numberLine(os, "furniture_density", w.furniture_density, d.scene.furniture_density,
             "[probability] of each furniture slot");
  numberLine(os, "furniture_lateral_max_m", w.furniture_lateral_max_m,
             d.scene.furniture_lateral_max_m, "[m] largest extra lateral furniture distance");
  numberLine(os, "texture_contrast", w.texture_contrast, d.scene.texture_contrast,
             "(0, 1] texture contrast");
  numberLine(os, "exposure_gain_amplitude", o.exposure.gain_amplitude, d.exposure.gain_amplitude,
             "[unitless] colour gain 1 +- this");
  numberLine(os, "exposure_period_s", o.exposure.period_s, d.exposure.period_s,
             "[s] of the gain drift");

  const ImuErrorOptions& e = o.imu.errors;
  const ImuErrorOptions& de = d.imu.errors;
  numberLine(os, "imu_acc_scale_max", e.acc_scale_max, de.acc_scale_max, "[unitless]");
  numberLine(os, "imu_gyr_scale_max", e.gyr_scale_max, de.gyr_scale_max, "[unitless]");
  numberLine(os, "imu_acc_misalignment_max_rad", e.acc_misalignment_max_rad,
             de.acc_misalignment_max_rad, "[rad]");
  numberLine(os, "imu_gyr_misalignment_max_rad", e.gyr_misalignment_max_rad,
             de.gyr_misalignment_max_rad, "[rad]");
  numberLine(os, "imu_gyr_g_sensitivity_max", e.gyr_g_sensitivity_max, de.gyr_g_sensitivity_max,
             "[rad/s per m/s^2]");
  numberLine(os, "imu_acc_bias_instability", e.acc_bias_instability, de.acc_bias_instability,
             "[m/s^2]");
  numberLine(os, "imu_gyr_bias_instability", e.gyr_bias_instability, de.gyr_bias_instability,
             "[rad/s]");
  numberLine(os, "imu_bias_instability_tau_s", e.bias_instability_tau_s, de.bias_instability_tau_s,
             "[s]");
  numberLine(os, "imu_acc_lsb", e.acc_lsb, de.acc_lsb, "[m/s^2]");
  numberLine(os, "imu_gyr_lsb", e.gyr_lsb, de.gyr_lsb, "[rad/s]");
  numberLine(os, "imu_accel_rate_hz", o.imu.accel_rate_hz, d.imu.accel_rate_hz, "[Hz]");
  numberLine(os, "imu_gyro_rate_hz", o.imu.gyro_rate_hz, d.imu.gyro_rate_hz, "[Hz]");

  const DepthArtefactOptions& a = o.depth_artefacts;
  const DepthArtefactOptions& da = d.depth_artefacts;
  numberLine(os, "depth_flying_pixel_prob", a.flying_pixel_prob, da.flying_pixel_prob,
             "[probability]");
  numberLine(os, "depth_edge_jump_m", a.edge_jump_m, da.edge_jump_m, "[m]");
  numberLine(os, "depth_dark_hole_prob", a.dark_hole_prob, da.dark_hole_prob, "[probability]");
  numberLine(os, "depth_dark_level", a.dark_level, da.dark_level, "[grey levels]");
  numberLine(os, "depth_grazing_hole_prob", a.grazing_hole_prob, da.grazing_hole_prob,
             "[probability]");
  numberLine(os, "depth_grazing_angle_deg", a.grazing_angle_deg, da.grazing_angle_deg, "[deg]");
  numberLine(os, "frame_stamp_jitter_s", o.frame_stamp_jitter_s, d.frame_stamp_jitter_s, "[s]");
  numberLine(os, "rolling_shutter_readout_s", o.rolling_shutter_readout_s,
             d.rolling_shutter_readout_s, "[s] colour rows read in this time (0 = global)");
  if (o.rolling_shutter_direction != d.rolling_shutter_direction)
    iniLine(os, "rolling_shutter_direction", o.rolling_shutter_direction,
            "top_to_bottom|bottom_to_top");
  if (o.rolling_shutter_reference_row != d.rolling_shutter_reference_row)
    iniLine(os, "rolling_shutter_reference_row", o.rolling_shutter_reference_row,
            "middle|first: the row the stamp and the ground truth refer to");
}

}  // namespace rgbdi::sim
