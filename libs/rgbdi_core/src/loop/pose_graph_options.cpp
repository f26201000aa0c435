#include "rgbdi/loop/pose_graph_options.h"

#include <string>
#include <vector>

#include "rgbdi/common/option_keys.h"

namespace rgbdi::loop {
namespace {

const char* const kSection = "loop";

// One table of keys and ranges serves load() and validate(), so options built in code are held
// to the same limits as options read from a file.
using IntKey = rgbdi::IntKey<PoseGraphOptions>;
using DoubleKey = rgbdi::DoubleKey<PoseGraphOptions>;

const std::vector<IntKey>& intKeys() {
  static const std::vector<IntKey> keys = {
      {"graph_sequential_edges", [](PoseGraphOptions& o) -> int& { return o.sequential_edges; }, 1,
       100},
      {"graph_max_iterations", [](PoseGraphOptions& o) -> int& { return o.max_iterations; }, 1,
       100000},
      {"graph_max_rollbacks", [](PoseGraphOptions& o) -> int& { return o.max_rollbacks_per_solve; },
       0, 100000},
  };
  return keys;
}

const std::vector<DoubleKey>& doubleKeys() {
  static const std::vector<DoubleKey> keys = {
      {"graph_odom_pos_sigma_floor_m",
       [](PoseGraphOptions& o) -> double& { return o.odom_pos_sigma_floor_m; }, 1e-6, 10.0},
      {"graph_odom_pos_sigma_per_sqrt_m",
       [](PoseGraphOptions& o) -> double& { return o.odom_pos_sigma_per_sqrt_m; }, 0.0, 10.0},
      {"graph_odom_yaw_sigma_floor_deg",
       [](PoseGraphOptions& o) -> double& { return o.odom_yaw_sigma_floor_deg; }, 1e-6, 180.0},
      {"graph_odom_yaw_sigma_per_sqrt_m_deg",
       [](PoseGraphOptions& o) -> double& { return o.odom_yaw_sigma_per_sqrt_m_deg; }, 0.0, 180.0},
      {"graph_odom_yaw_sigma_per_sqrt_rad_deg",
       [](PoseGraphOptions& o) -> double& { return o.odom_yaw_sigma_per_sqrt_rad_deg; }, 0.0,
       180.0},
      {"graph_odom_bridge_pos_sigma_m",
       [](PoseGraphOptions& o) -> double& { return o.odom_bridge_pos_sigma_m; }, 0.0, 100.0},
      {"graph_odom_bridge_yaw_sigma_deg",
       [](PoseGraphOptions& o) -> double& { return o.odom_bridge_yaw_sigma_deg; }, 0.0, 180.0},
      {"graph_loop_sigma_pos_m", [](PoseGraphOptions& o) -> double& { return o.loop_sigma_pos_m; },
       1e-6, 100.0},
      {"graph_loop_sigma_yaw_deg",
       [](PoseGraphOptions& o) -> double& { return o.loop_sigma_yaw_deg; }, 1e-6, 180.0},
      {"graph_loss_scale_sigma", [](PoseGraphOptions& o) -> double& { return o.loss_scale_sigma; },
       1e-3, 1000.0},
      {"graph_function_tolerance",
       [](PoseGraphOptions& o) -> double& { return o.function_tolerance; }, 0.0, 1.0},
      {"graph_gradient_tolerance",
       [](PoseGraphOptions& o) -> double& { return o.gradient_tolerance; }, 0.0, 1.0},
      {"graph_parameter_tolerance",
       [](PoseGraphOptions& o) -> double& { return o.parameter_tolerance; }, 0.0, 1.0},
      {"graph_rollback_gate_sigma",
       [](PoseGraphOptions& o) -> double& { return o.rollback_gate_sigma; }, 0.1, 1000.0},
  };
  return keys;
}

const char* lossName(RobustLoss l) { return l == RobustLoss::kHuber ? "huber" : "cauchy"; }

[[noreturn]] void failKey(const std::string& key, const std::string& what) {
  throw ConfigError("PoseGraphOptions [" + std::string(kSection) + "] " + key + ": " + what);
}

}  // namespace

void PoseGraphOptions::validate() const {
  checkKeyRanges(*this, intKeys(), doubleKeys(), failKey);
  if (loss != RobustLoss::kHuber && loss != RobustLoss::kCauchy)
    failKey("graph_loss", "unknown robust loss");
}

PoseGraphOptions PoseGraphOptions::load(IniReader& ini) {
  PoseGraphOptions o;
  loadKeys(ini, kSection, o, intKeys(), doubleKeys());
  const std::string loss =
      ini.getEnum(kSection, "graph_loss", lossName(o.loss), {"huber", "cauchy"});
  o.loss = loss == "huber" ? RobustLoss::kHuber : RobustLoss::kCauchy;
  return o;
}

}  // namespace rgbdi::loop
