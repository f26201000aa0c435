// The whole configuration of an rgbdi-slam run: every module's typed options, loaded from one INI
// file (share/config.ini format) and validated as a whole (unknown keys are errors).
#pragma once

#include <string>

#include "rgbdi/common/sensor_options.h"
#include "rgbdi/estimator/estimator_options.h"
#include "rgbdi/frontend/frontend_options.h"
#include "rgbdi/io/stream_options.h"
#include "rgbdi/loop/loop_options.h"
#include "rgbdi/mapping/mapping_options.h"
#include "rgbdi/navmap/navmap_options.h"
#include "rgbdi/output/output_options.h"
#include "rgbdi/reloc/reloc_options.h"
#include "rgbdi/system/pipeline_options.h"

namespace rgbdi::system {

struct SystemConfig {
  std::string source;  ///< file the values came from ("<defaults>" when none)
  CameraOptions camera;
  ImuOptions imu;
  ExtrinsicOptions extrinsic;
  io::StreamOptions stream;
  frontend::FrontendOptions frontend;
  estimator::EstimatorOptions estimator;
  output::OutputOptions output;
  mapping::MappingOptions mapping;
  navmap::NavMapOptions navmap;
  loop::LoopOptions loop;
  reloc::RelocOptions reloc;  ///< [relocalise]
  PipelineOptions pipeline;

  /// Loads and validates `path` (empty = built-in defaults). Throws ConfigError naming file,
  /// section, key and accepted range.
  static SystemConfig load(const std::string& path);
  static SystemConfig load(IniReader& ini);

  io::StreamConfig streamConfig() const { return {stream, imu, extrinsic}; }
};

}  // namespace rgbdi::system
