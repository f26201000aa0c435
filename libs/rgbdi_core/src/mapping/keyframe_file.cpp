// KeyframeStore::save / load: the binary keyframe file.
//
// Layout (all little-endian):
//   "RGBDIKFS" | u32 version | u64 keyframe count | records...
//   record: u32 'KFRM' | u64 id | u64 frame_index | f64 t | 12 x f64 (rows of [R | t])
//           | u32 nf | nf x (u64 id, f64 u, f64 v, u8 has_position, 3 x f64 p_cam)
//           | u32 type length, type bytes | u32 bytes per descriptor | u32 nk
//           | nk x (f32 u, f32 v) | nk x bytes-per-descriptor bytes
//           | u32 n3 (0 or nk) | n3 x (3 x f32 keypoint p_cam, all NaN = no depth)
//           | u32 np | np x (3 x f32 p_cam, 3 x u8 rgb)
// The pose is stored as the full matrix so that a save/load round trip is bit-exact.
// Version 2 added the keypoints' 3-D points (n3); version 1 files are refused.
#include <cerrno>
#include <cmath>
#include <cstring>
#include <string>

#include "mapping/byte_codec.h"
#include "mapping/descriptor_codec.h"
#include "mapping/pose_check.h"
#include "rgbdi/common/atomic_file.h"
#include "rgbdi/common/whole_file.h"
#include "rgbdi/mapping/keyframe_store.h"

namespace rgbdi::mapping {
namespace {

constexpr char kMagic[8] = {'R', 'G', 'B', 'D', 'I', 'K', 'F', 'S'};
constexpr std::uint32_t kRecordTag = 0x4D52464Bu;  // "KFRM" in file byte order
constexpr std::size_t kFeatureBytes = 8 + 2 * 8 + 1 + 3 * 8;
constexpr std::size_t kPointBytes = 3 * 4 + 3;

void writeKeyframe(detail::ByteWriter& w, const Keyframe& k) {
  w.u32(kRecordTag);
  w.u64(k.id);
  w.u64(k.frame_index);
  w.f64(k.t);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) w.f64(k.T_world_cam.matrix()(r, c));

  w.u32(static_cast<std::uint32_t>(k.features.size()));
  for (const KeyframeFeature& f : k.features) {
    w.u64(f.id);
    w.f64(f.uv.x());
    w.f64(f.uv.y());
    w.u8(f.has_position ? 1 : 0);
    for (int i = 0; i < 3; ++i) w.f64(f.p_cam[i]);
  }

  detail::writeDescriptors(w, k.descriptors);

  w.u32(static_cast<std::uint32_t>(k.points.size()));
  for (const MapPoint& p : k.points) {
    for (int i = 0; i < 3; ++i) w.f32(p.p_cam[i]);
    for (int i = 0; i < 3; ++i) w.u8(p.rgb[i]);
  }
}

std::vector<char> readKeyframeFile(const std::string& path) {
  std::vector<char> data;
  switch (readWholeFile(path, data)) {
    case FileReadError::kOpen:
      throw KeyframeFileError(path + ": cannot open keyframe file: " + std::strerror(errno));
    case FileReadError::kRead:
      throw KeyframeFileError(path + ": read error: " + std::strerror(errno));
    case FileReadError::kNone:
      break;
  }
  return data;
}

}  // namespace

void KeyframeStore::save(const std::string& path) const {
  std::vector<const Keyframe*> all;
  all.reserve(keyframes_.size());
  for (const Keyframe& k : keyframes_) all.push_back(&k);
  save(path, all);
}

void KeyframeStore::save(const std::string& path, const std::vector<const Keyframe*>& keyframes) {
  for (const Keyframe* k : keyframes) {
    // 32-bit counts in the file: refuse rather than wrap (never reached by real keyframes).
    const std::size_t limit = 0xFFFFFFFFu;
    if (k->features.size() > limit || k->points.size() > limit ||
        k->descriptors.keypoints_uv.size() > limit ||
        k->descriptors.type.size() > detail::kMaxDescriptorTypeLength)
      throw IoError(path + ": keyframe " + std::to_string(k->id) +
                    " has more features/points/descriptors than the file format holds");
  }
  writeFileAtomically(path, [&](std::ostream& os) {
    detail::ByteWriter header;
    header.raw(kMagic, sizeof kMagic);
    header.u32(kFileVersion);
    header.u64(keyframes.size());
    os.write(header.bytes().data(), static_cast<std::streamsize>(header.bytes().size()));
    // One record at a time keeps the temporary buffer small for large stores.
    for (const Keyframe* k : keyframes) {
      detail::ByteWriter w;
      writeKeyframe(w, *k);
      os.write(w.bytes().data(), static_cast<std::streamsize>(w.bytes().size()));
    }
  });
}

