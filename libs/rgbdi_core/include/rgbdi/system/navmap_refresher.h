// Live runs keep the navigation maps in the output directory current while they run
// (doc/navigation-maps.md): after each loop correction of the map and, between corrections, at
// [navmap] refresh_interval_s of wall-clock time (counted from the end of the last refresh), the
// maps are rebuilt from the keyframes' kept points (system::navMapPoints) and positions and
// rewritten (each file atomically: a planner reads a whole map). Called on the mapping thread
// (SlamSystemOptions::on_map_update), which owns the mapper.
#pragma once

#include <atomic>
#include <chrono>
#include <mutex>
#include <string>

#include "rgbdi/mapping/mapper.h"
#include "rgbdi/navmap/navmap_options.h"

namespace rgbdi::system {

class NavMapRefresher {
 public:
  NavMapRefresher(std::string dir, const navmap::NavMapOptions& options);

  /// After the mapper took a keyframe (correction = false) or a loop correction (true).
  void update(const mapping::Mapper& mapper, bool correction);

  std::size_t refreshes() const { return refreshes_.load(); }
  /// The last failure (a write error, a map without keyframes), empty when none.
  std::string lastError() const;

 private:
  void refresh(const mapping::Mapper& mapper);

  std::string dir_;
  navmap::NavMapOptions options_;
  std::chrono::steady_clock::time_point last_;
  bool refreshed_once_ = false;
  std::atomic<std::size_t> refreshes_{0};
  mutable std::mutex error_mutex_;
  std::string last_error_;
};

}  // namespace rgbdi::system
