// BagWriter: write a small sequence, read it back with rosbag::View and check topics, message
// types, encodings, stamps and values exactly, for every compression; error cases.
#include <geometry_msgs/PoseStamped.h>
#include <gtest/gtest.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>

#include <filesystem>
#include <map>

#include "rgbdi/bag/bag_writer.h"
#include "testing/fixtures.h"

namespace rgbdi::bag {
namespace {

namespace fs = std::filesystem;

RgbdFrame makeFrame(double t, std::uint64_t index) {
  RgbdFrame f;
  f.t = t;
  f.index = index;
  f.rgb = cv::Mat(4, 5, CV_8UC3);
  f.depth = cv::Mat(4, 5, CV_16UC1);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 5; ++c) {
      f.rgb.at<cv::Vec3b>(r, c) = cv::Vec3b(static_cast<uchar>(10 * r + c),
                                            static_cast<uchar>(index), static_cast<uchar>(200 + c));
      f.depth.at<std::uint16_t>(r, c) = static_cast<std::uint16_t>(1000 * r + 7 * c + 300 * index);
    }
  return f;
}

TEST(BagWriter, WritesTheDatasetLayoutReadableByRosbag) {
  for (Compression comp : {Compression::None, Compression::Bz2, Compression::Lz4}) {
    const std::string dir = test::makeTempDir("bag");
    const std::string path = dir + "/seq.bag";
    {
      BagWriter w(path, comp);
      for (int k = 0; k < 10; ++k) {
        ImuSample s;
        s.t = 1000.0 + 0.005 * k;
        s.acc = Eigen::Vector3d(0.1 * k, -0.2, 9.81);
        s.gyr = Eigen::Vector3d(0.01, 0.02 * k, -0.03);
        w.writeImu(s);
        w.writePose(s.t, Eigen::Isometry3d(Eigen::Translation3d(k, 2, 3) *
                                           Eigen::AngleAxisd(0.1 * k, Eigen::Vector3d::UnitZ())));
      }
      w.writeRgbd(makeFrame(1000.0, 0));
      w.writeRgbd(makeFrame(1000.0 + 1.0 / 30.0, 1));
      EXPECT_EQ(w.messages(), 24u);
      w.close();
    }
    ASSERT_TRUE(fs::exists(path)) << toString(comp);
    EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator{}), 1);

