#include "rgbdi/io/stream_checker.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

namespace rgbdi::io {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string num(double v, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

std::string gnum(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

std::string stamp(double t) { return num(t, 6); }

std::string sizeText(const cv::Mat& m) {
  return std::to_string(m.cols) + "x" + std::to_string(m.rows);
}
std::string sizeText(const PinholeCamera& c) {
  return std::to_string(c.width) + "x" + std::to_string(c.height);
}

std::string poseText(const Eigen::Isometry3d& T) {
  std::string s = "t = [" + gnum(T.translation().x()) + " " + gnum(T.translation().y()) + " " +
                  gnum(T.translation().z()) + "] m, R = [";
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) s += gnum(T.linear()(r, c)) + (c < 2 ? " " : "");
    s += r < 2 ? "; " : "]";
  }
  return s;
}

}  // namespace

StreamChecker::StreamChecker(std::string source, const StreamConfig& cfg,
                             std::function<void(const std::string&)> on_warning)
    : source_(std::move(source)),
      cfg_(cfg),
      on_warning_(std::move(on_warning)),
      prev_arrival_{kNaN, kNaN, kNaN},
      prev_delivered_imu_t_(kNaN) {
  diag_.source = source_;
  diag_.imu.gap_limit_s = cfg_.stream.imu_gap_factor / cfg_.imu.rate_hz;
}

std::string StreamChecker::at(std::size_t record) const {
  return source_ + " record " + std::to_string(record);
}

std::string StreamChecker::records(std::size_t a, std::size_t b) const {
  if (a == b) return at(a);
  return source_ + " records " + std::to_string(a) + "-" + std::to_string(b);
}

void StreamChecker::warn(const std::string& message) {
  diag_.warnings.push_back(message);
  if (on_warning_) on_warning_(message);
}

void StreamChecker::issue(const std::string& kind, std::size_t record, const std::string& message) {
  auto [it, inserted] = issues_.try_emplace(kind);
  if (inserted) issue_order_.push_back(kind);
  IssueKind& k = it->second;
  ++k.count;
  if (k.count <= static_cast<std::size_t>(cfg_.stream.max_listed_issues)) {
    warn(message);
    return;
  }
  if (k.unlisted == 0) k.first_unlisted = record;
  k.last_unlisted = record;
  ++k.unlisted;
}

void StreamChecker::onArrival(MeasurementKind kind, double t, std::size_t record,
                              TimeOrderingBuffer::Verdict verdict, double newest_same_kind) {
  const int k = static_cast<int>(kind);
  const bool rgbd = kind == MeasurementKind::Rgbd;
  const std::string name = kindName(kind);
  const std::string window_key = rgbd ? "image_reorder_window_s" : "imu_reorder_window_s";
  const double window =
      rgbd ? cfg_.stream.image_reorder_window_s : cfg_.stream.imu_reorder_window_s;
  SensorStreamStats& st = kind == MeasurementKind::Imu     ? diag_.imu
                          : kind == MeasurementKind::Wheel ? diag_.wheel
                                                           : diag_.images;
  if (t < prev_arrival_[k]) ++st.non_monotonic;
  if (std::isfinite(t)) prev_arrival_[k] = t;

  const std::string head = at(record) + ": " + name + " stamp t = " + stamp(t) + " s";
  using V = TimeOrderingBuffer::Verdict;
  switch (verdict) {
    case V::Accepted:
      break;
    case V::Reordered:
      ++st.reordered;
      issue(name + " order", record,
            head + " is older than the newest " + name + " stamp " + stamp(newest_same_kind) +
                " s read before it (non-monotonic); reordered (within " + window_key + " = " +
                gnum(window) + " s)");
      break;
    case V::Duplicate:
      ++st.duplicates;
      issue(name + " duplicate", record,
            head + " duplicates an earlier " + name + " stamp; dropped");
      break;
    case V::TooLate:
      ++st.dropped_late;
      issue(name + " order", record,
            head + " is " + num(newest_same_kind - t, 6) + " s older than the newest " + name +
                " stamp " + stamp(newest_same_kind) + " s, beyond " + window_key + " = " +
                gnum(window) + " s; dropped");
      break;
    case V::BehindOutput:
      ++st.dropped_late;
      issue(
          name + " order", record,
          head + " is older than measurements already delivered (it arrived more than " +
              gnum(std::max(cfg_.stream.imu_reorder_window_s, cfg_.stream.image_reorder_window_s)) +
              " s after newer data of another sensor); dropped");
      break;
    case V::InvalidStamp:
      ++st.invalid_stamps;
      issue(name + " stamp", record,
            at(record) + ": " + name + " stamp " + gnum(t) +
                " is not a valid time (zero, negative or not finite); dropped");
      break;
  }
}

