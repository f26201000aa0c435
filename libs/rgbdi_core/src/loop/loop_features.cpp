#include "rgbdi/loop/loop_features.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <opencv2/features2d.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "rgbdi/frontend/depth_registration.h"
#include "rgbdi/frontend/depth_sampling.h"

namespace rgbdi::loop {
namespace {

[[noreturn]] void fail(const RgbdFrame& frame, const std::string& what) {
  const std::string where =
      frame.source_label.empty() ? "frame " + std::to_string(frame.index) : frame.source_label;
  throw std::invalid_argument("loop features: " + where + ": " + what);
}

/// Strongest first; equal responses ordered by position and level so the order never depends
/// on how the detector happened to list them.
bool stronger(const cv::KeyPoint& a, const cv::KeyPoint& b) {
  if (a.response != b.response) return a.response > b.response;
  if (a.pt.y != b.pt.y) return a.pt.y < b.pt.y;
  if (a.pt.x != b.pt.x) return a.pt.x < b.pt.x;
  return a.octave < b.octave;
}

/// Grid bucketing by rounds: round r takes the r-th strongest corner of every cell that still
/// has one, so a richly textured cell cannot take the share of the others. When a round does not
/// fit entirely, its strongest corners are taken.
std::vector<cv::KeyPoint> spreadOverGrid(std::vector<cv::KeyPoint> corners, int width, int height,
                                         const LoopFeatureOptions& o) {
  std::sort(corners.begin(), corners.end(), stronger);
  const std::size_t max_keep = static_cast<std::size_t>(o.max_keypoints);
  if (corners.size() <= max_keep) return corners;
  const int cells = o.grid_cols * o.grid_rows;
  std::vector<std::vector<std::size_t>> in_cell(static_cast<std::size_t>(cells));
  for (std::size_t i = 0; i < corners.size(); ++i) {
    const int cx =
        std::clamp(static_cast<int>(corners[i].pt.x * o.grid_cols / width), 0, o.grid_cols - 1);
    const int cy =
        std::clamp(static_cast<int>(corners[i].pt.y * o.grid_rows / height), 0, o.grid_rows - 1);
    in_cell[static_cast<std::size_t>(cy * o.grid_cols + cx)].push_back(i);  // stays sorted
  }
  std::vector<std::size_t> chosen;
  chosen.reserve(max_keep);
  for (std::size_t round = 0; chosen.size() < max_keep; ++round) {
    std::vector<std::size_t> this_round;
    for (const std::vector<std::size_t>& cell : in_cell)
      if (round < cell.size()) this_round.push_back(cell[round]);
    if (this_round.empty()) break;
    std::sort(this_round.begin(), this_round.end());  // index order = strength order
    const std::size_t take = std::min(this_round.size(), max_keep - chosen.size());
    chosen.insert(chosen.end(), this_round.begin(),
                  this_round.begin() + static_cast<std::ptrdiff_t>(take));
  }
  std::sort(chosen.begin(), chosen.end());
  std::vector<cv::KeyPoint> out;
  out.reserve(chosen.size());
  for (std::size_t i : chosen) out.push_back(corners[i]);
  return out;
}

}  // namespace

struct LoopFeatureExtractor::Impl {
  LoopFeatureOptions options;
  frontend::FrontendOptions sampling;
  frontend::DepthRegistrar registrar;
  cv::Ptr<cv::ORB> orb;
  cv::Mat grey, depth_m;

