#include "rgbdi/system/navmap_refresher.h"

#include <utility>
#include <vector>

#include "rgbdi/navmap/nav_map.h"
#include "rgbdi/navmap/navmap_files.h"
#include "rgbdi/system/slam_navmap.h"

namespace rgbdi::system {

NavMapRefresher::NavMapRefresher(std::string dir, const navmap::NavMapOptions& options)
    : dir_(std::move(dir)),
      options_(options),
      last_(std::chrono::steady_clock::now()),
      updater_(options) {}

void NavMapRefresher::update(const mapping::Mapper& mapper, bool correction) {
  if (!options_.enable) return;
  feed(mapper.store());
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

void NavMapRefresher::feed(const mapping::KeyframeStore& store) {
  bool stale = store.poseRevision() != fed_pose_revision_ || store.size() < fed_.size();
  for (std::size_t slot = 0; slot < fed_.size() && !stale; ++slot)
    stale =
        store.at(slot).id != fed_[slot].first || store.at(slot).points.size() != fed_[slot].second;
  if (stale || fed_.empty()) {
    if (!fed_.empty() || updater_.pointCount() > 0) updater_.clear();
    fed_.clear();
    if (store.size() > 0) ++full_rebuilds_;
  }
  fed_pose_revision_ = store.poseRevision();
  std::vector<Eigen::Vector3f> points;
  for (std::size_t slot = fed_.size(); slot < store.size(); ++slot) {
    const mapping::Keyframe& kf = store.at(slot);
    points.clear();
    appendNavMapPoints(kf, options_, &points);
    updater_.addPoints(points);
    fed_.emplace_back(kf.id, kf.points.size());
  }
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
    const navmap::NavMap map = updater_.build(path);
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