void StreamChecker::onDelivered(const Measurement& m, std::size_t record) {
  if (const auto* w = std::get_if<WheelOdometrySample>(&m)) {
    onWheelDelivered(*w, record);
    return;
  }
  if (const auto* imu = std::get_if<ImuSample>(&m)) {
    onImuForWheelCheck(*imu);
    SensorStreamStats& st = diag_.imu;
    if (st.delivered == 0) {
      st.first_t = imu->t;
      first_imu_record_ = record;
    } else {
      const double dt = imu->t - prev_delivered_imu_t_;
      st.max_gap_s = std::max(st.max_gap_s, dt);
      if (dt > st.gap_limit_s) {
        ++st.gaps;
        issue("IMU gap", record,
              at(record) + ": IMU gap of " + num(dt, 4) +
                  " s between t = " + stamp(prev_delivered_imu_t_) + " s and t = " + stamp(imu->t) +
                  " s (limit " + num(st.gap_limit_s, 4) + " s = imu_gap_factor " +
                  gnum(cfg_.stream.imu_gap_factor) + " / [imu] rate_hz " + gnum(cfg_.imu.rate_hz) +
                  " Hz)");
      }
    }
    ++st.delivered;
    st.last_t = imu->t;
    last_imu_record_ = record;
    prev_delivered_imu_t_ = imu->t;
    acc_norm_sum_ += imu->acc.norm();
    return;
  }
  const auto& f = std::get<RgbdFrame>(m);
  SensorStreamStats& st = diag_.images;
  if (st.delivered == 0) {
    st.first_t = f.t;
    first_frame_record_ = record;
  }
  ++st.delivered;
  st.last_t = f.t;
  last_frame_record_ = record;
  frame_stamps_.emplace_back(f.t, record);
  checkFrame(f, record);
}

void StreamChecker::checkFrame(const RgbdFrame& f, std::size_t record) {
  if (f.hasColor()) ++diag_.frames_with_color;
  if (f.hasDepth()) ++diag_.frames_with_depth;
  if (f.hasDepth() && f.depth_aligned_to_color) ++diag_.frames_aligned;

  bool missing = false;
  if (f.hasColor() && f.cam_color.fx <= 0.0) {
    issue("missing intrinsics", record, at(record) + ": colour camera intrinsics missing (fx = 0)");
    missing = true;
  }
  if (f.hasDepth() && f.cam_depth.fx <= 0.0) {
    issue("missing intrinsics", record, at(record) + ": depth camera intrinsics missing (fx = 0)");
    missing = true;
  }
  if (missing) ++diag_.missing_intrinsics;

  std::string mismatch;
  if (f.hasColor() && f.hasDepth() && f.depth_aligned_to_color && f.rgb.size() != f.depth.size()) {
    mismatch = "colour image " + sizeText(f.rgb) + " and depth image " + sizeText(f.depth) +
               " differ in size although depth is declared aligned to colour";
  } else if (f.hasColor() && f.cam_color.valid() &&
             (f.rgb.cols != f.cam_color.width || f.rgb.rows != f.cam_color.height)) {
    mismatch = "colour image " + sizeText(f.rgb) + " does not match its intrinsics " +
               sizeText(f.cam_color);
  } else if (f.hasDepth() && f.cam_depth.valid() &&
             (f.depth.cols != f.cam_depth.width || f.depth.rows != f.cam_depth.height)) {
    mismatch = "depth image " + sizeText(f.depth) + " does not match its intrinsics " +
               sizeText(f.cam_depth);
  }
  if (!mismatch.empty()) {
    ++diag_.size_mismatches;
    issue("size mismatch", record, at(record) + ": " + mismatch);
  }

  if (f.hasDepth()) checkDepthUnits(f, record);
  if (f.hasColor()) checkConstantColor(f, record);
  checkExtrinsic(f, record);
}

