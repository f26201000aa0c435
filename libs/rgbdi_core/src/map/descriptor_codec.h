// The descriptor block of places.bin, in the same byte layout as the descriptor block of the
// keyframe file (mapping/keyframe_file.cpp) and with the same ByteWriter / ByteReader helpers:
//   u32 type length, type bytes | u32 bytes per descriptor | u32 nk | nk x (f32 u, f32 v)
//   | nk x bytes-per-descriptor bytes | u32 n3 (0 or nk) | n3 x (3 x f32 p_cam, all NaN = none)
#pragma once

#include <string>

#include "mapping/byte_codec.h"
#include "rgbdi/mapping/keyframe.h"

namespace rgbdi::map::detail {

/// Longest accepted descriptor type name (a corrupt length must not allocate gigabytes).
inline constexpr std::uint32_t kMaxDescriptorTypeLength = 256;

void writeDescriptors(mapping::detail::ByteWriter& w, const mapping::DescriptorSet& d);

/// Reads one block; `fail` must throw (it receives what is wrong).
mapping::DescriptorSet readDescriptors(mapping::detail::ByteReader& r,
                                       const std::function<void(const std::string&)>& fail);

}  // namespace rgbdi::map::detail
