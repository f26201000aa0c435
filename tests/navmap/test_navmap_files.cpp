// Navigation-map files written and read back cell by cell: ROS map_server YAML + PGM (read as
// map_server reads them), MRPT COccupancyGridMap2D and CHeightGridMap2D (read as MRPT tools
// load them), the layers file, the pictures; bad YAML refused naming the file and the key.
#include <gtest/gtest.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/maps/CHeightGridMap2D.h>
#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/serialization/CArchive.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "rgbdi/common/atomic_file.h"
#include "rgbdi/navmap/navmap_files.h"

using namespace rgbdi::navmap;
namespace fs = std::filesystem;

namespace {

/// A small map with every state: floor, a box (obstacle ring, raised top), a hole, unknown.
NavMap sampleMap() {
  std::vector<Eigen::Vector3f> pts;
  auto flat = [&](double x0, double x1, double y0, double y1, double z) {
    for (double x = x0 + 0.00625; x < x1; x += 0.0125)
      for (double y = y0 + 0.00625; y < y1; y += 0.0125) pts.emplace_back(x, y, z);
  };
  flat(-0.5, 1.5, -0.5, 1.0, 0.0);
  for (double z = 0; z <= 0.3; z += 0.01) flat(0.6, 0.65, 0.6, 0.65, z);
  flat(0.2, 0.3, 0.6, 0.7, -0.2);  // a hole's bottom (its floor removed below)
  std::vector<Eigen::Vector3f> kept;
  for (const auto& p : pts)
    if (!(p.z() == 0.0f && p.x() > 0.2 && p.x() < 0.3 && p.y() > 0.6 && p.y() < 0.7))
      kept.push_back(p);
  std::vector<Eigen::Vector3d> path{{0.0, 0.0, 0.3}, {1.0, 0.0, 0.3}};
  NavMapOptions o;
  o.range_m = 1.0;
  return buildNavMap(kept, path, o);
}

std::string tempDir(const std::string& name) {
  const fs::path d =
      fs::temp_directory_path() / ("rgbdi_navmap_" + name + "_" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d.string();
}

}  // namespace

TEST(NavMapFiles, RosMapRoundTripsCellByCell) {
  const NavMap m = sampleMap();
  ASSERT_GT(m.count(CellState::kFree), 0u);
  ASSERT_GT(m.count(CellState::kObstacle), 0u);
  ASSERT_GT(m.count(CellState::kLowered), 0u);
  ASSERT_GT(m.count(CellState::kUnknown), 0u);
  const std::string dir = tempDir("ros");
  writeRosMap(m, dir + "/map.yaml", dir + "/map.pgm");
  const RosMap r = readRosMap(dir + "/map.yaml");
  EXPECT_EQ(r.grid.width, m.grid.width);
  EXPECT_EQ(r.grid.height, m.grid.height);
  EXPECT_DOUBLE_EQ(r.grid.cell_size_m, m.grid.cell_size_m);
  EXPECT_NEAR(r.grid.origin_x_m, m.grid.origin_x_m, 1e-9);
  EXPECT_NEAR(r.grid.origin_y_m, m.grid.origin_y_m, 1e-9);
  EXPECT_FALSE(r.negate);
  EXPECT_EQ(r.occupied_thresh, 0.65);
  EXPECT_EQ(r.free_thresh, 0.196);
  ASSERT_EQ(r.occupancy.size(), m.grid.cellCount());
  for (std::size_t i = 0; i < r.occupancy.size(); ++i)
    ASSERT_EQ(r.occupancy[i], m.occupancy(i)) << "cell " << i;
  std::ifstream yaml(dir + "/map.yaml");
  std::string first;
  std::getline(yaml, first);
  EXPECT_EQ(first, "image: map.pgm");  // relative to the YAML, as map_server resolves it
  fs::remove_all(dir);
}

TEST(NavMapFiles, RosMapReadWithMapServerSemanticsGivesTheGridBack) {
  // map_server's image_loader (ROS 1 map_server, Nav2 map_io; map_server itself is not
  // installable here): pixel value v, with negate p = v / 255 else p = (255 - v) / 255;
  // occupied (100) when p > occupied_thresh, free (0) when p < free_thresh, else unknown (-1)
  // in trinary mode; image row r is map row height - 1 - r; origin = the lower-left pixel's
  // outer corner. Decoded here independently of readRosMap with OpenCV.
  const NavMap m = sampleMap();
  const std::string dir = tempDir("rossemantics");
  writeRosMap(m, dir + "/map.yaml", dir + "/map.pgm");
  const cv::Mat image = cv::imread(dir + "/map.pgm", cv::IMREAD_UNCHANGED);
  ASSERT_EQ(image.type(), CV_8UC1);
  ASSERT_EQ(image.cols, m.grid.width);
  ASSERT_EQ(image.rows, m.grid.height);
  auto mapServerValue = [&](int x, int map_row) {  // negate: 0 (as written)
    const double v = image.at<unsigned char>(image.rows - 1 - map_row, x);
    const double p = (255.0 - v) / 255.0;
    return p > 0.65 ? kOccOccupied : (p < 0.196 ? kOccFree : kOccUnknown);
  };
  for (int y = 0; y < m.grid.height; ++y)
    for (int x = 0; x < m.grid.width; ++x)
      ASSERT_EQ(mapServerValue(x, y), m.occupancy(m.grid.index(x, y))) << x << " " << y;
  // The origin places the cells in the world: the box at (0.625, 0.625) is occupied, the path's
  // start (0, 0) free.
  const RosMap r = readRosMap(dir + "/map.yaml");
  auto at = [&](double wx, double wy) {
    const int x = static_cast<int>(std::floor((wx - r.grid.origin_x_m) / r.grid.cell_size_m));
    const int y = static_cast<int>(std::floor((wy - r.grid.origin_y_m) / r.grid.cell_size_m));
    return mapServerValue(x, y);
  };
  EXPECT_EQ(at(0.625, 0.625), kOccOccupied);
  EXPECT_EQ(at(0.0, 0.0), kOccFree);
  // The same grid written negated (negate: 1, pixels inverted) reads back the same.
  cv::Mat inverted = 255 - image;
  ASSERT_TRUE(cv::imwrite(dir + "/neg.pgm", inverted));
  std::ifstream yaml_in(dir + "/map.yaml");
  std::string yaml((std::istreambuf_iterator<char>(yaml_in)), {});
  yaml.replace(yaml.find("image: map.pgm"), 14, "image: neg.pgm");
  yaml.replace(yaml.find("negate: 0"), 9, "negate: 1");
  std::ofstream(dir + "/neg.yaml") << yaml;
  const RosMap negated = readRosMap(dir + "/neg.yaml");
  EXPECT_TRUE(negated.negate);
  EXPECT_EQ(negated.occupancy, r.occupancy);
  fs::remove_all(dir);
}

TEST(NavMapFiles, RosMapReaderNamesTheFileAndKey) {
  const std::string dir = tempDir("rosbad");
  std::ofstream(dir + "/bad.yaml") << "image: x.pgm\nresolution: abc\norigin: [0, 0, 0]\n";
  try {
    readRosMap(dir + "/bad.yaml");
    FAIL() << "no error";
  } catch (const rgbdi::IoError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.yaml: resolution: not a number"), std::string::npos)
        << e.what();
  }
  std::ofstream(dir + "/noimg.yaml") << "image: missing.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n";
  EXPECT_THROW(readRosMap(dir + "/noimg.yaml"), rgbdi::IoError);
  fs::remove_all(dir);
}

TEST(NavMapFiles, MrptGridMapsLoadAsMrptToolsLoadThem) {
  const NavMap m = sampleMap();
  const std::string dir = tempDir("mrpt");
  writeMrptOccupancyGrid(m, dir + "/m.gridmap");
  writeMrptHeightMap(m, dir + "/h.gridmap");
  mrpt::maps::COccupancyGridMap2D grid;
  {
    mrpt::io::CFileGZInputStream in(dir + "/m.gridmap");
    mrpt::serialization::archiveFrom(in) >> grid;
  }
  ASSERT_EQ(grid.getSizeX(), static_cast<unsigned>(m.grid.width));
  ASSERT_EQ(grid.getSizeY(), static_cast<unsigned>(m.grid.height));
  EXPECT_NEAR(grid.getResolution(), m.grid.cell_size_m, 1e-6);
  mrpt::maps::CHeightGridMap2D dem;
  {
    mrpt::io::CFileGZInputStream in(dir + "/h.gridmap");
    mrpt::serialization::archiveFrom(in) >> dem;
  }
  for (int iy = 0; iy < m.grid.height; ++iy)
    for (int ix = 0; ix < m.grid.width; ++ix) {
      const std::size_t i = m.grid.index(ix, iy);
      const Eigen::Vector2d c = m.grid.centre(ix, iy);
      const float free = grid.getPos(static_cast<float>(c.x()), static_cast<float>(c.y()));
      if (m.occupancy(i) == kOccFree) {
        ASSERT_GT(free, 0.95f) << ix << " " << iy;
      }
      if (m.occupancy(i) == kOccOccupied) {
        ASSERT_LT(free, 0.05f) << ix << " " << iy;
      }
      if (m.occupancy(i) == kOccUnknown) {
        ASSERT_NEAR(free, 0.5f, 0.01f) << ix << " " << iy;
      }
      const mrpt::maps::THeightGridmapCell* h = dem.cellByPos(c.x(), c.y());
      ASSERT_NE(h, nullptr);
      if (std::isfinite(m.ground_z_m[i])) {
        ASSERT_EQ(h->w, 1u);
        ASSERT_EQ(h->h, m.ground_z_m[i]);
      } else {
        ASSERT_EQ(h->w, 0u);
      }
    }
  fs::remove_all(dir);
}

TEST(NavMapFiles, LayersFileRoundTrips) {
  const NavMap m = sampleMap();
  const std::string dir = tempDir("layers");
  writeLayers(m, dir + "/l.yml");
  const NavMap r = readLayers(dir + "/l.yml");
  EXPECT_EQ(r.grid.width, m.grid.width);
  EXPECT_EQ(r.grid.origin_x_m, m.grid.origin_x_m);
  EXPECT_EQ(r.state, m.state);
  EXPECT_EQ(r.driven, m.driven);
  auto same = [](const std::vector<float>& a, const std::vector<float>& b) {
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i)
      if (!(a[i] == b[i] || (std::isnan(a[i]) && std::isnan(b[i])))) return false;
    return true;
  };
  EXPECT_TRUE(same(r.ground_z_m, m.ground_z_m));
  EXPECT_TRUE(same(r.traversability, m.traversability));
  EXPECT_TRUE(same(r.slope_deg, m.slope_deg));
  // Compressed (the name ends in .gz): the same layers, a smaller file.
  writeLayers(m, dir + "/l.yml.gz");
  const NavMap z = readLayers(dir + "/l.yml.gz");
  EXPECT_EQ(z.state, m.state);
  EXPECT_TRUE(same(z.ground_z_m, m.ground_z_m));
  EXPECT_LT(fs::file_size(dir + "/l.yml.gz"), fs::file_size(dir + "/l.yml") / 2);
  std::ofstream(dir + "/bad.yml") << "%YAML:1.0\n---\nwidth: 3\n";
  EXPECT_THROW(readLayers(dir + "/bad.yml"), rgbdi::IoError);
  fs::remove_all(dir);
}

