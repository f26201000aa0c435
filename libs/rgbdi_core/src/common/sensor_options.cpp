#include "rgbdi/common/sensor_options.h"

#include <cmath>
#include <sstream>

namespace rgbdi {
namespace {

// D435i colour camera of the VINS-RGBD dataset (SPEC section 2).
PinholeCamera d435iColor() {
  PinholeCamera c;
  c.width = 640;
  c.height = 480;
  c.fx = 616.5911;
  c.fy = 616.6796;
  c.cx = 324.2194;
  c.cy = 239.4270;
  return c;
}

Eigen::Matrix3d datasetRotation() {
  Eigen::Matrix3d R;
  R << 0.0008748, -0.0047406, 0.9999884,  //
      -0.9999681, -0.0079460, 0.0008371,  //
      0.0079419, -0.9999572, -0.0047474;
  return R;
}

}  // namespace

CameraOptions::CameraOptions() : camera(d435iColor()) {}

CameraOptions CameraOptions::load(IniReader& ini) {
  CameraOptions o;
  const std::string s = "camera";
  PinholeCamera& c = o.camera;
  c.width = ini.getInt(s, "width", c.width, 16, 8192);
  c.height = ini.getInt(s, "height", c.height, 16, 8192);
  c.fx = ini.getDouble(s, "fx", c.fx, 1.0, 1e5);
  c.fy = ini.getDouble(s, "fy", c.fy, 1.0, 1e5);
  c.cx = ini.getDouble(s, "cx", c.cx, 0.0, c.width);
  c.cy = ini.getDouble(s, "cy", c.cy, 0.0, c.height);
  Eigen::VectorXd d(5);
  d << c.dist[0], c.dist[1], c.dist[2], c.dist[3], c.dist[4];
  d = ini.getVector(s, "distortion", d);
  for (int i = 0; i < 5; ++i) {
    if (std::abs(d[i]) > 10.0)
      ini.fail(s, "distortion", "coefficient " + std::to_string(i) + " outside [-10, 10]");
    c.dist[static_cast<size_t>(i)] = d[i];
  }
  o.intrinsics_source =
      ini.getEnum(s, "intrinsics_source", o.intrinsics_source, {"stream", "config"});
  o.rolling_shutter_readout_s =
      ini.getDouble(s, "rolling_shutter_readout_s", o.rolling_shutter_readout_s, 0.0, 1.0);
  return o;
}

RollingShutter CameraOptions::rollingShutter() const {
  RollingShutter rs;
  rs.readout_s = rolling_shutter_readout_s;
  rs.rows = camera.height;
  return rs;
}

ImuOptions ImuOptions::load(IniReader& ini) {
  ImuOptions o;
  const std::string s = "imu";
  o.rate_hz = ini.getDouble(s, "rate_hz", o.rate_hz, 10.0, 10000.0);
  o.acc_noise_density = ini.getDouble(s, "acc_noise_density", o.acc_noise_density, 1e-6, 10.0);
  o.gyr_noise_density = ini.getDouble(s, "gyr_noise_density", o.gyr_noise_density, 1e-7, 1.0);
  o.acc_random_walk = ini.getDouble(s, "acc_random_walk", o.acc_random_walk, 1e-9, 1.0);
  o.gyr_random_walk = ini.getDouble(s, "gyr_random_walk", o.gyr_random_walk, 1e-10, 0.1);
  o.gravity_m_s2 = ini.getDouble(s, "gravity_m_s2", o.gravity_m_s2, 9.7, 9.9);
  return o;
}

ExtrinsicOptions::ExtrinsicOptions() {
  // The published rotation is rounded to 7 digits: re-orthonormalise, exactly as load() does.
  T_body_cam.linear() = Eigen::Quaterniond(datasetRotation()).normalized().toRotationMatrix();
  T_body_cam.translation() = Eigen::Vector3d(1.30441e-05, 0.0149225, 0.000316835);
}

ExtrinsicOptions ExtrinsicOptions::load(IniReader& ini) {
  ExtrinsicOptions o;
  const std::string s = "extrinsic";
  Eigen::Matrix3d R0 = o.T_body_cam.rotation();
  Eigen::VectorXd r(9);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r[3 * i + j] = R0(i, j);
  r = ini.getVector(s, "R_body_cam", r);
  Eigen::Matrix3d R;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) R(i, j) = r[3 * i + j];
  // Accept calibration round-off but not a matrix that is not a rotation.
  const double orth_err = (R.transpose() * R - Eigen::Matrix3d::Identity()).norm();
  if (orth_err > 1e-3 || R.determinant() < 0.0) {
    std::ostringstream os;
    os << "not a rotation matrix (|R^T R - I| = " << orth_err << ", det = " << R.determinant()
       << "); give 9 numbers row-major with |R^T R - I| <= 1e-3 and det = +1";
    ini.fail(s, "R_body_cam", os.str());
  }
  // Re-orthonormalise so downstream maths sees an exact rotation.
  o.T_body_cam.linear() = Eigen::Quaterniond(R).normalized().toRotationMatrix();
  Eigen::VectorXd t = ini.getVector(s, "t_body_cam_m", Eigen::VectorXd(o.T_body_cam.translation()));
  if (t.norm() > 2.0)
    ini.fail(s, "t_body_cam_m", "translation longer than 2 m; accepted range |t| <= 2 m");
  o.T_body_cam.translation() = t;
  o.time_offset_s = ini.getDouble(s, "time_offset_s", o.time_offset_s, -0.5, 0.5);
  o.sensor_pose_tolerance_m =
      ini.getDouble(s, "sensor_pose_tolerance_m", o.sensor_pose_tolerance_m, 0.0, 10.0);
  o.sensor_pose_tolerance_deg =
      ini.getDouble(s, "sensor_pose_tolerance_deg", o.sensor_pose_tolerance_deg, 0.0, 180.0);
  return o;
}

}  // namespace rgbdi