void StreamChecker::checkConstantColor(const RgbdFrame& f, std::size_t record) {
  const int step = cfg_.stream.image_check_step_px;
  // Per channel: a flat colour is as useless for tracking as black.
  int lo = 255, hi = 0, spread = 0;
  if (f.rgb.depth() == CV_8U && f.rgb.channels() <= 4) {
    const int channels = f.rgb.channels();
    int clo[4] = {255, 255, 255, 255}, chi[4] = {0, 0, 0, 0};
    for (int v = 0; v < f.rgb.rows; v += step) {
      const auto* row = f.rgb.ptr<std::uint8_t>(v);
      for (int u = 0; u < f.rgb.cols; u += step)
        for (int c = 0; c < channels; ++c) {
          clo[c] = std::min<int>(clo[c], row[u * channels + c]);
          chi[c] = std::max<int>(chi[c], row[u * channels + c]);
        }
    }
    for (int c = 0; c < channels; ++c) {
      spread = std::max(spread, chi[c] - clo[c]);
      lo = std::min(lo, clo[c]);
      hi = std::max(hi, chi[c]);
    }
  } else {
    spread = 256;  // not an 8-bit image: not judged here
  }
  if (spread > cfg_.stream.constant_image_max_range) {
    closeConstantRun();
    return;
  }
  ConstantRun& r = constant_run_;
  if (r.frames == 0) {
    r.first_record = record;
    r.first_t = f.t;
  }
  ++r.frames;
  r.last_record = record;
  r.last_t = f.t;
  r.lo = std::min(r.lo, lo);
  r.hi = std::max(r.hi, hi);
}

void StreamChecker::closeConstantRun() {
  ConstantRun& r = constant_run_;
  if (r.frames == 0) return;
  const double span = r.last_t - r.first_t;
  diag_.constant_color_frames += r.frames;
  diag_.constant_color_s += span;
  const bool black = r.hi <= cfg_.stream.constant_image_max_range;
  issue("constant images", r.first_record,
        records(r.first_record, r.last_record) + ": " + std::to_string(r.frames) + " colour image" +
            (r.frames == 1 ? " is " : "s are ") + (black ? "black" : "one flat colour") +
            " (sampled values " + std::to_string(r.lo) + "-" + std::to_string(r.hi) +
            ", constant_image_max_range " + std::to_string(cfg_.stream.constant_image_max_range) +
            ") for " + num(span, 3) + " s from t = " + stamp(r.first_t) +
            " s to t = " + stamp(r.last_t) + " s: no visual tracking there");
  r = ConstantRun();
}

