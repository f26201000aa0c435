// Damaged bags: truncated copies (the index at the end is lost) are read by scanning their chunks,
// every message before the damage is delivered and the error names the file and the byte offset;
// a corrupt chunk in an indexed bag ends the stream with the position; not-a-bag files are refused.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>

#include "rgbdi/bag/bag_converter.h"
#include "rgbdi/bag/bag_reader.h"
#include "rgbdi/bag/bag_writer.h"
#include "testing/fixtures.h"

namespace rgbdi::bag {
namespace {

namespace fs = std::filesystem;

struct CountingSink : ConversionSink {
  std::vector<double> frame_t, imu_t;
  void imu(const ImuSample& s) override { imu_t.push_back(s.t); }
  void accelerometer(double, const Eigen::Vector3d&) override {}
  void frame(const RgbdFrame& f) override { frame_t.push_back(f.t); }
  void groundTruth(const StampedPose&) override {}
};

/// 2 s at 200 Hz IMU and 20 Hz frames of 160x120 noise (96 kB per frame pair: about five chunks of
/// rosbag's 768 kB).
std::string writeBag(const std::string& path, Compression comp) {
  BagWriter w(path, comp);
  cv::theRNG().state = 3;
  for (int k = 0; k < 400; ++k) {
    ImuSample s;
    s.t = 300.0 + 0.005 * k;
    s.acc = Eigen::Vector3d(0, 0, 9.81);
    w.writeImu(s);
    if (k % 10 == 0) {
      RgbdFrame f;
      f.t = s.t;
      f.rgb = cv::Mat(120, 160, CV_8UC3);
      f.depth = cv::Mat(120, 160, CV_16UC1);
      cv::randu(f.rgb, 0, 256);
      cv::randu(f.depth, 0, 5000);
      w.writeRgbd(f);
    }
  }
  w.close();
  return path;
}

FallbackCalibration camera160() {
  FallbackCalibration cal = FallbackCalibration::defaults();
  cal.color.width = 160;
  cal.color.height = 120;
  cal.color.fx = cal.color.fy = 120;
  cal.color.cx = 80;
  cal.color.cy = 60;
  return cal;
}

std::size_t countMessages(BagReader& r) {
  BagMessage m;
  std::size_t n = 0;
  while (r.next(m)) ++n;
  return n;
}

TEST(BagConvertDamage, TruncatedCopiesKeepEverythingBeforeTheCut) {
  for (Compression comp : {Compression::None, Compression::Bz2, Compression::Lz4}) {
    SCOPED_TRACE(toString(comp));
    const std::string dir = test::makeTempDir("bag_damage");
    const std::string full = writeBag(dir + "/full.bag", comp);
    std::size_t full_frames = 0, full_imu = 0;
    {
      BagConverter conv(full, ConvertOptions(), BagInputOptions(), camera160());
      CountingSink sink;
      ASSERT_TRUE(conv.run(sink).ok());
      full_frames = sink.frame_t.size();
      full_imu = sink.imu_t.size();
      ASSERT_EQ(full_frames, 40u);
      ASSERT_EQ(full_imu, 400u);
    }
    const auto size = fs::file_size(full);
    std::size_t previous_frames = 0;
    for (double keep : {0.3, 0.6, 0.9}) {
      const std::string cut = dir + "/cut.bag";
      fs::copy_file(full, cut, fs::copy_options::overwrite_existing);
      fs::resize_file(cut, static_cast<std::uintmax_t>(static_cast<double>(size) * keep));
      BagReader reader(cut);
      EXPECT_FALSE(reader.indexed());
      EXPECT_NE(reader.recoveryReason().find("the file is truncated"), std::string::npos)
          << reader.recoveryReason();
      EXPECT_NE(reader.damage().find(cut + ": truncated: the file ends inside the chunk at byte "),
                std::string::npos)
          << reader.damage();

      BagConverter conv(cut, ConvertOptions(), BagInputOptions(), camera160());
      CountingSink sink;
      const ConversionReport r = conv.run(sink);
      EXPECT_FALSE(r.ok());
      EXPECT_NE(r.error.find(cut + ": truncated: the file ends inside the chunk at byte "),
                std::string::npos)
          << r.error;
      // What was delivered is a prefix of the full stream, growing with what was kept.
      EXPECT_GT(sink.frame_t.size(), previous_frames);
      EXPECT_LT(sink.frame_t.size(), full_frames);
      for (std::size_t i = 0; i < sink.frame_t.size(); ++i)
        EXPECT_NEAR(sink.frame_t[i], 300.0 + 0.05 * i, 1e-9);
      for (std::size_t i = 0; i < sink.imu_t.size(); ++i)
        EXPECT_NEAR(sink.imu_t[i], 300.0 + 0.005 * i, 1e-9);
      // Roughly the kept share of the data (chunks are whole; an uncompressed cut chunk keeps its
      // complete records).
      EXPECT_NEAR(static_cast<double>(sink.frame_t.size()) / full_frames, keep, 0.25);
      previous_frames = sink.frame_t.size();
    }
  }
}

TEST(BagConvertDamage, CutAtTheIndexKeepsAllMessages) {
  const std::string dir = test::makeTempDir("bag_damage");
  const std::string full = writeBag(dir + "/full.bag", Compression::Lz4);
  // Find where the index starts: the file header record holds index_pos (little-endian uint64).
  std::ifstream in(full, std::ios::binary);
  std::string head(4096 + 13, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  const auto field = head.find("index_pos=");
  ASSERT_NE(field, std::string::npos);
  std::uint64_t index_pos = 0;
  std::memcpy(&index_pos, head.data() + field + 10, 8);
  const std::string cut = dir + "/noindex.bag";
  fs::copy_file(full, cut);
  fs::resize_file(cut, index_pos);
  BagReader reader(cut);
  EXPECT_FALSE(reader.indexed());
  EXPECT_TRUE(reader.damage().empty()) << reader.damage();
  EXPECT_EQ(countMessages(reader), 480u);
  ASSERT_EQ(reader.topics().size(), 3u);
  BagConverter conv(cut, ConvertOptions(), BagInputOptions(), camera160());
  CountingSink sink;
  const ConversionReport r = conv.run(sink);
  EXPECT_EQ(sink.frame_t.size(), 40u);
  EXPECT_EQ(sink.imu_t.size(), 400u);
  EXPECT_NE(r.error.find("every chunk up to the end of the file was read"), std::string::npos)
      << r.error;
}

TEST(BagConvertDamage, CorruptCompressedChunkInAnIndexedBag) {
  const std::string dir = test::makeTempDir("bag_damage");
  const std::string path = writeBag(dir + "/bad.bag", Compression::Bz2);
  {
    // Overwrite bytes in the middle of the file (inside a bz2 chunk); the index stays intact.
    std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(static_cast<std::streamoff>(fs::file_size(path) / 2));
    const std::string junk(64, '\x55');
    f.write(junk.data(), static_cast<std::streamsize>(junk.size()));
  }
  BagReader reader(path);
  ASSERT_TRUE(reader.indexed());
  BagMessage m;
  std::size_t n = 0;
  try {
    while (reader.next(m)) ++n;
    FAIL() << "expected BagReadError";
  } catch (const BagReadError& e) {
    const std::string w = e.what();
    EXPECT_NE(w.find(path + ": cannot read message " + std::to_string(n) + " (topic /camera/"),
              std::string::npos)
        << w;
    EXPECT_NE(w.find("the bag is damaged from here on"), std::string::npos) << w;
  }
  EXPECT_GT(n, 100u);
  EXPECT_LT(n, 480u);
  EXPECT_FALSE(reader.next(m));  // once

  BagConverter conv(path, ConvertOptions(), BagInputOptions(), camera160());
  CountingSink sink;
  const ConversionReport r = conv.run(sink);
  EXPECT_FALSE(r.ok());
  EXPECT_FALSE(sink.imu_t.empty());
  EXPECT_LT(sink.imu_t.size(), 400u);
}

TEST(BagConvertDamage, NotABag) {
  const std::string dir = test::makeTempDir("bag_damage");
  std::ofstream(dir + "/x.bag") << "#ROSBAG V2.0\nnonsense";
  std::ofstream(dir + "/y.bag") << "hello";
  EXPECT_THROW(BagReader(dir + "/none.bag"), BagError);
  try {
    BagReader r(dir + "/y.bag");
    FAIL();
  } catch (const BagError& e) {
    EXPECT_NE(std::string(e.what()).find(dir + "/y.bag: cannot open as a ROS1 bag"),
              std::string::npos)
        << e.what();
  }
  // The magic line is there but nothing readable follows: recovery finds the damage at once.
  BagReader r(dir + "/x.bag");
  EXPECT_FALSE(r.indexed());
  EXPECT_TRUE(r.topics().empty());
  EXPECT_FALSE(r.damage().empty());
}

}  // namespace
}  // namespace rgbdi::bag