    rosbag::Bag bag(path, rosbag::bagmode::Read);
    rosbag::View view(bag);
    std::map<std::string, int> count;
    std::map<std::string, std::string> types;
    for (const rosbag::MessageInstance& m : view) {
      ++count[m.getTopic()];
      types[m.getTopic()] = m.getDataType();
      if (auto img = m.instantiate<sensor_msgs::Image>()) {
        const int index = static_cast<int>(img->header.seq);
        EXPECT_EQ(img->width, 5u);
        EXPECT_EQ(img->height, 4u);
        EXPECT_DOUBLE_EQ(img->header.stamp.toSec(), m.getTime().toSec());
        EXPECT_NEAR(img->header.stamp.toSec(), 1000.0 + index / 30.0, 1e-9);
        const RgbdFrame ref = makeFrame(0.0, static_cast<std::uint64_t>(index));
        if (m.getTopic() == "/camera/color/image_raw") {
          EXPECT_EQ(img->encoding, "rgb8");
          EXPECT_EQ(img->step, 15u);
          EXPECT_EQ(img->header.frame_id, "camera_color_optical_frame");
          for (int r = 0; r < 4; ++r)
            for (int c = 0; c < 5; ++c)
              for (int ch = 0; ch < 3; ++ch)
                EXPECT_EQ(img->data[static_cast<size_t>(r * 15 + c * 3 + ch)],
                          ref.rgb.at<cv::Vec3b>(r, c)[ch]);
        } else {
          EXPECT_EQ(m.getTopic(), "/camera/aligned_depth_to_color/image_raw");
          EXPECT_EQ(img->encoding, "16UC1");
          EXPECT_EQ(img->is_bigendian, 0);
          EXPECT_EQ(img->step, 10u);
          for (int r = 0; r < 4; ++r)
            for (int c = 0; c < 5; ++c) {
              const size_t o = static_cast<size_t>(r * 10 + c * 2);
              EXPECT_EQ(img->data[o] | (img->data[o + 1] << 8), ref.depth.at<std::uint16_t>(r, c));
            }
        }
      } else if (auto imu = m.instantiate<sensor_msgs::Imu>()) {
        const int k = static_cast<int>(imu->header.seq);
        EXPECT_NEAR(imu->header.stamp.toSec(), 1000.0 + 0.005 * k, 1e-9);
        EXPECT_DOUBLE_EQ(imu->linear_acceleration.x, 0.1 * k);
        EXPECT_DOUBLE_EQ(imu->linear_acceleration.z, 9.81);
        EXPECT_DOUBLE_EQ(imu->angular_velocity.y, 0.02 * k);
        EXPECT_DOUBLE_EQ(imu->orientation_covariance[0], -1.0);
      } else if (auto pose = m.instantiate<geometry_msgs::PoseStamped>()) {
        const int k = static_cast<int>(pose->header.seq);
        EXPECT_DOUBLE_EQ(pose->pose.position.x, k);
        EXPECT_NEAR(pose->pose.orientation.z, std::sin(0.05 * k), 1e-15);
        EXPECT_NEAR(pose->pose.orientation.w, std::cos(0.05 * k), 1e-15);
        EXPECT_EQ(pose->header.frame_id, "world");
      } else {
        ADD_FAILURE() << "unexpected type " << m.getDataType();
      }
    }
    EXPECT_EQ(count["/camera/color/image_raw"], 2);
    EXPECT_EQ(count["/camera/aligned_depth_to_color/image_raw"], 2);
    EXPECT_EQ(count["/camera/imu"], 10);
    EXPECT_EQ(count["/vrpn_client_node/rgbdi/pose"], 10);
    EXPECT_EQ(types["/camera/imu"], "sensor_msgs/Imu");
    EXPECT_EQ(types["/vrpn_client_node/rgbdi/pose"], "geometry_msgs/PoseStamped");
    EXPECT_EQ(types["/camera/color/image_raw"], "sensor_msgs/Image");
    EXPECT_EQ(count.size(), 4u);  // no camera_info
  }
}

TEST(BagWriter, ConvertsDepthUnitsToMillimetres) {
  const std::string dir = test::makeTempDir("bag");
  RgbdFrame f = makeFrame(5.0, 0);
  f.depth.setTo(cv::Scalar(1234));
  f.depth_unit_m = 1e-4;  // 0.1 mm units -> 123.4 mm -> 123
  {
    BagWriter w(dir + "/d.bag", Compression::None);
    w.writeRgbd(f);
    w.close();
  }
  rosbag::Bag bag(dir + "/d.bag", rosbag::bagmode::Read);
  rosbag::View view(bag);
  int checked = 0;
  for (const rosbag::MessageInstance& m : view) {
    auto img = m.instantiate<sensor_msgs::Image>();
    if (img->encoding != "16UC1") continue;
    EXPECT_EQ(img->data[0] | (img->data[1] << 8), 123);
    ++checked;
  }
  EXPECT_EQ(checked, 1);
}

TEST(BagWriter, ErrorsNameThePathAndNothingIsLeftBehind) {
  const std::string dir = test::makeTempDir("bag");
  EXPECT_THROW(BagWriter(dir + "/missing/x.bag", Compression::None), BagError);
  {
    BagWriter w(dir + "/bad.bag", Compression::Lz4);
    RgbdFrame f = makeFrame(1.0, 0);
    f.rgb = cv::Mat(4, 5, CV_8UC1);
    try {
      w.writeRgbd(f);
      ADD_FAILURE() << "expected BagError";
    } catch (const BagError& e) {
      EXPECT_NE(std::string(e.what()).find("bad.bag frame 0"), std::string::npos) << e.what();
    }
    ImuSample s;
    s.t = -1.0;
    EXPECT_THROW(w.writeImu(s), BagError);
    // No close(): the temporary is removed.
  }
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator{}), 0);
  EXPECT_EQ(parseCompression("bz2"), Compression::Bz2);
  EXPECT_THROW(parseCompression("zip"), std::invalid_argument);
}

}  // namespace
}  // namespace rgbdi::bag