KeyframeStore KeyframeStore::load(const std::string& path) {
  const std::vector<char> data = readKeyframeFile(path);
  std::string context = "header";
  detail::ByteReader r(data, [&](const std::string& what) {
    throw KeyframeFileError(path + ": " + context + ": " + what);
  });
  const auto fail = [&](const std::string& what) {
    throw KeyframeFileError(path + ": " + context + ": " + what);
  };

  char magic[sizeof kMagic];
  r.raw(magic, sizeof magic, "the file signature");
  if (std::memcmp(magic, kMagic, sizeof kMagic) != 0)
    fail("not an rgbdi keyframe file (signature is not RGBDIKFS)");
  const std::uint32_t version = r.u32("the format version");
  if (version != kFileVersion)
    fail("unsupported format version " + std::to_string(version) + " (this build reads version " +
         std::to_string(kFileVersion) + ")");
  const std::uint64_t count = r.u64("the keyframe count");
  r.needRecords(count, 4 + 8 + 8 + 8 + 12 * 8 + 4 + 4 + 4 + 4 + 4 + 4, "keyframes");

  KeyframeStore store;
  store.keyframes_.reserve(static_cast<std::size_t>(count));
  for (std::uint64_t n = 0; n < count; ++n) {
    context = "keyframe record " + std::to_string(n) + " (byte " + std::to_string(r.offset()) + ")";
    if (r.u32("the record tag") != kRecordTag) fail("record tag is not KFRM (corrupt file)");
    Keyframe k;
    k.id = r.u64("the keyframe id");
    context = "keyframe record " + std::to_string(n) + " (id " + std::to_string(k.id) + ")";
    if (!store.keyframes_.empty() && store.keyframes_.back().id >= k.id)
      fail("ids are not strictly increasing (previous id " +
           std::to_string(store.keyframes_.back().id) + ")");
    k.frame_index = r.u64("the frame index");
    k.t = r.f64("the stamp");
    if (!std::isfinite(k.t)) fail("stamp is not finite");
    for (int row = 0; row < 3; ++row)
      for (int c = 0; c < 4; ++c) k.T_world_cam.matrix()(row, c) = r.f64("the pose");
    if (!detail::isRigid(k.T_world_cam)) fail("pose is not a finite rigid transform");

    const std::uint32_t nf = r.u32("the feature count");
    r.needRecords(nf, kFeatureBytes, "features");
    k.features.resize(nf);
    for (KeyframeFeature& f : k.features) {
      f.id = r.u64("a feature id");
      // Stored as doubles (format version 2); held in single precision.
      f.uv.x() = static_cast<float>(r.f64("a feature pixel"));
      f.uv.y() = static_cast<float>(r.f64("a feature pixel"));
      const std::uint8_t has = r.u8("a feature position flag");
      if (has > 1) fail("feature " + std::to_string(f.id) + " has an invalid position flag");
      f.has_position = has == 1;
      for (int i = 0; i < 3; ++i) f.p_cam[i] = static_cast<float>(r.f64("a feature position"));
      if (!f.uv.allFinite() || !f.p_cam.allFinite())
        fail("feature " + std::to_string(f.id) + " has a non-finite coordinate");
    }

    k.descriptors = detail::readDescriptors(r, fail);

    const std::uint32_t np = r.u32("the point count");
    r.needRecords(np, kPointBytes, "points");
    k.points.resize(np);
    for (MapPoint& p : k.points) {
      for (int i = 0; i < 3; ++i) p.p_cam[i] = r.f32("a point position");
      for (int i = 0; i < 3; ++i) p.rgb[i] = r.u8("a point colour");
      if (!p.p_cam.allFinite()) fail("a point has a non-finite position");
    }
    store.keyframes_.push_back(std::move(k));
  }
  context = "end of file";
  if (r.remaining() != 0)
    fail(std::to_string(r.remaining()) + " unexpected bytes after the last keyframe record");
  return store;
}

}  // namespace rgbdi::mapping
