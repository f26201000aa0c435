#include "rgbdi/bag/ros_image.h"

#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "rgbdi/io/image_decode.h"

namespace rgbdi::bag {
namespace {

// image_transport's compressedDepth prefix: int32 format, float depthQuantA, float depthQuantB.
constexpr std::size_t kCompressedDepthHeaderBytes = 12;

/// Rows of the message as a Mat header (no copy); checks sizes against the data.
cv::Mat view(const sensor_msgs::Image& m, int type, const std::string& label) {
  const std::size_t bpp = CV_ELEM_SIZE(type);
  if (m.width == 0 || m.height == 0)
    throw ImageDecodeError(label + ": empty image (" + std::to_string(m.width) + "x" +
                           std::to_string(m.height) + ")");
  if (m.step < m.width * bpp)
    throw ImageDecodeError(label + ": row step " + std::to_string(m.step) +
                           " bytes is shorter than " + std::to_string(m.width) +
                           " pixels of encoding " + m.encoding);
  if (m.data.size() < static_cast<std::size_t>(m.step) * m.height)
    throw ImageDecodeError(label + ": " + std::to_string(m.data.size()) + " bytes of data for " +
                           std::to_string(m.height) + " rows of " + std::to_string(m.step) +
                           " bytes");
  if (m.width > static_cast<std::uint32_t>(std::numeric_limits<int>::max()) ||
      m.height > static_cast<std::uint32_t>(std::numeric_limits<int>::max()))
    throw ImageDecodeError(label + ": image size " + std::to_string(m.width) + "x" +
                           std::to_string(m.height) + " is too large");
  const int rows = static_cast<int>(m.height), cols = static_cast<int>(m.width);
  if (m.step % CV_ELEM_SIZE1(type) == 0)
    return cv::Mat(rows, cols, type, const_cast<std::uint8_t*>(m.data.data()), m.step);
  // A row padding that is not a whole number of channel values (legal in the message, refused
  // by a cv::Mat header): copy the rows out.
  cv::Mat packed(rows, cols, type);
  for (int r = 0; r < rows; ++r)
    std::memcpy(packed.ptr(r), m.data.data() + static_cast<std::size_t>(r) * m.step, cols * bpp);
  return packed;
}

/// 16-bit data in host order (copy; byte-swapped when the message is big-endian).
cv::Mat host16(const sensor_msgs::Image& m, const std::string& label) {
  cv::Mat out = view(m, CV_16UC1, label).clone();
  if (m.is_bigendian) {
    for (int r = 0; r < out.rows; ++r) {
      auto* p = out.ptr<std::uint16_t>(r);
      for (int c = 0; c < out.cols; ++c)
        p[c] = static_cast<std::uint16_t>((p[c] >> 8) | (p[c] << 8));
    }
  }
  return out;
}

cv::Mat host32f(const sensor_msgs::Image& m, const std::string& label) {
  cv::Mat out = view(m, CV_32FC1, label).clone();
  if (m.is_bigendian) {
    for (int r = 0; r < out.rows; ++r) {
      auto* p = out.ptr<std::uint32_t>(r);
      for (int c = 0; c < out.cols; ++c) {
        const std::uint32_t v = p[c];
        p[c] = (v >> 24) | ((v >> 8) & 0xff00u) | ((v << 8) & 0xff0000u) | (v << 24);
      }
    }
  }
  return out;
}

cv::Mat toRgb(const cv::Mat& decoded_bgr_like, const std::string& label) {
  cv::Mat rgb;
  switch (decoded_bgr_like.channels()) {
    case 1:
      cv::cvtColor(decoded_bgr_like, rgb, cv::COLOR_GRAY2RGB);
      break;
    case 3:
      cv::cvtColor(decoded_bgr_like, rgb, cv::COLOR_BGR2RGB);
      break;
    case 4:
      cv::cvtColor(decoded_bgr_like, rgb, cv::COLOR_BGRA2RGB);
      break;
    default:
      throw ImageDecodeError(label + ": decoded image has " +
                             std::to_string(decoded_bgr_like.channels()) + " channels");
  }
  return rgb;
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

cv::Mat imdecodeOrThrow(const std::uint8_t* p, std::size_t n, int flags, const std::string& label,
                        const std::string& format) {
  if (n == 0)
    throw ImageDecodeError(label + ": compressed image (format '" + format + "') has no data");
  // ROS compressed images are JPEG or PNG. Anything else never reaches cv::imdecode, which tries
  // every codec OpenCV was built with (fuzzing finding 20: data starting with OpenEXR's magic
  // made OpenEXR allocate 1.1 GB for an attribute of a 300-byte message).
  if (!io::isJpegData(p, n) && !io::isPngData(p, n))
    throw ImageDecodeError(label + ": compressed image (format '" + format +
                           "') is neither JPEG nor PNG (its data do not start with either's "
                           "signature)");
  const cv::Mat buf(1, static_cast<int>(n), CV_8UC1, const_cast<std::uint8_t*>(p));
  cv::Mat img;
  try {
    img = cv::imdecode(buf, flags);
  } catch (const cv::Exception& e) {
    throw ImageDecodeError(label + ": cannot decode compressed image (format '" + format +
                           "'): " + e.what());
  }
  if (img.empty())
    throw ImageDecodeError(label + ": cannot decode compressed image (format '" + format + "')");
  return img;
}

}  // namespace

cv::Mat metresToUnits(const cv::Mat& metres, double unit_m, std::size_t& clipped) {
  cv::Mat out(metres.size(), CV_16UC1);
  const double per_metre = 1.0 / unit_m;
  for (int r = 0; r < metres.rows; ++r) {
    const float* src = metres.ptr<float>(r);
    auto* dst = out.ptr<std::uint16_t>(r);
    for (int c = 0; c < metres.cols; ++c) {
      const double u = std::round(static_cast<double>(src[c]) * per_metre);
      if (!(u > 0.0) || !std::isfinite(u)) {
        dst[c] = 0;
      } else if (u > 65535.0) {
        dst[c] = 0;
        ++clipped;
      } else {
        dst[c] = static_cast<std::uint16_t>(u);
      }
    }
  }
  return out;
}

cv::Mat decodeColorImage(const sensor_msgs::Image& m, const std::string& label) {
  const std::string& e = m.encoding;
  cv::Mat rgb;
  if (e == "rgb8") {
    rgb = view(m, CV_8UC3, label).clone();
  } else if (e == "bgr8" || e == "8UC3") {
    cv::cvtColor(view(m, CV_8UC3, label), rgb, cv::COLOR_BGR2RGB);
  } else if (e == "rgba8") {
    cv::cvtColor(view(m, CV_8UC4, label), rgb, cv::COLOR_RGBA2RGB);
  } else if (e == "bgra8") {
    cv::cvtColor(view(m, CV_8UC4, label), rgb, cv::COLOR_BGRA2RGB);
  } else if (e == "mono8" || e == "8UC1") {
    cv::cvtColor(view(m, CV_8UC1, label), rgb, cv::COLOR_GRAY2RGB);
  } else if (e == "yuv422") {  // ROS: UYVY byte order
    cv::cvtColor(view(m, CV_8UC2, label), rgb, cv::COLOR_YUV2RGB_UYVY);
  } else if (e == "yuv422_yuy2" || e == "yuyv") {
    cv::cvtColor(view(m, CV_8UC2, label), rgb, cv::COLOR_YUV2RGB_YUY2);
  } else {
    throw ImageDecodeError(label + ": unsupported colour encoding '" + e +
                           "' (supported: rgb8, bgr8, rgba8, bgra8, mono8, 8UC1, 8UC3, yuv422, "
                           "yuv422_yuy2)");
  }
  return rgb;
}

cv::Mat decodeColorImage(const sensor_msgs::CompressedImage& m, const std::string& label) {
  const std::string f = lower(m.format);
  if (f.find("compresseddepth") != std::string::npos)
    throw ImageDecodeError(label + ": compressed depth image (format '" + m.format +
                           "') on the colour topic");
  const cv::Mat img =
      imdecodeOrThrow(m.data.data(), m.data.size(), cv::IMREAD_UNCHANGED, label, m.format);
  if (img.depth() != CV_8U)
    throw ImageDecodeError(label + ": compressed colour image (format '" + m.format +
                           "') decodes to " + std::to_string(img.elemSize1() * 8) +
                           "-bit pixels; expected 8-bit colour");
  return toRgb(img, label);
}

DepthImage decodeDepthImage(const sensor_msgs::Image& m, double integer_unit_m, double float_unit_m,
                            const std::string& label) {
  DepthImage d;
  if (m.encoding == "16UC1" || m.encoding == "mono16") {
    d.depth = host16(m, label);
    d.unit_m = integer_unit_m;
  } else if (m.encoding == "32FC1") {
    d.depth = metresToUnits(host32f(m, label), float_unit_m, d.clipped);
    d.unit_m = float_unit_m;
  } else {
    throw ImageDecodeError(label + ": unsupported depth encoding '" + m.encoding +
                           "' (supported: 16UC1, mono16, 32FC1)");
  }
  return d;
}

DepthImage decodeDepthImage(const sensor_msgs::CompressedImage& m, double integer_unit_m,
                            double float_unit_m, const std::string& label) {
  const std::string f = lower(m.format);
  const std::uint8_t* p = m.data.data();
  std::size_t n = m.data.size();
  DepthImage d;
  if (f.find("compresseddepth") != std::string::npos) {
    if (f.find("rvl") != std::string::npos)
      throw ImageDecodeError(label + ": unsupported compressed depth format '" + m.format +
                             "' (RVL); supported: compressedDepth png");
    const bool is_float = f.rfind("32fc1", 0) == 0;
    if (!is_float && f.rfind("16uc1", 0) != 0)
      throw ImageDecodeError(label + ": unsupported compressed depth format '" + m.format +
                             "' (expected 16UC1 or 32FC1 compressedDepth)");
    float quant_a = 0.0f, quant_b = 0.0f;
    if (!io::isPngData(p, n)) {
      if (n < kCompressedDepthHeaderBytes ||
          !io::isPngData(p + kCompressedDepthHeaderBytes, n - kCompressedDepthHeaderBytes))
        throw ImageDecodeError(label + ": compressed depth (format '" + m.format +
                               "') holds no PNG image");
      std::memcpy(&quant_a, p + 4, 4);
      std::memcpy(&quant_b, p + 8, 4);
      p += kCompressedDepthHeaderBytes;
      n -= kCompressedDepthHeaderBytes;
    }
    const cv::Mat raw = imdecodeOrThrow(p, n, cv::IMREAD_UNCHANGED, label, m.format);
    if (raw.type() != CV_16UC1)
      throw ImageDecodeError(label + ": compressed depth (format '" + m.format +
                             "') does not decode to a 16-bit single-channel image");
    if (!is_float) {
      d.depth = raw;
      d.unit_m = integer_unit_m;
      return d;
    }
    if (!(quant_a != 0.0f) || !std::isfinite(quant_a))
      throw ImageDecodeError(label + ": 32FC1 compressedDepth without its quantisation header");
    // Inverse-depth quantisation: stored q = A / depth + B, so depth = A / (q - B); q = 0 is
    // invalid.
    cv::Mat metres(raw.size(), CV_32FC1);
    for (int r = 0; r < raw.rows; ++r) {
      const auto* q = raw.ptr<std::uint16_t>(r);
      float* z = metres.ptr<float>(r);
      for (int c = 0; c < raw.cols; ++c)
        z[c] = q[c] == 0 ? std::numeric_limits<float>::quiet_NaN()
                         : quant_a / (static_cast<float>(q[c]) - quant_b);
    }
    d.depth = metresToUnits(metres, float_unit_m, d.clipped);
    d.unit_m = float_unit_m;
    return d;
  }
  const cv::Mat img = imdecodeOrThrow(p, n, cv::IMREAD_UNCHANGED, label, m.format);
  if (img.type() != CV_16UC1)
    throw ImageDecodeError(label + ": compressed depth image (format '" + m.format +
                           "') is not 16-bit single-channel");
  d.depth = img;
  d.unit_m = integer_unit_m;
  return d;
}

}  // namespace rgbdi::bag
