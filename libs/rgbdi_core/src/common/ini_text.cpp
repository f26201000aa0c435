#include "rgbdi/common/ini_text.h"

#include <iomanip>
#include <sstream>

namespace rgbdi {

std::string iniNumber(double v) {
  for (int p = 6; p <= 17; ++p) {
    std::ostringstream t;
    t << std::setprecision(p) << v;
    double back = 0.0;
    std::istringstream(t.str()) >> back;
    if (back == v) return t.str();
  }
  std::ostringstream os;
  os << std::setprecision(17) << v;
  return os.str();
}

std::string iniNumbers(const Eigen::VectorXd& v) {
  std::string s;
  for (Eigen::Index i = 0; i < v.size(); ++i) s += (i ? " " : "") + iniNumber(v[i]);
  return s;
}

std::string iniDistortion(const PinholeCamera& camera) {
  std::string s;
  for (int i = 0; i < 5; ++i) s += (i ? " " : "") + iniNumber(camera.dist[i]);
  return s;
}

void iniLine(std::ostream& os, const std::string& key, const std::string& value,
             const std::string& comment) {
  std::string kv = key + " = " + value;
  if (kv.size() < 28) kv.resize(28, ' ');
  os << kv << " ; " << comment << "\n";
}

}  // namespace rgbdi