TEST(NavMapFiles, AllFilesAndPicturesAreWritten) {
  const NavMap m = sampleMap();
  const std::string dir = tempDir("all");
  const std::vector<Eigen::Vector3d> path{{0.0, 0.0, 0.3}, {1.0, 0.0, 0.3}};
  const auto files = writeNavMapFiles(m, dir, &path);
  EXPECT_EQ(files.size(), 7u);
  for (const auto& [name, file] : files) EXPECT_TRUE(fs::exists(file)) << name;
  const cv::Mat png = cv::imread(dir + "/navmap.png");
  ASSERT_EQ(png.rows, m.grid.height);
  ASSERT_EQ(png.cols, m.grid.width);
  // The obstacle cell at (0.625, 0.625) is black, +y up.
  int ix = 0, iy = 0;
  ASSERT_TRUE(m.grid.cellOf(0.625, 0.625, &ix, &iy));
  EXPECT_EQ(png.at<cv::Vec3b>(m.grid.height - 1 - iy, ix), cv::Vec3b(0, 0, 0));
  const cv::Mat trav = cv::imread(dir + "/navmap_traversability.png");
  EXPECT_EQ(trav.rows, m.grid.height);
  for (const auto& e : fs::directory_iterator(dir))
    EXPECT_EQ(e.path().string().find(".tmp."), std::string::npos) << e.path();
  fs::remove_all(dir);
}