void StreamChecker::checkDepthUnits(const RgbdFrame& f, std::size_t record) {
  diag_.depth_unit_m = f.depth_unit_m;
  const int step = cfg_.stream.depth_check_step_px;
  // The median of the sampled raw values, exactly (the (n/2)-th smallest), by counting: first
  // their high bytes, then the low bytes of those in the median's high-byte bin (two passes
  // over ~20,000 values instead of a selection on them every frame).
  auto forEachSample = [&](auto&& visit) {
    for (int v = 0; v < f.depth.rows; v += step) {
      const auto* row = f.depth.ptr<std::uint16_t>(v);
      for (int u = 0; u < f.depth.cols; u += step)
        if (row[u] != 0) visit(row[u]);
    }
  };
  std::array<std::uint32_t, 256> high{}, low{};
  std::size_t n = 0;
  forEachSample([&](std::uint16_t d) {
    ++high[d >> 8];
    ++n;
  });
  if (n == 0) return;
  std::size_t rank = n / 2, bin = 0;
  while (rank >= high[bin]) rank -= high[bin++];
  forEachSample([&](std::uint16_t d) {
    if ((d >> 8) == bin) ++low[d & 0xFF];
  });
  std::size_t low_bin = 0;
  while (rank >= low[low_bin]) rank -= low[low_bin++];
  const double median_m = static_cast<double>((bin << 8) | low_bin) * f.depth_unit_m;
  frame_median_depths_.push_back(median_m);

  const std::string head = at(record) + ": median valid depth " + gnum(median_m) + " m is ";
  const std::string unit = " (depth unit " + gnum(f.depth_unit_m) + " m): ";
  if (median_m < cfg_.stream.depth_median_min_m) {
    ++diag_.depth_unit_suspects;
    issue("depth units", record,
          head + "below depth_median_min_m = " + gnum(cfg_.stream.depth_median_min_m) + " m" +
              unit + "metres stored as millimetres?");
  } else if (median_m > cfg_.stream.depth_median_max_m) {
    ++diag_.depth_unit_suspects;
    issue("depth units", record,
          head + "above depth_median_max_m = " + gnum(cfg_.stream.depth_median_max_m) + " m" +
              unit + "millimetres stored as metres?");
  }
}

void StreamChecker::checkExtrinsic(const RgbdFrame& f, std::size_t record) {
  if (extrinsic_checked_mismatch_ || !f.has_source_T_body_cam) return;
  const Eigen::Isometry3d& A = f.source_T_body_cam;
  const Eigen::Isometry3d& B = cfg_.extrinsic.T_body_cam;
  const double dt = (A.translation() - B.translation()).norm();
  const double dang = Eigen::AngleAxisd(A.linear().transpose() * B.linear()).angle() * 180.0 / M_PI;
  if (dt <= cfg_.extrinsic.sensor_pose_tolerance_m &&
      dang <= cfg_.extrinsic.sensor_pose_tolerance_deg)
    return;
  extrinsic_checked_mismatch_ = true;
  diag_.extrinsic_mismatch = true;
  warn(at(record) + ": the rawlog's sensorPose places the colour camera at " + poseText(A) +
       " in the body frame, but [extrinsic] T_body_cam is " + poseText(B) + "; they differ by " +
       num(dt, 4) + " m and " + num(dang, 2) + " deg (tolerances " +
       gnum(cfg_.extrinsic.sensor_pose_tolerance_m) + " m, " +
       gnum(cfg_.extrinsic.sensor_pose_tolerance_deg) + " deg); [extrinsic] is the one used");
}

void StreamChecker::onUnusable(std::size_t record, const std::string& why) {
  ++diag_.unusable;
  issue("unusable observation", record, why);
}

void StreamChecker::onSkipped(std::size_t, const std::string& class_name) {
  ++diag_.skipped[class_name];
}

