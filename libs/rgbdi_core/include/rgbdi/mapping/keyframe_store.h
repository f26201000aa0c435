// The keyframes of a run, ordered by id, with their poses, features, descriptors and kept map
// points; serialisable to a versioned binary file so that a map can be saved and reloaded (the
// point map is rebuilt from it with PointMap::rebuild) and loop closure can look keyframes up.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "rgbdi/common/types.h"
#include "rgbdi/mapping/keyframe.h"

namespace rgbdi::mapping {

/// A keyframe file that cannot be read: the message names the file, the record and the problem.
class KeyframeFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class KeyframeStore {
 public:
  /// Version of the file format written by save() (load() reads this version only). Version 2
  /// added the depth-backed keypoint points of the descriptor sets.
  static constexpr std::uint32_t kFileVersion = 2;

  /// Adds a keyframe (kept ordered by id). Throws std::invalid_argument when the id is already
  /// present, the pose is not a finite rigid transform, or the descriptors are inconsistent.
  void add(Keyframe keyframe);

  std::size_t size() const { return keyframes_.size(); }
  bool empty() const { return keyframes_.empty(); }
  bool contains(std::uint64_t id) const;
  /// Throws std::out_of_range naming the id when it is not present.
  const Keyframe& get(std::uint64_t id) const;
  /// Keyframe at position `slot` (0 .. size()-1, increasing id).
  const Keyframe& at(std::size_t slot) const { return keyframes_.at(slot); }
  const std::vector<Keyframe>& keyframes() const { return keyframes_; }

  /// Sets a corrected pose (e.g. after a pose-graph update). Throws like get() and add().
  void setPose(std::uint64_t id, const Eigen::Isometry3d& T_world_cam);
  /// Incremented by every setPose(): a map built at an older revision is out of date.
  std::uint64_t poseRevision() const { return pose_revision_; }

  /// Replaces the kept points of the keyframe at `slot` (used when the map drops points).
  void replacePoints(std::size_t slot, std::vector<MapPoint> points);

  /// Total number of kept points over all keyframes.
  std::size_t pointCount() const;
  /// Estimated heap + object bytes of the whole store.
  std::size_t memoryBytes() const;
  /// Keyframe camera poses as a trajectory (stamp = keyframe stamp).
  Trajectory cameraTrajectory() const;

  /// Writes all keyframes (binary, little-endian, versioned) atomically. Throws IoError.
  void save(const std::string& path) const;
  /// Writes `keyframes` (increasing id) as save() writes a store holding them, without copying
  /// them into one (a finished run saves a chosen subset of its store). Throws IoError.
  static void save(const std::string& path, const std::vector<const Keyframe*>& keyframes);
  /// Reads a file written by save(). Throws KeyframeFileError naming the file, the keyframe
  /// record and what is wrong (truncated, bad magic, unsupported version, invalid value).
  static KeyframeStore load(const std::string& path);

 private:
  std::size_t slotOf(std::uint64_t id) const;  // size() when absent

  std::vector<Keyframe> keyframes_;
  std::uint64_t pose_revision_ = 0;
};

}  // namespace rgbdi::mapping
