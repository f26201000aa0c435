#include "mapping/descriptor_codec.h"

#include <cmath>

namespace rgbdi::mapping::detail {

void writeDescriptors(ByteWriter& w, const DescriptorSet& d) {
  w.u32(static_cast<std::uint32_t>(d.type.size()));
  w.raw(d.type.data(), d.type.size());
  w.u32(d.bytes_per_descriptor);
  w.u32(static_cast<std::uint32_t>(d.keypoints_uv.size()));
  for (const Eigen::Vector2f& uv : d.keypoints_uv) {
    w.f32(uv.x());
    w.f32(uv.y());
  }
  w.raw(d.data.data(), d.data.size());
  w.u32(static_cast<std::uint32_t>(d.keypoints_p_cam.size()));
  for (const Eigen::Vector3f& p : d.keypoints_p_cam)
    for (int i = 0; i < 3; ++i) w.f32(p[i]);
}

DescriptorSet readDescriptors(ByteReader& r, const std::function<void(const std::string&)>& fail) {
  DescriptorSet d;
  const std::uint32_t type_length = r.u32("the descriptor type length");
  if (type_length > kMaxDescriptorTypeLength)
    fail("descriptor type name of " + std::to_string(type_length) + " bytes (corrupt file)");
  d.type.resize(type_length);
  r.raw(d.type.data(), type_length, "the descriptor type");
  d.bytes_per_descriptor = r.u32("the descriptor size");
  const std::uint32_t nk = r.u32("the keypoint count");
  r.needRecords(nk, 2 * 4 + static_cast<std::size_t>(d.bytes_per_descriptor), "keypoints");
  d.keypoints_uv.resize(nk);
  for (Eigen::Vector2f& uv : d.keypoints_uv) {
    uv.x() = r.f32("a keypoint pixel");
    uv.y() = r.f32("a keypoint pixel");
    if (!uv.allFinite()) fail("a keypoint has a non-finite pixel position");
  }
  d.data.resize(static_cast<std::size_t>(nk) * d.bytes_per_descriptor);
  r.raw(d.data.data(), d.data.size(), "the descriptors");
  const std::uint32_t n3 = r.u32("the keypoint point count");
  if (n3 != 0 && n3 != nk)
    fail(std::to_string(n3) + " keypoint points for " + std::to_string(nk) +
         " keypoints (must be 0 or equal)");
  r.needRecords(n3, 3 * 4, "keypoint points");
  d.keypoints_p_cam.resize(n3);
  for (Eigen::Vector3f& p : d.keypoints_p_cam) {
    for (int i = 0; i < 3; ++i) p[i] = r.f32("a keypoint point");
    // Either a known point (finite) or marked absent (all NaN); anything else is damage.
    if (!p.allFinite() && !(std::isnan(p.x()) && std::isnan(p.y()) && std::isnan(p.z())))
      fail("a keypoint point is neither finite nor absent (all NaN)");
  }
  return d;
}

}  // namespace rgbdi::mapping::detail
