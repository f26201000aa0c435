// Decoding ROS image messages (ros_image.h) and camera_info / tf (ros_calibration.h): known
// answers per encoding, padded rows, big-endian data, float depth, compressed formats, and the
// errors that name the message and the encoding.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <opencv2/imgcodecs.hpp>

#include "rgbdi/bag/ros_calibration.h"
#include "rgbdi/bag/ros_image.h"

namespace rgbdi::bag {
namespace {

sensor_msgs::Image image(const std::string& encoding, std::uint32_t w, std::uint32_t h,
                         std::uint32_t step, const std::vector<std::uint8_t>& data) {
  sensor_msgs::Image m;
  m.encoding = encoding;
  m.width = w;
  m.height = h;
  m.step = step;
  m.data = data;
  return m;
}

TEST(RosImage, ColourEncodingsGiveRgb) {
  // One 2x1 image: pixel 0 = (R 10, G 20, B 30), pixel 1 = (R 200, G 100, B 50).
  const cv::Vec3b p0(10, 20, 30), p1(200, 100, 50);
  const auto check = [&](const cv::Mat& rgb, const std::string& what) {
    ASSERT_EQ(rgb.type(), CV_8UC3) << what;
    ASSERT_EQ(rgb.cols, 2) << what;
    EXPECT_EQ(rgb.at<cv::Vec3b>(0, 0), p0) << what;
    EXPECT_EQ(rgb.at<cv::Vec3b>(0, 1), p1) << what;
  };
  check(decodeColorImage(image("rgb8", 2, 1, 6, {10, 20, 30, 200, 100, 50}), "l"), "rgb8");
  check(decodeColorImage(image("bgr8", 2, 1, 6, {30, 20, 10, 50, 100, 200}), "l"), "bgr8");
  check(decodeColorImage(image("8UC3", 2, 1, 6, {30, 20, 10, 50, 100, 200}), "l"), "8UC3");
  check(decodeColorImage(image("rgba8", 2, 1, 8, {10, 20, 30, 255, 200, 100, 50, 0}), "l"),
        "rgba8");
  check(decodeColorImage(image("bgra8", 2, 1, 8, {30, 20, 10, 255, 50, 100, 200, 0}), "l"),
        "bgra8");
  // Padded rows (step 8 > 6) on two rows: the padding is skipped.
  const cv::Mat padded = decodeColorImage(
      image("rgb8", 2, 2, 8, {10, 20, 30, 200, 100, 50, 99, 99, 1, 2, 3, 4, 5, 6, 99, 99}), "l");
  EXPECT_EQ(padded.at<cv::Vec3b>(1, 0), cv::Vec3b(1, 2, 3));
  EXPECT_EQ(padded.at<cv::Vec3b>(1, 1), cv::Vec3b(4, 5, 6));
  const cv::Mat grey = decodeColorImage(image("mono8", 2, 1, 2, {7, 250}), "l");
  EXPECT_EQ(grey.at<cv::Vec3b>(0, 0), cv::Vec3b(7, 7, 7));
  EXPECT_EQ(grey.at<cv::Vec3b>(0, 1), cv::Vec3b(250, 250, 250));
  // YUV 4:2:2 with neutral chroma (U = V = 128) is grey, brighter for the larger luma; UYVY (ROS
  // "yuv422") and YUYV hold the same two pixels in different byte orders.
  const cv::Mat uyvy = decodeColorImage(image("yuv422", 2, 1, 4, {128, 90, 128, 160}), "l");
  const cv::Mat yuyv = decodeColorImage(image("yuv422_yuy2", 2, 1, 4, {90, 128, 160, 128}), "l");
  for (int c = 0; c < 2; ++c) {
    const cv::Vec3b p = uyvy.at<cv::Vec3b>(0, c);
    EXPECT_EQ(p[0], p[1]);
    EXPECT_EQ(p[1], p[2]);
    EXPECT_EQ(yuyv.at<cv::Vec3b>(0, c), p);
  }
  EXPECT_LT(uyvy.at<cv::Vec3b>(0, 0)[0] + 50, uyvy.at<cv::Vec3b>(0, 1)[0]);
}

TEST(RosImage, DepthEncodingsKeepUnits) {
  const DepthImage d16 =
      decodeDepthImage(image("16UC1", 2, 1, 4, {0x34, 0x12, 0x00, 0x00}), 1e-3, 1e-3, "l");
  EXPECT_EQ(d16.depth.type(), CV_16UC1);
  EXPECT_EQ(d16.depth.at<std::uint16_t>(0, 0), 0x1234);
  EXPECT_EQ(d16.depth.at<std::uint16_t>(0, 1), 0);
  EXPECT_DOUBLE_EQ(d16.unit_m, 1e-3);
  // mono16 (RealSense SDK) is the same data; the unit is what the caller knows (e.g. 0.0001).
  const DepthImage mono = decodeDepthImage(image("mono16", 1, 1, 2, {0xe8, 0x03}), 1e-4, 1e-3, "l");
  EXPECT_EQ(mono.depth.at<std::uint16_t>(0, 0), 1000);
  EXPECT_DOUBLE_EQ(mono.unit_m, 1e-4);
  sensor_msgs::Image be = image("16UC1", 1, 1, 2, {0x12, 0x34});
  be.is_bigendian = 1;
  EXPECT_EQ(decodeDepthImage(be, 1e-3, 1e-3, "l").depth.at<std::uint16_t>(0, 0), 0x1234);

  // 32FC1 metres -> millimetres: rounding, invalid values and values beyond 65.535 m.
  const float values[6] = {1.2345f,
                           0.0f,
                           -1.0f,
                           std::numeric_limits<float>::quiet_NaN(),
                           std::numeric_limits<float>::infinity(),
                           70.0f};
  std::vector<std::uint8_t> bytes(sizeof values);
  std::memcpy(bytes.data(), values, sizeof values);
  const DepthImage f = decodeDepthImage(image("32FC1", 6, 1, 24, bytes), 1e-3, 1e-3, "l");
  EXPECT_EQ(f.depth.at<std::uint16_t>(0, 0),
            1235);  // 1234.5 mm rounds up (float 1.2345 is 1.23450005)
  for (int c = 1; c < 6; ++c) EXPECT_EQ(f.depth.at<std::uint16_t>(0, c), 0) << c;
  EXPECT_EQ(f.clipped, 1u);
  EXPECT_DOUBLE_EQ(f.unit_m, 1e-3);
  // Big-endian float.
  std::vector<std::uint8_t> be_bytes(4);
  const float two = 2.0f;
  std::memcpy(be_bytes.data(), &two, 4);
  std::swap(be_bytes[0], be_bytes[3]);
  std::swap(be_bytes[1], be_bytes[2]);
  sensor_msgs::Image bef = image("32FC1", 1, 1, 4, be_bytes);
  bef.is_bigendian = 1;
  EXPECT_EQ(decodeDepthImage(bef, 1e-3, 1e-4, "l").depth.at<std::uint16_t>(0, 0), 20000);
}

TEST(RosImage, RowPaddingThatIsNotAWholeValueIsCopiedOut) {
  // Fuzzing finding (2026-12-03): a 16/32-bit image whose row step is not a multiple of the value
  // size made OpenCV throw from the Mat header (an uncaught cv::Exception ended the converter).
  // Two rows of 2 uint16 with 1 byte of padding: step 5.
  const DepthImage d = decodeDepthImage(
      image("16UC1", 2, 2, 5, {0x01, 0x00, 0x02, 0x00, 0xff, 0x03, 0x00, 0x04, 0x00, 0xff}), 1e-3,
      1e-3, "l");
  ASSERT_EQ(d.depth.type(), CV_16UC1);
  EXPECT_EQ(d.depth.at<std::uint16_t>(0, 0), 1);
  EXPECT_EQ(d.depth.at<std::uint16_t>(0, 1), 2);
  EXPECT_EQ(d.depth.at<std::uint16_t>(1, 0), 3);
  EXPECT_EQ(d.depth.at<std::uint16_t>(1, 1), 4);
  const float a = 1.5f, b = 2.5f;
  std::vector<std::uint8_t> bytes(2 * 7, 0xee);  // 1x1 float rows, step 7
  std::memcpy(bytes.data(), &a, 4);
  std::memcpy(bytes.data() + 7, &b, 4);
  const DepthImage f = decodeDepthImage(image("32FC1", 1, 2, 7, bytes), 1e-3, 1e-3, "l");
  EXPECT_EQ(f.depth.at<std::uint16_t>(0, 0), 1500);
  EXPECT_EQ(f.depth.at<std::uint16_t>(1, 0), 2500);
  // Sizes beyond what an image header holds are refused, not wrapped round.
  EXPECT_THROW(decodeDepthImage(image("16UC1", 0x80000000u, 1, 0, {}), 1e-3, 1e-3, "l"),
               ImageDecodeError);
}

TEST(RosImage, ErrorsNameTheMessageAndTheEncoding) {
  try {
    decodeDepthImage(image("bayer_rggb8", 2, 1, 2, {1, 2}), 1e-3, 1e-3, "x.bag /d message 3");
    FAIL();
  } catch (const ImageDecodeError& e) {
    EXPECT_NE(
        std::string(e.what()).find("x.bag /d message 3: unsupported depth encoding 'bayer_rggb8'"),
        std::string::npos)
        << e.what();
  }
  try {
    decodeColorImage(image("16UC1", 2, 1, 4, {1, 2, 3, 4}), "x.bag /c message 0");
    FAIL();
  } catch (const ImageDecodeError& e) {
    EXPECT_NE(std::string(e.what()).find("unsupported colour encoding '16UC1'"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(decodeColorImage(image("rgb8", 2, 2, 6, {1, 2, 3}), "l"),
               ImageDecodeError);  // short data
  EXPECT_THROW(decodeColorImage(image("rgb8", 2, 1, 5, {1, 2, 3, 4, 5}), "l"),
               ImageDecodeError);  // short step
  EXPECT_THROW(decodeColorImage(image("rgb8", 0, 0, 0, {}), "l"), ImageDecodeError);
}

sensor_msgs::CompressedImage compressed(const std::string& format,
                                        const std::vector<std::uint8_t>& data) {
  sensor_msgs::CompressedImage m;
  m.format = format;
  m.data = data;
  return m;
}

TEST(RosImage, CompressedColourAndDepth) {
  cv::Mat bgr(3, 4, CV_8UC3);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c)
      bgr.at<cv::Vec3b>(r, c) =
          cv::Vec3b(static_cast<uchar>(10 * c), 50, static_cast<uchar>(60 * r));
  std::vector<std::uint8_t> png;
  cv::imencode(".png", bgr, png);
  const cv::Mat rgb = decodeColorImage(compressed("bgr8; png compressed bgr8", png), "l");
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c)
      EXPECT_EQ(rgb.at<cv::Vec3b>(r, c),
                cv::Vec3b(static_cast<uchar>(60 * r), 50, static_cast<uchar>(10 * c)));
  std::vector<std::uint8_t> jpg;
  cv::imencode(".jpg", cv::Mat(8, 8, CV_8UC3, cv::Scalar(40, 80, 160)), jpg);
  const cv::Mat from_jpeg = decodeColorImage(compressed("rgb8; jpeg compressed bgr8", jpg), "l");
  EXPECT_NEAR(from_jpeg.at<cv::Vec3b>(4, 4)[0], 160, 2);  // R was the third BGR channel
  EXPECT_NEAR(from_jpeg.at<cv::Vec3b>(4, 4)[2], 40, 2);

  cv::Mat depth(2, 3, CV_16UC1);
  for (int i = 0; i < 6; ++i)
    depth.at<std::uint16_t>(i / 3, i % 3) = static_cast<std::uint16_t>(1000 * i + 7);
  std::vector<std::uint8_t> dpng;
  cv::imencode(".png", depth, dpng);
  // image_transport's compressedDepth: a 12-byte header before the PNG (and older writers without).
  std::vector<std::uint8_t> with_header(12, 0);
  with_header.insert(with_header.end(), dpng.begin(), dpng.end());
  for (const auto& data : {with_header, dpng}) {
    const DepthImage d =
        decodeDepthImage(compressed("16UC1; compressedDepth png", data), 1e-3, 1e-3, "l");
    ASSERT_EQ(d.depth.type(), CV_16UC1);
    EXPECT_EQ(cv::countNonZero(d.depth != depth), 0);
  }
  EXPECT_EQ(
      cv::countNonZero(decodeDepthImage(compressed("png", dpng), 1e-3, 1e-3, "l").depth != depth),
      0);

  // 32FC1 compressedDepth: inverse depth q = A / z + B, here A = 100, B = 1 - A / 10 = -9; q = 0
  // invalid.
  const float A = 100.0f, B = -9.0f;
  cv::Mat q(1, 3, CV_16UC1);
  q.at<std::uint16_t>(0, 0) = static_cast<std::uint16_t>(A / 2.0f + B + 0.5f);  // 2 m -> 41
  q.at<std::uint16_t>(0, 1) = 0;
  q.at<std::uint16_t>(0, 2) = static_cast<std::uint16_t>(A / 0.5f + B + 0.5f);  // 0.5 m -> 191
  std::vector<std::uint8_t> qpng, fdata(12, 0);
  cv::imencode(".png", q, qpng);
  std::memcpy(fdata.data() + 4, &A, 4);
  std::memcpy(fdata.data() + 8, &B, 4);
  fdata.insert(fdata.end(), qpng.begin(), qpng.end());
  const DepthImage fz =
      decodeDepthImage(compressed("32FC1; compressedDepth png", fdata), 1e-3, 1e-3, "l");
  EXPECT_EQ(fz.depth.at<std::uint16_t>(0, 0), 2000);  // 100 / (41 + 9)
  EXPECT_EQ(fz.depth.at<std::uint16_t>(0, 1), 0);
  EXPECT_EQ(fz.depth.at<std::uint16_t>(0, 2), 500);  // 100 / (191 + 9)

  EXPECT_THROW(decodeDepthImage(compressed("16UC1; compressedDepth rvl", dpng), 1e-3, 1e-3, "l"),
               ImageDecodeError);
  EXPECT_THROW(decodeColorImage(compressed("jpeg", {1, 2, 3}), "l"), ImageDecodeError);
  EXPECT_THROW(decodeDepthImage(compressed("jpeg", jpg), 1e-3, 1e-3, "l"),
               ImageDecodeError);  // 8-bit
}

TEST(RosImage, CompressedDataThatIsNeitherJpegNorPngNeverReachesOpenCv) {
  // Fuzzing finding 20 (fuzz_ros_messages, 2026-12-04): cv::imdecode tries every codec OpenCV
  // has; data with OpenEXR's magic made OpenEXR allocate 1.1 GB for an attribute (AddressSanitizer:
  // out of memory). The message data of the fuzzer's input:
  std::vector<std::uint8_t> exr = {
      0x76, 0x2f, 0x31, 0x01, 0x02, 0x00, 0x00, 0x00, 0x3b, 0x96, 0x39, 0x91, 0x00, 0x00, 0x00,
      0x1b, 0x49, 0x44, 0x41, 0x54, 0x08, 0x1d, 0x63, 0x64, 0x66, 0x62, 0x64, 0x80, 0x01, 0x46,
      0x66, 0x26, 0x46, 0x06, 0x18, 0x60, 0x64, 0x66, 0x62, 0x64, 0x80, 0x01, 0x00, 0x02, 0x2b,
      0x00, 0x16, 0x66, 0xab, 0xa7, 0x9a, 0x00, 0x00, 0x00, 0x00, 0x49, 0xc8, 0xc8, 0xc8, 0xc8,
      0xc8, 0xc8, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,
      0x00, 0x03, 0x00, 0x00, 0x00, 0x70, 0x6e, 0x67, 0x54, 0x00, 0x00, 0x00};
  exr.insert(exr.end(), 75, 0xc8);
  const std::vector<std::uint8_t> end = {0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82};
  exr.insert(exr.end(), end.begin(), end.end());
  const std::string why =
      "l: compressed image (format 'png') is neither JPEG nor PNG (its data "
      "do not start with either's signature)";
  try {
    decodeColorImage(compressed("png", exr), "l");
    ADD_FAILURE() << "decoded";
  } catch (const ImageDecodeError& e) {
    EXPECT_EQ(std::string(e.what()), why);
  }
  EXPECT_THROW(decodeDepthImage(compressed("16UC1; compressedDepth png", exr), 1e-3, 1e-3, "l"),
               ImageDecodeError);
}

TEST(RosCalibration, CameraInfoAndTransform) {
  sensor_msgs::CameraInfo info;
  info.width = 640;
  info.height = 480;
  info.K = {600, 0, 320, 0, 601, 240, 0, 0, 1};
  info.distortion_model = "plumb_bob";
  info.D = {0.1, -0.2, 0.001, 0.002, 0.03};
  const PinholeCamera c = cameraFromInfo(info, "l");
  EXPECT_EQ(c.width, 640);
  EXPECT_DOUBLE_EQ(c.fy, 601);
  EXPECT_DOUBLE_EQ(c.cy, 240);
  EXPECT_DOUBLE_EQ(c.dist[4], 0.03);
  info.distortion_model = "equidistant";
  EXPECT_THROW(cameraFromInfo(info, "l"), CalibrationError);
  info.D = {0, 0, 0, 0};
  EXPECT_FALSE(cameraFromInfo(info, "l").hasDistortion());  // zero coefficients: any model is fine
  info.distortion_model = "rational_polynomial";
  info.D = {0.1, 0, 0, 0, 0, 0.5, 0, 0};
  EXPECT_THROW(cameraFromInfo(info, "l"), CalibrationError);  // k4 cannot be represented
  info.K = {0, 0, 0, 0, 0, 0, 0, 0, 0};                       // uncalibrated camera_info
  try {
    cameraFromInfo(info, "x.bag /info");
    FAIL();
  } catch (const CalibrationError& e) {
    EXPECT_NE(
        std::string(e.what()).find("x.bag /info: camera_info is not a calibrated pinhole camera"),
        std::string::npos);
  }

  geometry_msgs::Transform tf;
  tf.translation.x = 0.1;
  tf.rotation.z = std::sin(0.25);
  tf.rotation.w = std::cos(0.25);
  const Eigen::Isometry3d T = isometryFromTransform(tf, "l");
  EXPECT_NEAR(Eigen::AngleAxisd(T.rotation()).angle(), 0.5, 1e-12);
  EXPECT_DOUBLE_EQ(T.translation().x(), 0.1);
  tf.rotation.z = tf.rotation.w = 0.0;
  EXPECT_THROW(isometryFromTransform(tf, "l"), CalibrationError);
}

}  // namespace
}  // namespace rgbdi::bag
