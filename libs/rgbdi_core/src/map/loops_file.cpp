#include "map/loops_file.h"

#include <cerrno>
#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "map/file_io.h"
#include "mapping/pose_check.h"
#include "rgbdi/map/map_directory.h"

namespace rgbdi::map::detail {
namespace {

const std::string kVersionLine = "# rgbdi map loop edges, version ";

std::string formatDouble(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

}  // namespace

void writeLoopsFile(const std::string& path, const std::vector<MapLoopEdge>& loops) {
  std::string text = kVersionLine + std::to_string(kLoopsFileVersion) + "\n";
  text +=
      "# from_id to_id active r00 r01 r02 tx r10 r11 r12 ty r20 r21 r22 tz\n"
      "# T_from_to maps points of the `to` body frame into the `from` body frame [m];\n"
      "# active 0 = rolled back (kept for the record, not used)\n";
  for (const MapLoopEdge& e : loops) {
    text +=
        std::to_string(e.from_id) + " " + std::to_string(e.to_id) + " " + (e.active ? "1" : "0");
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) text += " " + formatDouble(e.T_from_to.matrix()(r, c));
    text += "\n";
  }
  writeDurably(path, text);
}

std::vector<MapLoopEdge> readLoopsFile(const std::string& path) {
  const std::vector<char> data = readWholeFile(path);
  std::istringstream is(std::string(data.begin(), data.end()));
  std::vector<MapLoopEdge> loops;
  std::string line;
  int line_no = 0;
  const auto fail = [&](const std::string& what) {
    throw MapError(path + ": line " + std::to_string(line_no) + ": " + what);
  };
  while (std::getline(is, line)) {
    ++line_no;
    if (line_no == 1) {
      if (line.rfind(kVersionLine, 0) != 0)
        fail("not an rgbdi loops file (first line is not \"" + kVersionLine + "N\")");
      const std::string v = line.substr(kVersionLine.size());
      if (v != std::to_string(kLoopsFileVersion))
        fail("unsupported loops file version " + v + " (this build reads version " +
             std::to_string(kLoopsFileVersion) + ")");
      continue;
    }
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    std::vector<std::string> tok;
    for (std::string t; fields >> t;) tok.push_back(t);
    if (tok.size() != 15)
      fail(std::to_string(tok.size()) + " fields, expected 15 (from_id to_id active + 12 numbers)");
    MapLoopEdge e;
    const auto id = [&](const std::string& s, const char* what) {
      char* end = nullptr;
      errno = 0;
      const unsigned long long v = std::strtoull(s.c_str(), &end, 10);
      if (s.empty() || s[0] == '-' || *end != '\0' || errno == ERANGE)
        fail(std::string("bad ") + what + " \"" + s + "\"");
      return static_cast<std::uint64_t>(v);
    };
    e.from_id = id(tok[0], "from_id");
    e.to_id = id(tok[1], "to_id");
    if (tok[2] != "0" && tok[2] != "1") fail("active flag \"" + tok[2] + "\" is not 0 or 1");
    e.active = tok[2] == "1";
    for (int k = 0; k < 12; ++k) {
      const std::string& s = tok[static_cast<std::size_t>(3 + k)];
      char* end = nullptr;
      const double v = std::strtod(s.c_str(), &end);
      if (*end != '\0') fail("bad number \"" + s + "\"");
      e.T_from_to.matrix()(k / 4, k % 4) = v;
    }
    if (!mapping::detail::isRigid(e.T_from_to))
      fail("T_from_to of loop " + tok[0] + " -> " + tok[1] + " is not a finite rigid transform");
    loops.push_back(e);
  }
  if (line_no == 0) throw MapError(path + ": empty file (no version line)");
  return loops;
}

}  // namespace rgbdi::map::detail
