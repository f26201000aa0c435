// Renderer throughput on one core: a furnished room (~150 primitives) rendered at 640x480 from
// several poses. Prints ms/frame and frames/s; `--save DIR` also writes the frames as PNG.
#include <time.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "rgbdi/common/sensor_options.h"
#include "rgbdi/sim/renderer.h"
#include "rgbdi/sim/scene_presets.h"

namespace {

// CPU time of this thread [ms]: meaningful on a machine shared with other jobs, where wall time
// also counts time the core spent elsewhere.
double threadCpuMs() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

// Camera optical frame looking along `forward` (horizontal), z forward, y down.
Eigen::Isometry3d lookFrom(const Eigen::Vector3d& eye, double yaw, double pitch) {
  const Eigen::Matrix3d R_world_body = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                                        Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()))
                                           .toRotationMatrix();
  Eigen::Matrix3d R_body_cam;  // optical (x right, y down, z fwd) in body (x fwd, y left, z up)
  R_body_cam << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = R_world_body * R_body_cam;
  T.translation() = eye;
  return T;
}

}  // namespace

int main(int argc, char** argv) {
  std::string save_dir;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--save" && i + 1 < argc) {
      save_dir = argv[++i];
    } else {
      std::cerr << "usage: bench_render [--save DIR]\n";
      return 2;
    }
  }
  const auto t_build0 = std::chrono::steady_clock::now();
  const rgbdi::sim::Scene scene = rgbdi::sim::makeFurnishedRoom(1);
  const double build_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t_build0)
          .count();
  const rgbdi::PinholeCamera cam = rgbdi::CameraOptions().camera;
  const rgbdi::sim::Renderer renderer(scene, cam);
  std::printf(
      "scene: %zu primitives, %zu materials, BVH %zu nodes depth %d, build+textures %.1f ms\n",
      scene.primitiveCount(), scene.materialCount(), scene.bvh().nodeCount(), scene.bvh().depth(),
      build_ms);

  std::vector<Eigen::Isometry3d> poses;
  for (int k = 0; k < 8; ++k) {
    const double yaw = k * M_PI / 4.0;
    poses.push_back(
        lookFrom({0.6 * std::cos(yaw), 0.6 * std::sin(yaw), 0.4}, yaw, 0.1 * (k % 3 - 1)));
  }
  cv::Mat rgb, depth;
  renderer.render(poses[0], rgb, depth);  // warm-up (allocates the outputs)
  const int repeats = 4;
  double total_ms = 0.0, total_cpu_ms = 0.0;
  int frames = 0;
  for (std::size_t p = 0; p < poses.size(); ++p) {
    const auto t0 = std::chrono::steady_clock::now();
    const double c0 = threadCpuMs();
    for (int k = 0; k < repeats; ++k) renderer.render(poses[p], rgb, depth);
    const double cpu_ms = (threadCpuMs() - c0) / repeats;
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() /
        repeats;
    total_ms += ms * repeats;
    total_cpu_ms += cpu_ms * repeats;
    frames += repeats;
    std::printf("pose %zu: %.2f ms/frame CPU (%.1f frames/s), %.2f ms wall\n", p, cpu_ms,
                1000.0 / cpu_ms, ms);
    if (!save_dir.empty()) {
      cv::Mat bgr, d16;
      cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
      depth.convertTo(d16, CV_16U, 1000.0);
      cv::imwrite(save_dir + "/render_" + std::to_string(p) + ".png", bgr);
      cv::imwrite(save_dir + "/depth_" + std::to_string(p) + ".png", d16);
    }
  }
  std::printf("mean: %.2f ms/frame CPU, %.1f frames/s at %dx%d on one core (wall %.2f ms/frame)\n",
              total_cpu_ms / frames, 1000.0 * frames / total_cpu_ms, cam.width, cam.height,
              total_ms / frames);
  return 0;
}
