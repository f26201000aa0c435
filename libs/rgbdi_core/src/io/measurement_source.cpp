#include "rgbdi/io/measurement_source.h"

namespace rgbdi::io {

void MeasurementSource::pump(MeasurementSink& sink, const std::atomic<bool>* stop) {
  Measurement m;
  bool stopped = false;
  try {
    for (;;) {
      if (!stopped && stop && stop->load()) {
        stopReading();
        stopped = true;
      }
      if (!next(m)) break;
      if (auto* imu = std::get_if<ImuSample>(&m)) {
        sink.feedImu(*imu);
      } else if (auto* wheel = std::get_if<WheelOdometrySample>(&m)) {
        sink.feedWheel(*wheel);
      } else {
        sink.feedRgbd(std::get<RgbdFrame>(m));
      }
    }
  } catch (...) {
    sink.endOfStream();
    throw;
  }
  sink.endOfStream();
}

}  // namespace rgbdi::io
