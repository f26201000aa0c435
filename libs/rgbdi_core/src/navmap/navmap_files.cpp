// Pictures and the whole set of navigation-map files.
#include "rgbdi/navmap/navmap_files.h"

#include <opencv2/imgcodecs.hpp>

#include "navmap/colours.h"
#include "rgbdi/common/atomic_file.h"

namespace rgbdi::navmap {
namespace {

void writePng(const std::string& path, const cv::Mat& image) {
  std::vector<unsigned char> png;
  if (!cv::imencode(".png", image, png)) throw IoError(path + ": cannot encode the PNG");
  writeFileAtomically(path, [&](std::ostream& os) {
    os.write(reinterpret_cast<const char*>(png.data()), static_cast<std::streamsize>(png.size()));
  });
}

/// A BGR image of the grid, +y up, one pixel per cell.
cv::Mat picture(const NavMap& m, const std::function<detail::Rgb(std::size_t)>& colour) {
  const GridGeometry& g = m.grid;
  cv::Mat image(g.height, g.width, CV_8UC3);
  for (int iy = 0; iy < g.height; ++iy)
    for (int ix = 0; ix < g.width; ++ix) {
      const detail::Rgb c = colour(g.index(ix, iy));
      image.at<cv::Vec3b>(g.height - 1 - iy, ix) = cv::Vec3b(c[2], c[1], c[0]);
    }
  return image;
}

}  // namespace

void writeOccupancyPicture(const NavMap& map, const std::string& path,
                           const std::vector<Eigen::Vector3d>* robot_path) {
  cv::Mat image = picture(map, [&](std::size_t i) { return detail::stateColour(map.state[i]); });
  if (robot_path)
    for (const Eigen::Vector3d& p : *robot_path) {
      int ix = 0, iy = 0;
      if (map.grid.cellOf(p.x(), p.y(), &ix, &iy))
        image.at<cv::Vec3b>(map.grid.height - 1 - iy, ix) = cv::Vec3b(0, 170, 0);
    }
  writePng(path, image);
}

void writeTraversabilityPicture(const NavMap& map, const std::string& path) {
  writePng(path, picture(map, [&](std::size_t i) { return detail::traversabilityColour(map, i); }));
}

std::vector<std::pair<std::string, std::string>> writeNavMapFiles(
    const NavMap& map, const std::string& dir, const std::vector<Eigen::Vector3d>* robot_path,
    const std::string& name) {
  std::vector<std::pair<std::string, std::string>> out;
  const std::string stem = dir + "/" + name;
  // The image first: a planner that sees the new YAML finds the image it names complete.
  writeRosMap(map, stem + ".yaml", stem + ".pgm");
  out.emplace_back(name + "_yaml", stem + ".yaml");
  out.emplace_back(name + "_pgm", stem + ".pgm");
  writeMrptOccupancyGrid(map, stem + ".gridmap");
  out.emplace_back(name + "_gridmap", stem + ".gridmap");
  writeMrptHeightMap(map, stem + "_height.gridmap");
  out.emplace_back(name + "_height_gridmap", stem + "_height.gridmap");
  writeLayers(map, stem + "_layers.yml.gz");
  out.emplace_back(name + "_layers", stem + "_layers.yml.gz");
  writeOccupancyPicture(map, stem + ".png", robot_path);
  out.emplace_back(name + "_png", stem + ".png");
  writeTraversabilityPicture(map, stem + "_traversability.png");
  out.emplace_back(name + "_traversability_png", stem + "_traversability.png");
  return out;
}

}  // namespace rgbdi::navmap
