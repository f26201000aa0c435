#include "rgbdi/bag/ros_odometry.h"

#include <ros/serialization.h>
#include <tf2_msgs/TFMessage.h>

#include <cmath>
#include <deque>
#include <iomanip>
#include <map>
#include <sstream>

#include "wire_check.h"

namespace rgbdi::bag {
namespace {

using WireCheck = detail::WireCheck<MessageDecodeError>;

template <typename M>
void deserializeRos(const std::uint8_t* data, std::uint32_t size, M& out) {
  ros::serialization::IStream s(const_cast<std::uint8_t*>(data), size);
  ros::serialization::deserialize(s, out);
}

/// geometry_msgs/PoseWithCovariance (7 + 36 float64) and TwistWithCovariance (6 + 36 float64).
constexpr std::uint32_t kPoseWithCovarianceBytes = (7 + 36) * 8;
constexpr std::uint32_t kTwistWithCovarianceBytes = (6 + 36) * 8;
/// geometry_msgs/Transform: translation (3 float64) and rotation (4 float64).
constexpr std::uint32_t kTransformBytes = 7 * 8;
/// The least bytes of one TransformStamped: header (seq, stamp, empty frame_id), empty
/// child_frame_id, transform.
constexpr std::uint32_t kMinTransformStampedBytes = 4 + 8 + 4 + 4 + kTransformBytes;

std::string frameName(const std::string& f) { return !f.empty() && f[0] == '/' ? f.substr(1) : f; }

std::string values(std::initializer_list<double> v) {
  std::ostringstream os;
  os << std::setprecision(9);
  bool first = true;
  for (double x : v) {
    os << (first ? "" : " ") << x;
    first = false;
  }
  return os.str();
}

}  // namespace

nav_msgs::Odometry deserializeOdometry(const std::uint8_t* data, std::uint32_t size,
                                       const std::string& label) {
  WireCheck w(data, size, label);
  w.header();
  w.sized("child_frame_id");
  w.fixed(kPoseWithCovarianceBytes, "pose (PoseWithCovariance)");
  w.fixed(kTwistWithCovarianceBytes, "twist (TwistWithCovariance)");
  nav_msgs::Odometry msg;
  deserializeRos(data, size, msg);
  return msg;
}

WheelOdometrySample wheelFromOdometry(const nav_msgs::Odometry& msg, double t,
                                      const std::string& label) {
  const auto& p = msg.pose.pose.position;
  const auto& q = msg.pose.pose.orientation;
  const auto& v = msg.twist.twist.linear;
  const auto& w = msg.twist.twist.angular;
  const bool finite = std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z) &&
                      std::isfinite(q.x) && std::isfinite(q.y) && std::isfinite(q.z) &&
                      std::isfinite(q.w) && std::isfinite(v.x) && std::isfinite(v.y) &&
                      std::isfinite(w.z);
  if (!finite)
    throw MessageDecodeError(label + ": value not finite (position " + values({p.x, p.y, p.z}) +
                             ", orientation x y z w " + values({q.x, q.y, q.z, q.w}) +
                             ", linear velocity x y " + values({v.x, v.y}) +
                             ", angular velocity z " + values({w.z}) + ")");
  const double n2 = q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w;
  if (!(n2 > 1e-12))
    throw MessageDecodeError(label + ": zero orientation quaternion (x y z w " +
                             values({q.x, q.y, q.z, q.w}) + ")");
  WheelOdometrySample s;
  s.t = t;
  s.x_m = p.x;
  s.y_m = p.y;
  // Yaw of the (normalised) rotation, ZYX convention: the planar heading of the child frame.
  s.yaw_rad =
      std::atan2(2.0 * (q.w * q.z + q.x * q.y) / n2, 1.0 - 2.0 * (q.y * q.y + q.z * q.z) / n2);
  s.has_velocities = true;
  s.v_forward_m_s = v.x;
  s.v_lateral_m_s = v.y;
  s.yaw_rate_rad_s = w.z;
  return s;
}

std::vector<geometry_msgs::TransformStamped> deserializeTfMessage(const std::uint8_t* data,
                                                                  std::uint32_t size,
                                                                  const std::string& label) {
  WireCheck w(data, size, label);
  const std::uint32_t n = w.u32("transforms (count)");
  // ROS resizes the vector to the count before reading: refuse a count the bytes cannot hold.
  if (static_cast<std::uint64_t>(n) * kMinTransformStampedBytes > w.left())
    throw MessageDecodeError(
        label + ": corrupt message: " + std::to_string(n) + " transforms need at least " +
        std::to_string(static_cast<std::uint64_t>(n) * kMinTransformStampedBytes) +
        " bytes, the message has " + std::to_string(w.left()) + " left");
  for (std::uint32_t i = 0; i < n; ++i) {
    w.header();
    w.sized("child_frame_id");
    w.fixed(kTransformBytes, "transform");
  }
  tf2_msgs::TFMessage msg;
  deserializeRos(data, size, msg);
  return msg.transforms;
}

std::optional<Eigen::Isometry3d> lookupStaticTransform(
    const std::vector<geometry_msgs::TransformStamped>& transforms, const std::string& target,
    const std::string& source, const std::string& label) {
  // Undirected graph of frames; an edge parent->child carries T_parent_child.
  struct Edge {
    std::string to;
    const geometry_msgs::TransformStamped* tf;
    bool forward;  ///< from the parent to the child
  };
  std::map<std::string, std::vector<Edge>> graph;
  for (const auto& t : transforms) {
    const std::string parent = frameName(t.header.frame_id), child = frameName(t.child_frame_id);
    graph[parent].push_back({child, &t, true});
    graph[child].push_back({parent, &t, false});
  }
  // Breadth-first from the target: pose of each reached frame in the target.
  const std::string from = frameName(target), to = frameName(source);
  std::map<std::string, Eigen::Isometry3d> T_target;
  T_target[from] = Eigen::Isometry3d::Identity();
  std::deque<std::string> open{from};
  while (!open.empty()) {
    const std::string f = open.front();
    open.pop_front();
    if (f == to) return T_target.at(f);
    for (const Edge& e : graph[f]) {
      if (T_target.count(e.to)) continue;
      const auto& tr = e.tf->transform.translation;
      const auto& r = e.tf->transform.rotation;
      const double n = std::sqrt(r.x * r.x + r.y * r.y + r.z * r.z + r.w * r.w);
      if (!std::isfinite(tr.x) || !std::isfinite(tr.y) || !std::isfinite(tr.z) ||
          !std::isfinite(n) || !(n > 1e-6))
        throw MessageDecodeError(label + ": transform " + e.tf->header.frame_id + " -> " +
                                 e.tf->child_frame_id +
                                 " has a non-finite value or a zero quaternion");
      Eigen::Isometry3d T_parent_child = Eigen::Isometry3d::Identity();
      T_parent_child.linear() = Eigen::Quaterniond(r.w, r.x, r.y, r.z).normalized().matrix();
      T_parent_child.translation() = Eigen::Vector3d(tr.x, tr.y, tr.z);
      T_target[e.to] = T_target.at(f) * (e.forward ? T_parent_child : T_parent_child.inverse());
      open.push_back(e.to);
    }
  }
  return std::nullopt;
}

}  // namespace rgbdi::bag
