// Timings of the imu stage: cost per pushed sample (integration + covariance propagation), per
// repropagated sample, and per ImuFactor evaluation with and without Jacobians.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <vector>

#include "rgbdi/common/so3.h"
#include "rgbdi/imu/imu_factor.h"
#include "rgbdi/imu/preintegration.h"

using namespace rgbdi;
using namespace rgbdi::imu;

namespace {

using Clock = std::chrono::steady_clock;

double microsecondsSince(Clock::time_point start) {
  return std::chrono::duration<double, std::micro>(Clock::now() - start).count();
}

// Smooth rotating, accelerating motion sampled at 200 Hz (values only need to be realistic).
std::vector<ImuSample> makeSamples(int count) {
  std::vector<ImuSample> out;
  for (int k = 0; k < count; ++k) {
    const double t = k / 200.0;
    ImuSample s;
    s.t = t;
    s.acc = Eigen::Vector3d(0.5 * std::sin(1.3 * t), 0.3 * std::cos(0.9 * t), 9.81);
    s.gyr = Eigen::Vector3d(0.2 * std::cos(1.7 * t), 0.1 * std::sin(1.1 * t), 0.4);
    out.push_back(s);
  }
  return out;
}

ImuNoise defaultNoise() {
  ImuNoise n;
  n.acc_nd = 0.005;
  n.gyr_nd = 0.0005;
  n.acc_rw = 1.4142e-5;
  n.gyr_rw = 1.4142e-6;
  return n;
}

}  // namespace

int main() {
  const auto samples = makeSamples(201);  // 1 s
  const Eigen::Vector3d ba(0.05, -0.02, 0.1), bg(0.002, -0.001, 0.003);
  const int rounds = 500;

  double checksum = 0.0;  // printed so the compiler cannot drop the timed work
  auto t0 = Clock::now();
  for (int r = 0; r < rounds; ++r) {
    Preintegration pre(ba, bg, defaultNoise());
    for (const auto& s : samples) pre.push(s);
    checksum += pre.deltaP().x();
  }
  const double us_push = microsecondsSince(t0) / (rounds * static_cast<double>(samples.size()));

  Preintegration pre(ba, bg, defaultNoise());
  for (const auto& s : samples) pre.push(s);
  t0 = Clock::now();
  for (int r = 0; r < rounds; ++r) {
    pre.repropagate(ba + Eigen::Vector3d::Constant(1e-3 * (r % 2)), bg);
    checksum += pre.deltaV().y();
  }
  const double us_repro = microsecondsSince(t0) / (rounds * static_cast<double>(samples.size()));

  // A 30 Hz frame interval (7 samples) as the estimator builds it.
  Preintegration frame(ba, bg, defaultNoise());
  for (int k = 0; k <= 6; ++k) frame.push(samples[static_cast<std::size_t>(k)]);
  const Eigen::Vector3d g(0, 0, -9.81);
  Eigen::Vector3d Pj, Vj;
  Eigen::Quaterniond Qj;
  const Eigen::Quaterniond Qi = expQuat(Eigen::Vector3d(0.1, -0.2, 0.3));
  frame.predict(Eigen::Vector3d(1, 2, 3), Qi, Eigen::Vector3d(0.5, 0, 0), g, Pj, Qj, Vj);
  std::array<double, 7> pose_i = {1, 2, 3, Qi.x(), Qi.y(), Qi.z(), Qi.w()};
  std::array<double, 7> pose_j = {Pj.x() + 0.01, Pj.y(), Pj.z(), Qj.x(), Qj.y(), Qj.z(), Qj.w()};
  std::array<double, 9> sb_i = {0.5, 0, 0, ba.x(), ba.y(), ba.z(), bg.x(), bg.y(), bg.z()};
  std::array<double, 9> sb_j = {Vj.x(), Vj.y(), Vj.z(), ba.x(), ba.y(),
                                ba.z(), bg.x(), bg.y(), bg.z()};
  const ImuFactor factor(&frame, g);
  const double* params[] = {pose_i.data(), sb_i.data(), pose_j.data(), sb_j.data()};
  std::array<double, 15> res{};
  std::array<double, 15 * 7> j0{}, j2{};
  std::array<double, 15 * 9> j1{}, j3{};
  double* jacs[] = {j0.data(), j1.data(), j2.data(), j3.data()};
  const int evals = 50000;

  t0 = Clock::now();
  for (int r = 0; r < evals; ++r) {
    factor.Evaluate(params, res.data(), nullptr);
    checksum += res[0];
  }
  const double us_res = microsecondsSince(t0) / evals;
  t0 = Clock::now();
  for (int r = 0; r < evals; ++r) {
    factor.Evaluate(params, res.data(), jacs);
    checksum += j1[3];
  }
  const double us_jac = microsecondsSince(t0) / evals;

  std::printf("bench_imu (checksum %.6g)\n", checksum);
  std::printf("  Preintegration::push           %8.3f us per sample\n", us_push);
  std::printf("  Preintegration::repropagate    %8.3f us per sample\n", us_repro);
  std::printf("  ImuFactor::Evaluate residual   %8.3f us\n", us_res);
  std::printf("  ImuFactor::Evaluate + Jacobians%8.3f us\n", us_jac);
  return 0;
}
