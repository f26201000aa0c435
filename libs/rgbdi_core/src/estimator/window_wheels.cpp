#include "estimator/window_wheels.h"

namespace rgbdi::estimator {

void WindowWheels::add(const WheelOdometrySample& w) {
  if (!isFinite(w) || (!readings.empty() && w.t <= readings.back().t)) return;
  readings.push_back(w);
}

std::optional<WheelPreintegration> WindowWheels::interval(double t_a, double t_b,
                                                          const WheelOptions& opt) const {
  return WheelPreintegration::between(readings, t_a, t_b, opt.time_offset_s, opt.noise);
}

void WindowWheels::trimBefore(double t, const WheelOptions& opt) {
  // Keep the newest reading at or before t: the interval from t interpolates from it.
  while (readings.size() >= 2 && readings[1].t + opt.time_offset_s <= t) readings.pop_front();
}

void WindowWheels::priorDropped() {
  if (scale_prior_pending) return;  // its prior is still the problem's, around its mean
  scale_prior_pending = true;
  prior_mean_v = scale_v[0];
  prior_mean_w = scale_w[0];
}

}  // namespace rgbdi::estimator
