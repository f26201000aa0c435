#include "rgbdi/bag/ros_calibration.h"

#include <cmath>
#include <iomanip>
#include <sstream>

namespace rgbdi::bag {

PinholeCamera cameraFromInfo(const sensor_msgs::CameraInfo& info, const std::string& label) {
  const auto& K = info.K;
  PinholeCamera c;
  c.width = static_cast<int>(info.width);
  c.height = static_cast<int>(info.height);
  c.fx = K[0];
  c.fy = K[4];
  c.cx = K[2];
  c.cy = K[5];
  if (!c.valid() || K[8] != 1.0 || K[1] != 0.0 || K[3] != 0.0 || K[6] != 0.0 || K[7] != 0.0) {
    std::ostringstream os;
    os << label << ": camera_info is not a calibrated pinhole camera (" << info.width << "x"
       << info.height << ", K = [" << K[0] << " " << K[1] << " " << K[2] << "; " << K[3] << " "
       << K[4] << " " << K[5] << "; " << K[6] << " " << K[7] << " " << K[8] << "])";
    throw CalibrationError(os.str());
  }
  bool all_zero = true;
  for (double d : info.D) all_zero = all_zero && d == 0.0;
  if (all_zero) return c;
  const std::string& model = info.distortion_model;
  const bool radtan =
      model == "plumb_bob" || model == "Brown Conrady" || model == "rational_polynomial";
  bool extra = false;
  for (std::size_t i = 5; i < info.D.size(); ++i) extra = extra || info.D[i] != 0.0;
  if (!radtan || extra) {
    throw CalibrationError(
        label + ": distortion model '" + model + "' with " + std::to_string(info.D.size()) +
        " non-zero coefficients cannot be represented (supported: radial-tangential "
        "k1 k2 p1 p2 k3); give the intrinsics with --config or --camera-yaml");
  }
  for (std::size_t i = 0; i < 5 && i < info.D.size(); ++i) c.dist[i] = info.D[i];
  return c;
}

Eigen::Isometry3d isometryFromTransform(const geometry_msgs::Transform& tf,
                                        const std::string& label) {
  const Eigen::Quaterniond q(tf.rotation.w, tf.rotation.x, tf.rotation.y, tf.rotation.z);
  const Eigen::Vector3d t(tf.translation.x, tf.translation.y, tf.translation.z);
  if (!(q.norm() > 1e-6) || !q.coeffs().allFinite() || !t.allFinite())
    throw CalibrationError(label + ": transform has an invalid rotation or translation");
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = q.normalized().toRotationMatrix();
  T.translation() = t;
  return T;
}

std::string describePose(const Eigen::Isometry3d& T) {
  const Eigen::AngleAxisd aa(T.rotation());
  std::ostringstream os;
  os << std::fixed << std::setprecision(4) << "translation (" << T.translation().x() << ", "
     << T.translation().y() << ", " << T.translation().z() << ") m, rotation "
     << std::setprecision(3) << aa.angle() * 180.0 / M_PI << " deg";
  return os.str();
}

}  // namespace rgbdi::bag
