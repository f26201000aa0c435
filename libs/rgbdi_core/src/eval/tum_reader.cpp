#include "rgbdi/eval/tum_reader.h"

#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "rgbdi/eval/eval_error.h"

namespace rgbdi::eval {
namespace {

constexpr std::size_t kFieldsPerLine = 8;  // t tx ty tz qx qy qz qw
constexpr std::size_t kQuotedTextMax = 120;

std::string trim(const std::string& s) {
  const auto first = s.find_first_not_of(" \t\r\n");
  if (first == std::string::npos) return {};
  const auto last = s.find_last_not_of(" \t\r\n");
  return s.substr(first, last - first + 1);
}

std::string quoted(const std::string& line) {
  if (line.size() <= kQuotedTextMax) return "'" + line + "'";
  return "'" + line.substr(0, kQuotedTextMax) + "...'";
}

[[noreturn]] void fail(const std::string& path, std::size_t line_no, const std::string& what,
                       const std::string& line) {
  std::ostringstream msg;
  msg << path << ":" << line_no << ": " << what << ": " << quoted(line);
  throw EvalError(msg.str());
}

// Splits on commas first (so "a, b" and "a,b" both work, while "a,,b" is an empty field), then on
// whitespace inside each comma-separated piece.
bool splitFields(const std::string& line, std::vector<std::string>& fields) {
  fields.clear();
  std::vector<std::string> pieces;
  if (line.find(',') == std::string::npos) {
    pieces.push_back(line);
  } else {
    std::size_t start = 0;
    while (true) {
      const auto comma = line.find(',', start);
      pieces.push_back(trim(line.substr(start, comma - start)));
      if (pieces.back().empty()) return false;
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
  }
  for (const auto& piece : pieces) {
    std::istringstream is(piece);
    std::string token;
    while (is >> token) fields.push_back(token);
  }
  return true;
}

// Locale-independent, whole-token number parsing (std::from_chars rejects a leading '+').
bool parseNumber(const std::string& token, double& value) {
  const char* begin = token.data();
  const char* end = token.data() + token.size();
  if (begin != end && *begin == '+') ++begin;
  const auto [ptr, ec] = std::from_chars(begin, end, value);
  return ec == std::errc() && ptr == end;
}

}  // namespace

Trajectory readTum(const std::string& path, const TumReadOptions& options) {
  std::ifstream in(path);
  if (!in) throw EvalError(path + ": cannot open trajectory file");

  Trajectory traj;
  std::string raw;
  std::vector<std::string> fields;
  std::size_t line_no = 0;
  std::size_t previous_line_no = 0;
  while (std::getline(in, raw)) {
    ++line_no;
    const std::string line = trim(raw);
    if (line.empty() || line[0] == '#') continue;

    if (!splitFields(line, fields)) fail(path, line_no, "empty field between separators", line);
    if (fields.size() != kFieldsPerLine) {
      fail(path, line_no,
           "expected 8 values (timestamp tx ty tz qx qy qz qw), found " +
               std::to_string(fields.size()),
           line);
    }
    double v[kFieldsPerLine];
    for (std::size_t k = 0; k < kFieldsPerLine; ++k) {
      if (!parseNumber(fields[k], v[k])) {
        fail(path, line_no,
             "value " + std::to_string(k + 1) + " '" + fields[k] + "' is not a number", line);
      }
      if (!std::isfinite(v[k])) {
        fail(path, line_no, "value " + std::to_string(k + 1) + " is not finite (NaN or inf)", line);
      }
    }

    StampedPose pose;
    pose.t = v[0];
    pose.p = Eigen::Vector3d(v[1], v[2], v[3]);
    pose.q = Eigen::Quaterniond(v[7], v[4], v[5], v[6]);  // Eigen: (w, x, y, z)
    const double norm = pose.q.norm();
    if (std::abs(norm - 1.0) > options.quaternion_norm_tolerance) {
      std::ostringstream what;
      what << "quaternion norm " << norm << " is not close to 1 (tolerance "
           << options.quaternion_norm_tolerance << ")";
      fail(path, line_no, what.str(), line);
    }
    pose.q.normalize();

    if (!traj.empty() && pose.t <= traj.back().t) {
      std::ostringstream what;
      what.precision(17);
      what << "timestamp " << pose.t << " is not larger than " << traj.back().t << " on line "
           << previous_line_no << " (timestamps must be strictly increasing)";
      fail(path, line_no, what.str(), line);
    }
    traj.push_back(pose);
    previous_line_no = line_no;
  }
  if (in.bad()) throw EvalError(path + ": read error after line " + std::to_string(line_no));
  if (traj.empty()) throw EvalError(path + ": contains no poses (only comments or blank lines)");
  return traj;
}

}  // namespace rgbdi::eval