void StreamChecker::finishImu() {
  SensorStreamStats& st = diag_.imu;
  const std::size_t last_record = diag_.records == 0 ? 0 : diag_.records - 1;
  if (st.delivered == 0) {
    warn(records(0, last_record) +
         ": no IMU samples (CObservationIMU with accelerometer and gyroscope)");
    return;
  }
  st.duration_s = st.last_t - st.first_t;
  if (st.delivered >= 2 && st.duration_s > 0.0) {
    st.rate_hz = static_cast<double>(st.delivered - 1) / st.duration_s;
    st.median_period_s = 1.0 / st.rate_hz;
    const double nominal = cfg_.imu.rate_hz;
    if (std::abs(st.rate_hz - nominal) > cfg_.stream.imu_rate_tolerance * nominal) {
      warn(records(first_imu_record_, last_imu_record_) + ": measured IMU rate " +
           num(st.rate_hz, 1) + " Hz differs from [imu] rate_hz = " + gnum(nominal) +
           " Hz by more than " + gnum(100.0 * cfg_.stream.imu_rate_tolerance) +
           "% (imu_rate_tolerance); the IMU gap limit is based on [imu] rate_hz");
    }
  }
  const double mean = acc_norm_sum_ / static_cast<double>(st.delivered);
  diag_.mean_acc_norm_m_s2 = mean;
  const double g = cfg_.imu.gravity_m_s2;
  const std::string head = records(first_imu_record_, last_imu_record_) +
                           ": mean IMU acceleration magnitude " + num(mean, 3) + " m/s^2 over " +
                           std::to_string(st.delivered) + " samples ";
  if (mean >= cfg_.stream.g_units_min_m_s2 && mean <= cfg_.stream.g_units_max_m_s2) {
    diag_.acc_looks_like_g_units = true;
    warn(head + "looks like g units (expected about " + gnum(g) +
         " m/s^2): the accelerometer must be given in m/s^2 (set [stream] accel_scale = 9.80665 "
         "to read one recorded in g)");
  } else if (std::abs(mean - g) > cfg_.stream.acc_magnitude_tolerance * g) {
    warn(head + "is far from gravity " + gnum(g) + " m/s^2 (acc_magnitude_tolerance " +
         gnum(100.0 * cfg_.stream.acc_magnitude_tolerance) + "%): wrong units or gravity removed?");
  }
}

void StreamChecker::finishImages() {
  SensorStreamStats& st = diag_.images;
  const std::size_t last_record = diag_.records == 0 ? 0 : diag_.records - 1;
  if (st.delivered == 0) {
    warn(records(0, last_record) + ": no RGB-D frames (CObservation3DRangeScan)");
    return;
  }
  if (!frame_median_depths_.empty()) {
    std::vector<double> d = frame_median_depths_;
    auto mid = d.begin() + static_cast<std::ptrdiff_t>(d.size() / 2);
    std::nth_element(d.begin(), mid, d.end());
    diag_.median_depth_m = *mid;
  }
  st.duration_s = st.last_t - st.first_t;
  if (frame_stamps_.size() < 2 || st.duration_s <= 0.0) return;
  st.rate_hz = static_cast<double>(st.delivered - 1) / st.duration_s;
  std::vector<double> dts;
  dts.reserve(frame_stamps_.size() - 1);
  for (size_t i = 1; i < frame_stamps_.size(); ++i)
    dts.push_back(frame_stamps_[i].first - frame_stamps_[i - 1].first);
  std::vector<double> sorted = dts;
  auto mid = sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2);
  std::nth_element(sorted.begin(), mid, sorted.end());
  st.median_period_s = *mid;
  st.gap_limit_s = cfg_.stream.image_gap_factor * st.median_period_s;
  for (size_t i = 0; i < dts.size(); ++i) {
    st.max_gap_s = std::max(st.max_gap_s, dts[i]);
    if (dts[i] <= st.gap_limit_s) continue;
    ++st.gaps;
    const std::size_t record = frame_stamps_[i + 1].second;
    issue("image gap", record,
          at(record) + ": image gap of " + num(dts[i], 4) + " s between t = " +
              stamp(frame_stamps_[i].first) + " s and t = " + stamp(frame_stamps_[i + 1].first) +
              " s (limit " + num(st.gap_limit_s, 4) + " s = image_gap_factor " +
              gnum(cfg_.stream.image_gap_factor) + " x median period " +
              num(st.median_period_s, 4) + " s)");
  }
}

void StreamChecker::finish() {
  if (finished_) return;
  finished_ = true;
  closeConstantRun();
  finishImu();
  finishImages();
  finishWheel();
  for (const auto& kind : issue_order_) {
    const IssueKind& k = issues_.at(kind);
    if (k.unlisted == 0) continue;
    warn(records(k.first_unlisted, k.last_unlisted) + ": " + std::to_string(k.unlisted) +
         " more '" + kind + "' messages not listed (max_listed_issues = " +
         std::to_string(cfg_.stream.max_listed_issues) + ")");
  }
}

}  // namespace rgbdi::io
