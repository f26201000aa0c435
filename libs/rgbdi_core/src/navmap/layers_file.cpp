// navmap_layers.yml.gz: every layer as an OpenCV matrix (rows = iy), readable with
// cv::FileStorage in C++ and Python (which open a .gz file as such). Compressed because most
// cells of a large grid are unknown (NaN): a quarter of the size.
#include <mrpt/io/CFileGZOutputStream.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <opencv2/core.hpp>

#include "rgbdi/common/atomic_file.h"
#include "rgbdi/navmap/navmap_files.h"

namespace rgbdi::navmap {
namespace {

template <typename T>
cv::Mat asMat(const GridGeometry& g, const std::vector<T>& v, int type) {
  return cv::Mat(g.height, g.width, type, const_cast<T*>(v.data())).clone();
}

template <typename T>
void fromMat(const std::string& path, const cv::FileStorage& fs, const char* name, int type,
             const GridGeometry& g, std::vector<T>* out) {
  cv::Mat m;
  fs[name] >> m;
  if (m.empty() || m.rows != g.height || m.cols != g.width || m.type() != type)
    throw IoError(path + ": layer " + name + " missing or not " + std::to_string(g.height) + " x " +
                  std::to_string(g.width) + " of the expected type");
  out->assign(m.ptr<T>(0), m.ptr<T>(0) + g.cellCount());
}

}  // namespace

void writeLayers(const NavMap& map, const std::string& path) {
  const GridGeometry& g = map.grid;
  cv::FileStorage fs(".yml", cv::FileStorage::WRITE | cv::FileStorage::MEMORY |
                                 cv::FileStorage::FORMAT_YAML | cv::FileStorage::BASE64);
  fs << "origin_x_m" << g.origin_x_m << "origin_y_m" << g.origin_y_m << "cell_size_m"
     << g.cell_size_m << "width" << g.width << "height" << g.height;
  fs << "states"
     << "0 unknown, 1 free, 2 obstacle, 3 too steep, 4 step edge, 5 raised, 6 lowered";
  fs << "ground_z_m" << asMat(g, map.ground_z_m, CV_32F);
  fs << "ground_sigma_m" << asMat(g, map.ground_sigma_m, CV_32F);
  fs << "slope_deg" << asMat(g, map.slope_deg, CV_32F);
  fs << "step_m" << asMat(g, map.step_m, CV_32F);
  fs << "roughness_m" << asMat(g, map.roughness_m, CV_32F);
  fs << "traversability" << asMat(g, map.traversability, CV_32F);
  std::vector<std::uint8_t> state(map.state.size());
  for (std::size_t i = 0; i < state.size(); ++i) state[i] = static_cast<std::uint8_t>(map.state[i]);
  fs << "state" << asMat(g, state, CV_8U);
  fs << "driven" << asMat(g, map.driven, CV_8U);
  const std::string text = fs.releaseAndGetString();
  const bool gz = path.size() > 3 && path.compare(path.size() - 3, 3, ".gz") == 0;
  if (!gz) {
    writeFileAtomically(path, [&](std::ostream& os) { os << text; });
    return;
  }
  writeFileAtomicallyVia(path, [&](const std::string& tmp) {
    mrpt::io::CFileGZOutputStream out;
    if (!out.open(tmp)) throw IoError(path + ": cannot create the compressed layers file");
    if (out.Write(text.data(), text.size()) != text.size())
      throw IoError(path + ": cannot write the compressed layers file");
    out.close();
  });
}

NavMap readLayers(const std::string& path) {
  NavMap m;
  // Checked first: OpenCV would also log its own error line for a missing file.
  if (!std::ifstream(path).good()) throw IoError(path + ": cannot open");
  cv::FileStorage fs;
  try {
    if (!fs.open(path, cv::FileStorage::READ | cv::FileStorage::FORMAT_YAML))
      throw IoError(path + ": cannot open");
  } catch (const cv::Exception& e) {
    throw IoError(path + ": not a navigation-map layers file: " + e.what());
  }
  GridGeometry& g = m.grid;
  try {
    fs["origin_x_m"] >> g.origin_x_m;
    fs["origin_y_m"] >> g.origin_y_m;
    fs["cell_size_m"] >> g.cell_size_m;
    fs["width"] >> g.width;
    fs["height"] >> g.height;
    if (!(g.cell_size_m > 0) || g.width <= 0 || g.height <= 0)
      throw IoError(path + ": bad grid geometry (cell_size_m, width, height)");
    fromMat(path, fs, "ground_z_m", CV_32F, g, &m.ground_z_m);
    fromMat(path, fs, "ground_sigma_m", CV_32F, g, &m.ground_sigma_m);
    fromMat(path, fs, "slope_deg", CV_32F, g, &m.slope_deg);
    fromMat(path, fs, "step_m", CV_32F, g, &m.step_m);
    fromMat(path, fs, "roughness_m", CV_32F, g, &m.roughness_m);
    fromMat(path, fs, "traversability", CV_32F, g, &m.traversability);
    std::vector<std::uint8_t> state;
    fromMat(path, fs, "state", CV_8U, g, &state);
    m.state.resize(state.size());
    for (std::size_t i = 0; i < state.size(); ++i) {
      if (state[i] > static_cast<std::uint8_t>(CellState::kLowered))
        throw IoError(path + ": state of cell " + std::to_string(i) + " is " +
                      std::to_string(state[i]) + " (0..6)");
      m.state[i] = static_cast<CellState>(state[i]);
    }
    fromMat(path, fs, "driven", CV_8U, g, &m.driven);
  } catch (const cv::Exception& e) {
    throw IoError(path + ": " + e.what());
  }
  m.path_height_m = std::numeric_limits<double>::quiet_NaN();
  return m;
}

}  // namespace rgbdi::navmap
