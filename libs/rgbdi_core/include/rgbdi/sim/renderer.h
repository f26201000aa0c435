// Ray-cast renderer of a Scene: colour image and ideal depth, pixel-aligned.
//
// The unit ray of every pixel (through the pixel centre, integer coordinates, distortion
// included via PinholeCamera::pixelToNormalized) is computed once in the constructor. Each frame
// culls the primitives against the frustum of every 16x16-pixel tile (bounds of the tile's
// undistorted rays, so culling is exact-conservative with distortion too) and sorts them by
// distance; each pixel then tests the primitive its neighbour hit first and those of the tile's
// candidates that are nearer than the best hit and whose projected bounds contain the pixel.
// The result is identical to Scene::raycast per pixel.
// Rendering is single-threaded and deterministic; render() is const and may run concurrently.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>
#include <vector>

#include "rgbdi/common/camera.h"
#include "rgbdi/sim/scene.h"

namespace rgbdi::sim {

struct RenderOptions {
  double max_range_m = 40.0;  ///< [m] rays end here (no hit -> background, depth 0)
  /// Direction towards the (infinitely distant) light in the world frame; normalised on use.
  Eigen::Vector3d light_dir_world{0.35, 0.25, 0.90};
  double ambient = 0.45;  ///< [unitless] shading of surfaces facing away from the light
  double diffuse = 0.55;  ///< [unitless] added Lambert term (ambient + diffuse = full brightness)
  /// [px] Gaussian blur of the colour image standing for the lens point-spread function; it also
  /// smooths the staircase of geometric edges (0 = off).
  double optics_blur_sigma_px = 0.5;
  /// [mip levels] added to the level of detail (> 0 blurrier, < 0 sharper but risks aliasing).
  double lod_bias = 0.0;
  cv::Vec3b background{0, 0, 0};  ///< colour where no surface is hit (R,G,B)
};

class Renderer {
 public:
  /// The scene must be built and must outlive the renderer. Throws std::invalid_argument for an
  /// invalid camera or an unbuilt scene.
  Renderer(const Scene& scene, const PinholeCamera& cam, const RenderOptions& options = {});

  /// Renders from the colour camera pose T_world_cam (optical frame: x right, y down, z forward):
  /// rgb CV_8UC3 (R,G,B), depth CV_32FC1 = camera-frame z [m] of the surface (0 = no hit).
  /// Outputs are (re)allocated only when their size or type differs. Throws
  /// std::invalid_argument for a non-finite pose or a rotation that is not orthonormal.
  void render(const Eigen::Isometry3d& T_world_cam, cv::Mat& rgb, cv::Mat& depth) const;
  /// Rolling shutter: colour row v seen from T_world_cam_rows[v] (one pose per row, exact per
  /// row), depth a global-shutter image from T_world_cam_depth. With every pose equal the output
  /// is render()'s. Throws std::invalid_argument for a pose count other than the image height or
  /// an invalid pose.
  void renderRollingShutter(const std::vector<Eigen::Isometry3d>& T_world_cam_rows,
                            const Eigen::Isometry3d& T_world_cam_depth, cv::Mat& rgb,
                            cv::Mat& depth) const;

  const PinholeCamera& camera() const { return cam_; }
  const RenderOptions& options() const { return opt_; }

 private:
  /// Rows [v_begin, v_end) seen from one pose, into rgb and / or depth (null: not rendered);
  /// both already allocated. No blur.
  void renderRows(const Eigen::Isometry3d& T_world_cam, int v_begin, int v_end, cv::Mat* rgb,
                  cv::Mat* depth) const;
  void blur(cv::Mat& rgb) const;  ///< the optics blur of RenderOptions

  const Scene& scene_;
  PinholeCamera cam_;
  RenderOptions opt_;
  /// Per pixel (row-major): unit ray in the camera frame, and its z component (t -> depth).
  std::vector<Eigen::Vector3d> rays_cam_;
  /// Per pixel: undistorted normalised coordinates (x/z, y/z) of the ray, for bounds tests.
  std::vector<Eigen::Vector2f> normalized_;
  /// Per pixel: angular size of the pixel [rad] (footprint on a surface = t * spread / cos).
  std::vector<float> spread_;
  /// An image tile and the bounds of its pixels' undistorted normalised coordinates (x/z, y/z).
  struct Tile {
    int u0, v0, u1, v1;  ///< pixel range [u0, u1) x [v0, v1)
    double x_min, x_max, y_min, y_max;
  };
  std::vector<Tile> tiles_;
};

}  // namespace rgbdi::sim
