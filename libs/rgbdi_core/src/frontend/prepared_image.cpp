#include "rgbdi/frontend/prepared_image.h"

#include <stdexcept>
#include <string>

#include "frontend/stopwatch.h"

namespace rgbdi::frontend {
namespace {
// CLAHE tiles: the usual 8x8 grid, only used when clahe_clip_limit enables equalisation.
const cv::Size kClaheTiles(8, 8);
}  // namespace

PreparationRecipe PreparationRecipe::of(const FrontendOptions& options) {
  PreparationRecipe r;
  r.clahe_clip_limit = options.clahe_clip_limit;
  return r;
}

bool PreparedImage::matches(const RgbdFrame& frame, const PreparationRecipe& r) const {
  return recipe == r && frame_index == frame.index && t == frame.t &&
         grey.size() == frame.rgb.size();
}

ImagePreparer::ImagePreparer(const FrontendOptions& options)
    : recipe_(PreparationRecipe::of(options)) {
  options.validate();
  if (options.clahe_clip_limit > 0.0)
    clahe_ = cv::createCLAHE(options.clahe_clip_limit, kClaheTiles);
}

ImagePreparer::~ImagePreparer() = default;
ImagePreparer::ImagePreparer(ImagePreparer&&) noexcept = default;
ImagePreparer& ImagePreparer::operator=(ImagePreparer&&) noexcept = default;

bool ImagePreparer::accepts(const RgbdFrame& frame) {
  return frame.hasColor() && (frame.rgb.type() == CV_8UC3 || frame.rgb.type() == CV_8UC1);
}

void ImagePreparer::toGrey(const RgbdFrame& frame, cv::Mat& converted, cv::Mat& equalised,
                           cv::Mat& grey) const {
  if (!accepts(frame))
    throw std::invalid_argument("ImagePreparer: frame " + std::to_string(frame.index) +
                                " has no CV_8UC3 or CV_8UC1 colour image");
  grey = frame.rgb;  // already grey when CV_8UC1
  if (frame.rgb.type() == CV_8UC3) {
    cv::cvtColor(frame.rgb, converted, cv::COLOR_RGB2GRAY);
    grey = converted;
  }
  if (clahe_) {
    clahe_->apply(grey, equalised);
    grey = equalised;
  }
}

cv::Mat ImagePreparer::grey(const RgbdFrame& frame) {
  // Written into member buffers: fresh 300 kB images every frame cost page faults.
  cv::Mat grey;
  toGrey(frame, grey_, equalised_, grey);
  return grey;
}

PreparedImage ImagePreparer::prepare(const RgbdFrame& frame) {
  PreparedImage out;
  prepare(frame, out);
  return out;
}

void ImagePreparer::prepare(const RgbdFrame& frame, PreparedImage& out) {
  Stopwatch step;
  out.t = frame.t;
  out.frame_index = frame.index;
  out.recipe = recipe_;
  toGrey(frame, out.converted_storage, out.equalised_storage, out.grey);
  out.grey_ms = step.lapMs();
}

}  // namespace rgbdi::frontend
