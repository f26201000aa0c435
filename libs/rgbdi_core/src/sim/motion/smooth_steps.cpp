#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "rgbdi/sim/motion_smooth_steps.h"

namespace rgbdi::sim {

void SmoothSteps::addStep(double start, double width, double delta) {
  if (!(width > 0.0) || !std::isfinite(width) || !std::isfinite(start) || !std::isfinite(delta))
    throw std::invalid_argument("SmoothSteps::addStep: width must be positive and finite (got " +
                                std::to_string(width) + ")");
  const double u0 = -start / width;
  const Taylor<0> u(u0);
  const double at_zero = u0 >= 1.0 ? u0 - 0.5 : piece(kStepIntegral, u, 0.0).value();
  steps_.push_back(Step{start, width, delta, at_zero});
}

std::vector<double> SmoothSteps::breakpoints() const {
  std::vector<double> b;
  for (const Step& s : steps_) {
    b.push_back(s.start);
    b.push_back(s.start + s.width);
  }
  std::sort(b.begin(), b.end());
  return b;
}

}  // namespace rgbdi::sim
