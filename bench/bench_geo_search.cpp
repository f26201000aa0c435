// Cost of one geometric relocalisation attempt (reloc::GeometricRelocaliser::fit: the global
// branch-and-bound search over x, y, yaw, the height and the ICP refinement) against the size
// of the saved map. Synthetic floor plans of the given areas (outer walls, random crates and
// pillars), the map seen by a 360-degree depth scan every metre, the local submap by a camera
// with the D435's 87-degree field of view from three poses along 3 m of path, in a frame
// turned and shifted at random. Prints per area: map cells, time to build the map's plan, and
// the median / worst search time over the attempts, with the outcome and the error of each fit
// (views with too little structure to search are drawn again and counted, not timed).
//
//   bench_geo_search [--areas 100,1000] [--attempts 5] [--seed 1] [--detail (each fit, stderr)]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "rgbdi/reloc/geometric_relocaliser.h"

using namespace rgbdi;
using Clock = std::chrono::steady_clock;

namespace {

struct Box {
  double x0, y0, x1, y1;
};

constexpr double kCamZ = 0.3;  // wheeled robot camera height [m]

/// Depth samples of what a camera at (x, y, kCamZ) with heading `yaw` sees of the boxes within
/// `fov` (full angle) and 4 m: the nearest wall along each ray at three heights, and floor
/// samples before it.
void scan(const std::vector<Box>& boxes, double x, double y, double yaw, double fov,
          std::vector<reloc::DepthSample>* out) {
  const int rays = static_cast<int>(std::lround(fov / (0.25 * M_PI / 180.0)));
  const Eigen::Vector3d cam(x, y, kCamZ);
  for (int k = 0; k < rays; ++k) {
    const double a = yaw - fov / 2 + (k + 0.5) * fov / rays;
    const Eigen::Vector2d d(std::cos(a), std::sin(a));
    double best = 1e9;
    for (const Box& b : boxes) {
      for (double bx : {b.x0, b.x1}) {
        const double t = (bx - x) / d.x();
        const double yy = y + t * d.y();
        if (t > 0 && yy >= b.y0 && yy <= b.y1) best = std::min(best, t);
      }
      for (double by : {b.y0, b.y1}) {
        const double t = (by - y) / d.y();
        const double xx = x + t * d.x();
        if (t > 0 && xx >= b.x0 && xx <= b.x1) best = std::min(best, t);
      }
    }
    if (best > 4.0) continue;
    for (double dz : {-0.15, 0.0, 0.2, 0.4})
      out->push_back({cam, Eigen::Vector3d(x + best * d.x(), y + best * d.y(), kCamZ + dz)});
    for (double f : {0.3, 0.6, 0.9})
      out->push_back({cam, Eigen::Vector3d(x + f * best * d.x(), y + f * best * d.y(), 0.0)});
  }
}

struct World {
  double w = 0, h = 0;
  std::vector<Box> boxes;  // the first is the outer wall (seen from inside)
};

World makeWorld(double area_m2, std::mt19937& rng) {
  World wd;
  wd.w = std::sqrt(area_m2 * 1.6);
  wd.h = area_m2 / wd.w;
  wd.boxes.push_back({0, 0, wd.w, wd.h});
  std::uniform_real_distribution<double> ux(0.5, wd.w - 1.5), uy(0.5, wd.h - 1.5), us(0.2, 1.0);
  const int n = static_cast<int>(area_m2 / 4.0);  // a crate or pillar per 4 m^2
  for (int i = 0; i < n; ++i) {
    const double x = ux(rng), y = uy(rng);
    wd.boxes.push_back({x, y, x + us(rng), y + us(rng)});
  }
  return wd;
}

bool insideAny(const World& w, double x, double y) {
  for (std::size_t i = 1; i < w.boxes.size(); ++i)
    if (x > w.boxes[i].x0 - 0.2 && x < w.boxes[i].x1 + 0.2 && y > w.boxes[i].y0 - 0.2 &&
        y < w.boxes[i].y1 + 0.2)
      return true;
  return false;
}

Eigen::Isometry3d yawPose(double yaw, const Eigen::Vector3d& t) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = t;
  return T;
}

