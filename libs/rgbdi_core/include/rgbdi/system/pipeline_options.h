// Options of section [pipeline] of share/config.ini: how the SLAM system's stages are joined
// when they run on their own threads (odometry, loop closing, mapping; doc/loop.md "Where it
// runs"). Results do not depend on them offline; they trade memory against how far the feeding
// thread may run ahead of the stages.
#pragma once

#include <cstddef>

#include "rgbdi/common/ini_reader.h"

namespace rgbdi::system {

struct PipelineOptions {
  /// [packets] bound of each stage queue (IMU samples and images to the odometry, keyframes to
  /// loop closing and mapping); a full queue makes the feeding stage wait (offline) or a live
  /// source drop images.
  int queue_capacity_packets = 64;
  /// [images] threaded runs prepare each image for tracking (its grey image, CLAHE when on:
  /// frontend::ImagePreparer) on the feeding thread, off the odometry thread; at most this many
  /// prepared images (0.3 MB each at 640x480, twice that with CLAHE) wait untracked. 0: the
  /// odometry thread prepares them itself. Same results either way.
  int images_prepared_ahead = 4;

  static PipelineOptions load(IniReader& ini);
};

}  // namespace rgbdi::system
