#include "mapping/depth_grid_sampler.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace rgbdi::mapping::detail {
namespace {

bool sameCamera(const PinholeCamera& a, const PinholeCamera& b) {
  return a.width == b.width && a.height == b.height && a.fx == b.fx && a.fy == b.fy &&
         a.cx == b.cx && a.cy == b.cy && a.dist == b.dist;
}

[[noreturn]] void reject(const RgbdFrame& frame, const std::string& what) {
  throw std::invalid_argument("mapping: " + frameLabel(frame) + ": " + what);
}

std::string sizeText(int w, int h) { return std::to_string(w) + "x" + std::to_string(h); }

void validate(const RgbdFrame& frame, const PinholeCamera& depth_camera) {
  if (frame.depth.empty()) reject(frame, "the frame has no depth image");
  if (frame.depth.type() != CV_16UC1)
    reject(frame, "the depth image must be CV_16UC1 (16-bit depth units), got OpenCV type " +
                      std::to_string(frame.depth.type()));
  if (!(std::isfinite(frame.depth_unit_m) && frame.depth_unit_m > 0.0))
    reject(frame, "depth_unit_m must be a positive number of metres per unit");
  if (!depth_camera.valid())
    reject(frame, std::string("the ") + (frame.depth_aligned_to_color ? "colour" : "depth") +
                      " camera intrinsics are not set");
  if (depth_camera.width != frame.depth.cols || depth_camera.height != frame.depth.rows)
    reject(frame, "the depth image is " + sizeText(frame.depth.cols, frame.depth.rows) +
                      " but its camera is " + sizeText(depth_camera.width, depth_camera.height));
  if (frame.hasColor()) {
    if (frame.rgb.type() != CV_8UC3) reject(frame, "the colour image must be CV_8UC3 (R,G,B)");
    if (!frame.cam_color.valid() || frame.cam_color.width != frame.rgb.cols ||
        frame.cam_color.height != frame.rgb.rows)
      reject(frame, "the colour image is " + sizeText(frame.rgb.cols, frame.rgb.rows) +
                        " but the colour camera is " +
                        sizeText(frame.cam_color.width, frame.cam_color.height));
    if (frame.depth_aligned_to_color && frame.rgb.size() != frame.depth.size())
      reject(frame, "depth is marked aligned to colour but the images differ in size (depth " +
                        sizeText(frame.depth.cols, frame.depth.rows) + ", colour " +
                        sizeText(frame.rgb.cols, frame.rgb.rows) + ")");
  }
  if (!frame.depth_aligned_to_color && !frame.T_color_depth.matrix().allFinite())
    reject(frame, "T_color_depth is not finite");
}

Rgb pixelRgb(const cv::Mat& rgb, int u, int v) {
  const cv::Vec3b& c = rgb.at<cv::Vec3b>(v, u);
  return {c[0], c[1], c[2]};
}

}  // namespace

std::string frameLabel(const RgbdFrame& frame) {
  if (!frame.source_label.empty()) return frame.source_label;
  std::ostringstream os;
  os.precision(17);
  os << "frame " << frame.index << " (t = " << frame.t << ")";
  return os.str();
}

const DepthGridSampler::RayCache& DepthGridSampler::raysFor(const PinholeCamera& camera,
                                                            const std::string& label) {
  if (cache_valid_ && sameCamera(cache_.camera, camera)) return cache_;
  RayCache c;
  c.camera = camera;
  for (int u = grid_.u_min_px; u <= grid_.u_max_px && u < camera.width; u += grid_.step_px)
    c.us.push_back(u);
  for (int v = grid_.v_min_px; v <= grid_.v_max_px && v < camera.height; v += grid_.step_px)
    c.vs.push_back(v);
  if (c.us.empty() || c.vs.empty())
    throw std::invalid_argument(
        "mapping: " + label + ": the sampling grid (u " + std::to_string(grid_.u_min_px) + ".." +
        std::to_string(grid_.u_max_px) + ", v " + std::to_string(grid_.v_min_px) + ".." +
        std::to_string(grid_.v_max_px) + ") lies outside the " +
        sizeText(camera.width, camera.height) + " depth image");
  c.xn.reserve(c.us.size() * c.vs.size());
  for (int v : c.vs)
    for (int u : c.us)
      c.xn.push_back(camera.pixelToNormalized(Eigen::Vector2d(u, v)).cast<float>());
  cache_ = std::move(c);
  cache_valid_ = true;
  return cache_;
}

void DepthGridSampler::sample(const RgbdFrame& frame, int stride, double z_min, double z_max,
                              std::vector<MapPoint>& out, GridSampleCounts& counts) {
  if (stride < 1) throw std::invalid_argument("DepthGridSampler: stride must be >= 1");
  const bool aligned = frame.depth_aligned_to_color;
  const PinholeCamera& depth_camera = aligned ? frame.cam_color : frame.cam_depth;
  validate(frame, depth_camera);
  const RayCache& rays = raysFor(depth_camera, frameLabel(frame));

  const bool colour = frame.hasColor();
  const Eigen::Matrix3f R_color_depth = frame.T_color_depth.linear().cast<float>();
  const Eigen::Vector3f t_color_depth = frame.T_color_depth.translation().cast<float>();
  const std::size_t cols = rays.us.size();
  for (std::size_t r = 0; r < rays.vs.size(); r += static_cast<std::size_t>(stride)) {
    const int v = rays.vs[r];
    const std::uint16_t* depth_row = frame.depth.ptr<std::uint16_t>(v);
    for (std::size_t c = 0; c < cols; c += static_cast<std::size_t>(stride)) {
      ++counts.grid_points;
      const int u = rays.us[c];
      const std::uint16_t d = depth_row[u];
      if (d == 0) {
        ++counts.no_depth;
        continue;
      }
      const double z = d * frame.depth_unit_m;
      if (!(z > z_min && z < z_max)) {
        ++counts.out_of_range;
        continue;
      }
      const Eigen::Vector2f& xn = rays.xn[r * cols + c];
      const float zf = static_cast<float>(z);
      MapPoint p;
      p.p_cam = Eigen::Vector3f(xn.x() * zf, xn.y() * zf, zf);
      p.rgb = kUncolouredRgb;
      if (aligned) {
        if (colour) p.rgb = pixelRgb(frame.rgb, u, v);
      } else {
        p.p_cam = R_color_depth * p.p_cam + t_color_depth;
        Eigen::Vector2d uv;
        if (colour && frame.cam_color.project(p.p_cam.cast<double>(), uv)) {
          const int cu = static_cast<int>(std::lround(uv.x()));
          const int cv_ = static_cast<int>(std::lround(uv.y()));
          if (cu >= 0 && cv_ >= 0 && cu < frame.rgb.cols && cv_ < frame.rgb.rows)
            p.rgb = pixelRgb(frame.rgb, cu, cv_);
        }
      }
      out.push_back(p);
      ++counts.kept;
    }
  }
}

}  // namespace rgbdi::mapping::detail
