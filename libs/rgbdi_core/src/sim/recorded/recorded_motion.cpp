#include "rgbdi/sim/recorded_motion.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace rgbdi::sim {
namespace {

/// A rotation A with A e_z = axis (unit).
Eigen::Matrix3d frameWithZ(const Eigen::Vector3d& axis) {
  return Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), axis).toRotationMatrix();
}

/// z-y-x Euler angles (a, b, c) with R = Rz(a) Ry(b) Rx(c).
Eigen::Vector3d eulerZyx(const Eigen::Matrix3d& R) { return R.eulerAngles(2, 1, 0); }

void rotateZyx(MotionJet& jet, const Eigen::Vector3d& zyx) {
  jet.rotate(2, Taylor<2>(zyx[0]));
  jet.rotate(1, Taylor<2>(zyx[1]));
  jet.rotate(0, Taylor<2>(zyx[2]));
}

// Step of the positions from which the room and the corridor are laid out.
constexpr double kLayoutStepS = 0.01;
// Spacing of the path points that keep furniture away (the corridor is checked at them).
constexpr double kPathPointSpacingM = 0.1;

}  // namespace

RecordedTrajectory::RecordedTrajectory(const std::vector<RecordedPose>& samples) {
  if (samples.size() < 2)
    throw std::invalid_argument("RecordedTrajectory: at least 2 ground-truth samples needed");
  origin_ = samples.front().t;
  const std::size_t n = samples.size();
  for (std::size_t i = 0; i < n; ++i) {
    t_.push_back(samples[i].t - origin_);
    p_.push_back(samples[i].p_world);
    if (i > 0 && !(t_[i] > t_[i - 1]))
      throw std::invalid_argument("RecordedTrajectory: stamps must increase (sample " +
                                  std::to_string(i) + ")");
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (samples[i].has_velocity) {
      v_.push_back(samples[i].v_world);
    } else {
      const std::size_t a = i > 0 ? i - 1 : 0, b = std::min(i + 1, n - 1);
      v_.push_back((p_[b] - p_[a]) / (t_[b] - t_[a]));
    }
  }
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const Eigen::Quaterniond& q0 = samples[i].q_world_body;
    Eigen::Quaterniond d = q0.conjugate() * samples[i + 1].q_world_body;
    if (d.w() < 0.0) d.coeffs() = -d.coeffs();  // the shorter arc
    const Eigen::AngleAxisd aa(d.normalized());
    SegmentRotation r;
    const Eigen::Matrix3d A =
        aa.angle() > 0.0 ? frameWithZ(aa.axis()) : Eigen::Matrix3d::Identity().eval();
    r.angle = aa.angle();
    r.start_zyx = eulerZyx(q0.toRotationMatrix() * A);
    r.back_zyx = eulerZyx(A.transpose());
    rot_.push_back(r);
  }
}

MotionJet RecordedTrajectory::jetAt(double t) const {
  // Segment i with t_[i] <= t <= t_[i+1] (the last segment holds the end).
  const auto it = std::upper_bound(t_.begin(), t_.end(), t);
  const std::size_t i = std::min<std::size_t>(
      t_.size() - 2, static_cast<std::size_t>(std::max<std::ptrdiff_t>(0, it - t_.begin() - 1)));
  const double h = t_[i + 1] - t_[i], s = (t - t_[i]) / h;
  // Cubic Hermite in monomial form p = a0 + a1 s + a2 s^2 + a3 s^3; derivatives in t carry 1/h^k.
  const Eigen::Vector3d a0 = p_[i], a1 = h * v_[i];
  const Eigen::Vector3d a2 = 3.0 * (p_[i + 1] - p_[i]) - h * (2.0 * v_[i] + v_[i + 1]);
  const Eigen::Vector3d a3 = 2.0 * (p_[i] - p_[i + 1]) + h * (v_[i] + v_[i + 1]);
  MotionJet jet;
  for (int k = 0; k < 3; ++k) {
    Taylor<3>& c = jet.position[static_cast<std::size_t>(k)];
    c.coeff(0) = a0[k] + s * (a1[k] + s * (a2[k] + s * a3[k]));
    c.coeff(1) = (a1[k] + s * (2.0 * a2[k] + s * 3.0 * a3[k])) / h;
    c.coeff(2) = (a2[k] + 3.0 * a3[k] * s) / (h * h);  // p'' / 2
    c.coeff(3) = a3[k] / (h * h * h);                  // p''' / 6
  }
  const SegmentRotation& r = rot_[i];
  rotateZyx(jet, r.start_zyx);
  Taylor<2> angle(r.angle * s);
  angle.coeff(1) = r.angle / h;
  jet.rotate(2, angle);
  rotateZyx(jet, r.back_zyx);
  return jet;
}

