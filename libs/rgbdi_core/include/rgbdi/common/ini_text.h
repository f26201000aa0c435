// Writing rgbdi INI text (the inverse of IniReader): used wherever a config file is generated
// (the simulator's config.ini, the VINS yaml conversion), so that all generated files share the
// layout of share/config.ini and read back to the same numbers.
#pragma once

#include <Eigen/Core>
#include <ostream>
#include <string>

#include "rgbdi/common/camera.h"

namespace rgbdi {

/// Shortest decimal text that reads back to exactly the same double.
std::string iniNumber(double v);

/// Space-separated iniNumber() of every element.
std::string iniNumbers(const Eigen::VectorXd& v);

/// The five distortion coefficients "k1 k2 p1 p2 k3" of a camera.
std::string iniDistortion(const PinholeCamera& camera);

/// "key = value ; comment" with the value column aligned like share/config.ini.
void iniLine(std::ostream& os, const std::string& key, const std::string& value,
             const std::string& comment);

}  // namespace rgbdi
