#include "rgbdi/mapping/keyframe_store.h"

#include <algorithm>
#include <string>

#include "mapping/pose_check.h"

namespace rgbdi::mapping {

std::size_t Keyframe::memoryBytes() const {
  return sizeof(Keyframe) + features.capacity() * sizeof(KeyframeFeature) +
         descriptors.type.capacity() +
         descriptors.keypoints_uv.capacity() * sizeof(Eigen::Vector2f) +
         descriptors.keypoints_p_cam.capacity() * sizeof(Eigen::Vector3f) +
         descriptors.data.capacity() + points.capacity() * sizeof(MapPoint);
}

std::size_t KeyframeStore::slotOf(std::uint64_t id) const {
  const auto it = std::lower_bound(keyframes_.begin(), keyframes_.end(), id,
                                   [](const Keyframe& k, std::uint64_t v) { return k.id < v; });
  if (it == keyframes_.end() || it->id != id) return keyframes_.size();
  return static_cast<std::size_t>(it - keyframes_.begin());
}

bool KeyframeStore::contains(std::uint64_t id) const { return slotOf(id) < keyframes_.size(); }

const Keyframe& KeyframeStore::get(std::uint64_t id) const {
  const std::size_t slot = slotOf(id);
  if (slot == keyframes_.size())
    throw std::out_of_range("KeyframeStore: no keyframe with id " + std::to_string(id));
  return keyframes_[slot];
}

void KeyframeStore::add(Keyframe keyframe) {
  const std::string who = "KeyframeStore::add: keyframe " + std::to_string(keyframe.id);
  if (contains(keyframe.id)) throw std::invalid_argument(who + " is already in the store");
  if (!detail::isRigid(keyframe.T_world_cam))
    throw std::invalid_argument(who + ": T_world_cam is not a finite rigid transform");
  if (!std::isfinite(keyframe.t)) throw std::invalid_argument(who + ": stamp is not finite");
  if (!keyframe.descriptors.consistent())
    throw std::invalid_argument(
        who + ": descriptor data holds " + std::to_string(keyframe.descriptors.data.size()) +
        " bytes, expected " + std::to_string(keyframe.descriptors.keypoints_uv.size()) + " x " +
        std::to_string(keyframe.descriptors.bytes_per_descriptor));
  // Stored keyframes never grow again: drop the slack of vectors filled by push_back (up to
  // half of the store on long runs; the store holds every keyframe of the session).
  keyframe.features.shrink_to_fit();
  keyframe.points.shrink_to_fit();
  keyframe.descriptors.keypoints_uv.shrink_to_fit();
  keyframe.descriptors.keypoints_p_cam.shrink_to_fit();
  keyframe.descriptors.data.shrink_to_fit();
  // Keyframes normally arrive with increasing ids: appending is the common, O(1) case.
  if (keyframes_.empty() || keyframes_.back().id < keyframe.id) {
    keyframes_.push_back(std::move(keyframe));
    return;
  }
  const auto it = std::lower_bound(keyframes_.begin(), keyframes_.end(), keyframe.id,
                                   [](const Keyframe& k, std::uint64_t v) { return k.id < v; });
  keyframes_.insert(it, std::move(keyframe));
}

void KeyframeStore::setPose(std::uint64_t id, const Eigen::Isometry3d& T_world_cam) {
  const std::size_t slot = slotOf(id);
  if (slot == keyframes_.size())
    throw std::out_of_range("KeyframeStore::setPose: no keyframe with id " + std::to_string(id));
  if (!detail::isRigid(T_world_cam))
    throw std::invalid_argument("KeyframeStore::setPose: keyframe " + std::to_string(id) +
                                ": T_world_cam is not a finite rigid transform");
  keyframes_[slot].T_world_cam = T_world_cam;
  ++pose_revision_;
}

void KeyframeStore::replacePoints(std::size_t slot, std::vector<MapPoint> points) {
  keyframes_.at(slot).points = std::move(points);
}

std::size_t KeyframeStore::pointCount() const {
  std::size_t n = 0;
  for (const Keyframe& k : keyframes_) n += k.points.size();
  return n;
}

std::size_t KeyframeStore::memoryBytes() const {
  std::size_t bytes =
      sizeof(*this) + (keyframes_.capacity() - keyframes_.size()) * sizeof(Keyframe);
  for (const Keyframe& k : keyframes_) bytes += k.memoryBytes();
  return bytes;
}

Trajectory KeyframeStore::cameraTrajectory() const {
  Trajectory out;
  out.reserve(keyframes_.size());
  for (const Keyframe& k : keyframes_) out.push_back(StampedPose::fromIsometry(k.t, k.T_world_cam));
  return out;
}

}  // namespace rgbdi::mapping
