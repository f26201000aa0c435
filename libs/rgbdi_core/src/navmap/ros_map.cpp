// ROS map_server YAML + PGM (trinary).
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "rgbdi/common/atomic_file.h"
#include "rgbdi/navmap/navmap_files.h"

namespace rgbdi::navmap {
namespace {

constexpr unsigned char kPgmFree = 254, kPgmOccupied = 0, kPgmUnknown = 205;

std::string number(double v) {
  std::ostringstream os;
  os.precision(10);
  os << v;
  return os.str();
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\"'");
  if (b == std::string::npos) return {};
  return s.substr(b, s.find_last_not_of(" \t\r\"'") - b + 1);
}

std::string baseName(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

std::string dirName(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? std::string(".") : path.substr(0, slash);
}

double toNumber(const std::string& file, const std::string& key, const std::string& text) {
  std::size_t used = 0;
  double v = 0;
  try {
    v = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || trim(text.substr(used)).size() > 0 || !std::isfinite(v))
    throw IoError(file + ": " + key + ": not a number: '" + text + "'");
  return v;
}

}  // namespace

void writeRosMap(const NavMap& map, const std::string& yaml_path, const std::string& pgm_path) {
  const GridGeometry& g = map.grid;
  writeFileAtomically(pgm_path, [&](std::ostream& os) {
    os << "P5\n# rgbdi navigation map: free 254, occupied 0, unknown 205\n"
       << g.width << " " << g.height << "\n255\n";
    std::string row(static_cast<std::size_t>(g.width), '\0');
    for (int iy = g.height - 1; iy >= 0; --iy) {  // image row 0 is the largest y
      for (int ix = 0; ix < g.width; ++ix) {
        const std::int8_t o = map.occupancy(g.index(ix, iy));
        row[static_cast<std::size_t>(ix)] = static_cast<char>(
            o == kOccFree ? kPgmFree : (o == kOccOccupied ? kPgmOccupied : kPgmUnknown));
      }
      os.write(row.data(), static_cast<std::streamsize>(row.size()));
    }
  });
  // The image is named relative to the YAML when both are in one directory (map_server resolves
  // it against the YAML's directory).
  const std::string image = dirName(pgm_path) == dirName(yaml_path) ? baseName(pgm_path) : pgm_path;
  writeFileAtomically(yaml_path, [&](std::ostream& os) {
    os << "image: " << image << "\n"
       << "mode: trinary\n"
       << "resolution: " << number(g.cell_size_m) << "\n"
       << "origin: [" << number(g.origin_x_m) << ", " << number(g.origin_y_m) << ", 0.0]\n"
       << "negate: 0\n"
       << "occupied_thresh: 0.65\n"
       << "free_thresh: 0.196\n";
  });
}

RosMap readRosMap(const std::string& yaml_path) {
  std::ifstream in(yaml_path);
  if (!in) throw IoError(yaml_path + ": cannot open");
  RosMap m;
  std::string image;
  bool have_res = false, have_origin = false;
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    const std::string s = trim(line.substr(0, line.find('#')));
    if (s.empty()) continue;
    const auto colon = s.find(':');
    if (colon == std::string::npos)
      throw IoError(yaml_path + " line " + std::to_string(n) + ": not 'key: value': " + line);
    const std::string key = trim(s.substr(0, colon)), value = trim(s.substr(colon + 1));
    if (key == "image") {
      image = value;
    } else if (key == "resolution") {
      m.grid.cell_size_m = toNumber(yaml_path, key, value);
      if (!(m.grid.cell_size_m > 0)) throw IoError(yaml_path + ": resolution must be positive");
      have_res = true;
    } else if (key == "origin") {
      const auto a = value.find('['), b = value.find(']');
      if (a == std::string::npos || b == std::string::npos || b < a)
        throw IoError(yaml_path + ": origin: expected [x, y, yaw]: " + value);
      std::stringstream ss(value.substr(a + 1, b - a - 1));
      std::string item;
      double v[3] = {0, 0, 0};
      int k = 0;
      while (std::getline(ss, item, ',')) {
        if (k == 3) throw IoError(yaml_path + ": origin: more than 3 values");
        v[k++] = toNumber(yaml_path, key, trim(item));
      }
      if (k != 3)
        throw IoError(yaml_path + ": origin: expected 3 values, got " + std::to_string(k));
      m.grid.origin_x_m = v[0];
      m.grid.origin_y_m = v[1];
      have_origin = true;
    } else if (key == "negate") {
      m.negate = toNumber(yaml_path, key, value) != 0.0;
    } else if (key == "occupied_thresh") {
      m.occupied_thresh = toNumber(yaml_path, key, value);
    } else if (key == "free_thresh") {
      m.free_thresh = toNumber(yaml_path, key, value);
    } else if (key == "mode" && value != "trinary") {
      throw IoError(yaml_path + ": mode '" + value + "': only trinary maps are read");
    }
  }
  if (image.empty() || !have_res || !have_origin)
    throw IoError(yaml_path + ": needs the keys image, resolution and origin");
  const std::string pgm = image[0] == '/' ? image : dirName(yaml_path) + "/" + image;
  std::ifstream p(pgm, std::ios::binary);
  if (!p) throw IoError(pgm + ": cannot open (image of " + yaml_path + ")");
  std::string magic;
  p >> magic;
  auto field = [&](const char* what) {
    p >> std::ws;
    while (p.peek() == '#') {
      std::string comment;
      std::getline(p, comment);
      p >> std::ws;
    }
    long v = -1;
    if (!(p >> v) || v <= 0 || v > 1000000) throw IoError(pgm + ": bad PGM " + what);
    return v;
  };
  if (magic != "P5") throw IoError(pgm + ": not a binary PGM (P5)");
  m.grid.width = static_cast<int>(field("width"));
  m.grid.height = static_cast<int>(field("height"));
  if (field("maximum value") != 255) throw IoError(pgm + ": only 8-bit PGMs are read");
  p.get();  // the single whitespace before the pixels
  std::string pixels(m.grid.cellCount(), '\0');
  if (!p.read(pixels.data(), static_cast<std::streamsize>(pixels.size())))
    throw IoError(pgm + ": fewer pixels than width x height");
  m.occupancy.assign(m.grid.cellCount(), kOccUnknown);
  for (int row = 0; row < m.grid.height; ++row)
    for (int ix = 0; ix < m.grid.width; ++ix) {
      const double v = static_cast<unsigned char>(
          pixels[static_cast<std::size_t>(row) * static_cast<std::size_t>(m.grid.width) +
                 static_cast<std::size_t>(ix)]);
      const double occ = m.negate ? v / 255.0 : (255.0 - v) / 255.0;  // map_server's reading
      std::int8_t o = kOccUnknown;
      if (occ > m.occupied_thresh)
        o = kOccOccupied;
      else if (occ < m.free_thresh)
        o = kOccFree;
      m.occupancy[m.grid.index(ix, m.grid.height - 1 - row)] = o;
    }
  return m;
}

}  // namespace rgbdi::navmap
