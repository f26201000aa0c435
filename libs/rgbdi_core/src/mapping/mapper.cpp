#include "rgbdi/mapping/mapper.h"

#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>

#include "rgbdi/common/cpu_clock.h"

namespace rgbdi::mapping {
namespace {
using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}
}  // namespace

Mapper::Mapper(const MappingOptions& options, bool build_occupancy)
    : options_(options),
      points_(options),
      viewpoints_(options.view_update_distance_m, options.view_update_angle_deg) {
  if (build_occupancy) occupancy_ = std::make_unique<OccupancyMap>(options);
}

void Mapper::addKeyframe(Keyframe k, const RgbdFrame& frame) {
  const double t0 = threadCpuSeconds();  // stage cost: CPU time of the mapping thread
  if (store_.contains(k.id))
    throw std::invalid_argument("Mapper: keyframe " + std::to_string(k.id) + " added twice");
  k.points.clear();
  // A keyframe seen from where the map was already seen adds no points (bounded memory on
  // repeated routes); it is still stored with its features for the pose graph.
  if (frame.hasDepth() && !viewpoints_.covered(k.T_world_cam)) {
    k.points = points_.insertKeyframe(frame, k.T_world_cam, k.id);
    viewpoints_.add(k.T_world_cam);
    adding_ids_.push_back(k.id);
  }
  // Ray casting waits for finish() (see mapper.h): the poses known now are not the final ones.
  occupancy_outdated_ = occupancy_ != nullptr;
  insertions_.push_back({k.id, k.t, k.points.size()});
  store_.add(std::move(k));
  ++stats_.keyframes;
  stats_.keyframes_adding_points = adding_ids_.size();
  stats_.insert_ms_total += 1e3 * (threadCpuSeconds() - t0);
}

void Mapper::restore(const KeyframeStore& saved) {
  if (!store_.empty()) throw std::logic_error("Mapper::restore: keyframes were added already");
  for (std::size_t slot = 0; slot < saved.size(); ++slot) {
    Keyframe k = saved.at(slot);
    if (store_.contains(k.id))
      throw std::invalid_argument("Mapper::restore: keyframe " + std::to_string(k.id) +
                                  " appears twice");
    if (!k.points.empty()) {
      k.points = points_.insertPoints(k.points, k.T_world_cam, k.id);
      viewpoints_.add(k.T_world_cam);
      adding_ids_.push_back(k.id);
    }
    store_.add(std::move(k));
  }
  occupancy_outdated_ = occupancy_ != nullptr;
  stats_.keyframes_adding_points = adding_ids_.size();
}

MapCorrection Mapper::correct(
    const std::vector<std::pair<std::uint64_t, Eigen::Isometry3d>>& poses) {
  const auto t0 = Clock::now();
  MapCorrection c;
  // Corrections below the thresholds leave a keyframe where it is: re-inserting every point
  // for a millimetre would cost a rebuild and change nothing the map resolves.
  const double min_cos_half = std::cos(0.5 * options_.correction_min_rotation_deg * M_PI / 180.0);
  std::vector<std::uint64_t> moved;
  for (const auto& [id, T] : poses) {
    if (!store_.contains(id)) continue;
    const Eigen::Isometry3d& old = store_.get(id).T_world_cam;
    const double shift = (T.translation() - old.translation()).norm();
    const double cos_half =
        std::abs(Eigen::Quaterniond(old.rotation()).dot(Eigen::Quaterniond(T.rotation())));
    if (shift < options_.correction_min_shift_m && cos_half > min_cos_half) continue;
    store_.setPose(id, T);
    moved.push_back(id);
    ++c.keyframes_moved;
  }
  if (c.keyframes_moved == 0) return c;
  // Only the moved keyframes' points are re-inserted (the same map as a full rebuild).
  c.rebuild = points_.update(store_, moved);
  rebuildViewpoints();
  occupancy_outdated_ = occupancy_ != nullptr;
  c.milliseconds = msSince(t0);
  ++stats_.corrections;
  stats_.correction_ms_total += c.milliseconds;
  stats_.correction_ms_max = std::max(stats_.correction_ms_max, c.milliseconds);
  stats_.points_at_last_correction = c.rebuild.input_points;
  return c;
}

void Mapper::rebuildViewpoints() {
  viewpoints_ = ViewpointIndex(options_.view_update_distance_m, options_.view_update_angle_deg);
  for (std::uint64_t id : adding_ids_) viewpoints_.add(store_.get(id).T_world_cam);
}

void Mapper::finish() {
  if (!occupancy_outdated_) return;
  const double t0 = threadCpuSeconds();
  occupancy_->rebuild(store_);
  occupancy_outdated_ = false;
  stats_.occupancy_rebuild_ms = 1e3 * (threadCpuSeconds() - t0);
}

std::size_t Mapper::memoryBytes() const {
  return points_.memoryBytes() + store_.memoryBytes() +
         insertions_.capacity() * sizeof(KeyframeInsertion) +
         (occupancy_ ? occupancy_->memoryBytes() : 0);
}

}  // namespace rgbdi::mapping