RecordedWorldOptions RecordedWorldOptions::load(IniReader& ini) {
  RecordedWorldOptions o;
  const std::string s = "sim";
  o.room_margin_m = ini.getDouble(s, "recorded_room_margin_m", o.room_margin_m, 0.5, 100.0);
  o.floor_below_m = ini.getDouble(s, "recorded_floor_below_m", o.floor_below_m, 0.05, 100.0);
  o.ceiling_above_m = ini.getDouble(s, "recorded_ceiling_above_m", o.ceiling_above_m, 0.1, 100.0);
  o.path_clearance_m = ini.getDouble(s, "recorded_path_clearance_m", o.path_clearance_m, 0.1, 10.0);
  o.max_gap_s = ini.getDouble(s, "recorded_max_gap_s", o.max_gap_s, 0.001, 10.0);
  return o;
}

RecordedMotion makeRecordedMotion(const Recording& rec, const RecordedWorldOptions& options,
                                  double duration_s) {
  const std::string where = "recording " + rec.directory;
  if (rec.imu.size() < 2 || rec.ground_truth.size() < 2)
    throw RecordingError(where + ": needs at least 2 IMU and 2 ground-truth samples");
  const double imu_begin = rec.imu.front().t, imu_end = rec.imu.back().t;
  const auto& gt = rec.ground_truth;
  RecordedMotion m;
  const auto first =
      std::find_if(gt.begin(), gt.end(), [&](const RecordedPose& g) { return g.t >= imu_begin; });
  if (first == gt.end() || first->t > imu_end)
    throw RecordingError(where + ": no ground-truth sample inside the IMU's time span");
  m.first_pose = static_cast<std::size_t>(first - gt.begin());
  // 1 us of slack: a duration written back from simulation.ini cuts at the same sample.
  const double end = duration_s > 0.0 ? std::min(imu_end, first->t + duration_s + 1e-6) : imu_end;
  m.last_pose = m.first_pose;
  while (m.last_pose + 1 < gt.size() && gt[m.last_pose + 1].t <= end) ++m.last_pose;
  if (m.last_pose == m.first_pose)
    throw RecordingError(where + ": fewer than 2 ground-truth samples inside the IMU's time span");
  for (std::size_t i = m.first_pose; i < m.last_pose; ++i)
    if (gt[i + 1].t - gt[i].t > options.max_gap_s)
      throw RecordingError(where + ": ground truth has a gap of " +
                           std::to_string(gt[i + 1].t - gt[i].t) + " s after the sample at " +
                           std::to_string(gt[i].t) + " s (longer than [sim] recorded_max_gap_s = " +
                           std::to_string(options.max_gap_s) + " s)");
  m.imu_count = static_cast<std::size_t>(
      std::upper_bound(rec.imu.begin(), rec.imu.end(), gt[m.last_pose].t,
                       [](double t, const ImuSample& s) { return t < s.t; }) -
      rec.imu.begin());

  m.trajectory = std::make_shared<RecordedTrajectory>(
      std::vector<RecordedPose>(gt.begin() + static_cast<std::ptrdiff_t>(m.first_pose),
                                gt.begin() + static_cast<std::ptrdiff_t>(m.last_pose) + 1));
  const RecordedTrajectory& traj = *m.trajectory;

  // Bounds, horizontal length and the path points, from positions every kLayoutStepS.
  MotionProfile& prof = m.profile;
  ProfileLayout& l = prof.layout;
  Eigen::AlignedBox3d box;
  Eigen::Vector2d last_xy = traj.pose(0.0).translation().head<2>();
  l.path_xy.push_back(last_xy);
  double length = 0.0;
  Eigen::Vector2d prev_xy = last_xy;
  const std::size_t steps = static_cast<std::size_t>(std::ceil(traj.duration() / kLayoutStepS));
  for (std::size_t k = 0; k <= steps; ++k) {
    const Eigen::Vector3d p =
        traj.pose(std::min(traj.duration(), static_cast<double>(k) * kLayoutStepS)).translation();
    box.extend(p);
    length += (p.head<2>() - prev_xy).norm();
    prev_xy = p.head<2>();
    if ((p.head<2>() - last_xy).norm() >= kPathPointSpacingM || k == steps) {
      last_xy = p.head<2>();
      l.path_xy.push_back(last_xy);
    }
  }
  const Eigen::Vector3d margin(options.room_margin_m, options.room_margin_m, 0.0);
  l.room_min = box.min() - margin - Eigen::Vector3d(0.0, 0.0, options.floor_below_m);
  l.room_max = box.max() + margin + Eigen::Vector3d(0.0, 0.0, options.ceiling_above_m);
  l.path_clearance_m = options.path_clearance_m;
  prof.kind = ProfileKind::Recorded;
  prof.trajectory = m.trajectory;
  prof.path_length_m = length;
  prof.lap_length_m = length;  // the whole path is furnished
  prof.cruise_speed_m_s = length / traj.duration();
  prof.moving_start_s = prof.cruise_start_s = 0.0;
  prof.moving_end_s = prof.cruise_end_s = traj.duration();
  return m;
}

}  // namespace rgbdi::sim
