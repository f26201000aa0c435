#include "rgbdi/system/system_config.h"

namespace rgbdi::system {

SystemConfig SystemConfig::load(const std::string& path) {
  IniReader ini = path.empty() ? IniReader::empty() : IniReader::fromFile(path);
  return load(ini);
}

SystemConfig SystemConfig::load(IniReader& ini) {
  SystemConfig c;
  c.source = ini.label();
  c.camera = CameraOptions::load(ini);
  c.imu = ImuOptions::load(ini);
  c.extrinsic = ExtrinsicOptions::load(ini);
  c.stream = io::StreamOptions::load(ini);
  c.frontend = frontend::FrontendOptions::load(ini);
  c.estimator = estimator::EstimatorOptions::load(ini);
  c.output = output::OutputOptions::load(ini);
  c.mapping = mapping::MappingOptions::load(ini);
  c.navmap = navmap::NavMapOptions::load(ini);
  c.loop = loop::LoopOptions::load(ini);
  c.reloc = reloc::RelocOptions::load(ini);
  c.pipeline = PipelineOptions::load(ini);
  // Sections read by other tools.
  ini.acceptSection("sim");
  ini.acceptSection("convert");  // rawlog-convert
  ini.checkNoUnknownKeys();
  return c;
}

}  // namespace rgbdi::system
