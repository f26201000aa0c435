// MRPT's map classes: COccupancyGridMap2D and CHeightGridMap2D files, and scene objects.
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/maps/CHeightGridMap2D.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/opengl/CPointCloudColoured.h>
#include <mrpt/opengl/CSetOfObjects.h>
#include <mrpt/serialization/CArchive.h>

#include <algorithm>
#include <cmath>

#include "navmap/colours.h"
#include "rgbdi/common/atomic_file.h"
#include "rgbdi/navmap/navmap_files.h"

namespace rgbdi::navmap {
namespace {

void serializeGz(const std::string& path, const std::string& what,
                 const mrpt::serialization::CSerializable& object) {
  writeFileAtomicallyVia(path, [&](const std::string& tmp) {
    try {
      mrpt::io::CFileGZOutputStream out;
      if (!out.open(tmp)) throw IoError(path + ": cannot create the " + what);
      auto archive = mrpt::serialization::archiveFrom(out);
      archive << object;
      out.close();
    } catch (const IoError&) {
      throw;
    } catch (const std::exception& e) {
      throw IoError(path + ": MRPT could not write the " + what + ": " + e.what());
    }
  });
}

mrpt::maps::COccupancyGridMap2D toGridMap(const NavMap& map) {
  const GridGeometry& g = map.grid;
  mrpt::maps::COccupancyGridMap2D grid;
  // Cell edges on the nav map's (MRPT rounds the limits to multiples of the resolution, as they
  // are): one MRPT cell per nav-map cell.
  grid.setSize(
      static_cast<float>(g.origin_x_m), static_cast<float>(g.origin_x_m + g.width * g.cell_size_m),
      static_cast<float>(g.origin_y_m), static_cast<float>(g.origin_y_m + g.height * g.cell_size_m),
      static_cast<float>(g.cell_size_m), 0.5f);
  for (int iy = 0; iy < g.height; ++iy)
    for (int ix = 0; ix < g.width; ++ix) {
      const Eigen::Vector2d c = g.centre(ix, iy);
      const int cx = grid.x2idx(static_cast<float>(c.x())),
                cy = grid.y2idx(static_cast<float>(c.y()));
      const std::int8_t o = map.occupancy(g.index(ix, iy));
      // MRPT's cell value is the probability of being free.
      grid.setCell(cx, cy, o == kOccFree ? 1.0f : (o == kOccOccupied ? 0.0f : 0.5f));
    }
  return grid;
}

}  // namespace

void writeMrptOccupancyGrid(const NavMap& map, const std::string& path) {
  serializeGz(path, "occupancy grid", toGridMap(map));
}

void writeMrptHeightMap(const NavMap& map, const std::string& path) {
  const GridGeometry& g = map.grid;
  mrpt::maps::CHeightGridMap2D dem(mrpt::maps::CHeightGridMap2D::mrSimpleAverage, g.origin_x_m,
                                   g.origin_x_m + g.width * g.cell_size_m, g.origin_y_m,
                                   g.origin_y_m + g.height * g.cell_size_m, g.cell_size_m);
  for (int iy = 0; iy < g.height; ++iy)
    for (int ix = 0; ix < g.width; ++ix) {
      const std::size_t i = g.index(ix, iy);
      const Eigen::Vector2d c = g.centre(ix, iy);
      mrpt::maps::THeightGridmapCell* cell = dem.cellByPos(c.x(), c.y());
      if (!cell || !std::isfinite(map.ground_z_m[i])) continue;
      cell->h = map.ground_z_m[i];
      cell->var = map.ground_sigma_m[i];
      cell->u = map.ground_z_m[i];
      cell->w = 1;
    }
  serializeGz(path, "height grid", dem);
}

std::vector<mrpt::opengl::CRenderizable::Ptr> sceneObjects(const NavMap& map) {
  std::vector<mrpt::opengl::CRenderizable::Ptr> out;
  const GridGeometry& g = map.grid;
  float lowest = std::numeric_limits<float>::infinity();
  for (float h : map.ground_z_m)
    if (std::isfinite(h)) lowest = std::min(lowest, h);
  if (!std::isfinite(lowest)) lowest = 0.0f;
  auto occupancy = mrpt::opengl::CSetOfObjects::Create();
  toGridMap(map).getVisualizationInto(*occupancy);
  occupancy->setName("navmap_occupancy");
  // A little below the lowest ground, so that the traversability points stay visible.
  occupancy->setLocation(0.0, 0.0, lowest - 0.02);
  out.push_back(occupancy);
  auto cloud = mrpt::opengl::CPointCloudColoured::Create();
  cloud->setName("navmap_traversability");
  cloud->setPointSize(3.0f);
  for (int iy = 0; iy < g.height; ++iy)
    for (int ix = 0; ix < g.width; ++ix) {
      const std::size_t i = g.index(ix, iy);
      if (map.state[i] == CellState::kUnknown || !std::isfinite(map.ground_z_m[i])) continue;
      const detail::Rgb c = detail::traversabilityColour(map, i);
      const Eigen::Vector2d p = g.centre(ix, iy);
      cloud->push_back(static_cast<float>(p.x()), static_cast<float>(p.y()), map.ground_z_m[i],
                       c[0] / 255.0f, c[1] / 255.0f, c[2] / 255.0f);
    }
  out.push_back(cloud);
  return out;
}

}  // namespace rgbdi::navmap
