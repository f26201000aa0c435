#include "rgbdi/estimator/rolling_shutter_compensation.h"

namespace rgbdi::estimator {

void moveToReferenceTime(std::vector<frontend::FeatureObservation>& features,
                         const RollingShutter& rs) {
  if (rs.global()) return;
  for (frontend::FeatureObservation& f : features) f.xn -= rs.rowTime(f.uv.y()) * f.velocity_xn;
}

}  // namespace rgbdi::estimator
