// Live runs keep the navigation maps in the output directory current while they run
// (doc/navigation-maps.md): after each loop correction of the map and, between corrections, at
// [navmap] refresh_interval_s of wall-clock time (counted from the end of the last refresh), the
// maps are built from the keyframes' kept points (system::navMapPoints) and positions and
// rewritten (each file atomically: a planner reads a whole map). Called on the mapping thread
// (SlamSystemOptions::on_map_update), which owns the mapper.
//
// Incremental: every new keyframe's points go into a navmap::NavMapUpdater as the keyframe
// arrives (only the cells they fall in are derived again); a refresh derives the path-dependent
// layers from it. When keyframe poses moved (a loop correction: the store's pose revision
// changed) or a keyframe's kept points changed, the updater is emptied and filled again from
// every keyframe: a full rebuild. The maps equal a full build from the same keyframes.
#pragma once

#include <atomic>
#include <chrono>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "rgbdi/mapping/mapper.h"
#include "rgbdi/navmap/nav_map_updater.h"
#include "rgbdi/navmap/navmap_options.h"

namespace rgbdi::system {

class NavMapRefresher {
 public:
  NavMapRefresher(std::string dir, const navmap::NavMapOptions& options);

  /// After the mapper took a keyframe (correction = false) or a loop correction (true).
  void update(const mapping::Mapper& mapper, bool correction);

  std::size_t refreshes() const { return refreshes_.load(); }
  /// How often the updater was refilled from every keyframe (the first fill counts).
  std::size_t fullRebuilds() const { return full_rebuilds_; }
  /// The last failure (a write error, a map without keyframes), empty when none.
  std::string lastError() const;

 private:
  void refresh(const mapping::Mapper& mapper);
  /// Brings the updater up to date with the store's keyframes (see above).
  void feed(const mapping::KeyframeStore& store);

  std::string dir_;
  navmap::NavMapOptions options_;
  std::chrono::steady_clock::time_point last_;
  navmap::NavMapUpdater updater_;
  /// Keyframes in the updater, in store order: id and number of kept points.
  std::vector<std::pair<std::uint64_t, std::size_t>> fed_;
  std::uint64_t fed_pose_revision_ = 0;
  std::size_t full_rebuilds_ = 0;
  std::atomic<std::size_t> refreshes_{0};
  mutable std::mutex error_mutex_;
  std::string last_error_;
};

}  // namespace rgbdi::system
