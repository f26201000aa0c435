#include "rgbdi/reloc/keyframe_samples.h"

namespace rgbdi::reloc {

void appendDepthSamples(const loop::LoopKeyframe& kf, const Eigen::Isometry3d& T_world_body,
                        const PinholeCamera& cam, const Eigen::Isometry3d& T_body_cam,
                        std::vector<DepthSample>* out) {
  const loop::DepthGrid& g = kf.depth_grid;
  if (g.empty() || !g.consistent()) return;
  const Eigen::Isometry3d T_world_cam = T_world_body * T_body_cam;
  DepthSample s;
  s.origin = T_world_cam.translation();
  for (int r = 0; r < g.rows; ++r)
    for (int c = 0; c < g.cols; ++c) {
      const float d = g.at(c, r);
      if (!(d > 0.0f)) continue;
      const Eigen::Vector2d xn = cam.pixelToNormalized(g.pixel(c, r, cam.width, cam.height));
      s.point = T_world_cam * (Eigen::Vector3d(xn.x(), xn.y(), 1.0) * static_cast<double>(d));
      out->push_back(s);
    }
}

}  // namespace rgbdi::reloc
