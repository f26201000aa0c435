// D435-like depth artefacts beyond the range noise (sensor_noise.h), applied to the ideal depth
// before the noise, all off by default:
// - flying pixels: a pixel on a depth edge (a 4-neighbour differs by more than edge_jump_m) takes,
//   with probability flying_pixel_prob, a mixture w z + (1 - w) z_n of its depth and that
//   neighbour's (w uniform in (0, 1)), as stereo matching blends fore- and background;
// - holes on dark surfaces: probability dark_hole_prob on a black pixel (luminance 0 of the
//   rendered colour), falling linearly to 0 at luminance dark_level (the IR reflectance,
//   which the luminance of the rendered colour stands in for: dark surfaces return little of
//   the IR projector's pattern);
// - holes at grazing incidence: probability 0 up to grazing_angle_deg between the viewing ray and
//   the surface normal (estimated from the depth image), rising linearly to grazing_hole_prob at
//   90 deg (shiny and oblique surfaces return no pattern).
#pragma once

#include <opencv2/core.hpp>
#include <random>

#include "rgbdi/common/camera.h"
#include "rgbdi/common/ini_reader.h"

namespace rgbdi::sim {

struct DepthArtefactOptions {
  double flying_pixel_prob = 0.0;   ///< [probability] per depth-edge pixel; 0 = off
  double edge_jump_m = 0.1;         ///< [m] depth step that makes a pixel an edge pixel
  double dark_hole_prob = 0.0;      ///< [probability] of a hole on a black pixel; 0 = off
  double dark_level = 40.0;         ///< [grey levels] luminance where dark holes stop
  double grazing_hole_prob = 0.0;   ///< [probability] of a hole at 90 deg incidence; 0 = off
  double grazing_angle_deg = 70.0;  ///< [deg] incidence where grazing holes start

  bool any() const {
    return flying_pixel_prob > 0.0 || dark_hole_prob > 0.0 || grazing_hole_prob > 0.0;
  }
  /// Reads [sim] depth_flying_pixel_prob, depth_edge_jump_m, depth_dark_hole_prob,
  /// depth_dark_level, depth_grazing_hole_prob, depth_grazing_angle_deg.
  static DepthArtefactOptions load(IniReader& ini);
};

/// Applies the artefacts to ideal depth (CV_32FC1, metres, 0 = none) in place, given the ideal
/// colour (CV_8UC3 RGB, same size) and the camera (for the incidence angle). Holes read 0.
/// Throws std::invalid_argument on wrong image types, sizes or options.
void applyDepthArtefacts(cv::Mat& depth_m, const cv::Mat& rgb, const PinholeCamera& camera,
                         const DepthArtefactOptions& options, std::mt19937_64& rng);

/// Incidence angle [rad] between the viewing ray of pixel (x, y) and the surface normal
/// estimated from the depth of its 4 neighbours (central differences of back-projected points,
/// no distortion); negative when a neighbour has no depth or lies across a depth edge.
double incidenceAngle(const cv::Mat& depth_m, const PinholeCamera& camera, int x, int y,
                      double edge_jump_m);

}  // namespace rgbdi::sim
