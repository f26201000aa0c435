// Front-end timing on synthetic 640x480 images: a random-rectangle texture panned, rotated and
// zoomed across 300 frames, with D435-like depth that is not aligned to colour. Prints ms/frame
// per step. Single-threaded OpenCV, as on one core of the target machine.
//   bench_frontend [--set KEY=VALUE ...]   (keys of [frontend], e.g. --set klt_window_px=15)
#include <time.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <random>
#include <string>
#include <vector>

#include "rgbdi/common/ini_reader.h"
#include "rgbdi/frontend/feature_tracker.h"

namespace {

using rgbdi::PinholeCamera;
using rgbdi::RgbdFrame;
using namespace rgbdi::frontend;

constexpr int kFrames = 300;

cv::Mat texture(int w, int h, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int> x(0, w - 1), y(0, h - 1), side(4, 48), grey(20, 235);
  cv::Mat t(h, w, CV_8UC1, cv::Scalar(128));
  for (int i = 0; i < w * h / 400; ++i)
    t(cv::Rect(x(rng), y(rng), side(rng), side(rng)) & cv::Rect(0, 0, w, h)).setTo(grey(rng));
  cv::GaussianBlur(t, t, cv::Size(0, 0), 1.2);
  return t;
}

/// Texture -> image k: a slow pan with oscillating rotation and zoom (about 2-4 px per frame).
cv::Mat motion(int k) {
  const double a = 0.02 * std::sin(0.05 * k), s = 1.0 + 0.05 * std::sin(0.03 * k);
  cv::Mat M = (cv::Mat_<double>(3, 3) << s * std::cos(a), -s * std::sin(a), 0, s * std::sin(a),
               s * std::cos(a), 0, 0, 0, 1);
  const cv::Mat centre = (cv::Mat_<double>(3, 3) << 1, 0, 320, 0, 1, 240, 0, 0, 1);
  const cv::Mat pan =
      (cv::Mat_<double>(3, 3) << 1, 0, -500 - 2.0 * k, 0, 1, -400 - 0.7 * k, 0, 0, 1);
  return centre * M * pan;
}

/// CPU time of the calling thread [ms]: unlike wall time it does not count the time this thread
/// waits while other processes run, so the numbers hold on a busy machine too.
double threadCpuMs() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

struct Stat {
  std::vector<double> v;
  void add(double x) { v.push_back(x); }
  double percentile(double p) const {
    std::vector<double> c = v;
    std::sort(c.begin(), c.end());
    return c.empty() ? 0 : c[std::min(c.size() - 1, static_cast<size_t>(p * c.size()))];
  }
};

}  // namespace

int main(int argc, char** argv) {
  std::string overrides = "[frontend]\n";
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--set" && i + 1 < argc && std::string(argv[i + 1]).find('=') != std::string::npos) {
      overrides += std::string(argv[++i]) + "\n";
    } else {
      std::cerr << "usage: bench_frontend [--set KEY=VALUE ...]  (keys of [frontend])\n";
      return 2;
    }
  }
  rgbdi::IniReader ini = rgbdi::IniReader::fromText(overrides, "bench_frontend --set");
  const FrontendOptions options = FrontendOptions::load(ini);
  ini.checkNoUnknownKeys();
  cv::setNumThreads(1);
  PinholeCamera cam;
  cam.width = 640;
  cam.height = 480;
  cam.fx = 613.2;
  cam.fy = 612.9;
  cam.cx = 319.9;
  cam.cy = 243.1;
  cam.dist = {0.06, -0.12, 0.0005, -0.0003, 0.0};
  PinholeCamera cam_depth = cam;
  cam_depth.fx = cam_depth.fy = 390.4;
  cam_depth.cx = 331.4;
  cam_depth.cy = 237.8;
  cam_depth.dist = {0, 0, 0, 0, 0};

  const cv::Mat tex = texture(2000, 1500, 5);
  // A slanted plane 1.2-2.4 m away with a 2 % random hole fraction, in 1 mm units.
  cv::Mat depth(480, 640, CV_16UC1);
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int v = 0; v < 480; ++v)
    for (int u = 0; u < 640; ++u)
      depth.at<std::uint16_t>(v, u) =
          unit(rng) < 0.02 ? 0 : static_cast<std::uint16_t>(1200 + 1.9 * u);

  std::printf("preparing %d frames...\n", kFrames);
  std::vector<RgbdFrame> frames(kFrames);
  for (int k = 0; k < kFrames; ++k) {
    cv::Mat grey;
    cv::warpPerspective(tex, grey, motion(k), cv::Size(640, 480), cv::INTER_LINEAR,
                        cv::BORDER_REFLECT);
    RgbdFrame& f = frames[static_cast<size_t>(k)];
    f.t = k / 30.0;
    f.index = static_cast<std::uint64_t>(k);
    cv::cvtColor(grey, f.rgb, cv::COLOR_GRAY2RGB);
    f.depth = depth;
    f.depth_unit_m = 1e-3;
    f.cam_color = cam;
    f.cam_depth = cam_depth;
    f.T_color_depth.translation() = Eigen::Vector3d(-0.0143, -0.0006, -0.0006);
    f.depth_aligned_to_color = false;
  }

  FeatureTracker tracker(options, cam);
  Stat grey, pyramid, klt, ransac, detect, depth_ms, tracking, total, cpu, tracked, fresh,
      with_depth;
  for (int k = 0; k < kFrames; ++k) {
    const double cpu0 = threadCpuMs();
    const FeatureFrame f = tracker.track(frames[static_cast<size_t>(k)]);
    const double cpu_ms = threadCpuMs() - cpu0;
    if (k < 5) continue;  // warm-up (first-call allocations, the depth ray table)
    grey.add(f.timings.grey_ms);
    pyramid.add(f.timings.pyramid_ms);
    klt.add(f.timings.klt_ms);
    ransac.add(f.timings.ransac_ms);
    if (options.max_features - f.n_tracked >= options.detect_min_missing)
      detect.add(f.timings.detect_ms);  // frames that detected
    depth_ms.add(f.timings.depth_ms);
    tracking.add(f.timings.trackingMs());
    total.add(f.timings.total_ms);
    cpu.add(cpu_ms);
    tracked.add(f.n_tracked);
    fresh.add(f.n_new);
    with_depth.add(f.n_with_depth);
  }
  std::printf("frontend, %d frames 640x480, max_features %d, KLT window %d px, 1 OpenCV thread\n",
              kFrames, options.max_features, options.klt_window_px);
  std::printf("  wall-clock time per step (from FeatureFrame::timings):\n");
  std::printf("  %-32s %8s %8s %8s\n", "step", "min ms", "median", "p95");
  auto row = [](const char* name, const Stat& s) {
    std::printf("  %-32s %8.3f %8.3f %8.3f\n", name, s.percentile(0.0), s.percentile(0.5),
                s.percentile(0.95));
  };
  row("grey conversion", grey);
  row("pyramid + derivatives", pyramid);
  row("KLT forward + backward", klt);
  row("fundamental RANSAC", ransac);
  row("spacing + Shi-Tomasi detection *", detect);
  row("tracking + detection (budget 6)", tracking);
  row("depth registration + sampling", depth_ms);
  row("total per frame", total);
  std::printf("  (* over the %zu frames that ran the detector)\n", detect.v.size());
  std::printf("  thread CPU time of track():\n");
  row("total per frame (CPU)", cpu);
  std::printf("  features per frame (median): %.0f tracked, %.0f new, %.0f with depth\n",
              tracked.percentile(0.5), fresh.percentile(0.5), with_depth.percentile(0.5));
  return 0;
}
