// Rolling-shutter compensation of feature observations (first-order motion model).
//
// A rolling-shutter colour image exposes row y at t_ref + RollingShutter::rowTime(y). The
// estimator models every image at its reference time t_ref (the stamp), so an observation made at
// its row's time is moved to t_ref along its image velocity, as VINS-Mono does:
//   xn_ref = xn_row - rowTime(y) * velocity_xn
// (velocity in normalised-plane units per second). This is the same first-order shift the online
// camera-IMU time offset applies (ReprojectionFactor), with the row's share of the readout as the
// time. A feature without a velocity (newly detected) stays where it was seen.
#pragma once

#include <vector>

#include "rgbdi/common/rolling_shutter.h"
#include "rgbdi/frontend/feature_frame.h"

namespace rgbdi::estimator {

/// Moves each feature's xn from its row's exposure time to the image's reference time along its
/// tracked velocity. A global shutter (readout 0) leaves every feature untouched.
void moveToReferenceTime(std::vector<frontend::FeatureObservation>& features,
                         const RollingShutter& rs);

}  // namespace rgbdi::estimator
