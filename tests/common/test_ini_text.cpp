// INI text writing: numbers read back exactly, lines align like share/config.ini, and the text
// round-trips through IniReader.
#include <gtest/gtest.h>

#include <sstream>

#include "rgbdi/common/ini_reader.h"
#include "rgbdi/common/ini_text.h"

using namespace rgbdi;

TEST(IniText, NumbersAreShortestExactDecimals) {
  EXPECT_EQ(iniNumber(0.1), "0.1");
  EXPECT_EQ(iniNumber(460.0), "460");
  EXPECT_EQ(iniNumber(-2.5e-5), "-2.5e-05");
  EXPECT_EQ(iniNumber(1.0 / 3.0), "0.3333333333333333");
  for (double v : {1.0 / 3.0, 9.80665, 1e-300, -123456.789012345, 0.0012345678901234})
    EXPECT_EQ(std::stod(iniNumber(v)), v) << iniNumber(v);
  EXPECT_EQ(iniNumbers(Eigen::Vector3d(1, 0.5, -2)), "1 0.5 -2");
  PinholeCamera c;
  c.dist = {0.1, -0.2, 0.001, 0, 0.05};
  EXPECT_EQ(iniDistortion(c), "0.1 -0.2 0.001 0 0.05");
}

TEST(IniText, LinesAlignAndReadBack) {
  std::ostringstream os;
  os << "[camera]\n";
  iniLine(os, "fx", iniNumber(1.0 / 3.0), "[px]");
  iniLine(os, "a_rather_long_key_name_here", "12", "[count] long keys are not truncated");
  EXPECT_EQ(os.str(),
            "[camera]\n"
            "fx = 0.3333333333333333      ; [px]\n"
            "a_rather_long_key_name_here = 12 ; [count] long keys are not truncated\n");
  auto ini = IniReader::fromText(os.str(), "generated");
  EXPECT_EQ(ini.getDouble("camera", "fx", 0.0, 0.0, 1.0), 1.0 / 3.0);
  EXPECT_EQ(ini.getInt("camera", "a_rather_long_key_name_here", 0, 0, 100), 12);
}
