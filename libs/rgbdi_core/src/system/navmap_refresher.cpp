#include "rgbdi/system/navmap_refresher.h"

#include <utility>
#include <vector>

#include "rgbdi/navmap/nav_map.h"
#include "rgbdi/navmap/navmap_files.h"
#include "rgbdi/system/slam_navmap.h"

namespace rgbdi::system {

NavMapRefresher::NavMapRefresher(std::string dir, const navmap::NavMapOptions& options)
    : dir_(std::move(dir)), options_(options), last_(std::chrono::steady_clock::now()) {
  options_.validate();
}

void NavMapRefresher::update(const mapping::Mapper& mapper, bool correction) {
  if (!options_.enable) return;
  const auto now = std::chrono::steady_clock::now();
  const bool due =
      options_.refresh_interval_s > 0.0 &&
      std::chrono::duration<double>(now - last_).count() >= options_.refresh_interval_s;
  if (!correction && !due) return;
  refresh(mapper);
  // The period counts from the end of a refresh: a rebuild slower than the interval does not
  // make the mapping thread rebuild back to back.
  last_ = std::chrono::steady_clock::now();
}

void NavMapRefresher::refresh(const mapping::Mapper& mapper) {
  // The keyframes' camera positions stand for the path: the path's height above the ground is
  // measured from the data (NavMap::path_height_m), so the camera's offset from the body does
  // not matter.
  std::vector<Eigen::Vector3d> path;
  for (const mapping::Keyframe& kf : mapper.store().keyframes())
    path.push_back(kf.T_world_cam.translation());
  if (path.empty()) return;
  try {
    const navmap::NavMap map =
        navmap::buildNavMap(navMapPoints(mapper.store(), options_), path, options_);
    navmap::writeNavMapFiles(map, dir_, &path);
    ++refreshes_;
  } catch (const std::exception& e) {
    // A live run goes on without fresh maps; the summary reports the failure.
    std::lock_guard<std::mutex> lock(error_mutex_);
    last_error_ = e.what();
  }
}

std::string NavMapRefresher::lastError() const {
  std::lock_guard<std::mutex> lock(error_mutex_);
  return last_error_;
}

}  // namespace rgbdi::system