  Impl(const LoopFeatureOptions& o, const frontend::FrontendOptions& registration)
      : options(o), sampling(o.depthSampling(registration)), registrar(sampling) {
    // Harris score ranks FAST corners (more stable than the FAST score); patch size 31 is the
    // size ORB's sampling pattern was learned for.
    orb =
        cv::ORB::create(o.detect_candidates, static_cast<float>(o.pyramid_scale), o.pyramid_levels,
                        o.border_px, 0, 2, cv::ORB::HARRIS_SCORE, 31, o.fast_threshold);
  }
};

LoopFeatureExtractor::LoopFeatureExtractor(const LoopFeatureOptions& options,
                                           const frontend::FrontendOptions& registration) {
  options.validate();
  impl_ = std::make_unique<Impl>(options, registration);
}

LoopFeatureExtractor::~LoopFeatureExtractor() = default;

mapping::DescriptorSet LoopFeatureExtractor::extract(
    const RgbdFrame& frame, const PinholeCamera& cam,
    const std::function<Eigen::Vector2d(const Eigen::Vector2d&)>& to_stamp) {
  mapping::DescriptorSet set;
  set.type = kLoopDescriptorType;
  set.bytes_per_descriptor = kLoopDescriptorBytes;
  if (!frame.hasColor()) return set;
  if (frame.rgb.type() != CV_8UC3) fail(frame, "colour image is not CV_8UC3");
  if (frame.rgb.cols != cam.width || frame.rgb.rows != cam.height)
    fail(frame, "colour image is " + std::to_string(frame.rgb.cols) + "x" +
                    std::to_string(frame.rgb.rows) + " but the camera is " +
                    std::to_string(cam.width) + "x" + std::to_string(cam.height));

  Impl& im = *impl_;
  cv::cvtColor(frame.rgb, im.grey, cv::COLOR_RGB2GRAY);
  std::vector<cv::KeyPoint> corners;
  im.orb->detect(im.grey, corners);
  std::vector<cv::KeyPoint> keypoints =
      spreadOverGrid(std::move(corners), cam.width, cam.height, im.options);
  cv::Mat descriptors;
  im.orb->compute(im.grey, keypoints, descriptors);
  if (keypoints.empty()) return set;
  if (descriptors.type() != CV_8UC1 || descriptors.cols != static_cast<int>(kLoopDescriptorBytes) ||
      descriptors.rows != static_cast<int>(keypoints.size()))
    fail(frame, "ORB returned descriptors of an unexpected shape");

  const std::size_t n = keypoints.size();
  set.keypoints_uv.resize(n);
  set.data.resize(n * kLoopDescriptorBytes);
  for (std::size_t k = 0; k < n; ++k) {
    set.keypoints_uv[k] = Eigen::Vector2f(keypoints[k].pt.x, keypoints[k].pt.y);
    if (to_stamp) set.keypoints_uv[k] = to_stamp(set.keypoints_uv[k].cast<double>()).cast<float>();
    std::copy_n(descriptors.ptr<std::uint8_t>(static_cast<int>(k)), kLoopDescriptorBytes,
                set.data.begin() + static_cast<std::ptrdiff_t>(k * kLoopDescriptorBytes));
  }

  if (frame.hasDepth()) {
    std::vector<Eigen::Vector2d> centres(n);
    for (std::size_t k = 0; k < n; ++k) centres[k] = set.keypoints_uv[k].cast<double>();
    // Only the sampling windows are registered (one pixel more for the bilinear support).
    im.registrar.registerDepthAround(frame, cam, centres, im.options.depth_window_px + 1,
                                     im.depth_m);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    set.keypoints_p_cam.assign(n, Eigen::Vector3f(nan, nan, nan));
    for (std::size_t k = 0; k < n; ++k) {
      const double z = frontend::sampleDepth(im.depth_m, centres[k], im.sampling);
      if (z > 0.0) set.keypoints_p_cam[k] = cam.backProject(centres[k], z).cast<float>();
    }
  }
  return set;
}

DepthGrid LoopFeatureExtractor::depthGrid(const RgbdFrame& frame, const PinholeCamera& cam) {
  DepthGrid grid;
  Impl& im = *impl_;
  if (!frame.hasDepth() || im.options.depth_grid_cols == 0) return grid;
  grid.cols = im.options.depth_grid_cols;
  grid.rows = im.options.depth_grid_rows;
  std::vector<Eigen::Vector2d> centres;
  centres.reserve(static_cast<std::size_t>(grid.cols) * grid.rows);
  for (int r = 0; r < grid.rows; ++r)
    for (int c = 0; c < grid.cols; ++c) centres.push_back(grid.pixel(c, r, cam.width, cam.height));
  im.registrar.registerDepthAround(frame, cam, centres, im.options.depth_window_px + 1, im.depth_m);
  grid.depth_m.resize(centres.size());
  for (std::size_t k = 0; k < centres.size(); ++k)
    grid.depth_m[k] = static_cast<float>(
        std::max(0.0, frontend::sampleDepth(im.depth_m, centres[k], im.sampling)));
  return grid;
}

mapping::DescriptorSet extractLoopFeatures(const RgbdFrame& frame, const PinholeCamera& cam,
                                           const LoopFeatureOptions& options) {
  LoopFeatureExtractor extractor(options);
  return extractor.extract(frame, cam);
}

}  // namespace rgbdi::loop
