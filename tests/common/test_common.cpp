#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "rgbdi/common/atomic_file.h"
#include "rgbdi/common/camera.h"
#include "rgbdi/common/ini_reader.h"
#include "rgbdi/common/sensor_options.h"
#include "rgbdi/common/so3.h"
#include "testing/fixtures.h"

using namespace rgbdi;

TEST(IniReader, MissingKeyTakesDefaultPresentKeyIsParsed) {
  auto ini = IniReader::fromText("[imu]\nrate_hz = 400 ; Hz\n", "test.ini");
  EXPECT_DOUBLE_EQ(ini.getDouble("imu", "rate_hz", 200, 10, 1000), 400.0);
  EXPECT_DOUBLE_EQ(ini.getDouble("imu", "gravity_m_s2", 9.805, 9.7, 9.9), 9.805);
  EXPECT_NO_THROW(ini.checkNoUnknownKeys());
}

TEST(IniReader, OutOfRangeNamesFileSectionKeyAndRange) {
  auto ini = IniReader::fromText("[imu]\nrate_hz = 5\n", "my.ini");
  try {
    ini.getDouble("imu", "rate_hz", 200, 10, 1000);
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("my.ini"), std::string::npos) << msg;
    EXPECT_NE(msg.find("[imu]"), std::string::npos) << msg;
    EXPECT_NE(msg.find("rate_hz"), std::string::npos) << msg;
    EXPECT_NE(msg.find("[10, 1000]"), std::string::npos) << msg;
  }
}

TEST(IniReader, NotANumberIsAnError) {
  auto ini = IniReader::fromText("[a]\nx = 12abc\ny = 3.5\n");
  EXPECT_THROW(ini.getDouble("a", "x", 0, -100, 100), ConfigError);
  EXPECT_THROW(ini.getInt("a", "y", 0, -100, 100), ConfigError);
}

TEST(IniReader, UnknownKeyAndUnknownSectionAreErrors) {
  auto ini = IniReader::fromText("[imu]\nrate_hz = 200\nrte_hz = 3\n[bogus]\nk = 1\n", "f.ini");
  ini.getDouble("imu", "rate_hz", 200, 10, 1000);
  try {
    ini.checkNoUnknownKeys();
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("rte_hz"), std::string::npos) << msg;
    EXPECT_NE(msg.find("bogus"), std::string::npos) << msg;
  }
}

TEST(IniReader, EnumBoolAndVector) {
  auto ini = IniReader::fromText("[s]\nmode = fast\nflag = off\nv = 1, 2 3\n");
  EXPECT_EQ(ini.getEnum("s", "mode", "slow", {"slow", "fast"}), "fast");
  EXPECT_FALSE(ini.getBool("s", "flag", true));
  const Eigen::VectorXd v = ini.getVector("s", "v", Eigen::VectorXd::Zero(3));
  EXPECT_EQ(v, Eigen::Vector3d(1, 2, 3));
  EXPECT_THROW(ini.getVector("s", "v", Eigen::VectorXd::Zero(2)), ConfigError);
  EXPECT_THROW(ini.getEnum("s", "mode", "slow", {"slow", "normal"}), ConfigError);
}

