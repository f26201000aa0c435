// Cost of the wheel odometry in the odometry, per frame: pre-integrating the readings of one
// window interval (50 Hz odometry, frames at 15 Hz, one interval per keyframe gap of 0.2-0.5 s)
// and evaluating its WheelFactor with Jacobians, as a window of 10 frames does at each update
// (one factor per interval, every solver iteration), and the gate's check of an interval.
#include <Eigen/Geometry>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <deque>
#include <vector>

#include "rgbdi/estimator/wheel_calibration_factor.h"
#include "rgbdi/estimator/wheel_factor.h"
#include "rgbdi/estimator/wheel_preintegration.h"

using namespace rgbdi;
using namespace rgbdi::estimator;

namespace {

using Clock = std::chrono::steady_clock;

double microsecondsSince(Clock::time_point start) {
  return std::chrono::duration<double, std::micro>(Clock::now() - start).count();
}

/// 60 s of 50 Hz odometry along a wavy path at 0.5 m/s.
std::deque<WheelOdometrySample> readings() {
  std::deque<WheelOdometrySample> r;
  double x = 0.0, y = 0.0, yaw = 0.0;
  for (int k = 0; k <= 3000; ++k) {
    WheelOdometrySample w;
    w.t = k / 50.0;
    const double rate = 0.3 * std::sin(0.4 * w.t);
    x += 0.01 * std::cos(yaw);
    y += 0.01 * std::sin(yaw);
    yaw = std::remainder(yaw + rate / 50.0, 2.0 * M_PI);
    w.x_m = x;
    w.y_m = y;
    w.yaw_rad = yaw;
    r.push_back(w);
  }
  return r;
}

}  // namespace

int main() {
  const auto r = readings();
  const WheelNoise noise;
  for (const double gap_s : {0.2, 0.5}) {
    const int n = static_cast<int>(50.0 / gap_s);
    auto start = Clock::now();
    std::vector<WheelPreintegration> pre;
    for (int k = 0; k < n; ++k) {
      const double t = 1.0 + k * gap_s;
      pre.push_back(*WheelPreintegration::between(r, t, t + gap_s, 0.0, noise));
    }
    const double us_pre = microsecondsSince(start) / n;
    const Eigen::Isometry3d T_bw = Eigen::Isometry3d::Identity();
    double pose_a[7] = {0, 0, 0, 0, 0, 0, 1}, pose_b[7] = {0.1, 0.01, 0, 0, 0, 0.01, 1};
    double sv = 1.0, sw = 1.0;
    const double* params[] = {pose_a, pose_b, &sv, &sw};
    double res[6], ja[42], jb[42], jv[6], jw[6];
    double* jac[] = {ja, jb, jv, jw};
    const int evals = 20000;
    double sink = 0.0;
    start = Clock::now();
    for (int k = 0; k < evals; ++k) {
      const WheelFactor f(pre[static_cast<std::size_t>(k % n)], T_bw);
      f.Evaluate(params, res, jac);
      sink += res[0];
    }
    const double us_eval = microsecondsSince(start) / evals;
    start = Clock::now();
    for (int k = 0; k < evals; ++k) {
      const WheelFactor f(pre[static_cast<std::size_t>(k % n)], T_bw);
      sink += f.error(pose_a, pose_b, sv, sw).squaredNorm();
    }
    const double us_check = microsecondsSince(start) / evals;
    // The same with the online calibration (extrinsic yaw and time offset blocks).
    double yaw = 0.01, td = 0.002, jy[6], jt[6];
    const double* params_cal[] = {pose_a, pose_b, &sv, &sw, &yaw, &td};
    double* jac_cal[] = {ja, jb, jv, jw, jy, jt};
    start = Clock::now();
    for (int k = 0; k < evals; ++k) {
      const WheelCalibrationFactor f(pre[static_cast<std::size_t>(k % n)], T_bw);
      f.Evaluate(params_cal, res, jac_cal);
      sink += res[0];
    }
    const double us_eval_cal = microsecondsSince(start) / evals;
    // A 10-frame window: 9 intervals pre-integrated, checked and evaluated 8 times (iterations).
    std::printf(
        "interval %.1f s (%zu increments): pre-integration %.2f us, factor with Jacobians %.3f "
        "us (with the online calibration %.3f us), check %.3f us; per update of a 10-frame "
        "window (9 intervals, 8 iterations): %.1f us%s\n",
        gap_s, pre.front().increments(), us_pre, us_eval, us_eval_cal, us_check,
        9 * (us_pre + us_check + 8 * us_eval), sink == 12345.0 ? " " : "");
  }
  return 0;
}
