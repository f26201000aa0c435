#include "rgbdi/system/pipeline_options.h"

namespace rgbdi::system {

PipelineOptions PipelineOptions::load(IniReader& ini) {
  const std::string s = "pipeline";
  PipelineOptions o;
  o.queue_capacity_packets =
      ini.getInt(s, "queue_capacity_packets", o.queue_capacity_packets, 1, 1 << 20);
  o.images_prepared_ahead =
      ini.getInt(s, "images_prepared_ahead", o.images_prepared_ahead, 0, 1024);
  return o;
}

}  // namespace rgbdi::system
