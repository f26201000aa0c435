#include "rgbdi/output/output_options.h"

namespace rgbdi::output {

OutputOptions OutputOptions::load(IniReader& ini) {
  const std::string s = "output";
  OutputOptions o;
  o.write_ply = ini.getBool(s, "write_ply", o.write_ply);
  o.write_octomap = ini.getBool(s, "write_octomap", o.write_octomap);
  o.write_scene = ini.getBool(s, "write_scene", o.write_scene);
  o.write_plot = ini.getBool(s, "write_plot", o.write_plot);
  o.progress_interval_s =
      ini.getDouble(s, "progress_interval_s", o.progress_interval_s, 0.01, 3600.0);
  o.graph_translation_sigma_m =
      ini.getDouble(s, "graph_translation_sigma_m", o.graph_translation_sigma_m, 1e-6, 10.0);
  o.graph_rotation_sigma_rad =
      ini.getDouble(s, "graph_rotation_sigma_rad", o.graph_rotation_sigma_rad, 1e-7, 1.0);
  return o;
}

}  // namespace rgbdi::output
