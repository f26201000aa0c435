// Files of the navigation maps (doc/navigation-maps.md), every one written atomically (a planner
// reading one while a live run rewrites it sees the old or the new file, never a part):
//  * ROS map_server: NAME.yaml + NAME.pgm (trinary: free 254, occupied 0, unknown 205; negate 0,
//    occupied_thresh 0.65, free_thresh 0.196; origin = the outer corner of the lower-left cell);
//  * MRPT: NAME.gridmap (mrpt::maps::COccupancyGridMap2D, gzip-serialized, as pf-localization and
//    CMultiMetricMap load it; free 1, occupied 0, unknown 0.5) and NAME_height.gridmap
//    (mrpt::maps::CHeightGridMap2D: h = ground height, var = its standard deviation, w = 1 where
//    known);
//  * NAME_layers.yml.gz: every layer of the elevation grid (OpenCV FileStorage, base64
//    matrices, gzip-compressed);
//  * NAME.png and NAME_traversability.png: pictures for people (north = +y up).
// Failures throw IoError naming the file.
#pragma once

#include <mrpt/opengl/CRenderizable.h>

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "rgbdi/navmap/nav_map.h"

namespace rgbdi::navmap {

/// A map as ROS map_server reads it: geometry and trinary occupancy (kOcc* values).
struct RosMap {
  GridGeometry grid;
  std::vector<std::int8_t> occupancy;
  double occupied_thresh = 0.65;
  double free_thresh = 0.196;
  bool negate = false;
};

void writeRosMap(const NavMap& map, const std::string& yaml_path, const std::string& pgm_path);
/// Reads a map_server YAML (keys image, resolution, origin, negate, occupied_thresh, free_thresh,
/// optional mode = trinary) and its PGM (P5, 8 bit) as map_server interprets them. Throws
/// IoError naming the file and the key or line that is wrong.
RosMap readRosMap(const std::string& yaml_path);

void writeMrptOccupancyGrid(const NavMap& map, const std::string& path);
void writeMrptHeightMap(const NavMap& map, const std::string& path);

/// Gzip-compressed when the path ends in .gz (readLayers reads both).
void writeLayers(const NavMap& map, const std::string& path);
/// Reads writeLayers' file back (every layer, geometry and state; not `driven`, which it stores
/// too, nor path_height_m). Throws IoError naming the file.
NavMap readLayers(const std::string& path);

/// Colours per state (free white, obstacle black, too steep orange, step edge red, raised dark
/// red, lowered blue, unknown grey), the path in green when given.
void writeOccupancyPicture(const NavMap& map, const std::string& path,
                           const std::vector<Eigen::Vector3d>* robot_path = nullptr);
/// Traversability from red (0) through yellow to green (1); not traversable black, unknown grey.
void writeTraversabilityPicture(const NavMap& map, const std::string& path);

/// Objects for scene.3Dscene: "navmap_occupancy" (the grid as MRPT draws a
/// COccupancyGridMap2D, at the lowest ground height) and "navmap_traversability" (a point per
/// known cell at its ground height, coloured as in the picture).
std::vector<mrpt::opengl::CRenderizable::Ptr> sceneObjects(const NavMap& map);

/// Writes all files into dir as STEM.yaml, STEM.pgm, STEM.gridmap, STEM_height.gridmap,
/// STEM_layers.yml.gz, STEM.png, STEM_traversability.png; returns (output name, path) pairs, the
/// names STEM_yaml, STEM_pgm, STEM_gridmap, STEM_height_gridmap, STEM_layers, STEM_png,
/// STEM_traversability_png.
std::vector<std::pair<std::string, std::string>> writeNavMapFiles(
    const NavMap& map, const std::string& dir, const std::vector<Eigen::Vector3d>* robot_path,
    const std::string& stem = "navmap");

}  // namespace rgbdi::navmap
