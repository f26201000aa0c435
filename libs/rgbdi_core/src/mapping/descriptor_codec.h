// The descriptor block shared by the keyframe file (mapping/keyframe_file.cpp) and the saved
// map's places.bin (map/places_file.cpp):
//   u32 type length, type bytes | u32 bytes per descriptor | u32 nk | nk x (f32 u, f32 v)
//   | nk x bytes-per-descriptor bytes | u32 n3 (0 or nk) | n3 x (3 x f32 p_cam, all NaN = none)
#pragma once

#include <functional>
#include <string>

#include "mapping/byte_codec.h"
#include "rgbdi/mapping/keyframe.h"

namespace rgbdi::mapping::detail {

/// Longest accepted descriptor type name (a corrupt length must not allocate gigabytes).
inline constexpr std::uint32_t kMaxDescriptorTypeLength = 256;

void writeDescriptors(ByteWriter& w, const DescriptorSet& d);

/// Reads one block; `fail` must throw (it receives what is wrong).
DescriptorSet readDescriptors(ByteReader& r, const std::function<void(const std::string&)>& fail);

}  // namespace rgbdi::mapping::detail
