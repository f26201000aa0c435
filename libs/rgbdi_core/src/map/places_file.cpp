#include "map/places_file.h"

#include <cmath>
#include <cstring>

#include "map/file_io.h"
#include "mapping/byte_codec.h"
#include "mapping/descriptor_codec.h"
#include "mapping/pose_check.h"
#include "rgbdi/map/map_directory.h"

namespace rgbdi::map::detail {
namespace {

constexpr char kMagic[8] = {'R', 'G', 'B', 'D', 'I', 'P', 'L', 'C'};
constexpr std::uint32_t kRecordTag = 0x45434C50u;  // "PLCE" in file byte order
/// Smallest record: tag, id, segment, t, two poses, travelled, empty descriptor block, empty
/// depth grid.
constexpr std::size_t kMinRecordBytes = 4 + 8 + 4 + 8 + 2 * 12 * 8 + 8 + 4 + 4 + 4 + 4 + 4 + 4;
/// Largest depth grid a record may declare (the options allow 160 x 120).
constexpr std::uint32_t kMaxGridSide = 4096;

void writePose(mapping::detail::ByteWriter& w, const Eigen::Isometry3d& T) {
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) w.f64(T.matrix()(r, c));
}

Eigen::Isometry3d readPose(mapping::detail::ByteReader& r, const char* what) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  for (int row = 0; row < 3; ++row)
    for (int c = 0; c < 4; ++c) T.matrix()(row, c) = r.f64(what);
  return T;
}

}  // namespace

void writePlacesFile(const std::string& path, const std::vector<MapView::Place>& places) {
  DurableFile file(path);
  mapping::detail::ByteWriter header;
  header.raw(kMagic, sizeof kMagic);
  header.u32(kPlacesFileVersion);
  header.u64(places.size());
  file.write(header.bytes());
  // One record at a time keeps the buffer small for large maps.
  for (const MapView::Place& place : places) {
    const loop::LoopKeyframe& p = *place.keyframe;
    mapping::detail::ByteWriter w;
    w.u32(kRecordTag);
    w.u64(p.id);
    w.u32(static_cast<std::uint32_t>(p.segment));
    w.f64(p.t);
    writePose(w, p.T_world_body_odom);
    writePose(w, place.T_world_body);
    w.f64(p.travelled_m);
    mapping::detail::writeDescriptors(w, p.descriptors);
    w.u32(static_cast<std::uint32_t>(p.depth_grid.cols));
    w.u32(static_cast<std::uint32_t>(p.depth_grid.rows));
    for (float d : p.depth_grid.depth_m) w.f32(d);
    file.write(w.bytes());
  }
  file.close();
}

std::vector<loop::LoopKeyframe> readPlacesFile(const std::string& path) {
  const std::vector<char> data = readWholeFile(path);
  std::string context = "header";
  const auto fail = [&](const std::string& what) {
    throw MapError(path + ": " + context + ": " + what);
  };
  mapping::detail::ByteReader r(data, fail);

  char magic[sizeof kMagic];
  r.raw(magic, sizeof magic, "the file signature");
  if (std::memcmp(magic, kMagic, sizeof kMagic) != 0)
    fail("not an rgbdi places file (signature is not RGBDIPLC)");
  const std::uint32_t version = r.u32("the format version");
  if (version != kPlacesFileVersion)
    fail("unsupported places file version " + std::to_string(version) +
         " (this build reads version " + std::to_string(kPlacesFileVersion) + ")");
  const std::uint64_t count = r.u64("the place count");
  r.needRecords(count, kMinRecordBytes, "places");

  std::vector<loop::LoopKeyframe> places;
  places.reserve(static_cast<std::size_t>(count));
  for (std::uint64_t n = 0; n < count; ++n) {
    context = "place record " + std::to_string(n) + " (byte " + std::to_string(r.offset()) + ")";
    if (r.u32("the record tag") != kRecordTag) fail("record tag is not PLCE (corrupt file)");
    loop::LoopKeyframe p;
    p.id = r.u64("the place id");
    context = "place record " + std::to_string(n) + " (id " + std::to_string(p.id) + ")";
    if (!places.empty() && places.back().id >= p.id)
      fail("ids are not strictly increasing (previous id " + std::to_string(places.back().id) +
           ")");
    p.segment = static_cast<int>(r.u32("the segment"));
    if (p.segment < 0) fail("negative segment " + std::to_string(p.segment));
    p.t = r.f64("the stamp");
    if (!std::isfinite(p.t)) fail("stamp is not finite");
    p.T_world_body_odom = readPose(r, "the odometry pose");
    p.T_world_body = readPose(r, "the corrected pose");
    if (!mapping::detail::isRigid(p.T_world_body_odom) || !mapping::detail::isRigid(p.T_world_body))
      fail("a pose is not a finite rigid transform");
    p.travelled_m = r.f64("the distance travelled");
    if (!std::isfinite(p.travelled_m) || p.travelled_m < 0.0)
      fail("distance travelled is not a finite non-negative number");
    p.descriptors = mapping::detail::readDescriptors(r, fail);
    const std::uint32_t cols = r.u32("the depth grid columns");
    const std::uint32_t rows = r.u32("the depth grid rows");
    if (cols > kMaxGridSide || rows > kMaxGridSide || (cols == 0) != (rows == 0))
      fail("depth grid of " + std::to_string(cols) + " x " + std::to_string(rows) +
           " samples (corrupt file)");
    r.needRecords(static_cast<std::uint64_t>(cols) * rows, 4, "depth grid samples");
    p.depth_grid.cols = static_cast<int>(cols);
    p.depth_grid.rows = static_cast<int>(rows);
    p.depth_grid.depth_m.resize(static_cast<std::size_t>(cols) * rows);
    for (float& d : p.depth_grid.depth_m) {
      d = r.f32("a depth grid sample");
      if (!std::isfinite(d) || d < 0.0f) fail("a depth grid sample is not a finite depth >= 0");
    }
    places.push_back(std::move(p));
  }
  context = "end of file";
  if (r.remaining() != 0)
    fail(std::to_string(r.remaining()) + " unexpected bytes after the last place record");
  return places;
}

}  // namespace rgbdi::map::detail
