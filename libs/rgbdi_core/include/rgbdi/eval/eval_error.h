// The one exception type of the evaluation stage: bad trajectory files or trajectories that cannot
// be evaluated (no overlap, too few pairs). Messages name the file and line when there is one.
#pragma once

#include <stdexcept>

namespace rgbdi::eval {

class EvalError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace rgbdi::eval
