#include "rgbdi/convert/dataset_conversion.h"

#include <cmath>
#include <filesystem>
#include <iomanip>
#include <sstream>

#include "rgbdi/common/atomic_file.h"
#include "rgbdi/common/ini_reader.h"
#include "rgbdi/common/ini_text.h"
#include "rgbdi/common/sensor_options.h"
#include "rgbdi/convert/progress_meter.h"
#include "rgbdi/convert/rawlog_output.h"
#include "rgbdi/convert/tum_rgbd.h"
#include "rgbdi/io/input_format.h"

namespace rgbdi::convert {
namespace {

namespace fs = std::filesystem;

bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

/// Any [camera] key present: the user's intrinsics.
bool hasAny(const IniReader& ini, const std::string& section,
            std::initializer_list<const char*> keys) {
  for (const char* k : keys)
    if (ini.hasKey(section, k)) return true;
  return false;
}

/// The IMU rate written into OUT.ini: the measured rate rounded to 0.1 Hz.
double roundedRate(double hz) { return std::round(hz * 10.0) / 10.0; }

/// The [wheel] extrinsic keys for a T_body_wheel read from the input.
std::string wheelExtrinsicSection(const Eigen::Isometry3d& T_body_wheel, const std::string& from) {
  std::ostringstream os;
  Eigen::VectorXd r(9);
  const Eigen::Matrix3d R = T_body_wheel.rotation();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r[3 * i + j] = R(i, j);
  os << "[wheel]\n";
  iniLine(os, "R_body_wheel", iniNumbers(r),
          "row-major [unitless]: wheel frame in the IMU/body frame (" + from + ")");
  iniLine(os, "t_body_wheel_m", iniNumbers(T_body_wheel.translation()), "[m]");
  return os.str();
}

}  // namespace

ConversionSettings loadConversionSettings(const std::string& config_path,
                                          const std::string& camera_yaml) {
  ConversionSettings s;
  if (!config_path.empty()) {
    IniReader ini = IniReader::fromFile(config_path);
    s.options = bag::ConvertOptions::load(ini);
    const CameraOptions camera = CameraOptions::load(ini);
    const ExtrinsicOptions extrinsic = ExtrinsicOptions::load(ini);
    // A full rgbdi configuration is welcome; only the sections above matter here.
    ini.acceptConfigSectionsExcept({"camera", "extrinsic", "convert"});
    ini.checkNoUnknownKeys();
    if (hasAny(ini, "camera", {"width", "height", "fx", "fy", "cx", "cy", "distortion"})) {
      s.calibration.color = camera.camera;
      s.calibration.color_source = config_path + " [camera]";
      s.calibration.intrinsics_from_user = true;
    }
    if (hasAny(ini, "extrinsic", {"R_body_cam", "t_body_cam_m"})) {
      s.calibration.T_body_cam = extrinsic.T_body_cam;
      s.calibration.extrinsic_source = config_path + " [extrinsic]";
      s.calibration.extrinsic_from_user = true;
    }
  }
  if (!camera_yaml.empty()) {
    s.vins = readVinsYaml(camera_yaml);
    s.calibration.color = s.vins->camera;
    s.calibration.color_source = camera_yaml + " (VINS calibration)";
    s.calibration.intrinsics_from_user = true;
    if (s.vins->has_extrinsic) {
      s.calibration.T_body_cam = s.vins->T_body_cam;
      s.calibration.extrinsic_source = camera_yaml + " extrinsicRotation/extrinsicTranslation";
      s.calibration.extrinsic_from_user = true;
    }
  }
  return s;
}

bag::ConversionReport convertDataset(const ConversionRequest& q) {
  if (!endsWith(q.output, ".rawlog") && !endsWith(q.output, ".rawlog.gz"))
    throw UsageError("output '" + q.output + "' must end in .rawlog or .rawlog.gz");
  std::error_code ec;
  if (fs::exists(q.input, ec) && fs::exists(q.output, ec) && fs::equivalent(q.input, q.output, ec))
    throw UsageError("output '" + q.output + "' is the input");
  const io::InputFormat format = io::detectInputFormat(q.input);
  if (format == io::InputFormat::Rawlog)
    throw UsageError(q.input + ": is already an MRPT rawlog (use --info to inspect it)");
  if (format == io::InputFormat::Unknown)
    throw IoError(q.input +
                  ": unrecognised format (expected a ROS1 bag or a TUM RGB-D folder with rgb.txt "
                  "and depth.txt)");
  const bag::ConvertOptions& o = q.settings.options;

  std::unique_ptr<bag::BagConverter> bag_conv;
  std::unique_ptr<TumRgbdConverter> tum_conv;
  Eigen::Isometry3d T_body_cam;
  std::uint64_t input_bytes = 0;
  if (format == io::InputFormat::Ros1Bag) {
    bag::BagInputOptions in;
    in.topics = q.topics;
    in.depth_aligned = q.depth_aligned;
    bag_conv = std::make_unique<bag::BagConverter>(q.input, o, in, q.settings.calibration);
    T_body_cam = bag_conv->T_body_cam();
    input_bytes = bag_conv->reader().fileSize();
  } else {
    try {
      tum_conv =
          std::make_unique<TumRgbdConverter>(q.input, o, q.tum_camera, q.settings.calibration);
    } catch (const std::invalid_argument& e) {
      throw UsageError(e.what());
    }
    T_body_cam = tum_conv->T_body_cam();
    input_bytes = tum_conv->totalBytes();
  }

  bag::ConversionReport written;
  RawlogOutputOptions ro;
  ro.path = q.output;
  ro.external_images = q.external_images;
  ro.T_body_cam = T_body_cam;
  ro.reorder_window_s = o.reorder_window_s;
  ro.max_listed_issues = o.max_listed_issues;
  RawlogOutput out(ro, written);

  ProgressMeter meter(q.progress, q.progress_interactive, o.progress_interval_s, input_bytes);
  const bag::ProgressCallback progress = [&meter](double f) { meter.update(f); };
  bag::ConversionReport report;
  if (bag_conv) {
    report = bag_conv->run(out, progress, q.stop);
  } else {
    report = tum_conv->run(out, progress, q.stop);
  }
  meter.finish();
  out.finish();
  report.absorbWriter(written, o.max_listed_issues);

  // The configuration written next to the rawlog: the VINS calibration (--camera-yaml) and the
  // wheel extrinsic of the bag's /tf_static; absent when the input gives neither.
  std::string config_text, config_what;
  if (bag_conv && bag_conv->T_body_wheel()) {
    const std::string from =
        bag_conv->layout().tf_static + " of " + fs::path(q.input).filename().string();
    config_text = wheelExtrinsicSection(*bag_conv->T_body_wheel(), from);
    config_what = "wheel extrinsic from " + from;
  }
  if (q.settings.vins) {
    const double measured = out.imuRateHz();
    const double rate = measured > 0.0 ? roundedRate(measured) : 200.0;
    std::ostringstream note;
    if (measured > 0.0)
      note << "the rate measured in " << fs::path(q.input).filename().string() << ": " << std::fixed
           << std::setprecision(2) << measured << " Hz";
    else
      note << "no IMU data in the input; the VINS-RGBD dataset's 200 Hz assumed";
    const std::string what =
        "rgbdi configuration from " + q.settings.vins->path + ", IMU rate " + note.str();
    config_text = rgbdiConfigFromVins(*q.settings.vins, rate, note.str()) +
                  (config_text.empty() ? std::string() : "\n" + config_text);
    config_what = what + (config_what.empty() ? std::string() : "; " + config_what);
  }
  if (!config_text.empty()) {
    const std::string ini_path = outputStem(q.output) + ".ini";
    writeFileAtomically(ini_path, [&](std::ostream& os) { os << config_text; });
    report.outputs.push_back(ini_path + " (" + config_what + ")");
  }
  return report;
}

}  // namespace rgbdi::convert
