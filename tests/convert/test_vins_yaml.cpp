// VINS yaml -> rgbdi configuration: the noise mapping of doc/imu.md (known answers), reading a
// VINS-RGBD calibration file, the generated INI loaded back, and errors naming file and key.
#include <gtest/gtest.h>

#include <fstream>

#include "rgbdi/common/ini_reader.h"
#include "rgbdi/common/sensor_options.h"
#include "rgbdi/convert/vins_yaml.h"
#include "testing/fixtures.h"

namespace rgbdi::convert {
namespace {

// The calibration of the VINS-RGBD dataset (SPEC section 2) in VINS' own yaml format.
const char* const kDatasetYaml = R"(%YAML:1.0
imu_topic: "/camera/imu"
image_topic: "/camera/color/image_raw"
model_type: PINHOLE
camera_name: camera
image_width: 640
image_height: 480
distortion_parameters:
   k1: 0.0
   k2: 0.0
   p1: 0.0
   p2: 0.0
projection_parameters:
   fx: 616.5911
   fy: 616.6796
   cx: 324.2194
   cy: 239.4270
estimate_extrinsic: 0
extrinsicRotation: !!opencv-matrix
   rows: 3
   cols: 3
   dt: d
   data: [ 0.0008748, -0.0047406, 0.9999884, -0.9999681, -0.0079460, 0.0008371, 0.0079419, -0.9999572, -0.0047474 ]
extrinsicTranslation: !!opencv-matrix
   rows: 3
   cols: 1
   dt: d
   data: [ 1.30441e-05, 0.0149225, 0.000316835 ]
acc_n: 0.1
gyr_n: 0.01
acc_w: 0.0002
gyr_w: 2.0e-5
g_norm: 9.805
estimate_td: 1
td: 0.0
)";

std::string write(const std::string& dir, const std::string& name, const std::string& text) {
  const std::string path = dir + "/" + name;
  std::ofstream(path) << text;
  return path;
}

TEST(VinsYaml, NoiseMappingKnownAnswers) {
  // doc/imu.md's table at 200 Hz: nd = n sqrt(dt/2), rw = w sqrt(dt).
  const ImuOptions o = imuOptionsFromVins({0.1, 0.01, 0.0002, 2e-5}, 9.805, 200.0);
  EXPECT_NEAR(o.acc_noise_density, 0.005, 1e-15);
  EXPECT_NEAR(o.gyr_noise_density, 0.0005, 1e-16);
  EXPECT_NEAR(o.acc_random_walk, 1.41421356e-5, 1e-13);
  EXPECT_NEAR(o.gyr_random_walk, 1.41421356e-6, 1e-14);
  EXPECT_DOUBLE_EQ(o.gravity_m_s2, 9.805);
  EXPECT_DOUBLE_EQ(o.rate_hz, 200.0);
  const ImuOptions tracked = imuOptionsFromVins({0.5, 0.01, 0.001, 2e-5}, 9.805, 200.0);
  EXPECT_NEAR(tracked.acc_noise_density, 0.025, 1e-15);
  EXPECT_NEAR(tracked.acc_random_walk, 7.0710678e-5, 1e-12);
  // At 400 Hz the same per-sample values mean smaller densities (dt halves).
  EXPECT_NEAR(imuOptionsFromVins({0.1, 0.01, 0.0002, 2e-5}, 9.8, 400.0).acc_noise_density,
              0.1 * std::sqrt(1.0 / 800.0), 1e-15);
}

TEST(VinsYaml, DatasetCalibrationBecomesTheDefaultConfig) {
  const std::string dir = test::makeTempDir("vins_yaml");
  const VinsCalibration v = readVinsYaml(write(dir, "rs.yaml", kDatasetYaml));
  EXPECT_EQ(v.camera.width, 640);
  EXPECT_DOUBLE_EQ(v.camera.fx, 616.5911);
  EXPECT_DOUBLE_EQ(v.camera.cy, 239.4270);
  EXPECT_FALSE(v.camera.hasDistortion());
  ASSERT_TRUE(v.has_extrinsic);
  EXPECT_DOUBLE_EQ(v.R_body_cam_as_given(1, 0), -0.9999681);
  EXPECT_DOUBLE_EQ(v.T_body_cam.translation().y(), 0.0149225);
  EXPECT_DOUBLE_EQ(v.noise.gyr_w, 2e-5);
  EXPECT_DOUBLE_EQ(v.g_norm, 9.805);

  // The dataset's calibration is share/config.ini's default: the generated INI must load to it.
  const std::string text = rgbdiConfigFromVins(v, 200.0, "test");
  IniReader ini = IniReader::fromText(text, "generated");
  const CameraOptions cam = CameraOptions::load(ini);
  const ImuOptions imu = ImuOptions::load(ini);
  const ExtrinsicOptions ext = ExtrinsicOptions::load(ini);
  ini.checkNoUnknownKeys();
  const CameraOptions cam0;
  const ImuOptions imu0;
  const ExtrinsicOptions ext0;
  EXPECT_DOUBLE_EQ(cam.camera.fx, cam0.camera.fx);
  EXPECT_DOUBLE_EQ(cam.camera.cx, cam0.camera.cx);
  EXPECT_EQ(cam.intrinsics_source, "config");
  EXPECT_NEAR(imu.acc_noise_density, imu0.acc_noise_density, 1e-15);
  EXPECT_NEAR(imu.gyr_noise_density, imu0.gyr_noise_density, 1e-16);
  EXPECT_NEAR(imu.acc_random_walk, imu0.acc_random_walk, 1e-9);  // config.ini rounds to 1.4142e-5
  EXPECT_NEAR(imu.gyr_random_walk, imu0.gyr_random_walk, 1e-10);
  EXPECT_DOUBLE_EQ(imu.gravity_m_s2, imu0.gravity_m_s2);
  EXPECT_TRUE(ext.T_body_cam.isApprox(ext0.T_body_cam, 1e-12));
  EXPECT_DOUBLE_EQ(ext.time_offset_s, 0.0);
  EXPECT_NE(text.find("(VINS acc_n 0.1)"), std::string::npos) << text;
}

TEST(VinsYaml, NoiseFromDensitiesInvertsTheMapping) {
  // doc/imu.md's table read backwards: config.ini's default densities at 200 Hz are the
  // dataset's acc_n 0.1, gyr_n 0.01.
  ImuOptions imu;
  imu.rate_hz = 200.0;
  imu.acc_noise_density = 0.005;
  imu.gyr_noise_density = 0.0005;
  imu.acc_random_walk = 0.0002 * std::sqrt(1.0 / 200.0);
  imu.gyr_random_walk = 2e-5 * std::sqrt(1.0 / 200.0);
  const VinsImuNoise n = vinsNoiseFromImuOptions(imu);
  EXPECT_NEAR(n.acc_n, 0.1, 1e-15);
  EXPECT_NEAR(n.gyr_n, 0.01, 1e-16);
  EXPECT_NEAR(n.acc_w, 0.0002, 1e-18);
  EXPECT_NEAR(n.gyr_w, 2e-5, 1e-19);
  imu.rate_hz = 400.0;  // the same densities at 400 Hz are larger per-sample values
  EXPECT_NEAR(vinsNoiseFromImuOptions(imu).acc_n, 0.005 / std::sqrt(1.0 / 800.0), 1e-14);
}

TEST(VinsYaml, WrittenCalibrationReadsBackToTheSameValues) {
  PinholeCamera cam;
  cam.width = 640;
  cam.height = 480;
  cam.fx = 612.25;
  cam.fy = 611.0625;
  cam.cx = 321.7;
  cam.cy = 238.3;
  cam.dist = {0.0123, -0.0456, 0.0007, -0.0008, 0.0};
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = (Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(-M_PI / 2 + 0.013, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  T.translation() = Eigen::Vector3d(0.0123, -0.0149, 0.0031);
  ImuOptions imu;
  imu.rate_hz = 200.0;
  imu.acc_noise_density = 0.04;
  imu.gyr_noise_density = 0.004;
  imu.acc_random_walk = 8e-4;
  imu.gyr_random_walk = 4e-5;
  imu.gravity_m_s2 = 9.81;
  const std::string dir = test::makeTempDir("vins_yaml_write");
  const VinsCalibration v = readVinsYaml(write(dir, "w.yaml", vinsYamlText(cam, T, imu, 0.0125)));
  EXPECT_EQ(v.camera.width, 640);
  EXPECT_EQ(v.camera.height, 480);
  EXPECT_EQ(v.camera.fx, cam.fx);
  EXPECT_EQ(v.camera.fy, cam.fy);
  EXPECT_EQ(v.camera.cx, cam.cx);
  EXPECT_EQ(v.camera.cy, cam.cy);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(v.camera.dist[i], cam.dist[i]) << i;
  ASSERT_TRUE(v.has_extrinsic);
  EXPECT_TRUE(v.R_body_cam_as_given.isApprox(T.linear(), 1e-15));
  EXPECT_TRUE(v.T_body_cam.isApprox(T, 1e-12));
  EXPECT_EQ(v.g_norm, 9.81);
  EXPECT_EQ(v.td, 0.0125);
  const ImuOptions back = imuOptionsFromVins(v.noise, v.g_norm, 200.0);
  EXPECT_NEAR(back.acc_noise_density, 0.04, 1e-15);
  EXPECT_NEAR(back.gyr_noise_density, 0.004, 1e-16);
  EXPECT_NEAR(back.acc_random_walk, 8e-4, 1e-17);
  EXPECT_NEAR(back.gyr_random_walk, 4e-5, 1e-18);
  // VINS' model has no k3: refused, not dropped.
  cam.dist[4] = 0.001;
  EXPECT_THROW(vinsYamlText(cam, T, imu, 0.0), ConfigError);
}

TEST(VinsYaml, ErrorsNameFileAndKey) {
  const std::string dir = test::makeTempDir("vins_yaml");
  std::string text = kDatasetYaml;
  // The message names the file: `after_path` follows its path directly.
  const auto expectMessage = [&](const std::string& yaml, const std::string& after_path) {
    const std::string path = write(dir, "bad.yaml", yaml);
    try {
      readVinsYaml(path);
      ADD_FAILURE() << "expected ConfigError containing " << after_path;
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(path + after_path), std::string::npos) << e.what();
    }
  };
  const auto expectError = [&](const std::string& yaml, const std::string& fragment) {
    expectMessage(yaml, " " + fragment);
  };
  std::string no_acc = text;
  no_acc.replace(no_acc.find("acc_n: 0.1"), 10, "");
  expectError(no_acc, "acc_n: missing");
  std::string fisheye = text;
  fisheye.replace(fisheye.find("PINHOLE"), 7, "KANNALA_BRANDT");
  expectError(fisheye, "model_type: 'KANNALA_BRANDT' is not supported");
  std::string scaled = text;
  scaled.replace(scaled.find("0.0008748, -0.0047406, 0.9999884"), 32, "2.0, 0.0, 0.0");
  expectError(scaled, "extrinsicRotation: not a rotation matrix");
  std::string negative = text;
  negative.replace(negative.find("gyr_w: 2.0e-5"), 13, "gyr_w: -1");
  expectError(negative, "gyr_w: must be positive");
  EXPECT_THROW(readVinsYaml(dir + "/none.yaml"), ConfigError);
  // Fuzzing finding 5 (2026-12-03): a damaged matrix block made OpenCV's YAML parser throw
  // std::length_error, which ended the converter instead of a ConfigError naming the file.
  std::string damaged = text;
  const std::size_t block = damaged.find("extrinsicTranslation");
  damaged.replace(damaged.find("cols: 1", block), 7, ":cosl 1");
  // Since finding 16's fix the line check refuses it before OpenCV parses (the catch of
  // standard exceptions stays for what the line check lets through).
  expectMessage(damaged, " line 26: ':cosl 1' is not 'key: value'");
  // Finding 6: a top-level sequence made OpenCV assert in every key look-up.
  // Finding 6's input (a top level that is a sequence) is now refused by the line check of
  // finding 17, before OpenCV parses it.
  expectMessage("%YAML:1.0\n- model_type: PINHOLE\n- 1\n",
                " line 2: '- model_type: PINHOLE' is not 'key: value' (a VINS yaml is a mapping of "
                "keys)");
  // A value rgbdi does not accept is reported when the INI is generated.
  std::string low_g = text;
  low_g.replace(low_g.find("g_norm: 9.805"), 13, "g_norm: 1.0");
  const VinsCalibration v = readVinsYaml(write(dir, "g.yaml", low_g));
  EXPECT_THROW(rgbdiConfigFromVins(v, 200.0, "test"), ConfigError);
}

// Issue 37: VINS-RGBD's D435i colour configuration has rolling_shutter: 1 and
// rolling_shutter_tr: 0.033; rawlog-convert --camera-yaml makes it [camera]
// rolling_shutter_readout_s, and vinsYamlText writes it back.
TEST(VinsYaml, RollingShutterReadoutIsReadAndWritten) {
  const std::string dir = test::makeTempDir("vins_yaml_rs");
  // The dataset's yaml without the keys: a global shutter, and the INI says so.
  const VinsCalibration global = readVinsYaml(write(dir, "g.yaml", kDatasetYaml));
  EXPECT_EQ(global.rolling_shutter_readout_s, 0.0);
  IniReader gini = IniReader::fromText(rgbdiConfigFromVins(global, 200.0, "test"), "g");
  EXPECT_EQ(CameraOptions::load(gini).rolling_shutter_readout_s, 0.0);

  const std::string rolling =
      std::string(kDatasetYaml) + "rolling_shutter: 1\nrolling_shutter_tr: 0.033\n";
  const VinsCalibration v = readVinsYaml(write(dir, "rs.yaml", rolling));
  EXPECT_EQ(v.rolling_shutter_readout_s, 0.033);
  const std::string text = rgbdiConfigFromVins(v, 200.0, "test");
  IniReader ini = IniReader::fromText(text, "generated");
  EXPECT_EQ(CameraOptions::load(ini).rolling_shutter_readout_s, 0.033) << text;

  // rolling_shutter 0: VINS ignores the readout time, so does rgbdi.
  const std::string off =
      std::string(kDatasetYaml) + "rolling_shutter: 0\nrolling_shutter_tr: 0.033\n";
  EXPECT_EQ(readVinsYaml(write(dir, "off.yaml", off)).rolling_shutter_readout_s, 0.0);

  // Round trip through vinsYamlText; readout 0 writes neither key (the text as before).
  ImuOptions imu;
  const Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  const std::string written = vinsYamlText(global.camera, T, imu, 0.0, 0.0275);
  EXPECT_NE(written.find("rolling_shutter: 1\nrolling_shutter_tr: 0.0275\n"), std::string::npos)
      << written;
  EXPECT_EQ(readVinsYaml(write(dir, "w.yaml", written)).rolling_shutter_readout_s, 0.0275);
  const std::string written0 = vinsYamlText(global.camera, T, imu, 0.0);
  EXPECT_EQ(written0.find("rolling_shutter"), std::string::npos) << written0;
  EXPECT_EQ(vinsYamlText(global.camera, T, imu, 0.0, 0.0), written0);

  // Errors name the file and the key.
  const auto expectError = [&](const std::string& tail, const std::string& fragment) {
    const std::string path = write(dir, "bad.yaml", std::string(kDatasetYaml) + tail);
    try {
      readVinsYaml(path);
      ADD_FAILURE() << "expected ConfigError containing " << fragment;
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(path + " " + fragment), std::string::npos) << e.what();
    }
  };
  expectError("rolling_shutter: 1\n", "rolling_shutter_tr: missing (rolling_shutter is 1)");
  expectError("rolling_shutter: 2\nrolling_shutter_tr: 0.03\n", "rolling_shutter: must be 0 or 1");
  expectError("rolling_shutter: 1\nrolling_shutter_tr: -0.03\n",
              "rolling_shutter_tr: must be a readout time from 0 to 1 s, got -0.03");
  expectError("rolling_shutter: 1\nrolling_shutter_tr: fast\n", "rolling_shutter_tr: not a number");
}

// Fuzzing finding 7 (2026-12-03): an image side beyond INT_MAX was converted from double to int
// (undefined behaviour, UBSan; INT_MIN in practice, accepted without an error). Sides must be
// whole pixel counts in the range rgbdi's [camera] section accepts.
TEST(VinsYaml, ImageSidesAreWholePixelCountsInRange) {
  const std::string dir = test::makeTempDir("vins_yaml_size");
  const std::string text = kDatasetYaml;
  const auto withWidth = [&](const std::string& value) {
    std::string t = text;
    t.replace(t.find("image_width: 640"), 16, "image_width: " + value);
    return write(dir, "size.yaml", t);
  };
  for (const std::string bad : {"1e10", "4294967296", "2147483648", "640.5", "8193", "15"}) {
    const std::string path = withWidth(bad);
    try {
      const VinsCalibration v = readVinsYaml(path);
      ADD_FAILURE() << "image_width " << bad << " accepted as " << v.camera.width;
    } catch (const ConfigError& e) {
      EXPECT_NE(std::string(e.what()).find(path + " image_width: must be a whole number of pixels "
                                                  "from 16 to 8192"),
                std::string::npos)
          << e.what();
    }
  }
  EXPECT_EQ(readVinsYaml(withWidth("8192")).camera.width, 8192);
  EXPECT_EQ(readVinsYaml(withWidth("16")).camera.width, 16);
}

// Fuzzing finding 16 (2026-12-03 evening, fuzz_vins_yaml after 851 989 runs): OpenCV's YAML
// parser looped forever on an indented key followed by a line that is no key (libFuzzer timeout;
// rawlog-convert --camera-yaml would hang). Lines that are no "key: value" outside a flow
// collection are refused before OpenCV parses the text; the dataset yaml still reads.
TEST(VinsYaml, LinesThatAreNoKeysAreRefusedBeforeOpenCvParses) {
  const std::string dir = test::makeTempDir("vins_yaml_lines");
  // The ConfigError's text, "accepted" if the file was read.
  const auto refusal = [](const std::string& path) -> std::string {
    try {
      readVinsYaml(path);
      return "accepted";
    } catch (const ConfigError& e) {
      return e.what();
    }
  };
  const std::string hang = write(dir, "hang.yaml", "%YAML:1.0\n  t: f\n9, -\n");
  EXPECT_EQ(refusal(hang),
            hang + " line 3: '9, -' is not 'key: value' (a VINS yaml is a mapping of keys)");
  // Finding 17 (fuzz_vins_yaml, 2026-12-03 evening, after 387 471 runs): OpenCV's parser looped
  // on block sequence items among the keys (the fuzzer's input shortened to its first lines,
  // which still make cv::FileStorage loop); a VINS yaml has none.
  const std::string items =
      write(dir, "items.yaml", "%YAML:1.0\n  k1: fx.59\n .:\n-  \n-    fx.59o:\n");
  // (Since finding 21 its key ".", which starts with no letter, digit or '_', is refused first.)
  EXPECT_EQ(refusal(items),
            items + " line 3: '.:' is not 'key: value' (a VINS yaml is a mapping of keys)");
  const std::string items_only = write(dir, "items_only.yaml", "%YAML:1.0\n  k1: fx.59\n-  \n");
  EXPECT_EQ(refusal(items_only),
            items_only + " line 3: '-  ' is not 'key: value' (a VINS yaml is a mapping of keys)");
  // Finding 18 (fuzz_vins_yaml, 2026-12-03 night): a directive line with a bracket opened a flow
  // collection for the line check, so the lines after it were not checked; OpenCV looped on
  // them (the fuzzer's input shortened by hand; it still makes cv::FileStorage loop).
  const std::string directive = write(dir, "directive.yaml", "%YAML:1.![:\n   a:6\n  : 2\n-\n");
  EXPECT_EQ(refusal(directive),
            directive + " line 1: '%YAML:1.![:' is not a YAML version directive (%YAML:1.0)");
  // Finding 21 (fuzz_vins_yaml, 2026-12-04, after 342 k runs): OpenCV looped on keys that
  // begin like a document marker (the fuzzer's input as found; it makes cv::FileStorage loop).
  const std::string marker = write(dir, "marker.yaml",
                                   "%YAML:1.0\n ---k2: gtop\n   k---2: \x03.0\n\n   ---k2:\n\n\n"
                                   "r-dth: 640\n   ---k2: came\n   ---k2: cameQ");
  EXPECT_EQ(
      refusal(marker),
      marker + " line 2: '---k2: gtop' is not 'key: value' (a VINS yaml is a mapping of keys)");
  const std::string nul = write(dir, "nul.yaml", std::string("%YAML:1.0\nacc_n: 0.1\0\n", 22));
  EXPECT_THROW(readVinsYaml(nul), ConfigError);
  // Flow sequences over several lines, comments, quoted keys and CRLF line ends are YAML a VINS
  // file may use.
  std::string text = kDatasetYaml;
  text.replace(text.find("0.0008748, -0.0047406, 0.9999884,"), 33,
               "0.0008748, -0.0047406, 0.9999884,\n           ");
  text += "# a comment\n\"quoted key\": 1\r\n";
  EXPECT_NO_THROW(readVinsYaml(write(dir, "ok.yaml", text)));
}

}  // namespace
}  // namespace rgbdi::convert