namespace {
/// The ConfigError message of parsing `text`, or "" when it parses.
std::string lineError(const std::string& text) {
  try {
    IniReader::fromText(text, "bad.ini");
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(IniReader, ALineThatIsNotAKeyValueIsAnErrorNamingFileAndLine) {
  EXPECT_EQ(lineError("[imu]\nrate_hz = 200\nrate_hz 400\n"),
            "bad.ini line 3: 'rate_hz 400' is not 'key = value', a [section] header, a comment or "
            "blank");
  EXPECT_EQ(lineError("[imu\nrate_hz = 200\n"),
            "bad.ini line 1: '[imu' is not a valid [section] header");
  EXPECT_EQ(lineError("[imu] rate_hz = 200\n"),
            "bad.ini line 1: '[imu] rate_hz = 200' is not a valid [section] header");
  EXPECT_EQ(lineError("[imu]\n= 200\n"),
            "bad.ini line 2: '= 200' is not 'key = value', a [section] header, a comment or blank");
}

TEST(IniReader, PlainTextIsRejectedAtItsFirstLine) {
  const std::string msg = lineError("This is a README, not a configuration.\nSecond line.\n");
  EXPECT_EQ(msg.rfind("bad.ini line 1: ", 0), 0u) << msg;
}

TEST(IniReader, CommentsBlanksHeadersAndDirectivesAreAccepted) {
  EXPECT_EQ(lineError("; comment\n# comment\n// comment\n\n   \n[imu]  ; trailing\n"
                      "@define RATE 400\nrate_hz = ${RATE}\nempty_value =\n"),
            "");
  auto ini = IniReader::fromText("@define RATE 400\n[imu]\nrate_hz = ${RATE}\n", "d.ini");
  EXPECT_DOUBLE_EQ(ini.getDouble("imu", "rate_hz", 200, 10, 1000), 400.0);
}

TEST(IniReader, ShippedConfigurationsPassTheLineCheck) {
  for (const char* f : {"/share/config.ini", "/share/sensors/d435i.ini",
                        "/share/sensors/replay.ini", "/share/sensors/simulator.ini"})
    EXPECT_NO_THROW(IniReader::fromFile(rgbdi::test::sourceDir() + f)) << f;
}

TEST(SensorOptions, ShippedConfigLoadsWithoutUnknownKeysInSensorSections) {
  const std::string path = rgbdi::test::sourceDir() + "/share/config.ini";
  auto ini = IniReader::fromFile(path);
  const auto cam = CameraOptions::load(ini);
  const auto imu = ImuOptions::load(ini);
  const auto ext = ExtrinsicOptions::load(ini);
  EXPECT_DOUBLE_EQ(cam.camera.fx, 616.5911);
  EXPECT_DOUBLE_EQ(cam.camera.cy, 239.4270);
  EXPECT_DOUBLE_EQ(imu.gravity_m_s2, 9.805);
  // The dataset extrinsic: the camera looks along body +x.
  EXPECT_NEAR((ext.T_body_cam.rotation() * Eigen::Vector3d::UnitZ()).x(), 1.0, 1e-4);
  EXPECT_NEAR(ext.T_body_cam.translation().y(), 0.0149225, 1e-9);
}

TEST(SensorOptions, NonRotationExtrinsicIsRejected) {
  auto ini = IniReader::fromText("[extrinsic]\nR_body_cam = 1 0 0 0 1 0 0 0 2\n", "x.ini");
  EXPECT_THROW(ExtrinsicOptions::load(ini), ConfigError);
}

TEST(Camera, ProjectBackProjectRoundTripWithDistortion) {
  PinholeCamera c;
  c.width = 640;
  c.height = 480;
  c.fx = 600;
  c.fy = 610;
  c.cx = 320;
  c.cy = 240;
  c.dist = {0.1, -0.05, 0.001, -0.002, 0.01};
  for (double u : {5.0, 100.0, 320.0, 630.0})
    for (double v : {3.0, 240.0, 470.0}) {
      const Eigen::Vector3d p = c.backProject({u, v}, 2.5);
      EXPECT_NEAR(p.z(), 2.5, 1e-12);
      Eigen::Vector2d uv;
      ASSERT_TRUE(c.project(p, uv));
      EXPECT_NEAR(uv.x(), u, 1e-8);
      EXPECT_NEAR(uv.y(), v, 1e-8);
    }
  Eigen::Vector2d uv;
  EXPECT_FALSE(c.project({0, 0, -1}, uv));
}

TEST(So3, ExpLogAndRightJacobian) {
  const Eigen::Vector3d phi(0.3, -1.2, 0.7);
  EXPECT_TRUE(logSO3(expSO3(phi)).isApprox(phi, 1e-12));
  // Jr against finite differences: exp(phi + d) = exp(phi) exp(Jr d)
  const Eigen::Matrix3d Jr = rightJacobianSO3(phi);
  for (int i = 0; i < 3; ++i) {
    Eigen::Vector3d d = Eigen::Vector3d::Zero();
    d[i] = 1e-7;
    const Eigen::Vector3d num = logSO3(expSO3(phi).transpose() * expSO3(phi + d)) / 1e-7;
    EXPECT_TRUE(num.isApprox(Jr.col(i), 1e-5)) << i;
  }
  EXPECT_TRUE((rightJacobianInvSO3(phi) * Jr).isApprox(Eigen::Matrix3d::Identity(), 1e-12));
}

TEST(So3, SphereTangentBasisIsOrthonormalAndOrthogonalToTheDirection) {
  for (const Eigen::Vector3d g : {Eigen::Vector3d(0, 0, -9.81), Eigen::Vector3d(1, 0, 0),
                                  Eigen::Vector3d(0, 1e-3, 0), Eigen::Vector3d(0.3, -2.0, 5.0)}) {
    const Eigen::Matrix<double, 3, 2> B = sphereTangentBasis(g);
    EXPECT_NEAR((B.transpose() * B - Eigen::Matrix2d::Identity()).norm(), 0.0, 1e-15);
    EXPECT_NEAR((g.normalized().transpose() * B).norm(), 0.0, 1e-15);
  }
}

TEST(AtomicFile, WritesCompleteFileAndLeavesOldContentOnFailure) {
  const std::string dir = rgbdi::test::makeTempDir("rgbdi_atomic");
  const std::string path = dir + "/out.txt";
  writeFileAtomically(path, [](std::ostream& os) { os << "first\n"; });
  EXPECT_THROW(writeFileAtomically(path,
                                   [](std::ostream& os) {
                                     os << "partial";
                                     throw std::runtime_error("interrupted");
                                   }),
               std::runtime_error);
  std::ifstream f(path);
  std::stringstream ss;
  ss << f.rdbuf();
  EXPECT_EQ(ss.str(), "first\n");
  // No temporary left behind.
  int files = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    (void)e;
    ++files;
  }
  EXPECT_EQ(files, 1);
  EXPECT_THROW(writeFileAtomically("/nonexistent_dir_rgbdi/x.txt", [](std::ostream&) {}), IoError);
}
