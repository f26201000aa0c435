#include "rgbdi/system/slam_navmap.h"

#include <cmath>

namespace rgbdi::system {

void appendNavMapPoints(const mapping::Keyframe& kf, const navmap::NavMapOptions& options,
                        std::vector<Eigen::Vector3f>* out) {
  const float max_depth = static_cast<float>(options.max_depth_m);
  const Eigen::Isometry3f T_world_cam = kf.T_world_cam.cast<float>();
  for (const mapping::MapPoint& p : kf.points)
    if (p.p_cam.z() <= max_depth) out->push_back(T_world_cam * p.p_cam);
}

std::vector<Eigen::Vector3f> navMapPoints(const mapping::KeyframeStore& store,
                                          const navmap::NavMapOptions& options) {
  std::vector<Eigen::Vector3f> points;
  for (const mapping::Keyframe& kf : store.keyframes()) appendNavMapPoints(kf, options, &points);
  return points;
}

navmap::NavMap slamNavMap(const SlamSystem& sys, const navmap::NavMapOptions& options) {
  const Trajectory path = sys.finalTrajectory();
  std::vector<Eigen::Vector3d> positions;
  positions.reserve(path.size());
  for (const StampedPose& p : path) positions.push_back(p.p);
  return navmap::buildNavMap(navMapPoints(sys.mapper().store(), options), positions, options);
}

nlohmann::json navMapSummary(const navmap::NavMap& m, double build_ms) {
  using navmap::CellState;
  const double cell_area = m.grid.cell_size_m * m.grid.cell_size_m;
  nlohmann::json j;
  j["cell_size_m"] = m.grid.cell_size_m;
  j["width_cells"] = m.grid.width;
  j["height_cells"] = m.grid.height;
  std::size_t occupied = 0;
  nlohmann::json states;
  for (CellState s :
       {CellState::kUnknown, CellState::kFree, CellState::kObstacle, CellState::kTooSteep,
        CellState::kStepEdge, CellState::kRaised, CellState::kLowered}) {
    states[navmap::toString(s)] = m.count(s);
    if (s != CellState::kUnknown && s != CellState::kFree) occupied += m.count(s);
  }
  j["cells"] = states;
  j["free_area_m2"] = static_cast<double>(m.count(CellState::kFree)) * cell_area;
  j["occupied_area_m2"] = static_cast<double>(occupied) * cell_area;
  j["path_height_m"] = std::isfinite(m.path_height_m) ? nlohmann::json(m.path_height_m) : nullptr;
  j["build_ms"] = build_ms;
  return j;
}

}  // namespace rgbdi::system