double ms(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<double> areas = {100.0, 1000.0};
  int attempts = 5;
  unsigned seed = 1;
  bool detail = false;
  for (int i = 1; i < argc; ++i) {
    const std::string k = argv[i];
    if (k == "--areas" && i + 1 < argc) {
      areas.clear();
      std::stringstream ss(argv[++i]);
      for (std::string v; std::getline(ss, v, ',');) areas.push_back(std::stod(v));
    } else if (k == "--attempts" && i + 1 < argc) {
      attempts = std::stoi(argv[++i]);
    } else if (k == "--detail") {
      detail = true;
    } else if (k == "--seed" && i + 1 < argc) {
      seed = static_cast<unsigned>(std::stoul(argv[++i]));
    } else {
      std::cerr
          << "usage: bench_geo_search [--areas 100,1000] [--attempts 5] [--seed 1] [--detail]\n";
      return 2;
    }
  }
  const reloc::RelocOptions options;  // the defaults of share/config.ini
  std::cout
      << "| map area [m^2] | map plan [cells] | map samples | plan build [ms] | search "
         "median [ms] | search worst [ms] | outcomes | worst fit error [cm, deg] | views with too "
         "little structure (redrawn) |\n"
         "|---|---|---|---|---|---|---|---|---|\n";
  for (double area : areas) {
    std::mt19937 rng(seed);
    const World world = makeWorld(area, rng);
    std::vector<reloc::DepthSample> map_samples;
    for (double x = 0.5; x < world.w; x += 1.0)
      for (double y = 0.5; y < world.h; y += 1.0)
        if (!insideAny(world, x, y)) scan(world.boxes, x, y, 0.0, 2 * M_PI, &map_samples);
    auto t0 = Clock::now();
    const reloc::GeometricRelocaliser reloc(map_samples, options);
    const double build_ms = ms(t0);
    std::vector<double> times;
    std::string outcomes;
    double worst_m = 0.0, worst_deg = 0.0;
    std::uniform_real_distribution<double> ux(1.0, world.w - 4.0), uy(1.0, world.h - 1.0),
        uyaw(-M_PI, M_PI);
    int skipped = 0;  // draws whose view held too little structure to search (not timed)
    for (int a = 0, draws = 0; a < attempts && draws < 20 * attempts; ++draws) {
      // Three poses along 3 m of path (+x), clear of the furniture.
      double x = 0, y = 0;
      for (int tries = 0; tries < 1000; ++tries) {
        x = ux(rng);
        y = uy(rng);
        if (!insideAny(world, x, y) && !insideAny(world, x + 1.5, y) && !insideAny(world, x + 3, y))
          break;
      }
      const double heading = uyaw(rng);
      std::vector<reloc::DepthSample> local_world;
      for (double s : {0.0, 1.5, 3.0})
        scan(world.boxes, x + s, y, heading, 87.0 * M_PI / 180.0, &local_world);
      const Eigen::Isometry3d T_part_map =
          yawPose(uyaw(rng), Eigen::Vector3d(uyaw(rng) * 3, uyaw(rng) * 3, 0.1));
      reloc::RelocJob job;
      job.number = static_cast<std::uint64_t>(a + 1);
      job.T_anchor = T_part_map * yawPose(0.0, Eigen::Vector3d(x + 3, y, kCamZ));
      for (const reloc::DepthSample& d : local_world)
        job.samples.push_back({T_part_map * d.origin, T_part_map * d.point});
      t0 = Clock::now();
      const reloc::RelocFit f = reloc.fit(job);
      const double t_ms = ms(t0);
      if (f.outcome == reloc::FitOutcome::kTooLittle) {
        ++skipped;
        continue;
      }
      ++a;
      times.push_back(t_ms);
      outcomes += std::string(outcomes.empty() ? "" : ", ") + reloc::toString(f.outcome);
      if (f.outcome == reloc::FitOutcome::kFit) {
        const Eigen::Isometry3d E = f.T_map_part * T_part_map;  // identity when right
        worst_m = std::max(worst_m, E.translation().norm());
        worst_deg = std::max(worst_deg, Eigen::AngleAxisd(E.linear()).angle() * 180.0 / M_PI);
        if (detail)
          std::cerr << "  fit error " << 100.0 * E.translation().norm() << " cm, overlap "
                    << f.overlap << ", conflicts " << f.conflict_fraction << ", ICP pairs "
                    << f.refine_pairs << ", rms " << f.refine_rms_m << " m, horizontal "
                    << f.refine_horizontal_constraint << ", local cells " << f.local_obstacles
                    << "\n";
      }
    }
    std::sort(times.begin(), times.end());
    std::cout << std::fixed << std::setprecision(0) << "| " << area << " | "
              << reloc.search().map().width() * reloc.search().map().height() << " | "
              << map_samples.size() << " | " << build_ms << " | " << times[times.size() / 2]
              << " | " << times.back() << " | " << outcomes << " | " << std::setprecision(1)
              << 100.0 * worst_m << ", " << std::setprecision(2) << worst_deg << " | " << skipped
              << " |" << std::endl;
  }
  return 0;
}
