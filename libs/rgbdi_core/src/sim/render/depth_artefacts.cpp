#include "rgbdi/sim/depth_artefacts.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "sim/render/det_random.h"

namespace rgbdi::sim {

DepthArtefactOptions DepthArtefactOptions::load(IniReader& ini) {
  DepthArtefactOptions o;
  const std::string s = "sim";
  o.flying_pixel_prob = ini.getDouble(s, "depth_flying_pixel_prob", o.flying_pixel_prob, 0.0, 1.0);
  o.edge_jump_m = ini.getDouble(s, "depth_edge_jump_m", o.edge_jump_m, 0.001, 10.0);
  o.dark_hole_prob = ini.getDouble(s, "depth_dark_hole_prob", o.dark_hole_prob, 0.0, 1.0);
  o.dark_level = ini.getDouble(s, "depth_dark_level", o.dark_level, 1.0, 255.0);
  o.grazing_hole_prob = ini.getDouble(s, "depth_grazing_hole_prob", o.grazing_hole_prob, 0.0, 1.0);
  o.grazing_angle_deg = ini.getDouble(s, "depth_grazing_angle_deg", o.grazing_angle_deg, 0.0, 89.0);
  return o;
}

namespace {

void validate(const DepthArtefactOptions& o) {
  for (double p : {o.flying_pixel_prob, o.dark_hole_prob, o.grazing_hole_prob})
    if (!(p >= 0.0 && p <= 1.0))
      throw std::invalid_argument("DepthArtefactOptions: probabilities must be in [0, 1]");
  if (!(o.edge_jump_m > 0.0) || !(o.dark_level > 0.0) ||
      !(o.grazing_angle_deg >= 0.0 && o.grazing_angle_deg < 90.0))
    throw std::invalid_argument(
        "DepthArtefactOptions: need edge_jump_m > 0, dark_level > 0, grazing angle in [0, 90)");
}

Eigen::Vector3d backProject(const PinholeCamera& c, int x, int y, double z) {
  return {(x - c.cx) / c.fx * z, (y - c.cy) / c.fy * z, z};
}

}  // namespace

double incidenceAngle(const cv::Mat& depth_m, const PinholeCamera& camera, int x, int y,
                      double edge_jump_m) {
  if (x < 1 || y < 1 || x + 1 >= depth_m.cols || y + 1 >= depth_m.rows) return -1.0;
  const double z = depth_m.at<float>(y, x);
  const double zl = depth_m.at<float>(y, x - 1), zr = depth_m.at<float>(y, x + 1);
  const double zu = depth_m.at<float>(y - 1, x), zd = depth_m.at<float>(y + 1, x);
  for (double n : {zl, zr, zu, zd})
    if (!(z > 0.0) || !(n > 0.0) || std::abs(n - z) > edge_jump_m) return -1.0;
  const Eigen::Vector3d du = backProject(camera, x + 1, y, zr) - backProject(camera, x - 1, y, zl);
  const Eigen::Vector3d dv = backProject(camera, x, y + 1, zd) - backProject(camera, x, y - 1, zu);
  const Eigen::Vector3d normal = du.cross(dv);
  const Eigen::Vector3d ray = backProject(camera, x, y, 1.0);
  const double c = std::abs(normal.dot(ray)) / (normal.norm() * ray.norm());
  return std::acos(std::min(1.0, c));
}

void applyDepthArtefacts(cv::Mat& depth_m, const cv::Mat& rgb, const PinholeCamera& camera,
                         const DepthArtefactOptions& options, std::mt19937_64& rng) {
  if (depth_m.type() != CV_32FC1 || rgb.type() != CV_8UC3 || depth_m.size() != rgb.size() ||
      depth_m.empty())
    throw std::invalid_argument(
        "applyDepthArtefacts: need CV_32FC1 depth and CV_8UC3 colour of the same size");
  validate(options);
  if (!options.any()) return;
  detail::DetRandom r(rng());
  const cv::Mat ideal = depth_m.clone();  // decisions on the ideal depth, not on edited pixels
  const double grazing = options.grazing_angle_deg * M_PI / 180.0;
  const int dx[4] = {-1, 1, 0, 0}, dy[4] = {0, 0, -1, 1};
  for (int y = 0; y < ideal.rows; ++y)
    for (int x = 0; x < ideal.cols; ++x) {
      const double z = ideal.at<float>(y, x);
      if (!(z > 0.0)) continue;
      // Every pixel draws the same four numbers, so one effect never shifts another's draws.
      const double u_dark = r.uniform(0.0, 1.0), u_graze = r.uniform(0.0, 1.0);
      const double u_fly = r.uniform(0.0, 1.0), w = r.uniform(0.0, 1.0);
      const cv::Vec3b c = rgb.at<cv::Vec3b>(y, x);
      const double luminance = 0.299 * c[0] + 0.587 * c[1] + 0.114 * c[2];
      const double p_dark =
          options.dark_hole_prob * std::max(0.0, 1.0 - luminance / options.dark_level);
      if (u_dark < p_dark) {
        depth_m.at<float>(y, x) = 0.0f;
        continue;
      }
      if (options.grazing_hole_prob > 0.0) {
        const double angle = incidenceAngle(ideal, camera, x, y, options.edge_jump_m);
        const double p =
            angle > grazing ? options.grazing_hole_prob * (angle - grazing) / (0.5 * M_PI - grazing)
                            : 0.0;
        if (u_graze < p) {
          depth_m.at<float>(y, x) = 0.0f;
          continue;
        }
      }
      if (options.flying_pixel_prob > 0.0 && u_fly < options.flying_pixel_prob) {
        // The neighbour across the largest step (if it is an edge).
        double other = 0.0, step = options.edge_jump_m;
        for (int k = 0; k < 4; ++k) {
          const int xn = x + dx[k], yn = y + dy[k];
          if (xn < 0 || yn < 0 || xn >= ideal.cols || yn >= ideal.rows) continue;
          const double zn = ideal.at<float>(yn, xn);
          if (zn > 0.0 && std::abs(zn - z) > step) {
            step = std::abs(zn - z);
            other = zn;
          }
        }
        if (other > 0.0) depth_m.at<float>(y, x) = static_cast<float>(w * z + (1.0 - w) * other);
      }
    }
}

}  // namespace rgbdi::sim
