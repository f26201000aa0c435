// Damage that the readers must refuse cheaply (fuzz findings 2 and 3 of doc/robustness.md):
// a corrupt pixel length in a ROS image message is refused before anything is allocated, and a
// bag whose record sizes are corrupt is never handed to rosbag (which aborts on them): it is read
// in recovery mode, with the file and byte offset named.
#include <gtest/gtest.h>
#include <ros/serialization.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>

#include "rgbdi/bag/bag_reader.h"
#include "rgbdi/bag/bag_writer.h"
#include "rgbdi/bag/ros_image.h"
#include "rgbdi/bag/ros_wire.h"
#include "testing/fixtures.h"

using namespace rgbdi;
using namespace rgbdi::bag;

namespace {

std::vector<std::uint8_t> serialized(const sensor_msgs::Image& m) {
  std::vector<std::uint8_t> b(ros::serialization::serializationLength(m));
  ros::serialization::OStream s(b.data(), static_cast<std::uint32_t>(b.size()));
  ros::serialization::serialize(s, m);
  return b;
}

sensor_msgs::Image smallImage() {
  sensor_msgs::Image m;
  m.header.frame_id = "cam";
  m.height = 2;
  m.width = 3;
  m.encoding = "mono8";
  m.step = 3;
  m.data = {1, 2, 3, 4, 5, 6};
  return m;
}

void putU32(std::vector<std::uint8_t>& b, std::size_t at, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) b[at + i] = static_cast<std::uint8_t>(v >> (8 * i));
}
std::uint32_t getU32(const std::vector<std::uint8_t>& b, std::size_t at) {
  std::uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = v << 8 | b[at + i];
  return v;
}

std::string writeBag(const std::string& dir, Compression c) {
  const std::string path = dir + "/b" + toString(c) + ".bag";
  BagWriter w(path, c);
  for (int i = 0; i < 6; ++i) {
    ImuSample s;
    s.t = 100.0 + 0.005 * i;
    s.acc = Eigen::Vector3d(0.1, 0.0, 9.8);
    w.writeImu(s);
  }
  RgbdFrame f;
  f.t = 100.01;
  f.rgb = cv::Mat(4, 6, CV_8UC3, cv::Scalar(20, 40, 60));
  f.depth = cv::Mat(4, 6, CV_16UC1, cv::Scalar(1200));
  f.depth_unit_m = 1e-3;
  f.cam_color.width = f.cam_depth.width = 6;
  f.cam_color.height = f.cam_depth.height = 4;
  f.cam_color.fx = f.cam_color.fy = f.cam_depth.fx = f.cam_depth.fy = 10.0;
  f.depth_aligned_to_color = true;
  w.writeRgbd(f);
  w.close();
  return path;
}

/// Top-level records of a bag: position, op and where each header field's value starts.
struct RecordAt {
  std::size_t pos = 0;
  std::uint8_t op = 0;
  std::map<std::string, std::size_t> value_at;
};
std::vector<RecordAt> records(const std::vector<std::uint8_t>& b) {
  std::vector<RecordAt> out;
  for (std::size_t pos = 13; pos + 8 <= b.size();) {
    RecordAt r;
    r.pos = pos;
    const std::uint32_t hl = getU32(b, pos);
    for (std::size_t off = pos + 4; off < pos + 4 + hl;) {
      const std::uint32_t len = getU32(b, off);
      const char* s = reinterpret_cast<const char*>(&b[off + 4]);
      const std::size_t eq = static_cast<const char*>(std::memchr(s, '=', len)) - s;
      r.value_at[std::string(s, eq)] = off + 4 + eq + 1;
      off += 4 + len;
    }
    r.op = b[r.value_at.at("op")];
    out.push_back(r);
    pos += 8 + hl + getU32(b, pos + 4 + hl);
  }
  return out;
}

std::vector<std::uint8_t> readBytes(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), {}};
}
void writeBytes(const std::string& path, const std::vector<std::uint8_t>& b) {
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(b.data()), b.size());
}

std::size_t countMessages(BagReader& r) {
  BagMessage m;
  std::size_t n = 0;
  while (r.next(m)) ++n;
  return n;
}

}  // namespace

/// A bag written by writeBag, its messages counted by an indexed read, its bytes and records
/// for patching, and its index_pos.
struct BagToDamage {
  std::string path;
  std::size_t messages = 0;
  std::vector<std::uint8_t> bytes;
  std::vector<RecordAt> records;
  std::uint64_t index_pos = 0;
};
BagToDamage bagToDamage(const std::string& name, Compression c) {
  BagToDamage d;
  d.path = writeBag(test::makeTempDir(name), c);
  BagReader clean(d.path);
  EXPECT_TRUE(clean.indexed());
  d.messages = countMessages(clean);
  d.bytes = readBytes(d.path);
  d.records = records(d.bytes);
  std::memcpy(&d.index_pos, &d.bytes[d.records.front().value_at.at("index_pos")], 8);
  return d;
}

TEST(RosWire, ACleanImageMessageDeserialisesAsRos) {
  const auto bytes = serialized(smallImage());
  sensor_msgs::Image m;
  deserializeImage(bytes.data(), static_cast<std::uint32_t>(bytes.size()), m, "msg 1");
  EXPECT_EQ(m.encoding, "mono8");
  EXPECT_EQ(m.header.frame_id, "cam");
  EXPECT_EQ(m.data, smallImage().data);
}

TEST(RosWire, ACorruptPixelLengthIsRefusedBeforeAnythingIsAllocated) {
  auto bytes = serialized(smallImage());
  const std::size_t data_len_at = bytes.size() - 6 - 4;  // u32 length before the 6 pixels
  ASSERT_EQ(getU32(bytes, data_len_at), 6u);
  putU32(bytes, data_len_at, 0xfffffff0u);  // ROS alone would zero-fill 4 GiB first
  sensor_msgs::Image m;
  try {
    deserializeImage(bytes.data(), static_cast<std::uint32_t>(bytes.size()), m, "x.bag msg 7");
    FAIL() << "accepted";
  } catch (const ImageDecodeError& e) {
    EXPECT_STREQ(e.what(), ("x.bag msg 7: corrupt message: data needs 4294967280 bytes at offset " +
                            std::to_string(data_len_at + 4) + ", the message has 6 left (of " +
                            std::to_string(bytes.size()) + ")")
                               .c_str());
  }
  EXPECT_TRUE(m.data.empty());
}

TEST(RosWire, ACorruptStringLengthOrATruncatedMessageIsRefused) {
  auto bytes = serialized(smallImage());
  putU32(bytes, 12, 1000);  // header.frame_id length
  sensor_msgs::Image m;
  EXPECT_THROW(deserializeImage(bytes.data(), static_cast<std::uint32_t>(bytes.size()), m, "m"),
               ImageDecodeError);
  const auto clean = serialized(smallImage());
  for (std::uint32_t n = 0; n < clean.size(); ++n)
    EXPECT_THROW(deserializeImage(clean.data(), n, m, "m"), ImageDecodeError) << n;
  sensor_msgs::CompressedImage c;
  c.format = "png";
  c.data = {1, 2, 3};
  std::vector<std::uint8_t> cb(ros::serialization::serializationLength(c));
  ros::serialization::OStream s(cb.data(), static_cast<std::uint32_t>(cb.size()));
  ros::serialization::serialize(s, c);
  putU32(cb, cb.size() - 3 - 4, 0x7fffffffu);
  try {
    deserializeImage(cb.data(), static_cast<std::uint32_t>(cb.size()), c, "c");
    FAIL() << "accepted";
  } catch (const ImageDecodeError& e) {
    EXPECT_NE(std::string(e.what()).find("data needs 2147483647 bytes"), std::string::npos)
        << e.what();
  }
}

TEST(BagStructureCheck, ACorruptRecordHeaderInTheIndexIsReadInRecoveryModeWithItsOffset) {
  BagToDamage d = bagToDamage("bag_check_index", Compression::Bz2);
  const std::string& path = d.path;
  const std::size_t messages = d.messages, index_pos = d.index_pos;
  auto& b = d.bytes;
  // Fuzz finding 3 (replay input 158): a burst over the index section; rosbag reallocated by
  // the header length of the record at index_pos and aborted.
  putU32(b, index_pos, 0xf0000000u);
  writeBytes(path, b);
  BagReader r(path);
  EXPECT_FALSE(r.indexed());
  EXPECT_NE(r.recoveryReason().find(path + ": byte " + std::to_string(index_pos) +
                                    ": record header of 4026531840 bytes (limit 1048576)"),
            std::string::npos)
      << r.recoveryReason();
  // Every message of the chunks before the damage, then the damage itself, once.
  BagMessage m;
  std::size_t n = 0;
  try {
    while (r.next(m)) ++n;
    FAIL() << "the damaged index was not reported";
  } catch (const BagReadError& e) {
    EXPECT_NE(std::string(e.what()).find("corrupt record at byte " + std::to_string(index_pos)),
              std::string::npos)
        << e.what();
  }
  EXPECT_EQ(n, messages);
  EXPECT_FALSE(r.next(m));
}

// Fuzz finding of 2026-12-03 night (fuzz_bag, heap-buffer-overflow in ros::Header::parse from
// Bag::readConnectionRecord): a connection record's data is the connection header, whose field
// lengths rosbag copies unchecked. A field length beyond it sends the bag to recovery mode.
TEST(BagStructureCheck, AConnectionHeaderFieldBeyondItsHeaderIsCaughtBeforeRosbagReadsIt) {
  BagToDamage d = bagToDamage("bag_check_connection", Compression::None);
  const std::string& path = d.path;
  const std::size_t messages = d.messages, index_pos = d.index_pos;
  auto& b = d.bytes;
  const auto& recs = d.records;
  const auto connection = std::find_if(recs.begin(), recs.end(), [&](const RecordAt& r) {
    return r.op == 0x07 && r.pos >= index_pos;
  });
  ASSERT_NE(connection, recs.end());
  const std::size_t data_at = connection->pos + 4 + getU32(b, connection->pos) + 4;
  putU32(b, data_at, 0x7fffu);  // the first field of the connection header: 32 KB
  writeBytes(path, b);
  BagReader r(path);
  EXPECT_FALSE(r.indexed());
  EXPECT_NE(r.recoveryReason().find(path + ": byte " + std::to_string(connection->pos) +
                                    ": corrupt connection header field"),
            std::string::npos)
      << r.recoveryReason();
  EXPECT_EQ(countMessages(r), messages);  // recovery mode finds the connections in the chunks
}

TEST(BagStructureCheck, AChunkSizeAboveTheLimitIsABagErrorNamingFileAndOffset) {
  const std::string dir = test::makeTempDir("bag_check_chunk");
  for (const Compression c : {Compression::None, Compression::Bz2, Compression::Lz4}) {
    const std::string path = writeBag(dir, c);
    auto b = readBytes(path);
    std::size_t chunk_pos = 0, size_at = 0;
    for (const RecordAt& r : records(b))
      if (r.op == 0x05) {
        chunk_pos = r.pos;
        size_at = r.value_at.at("size");
        break;
      }
    ASSERT_GT(size_at, 0u);
    putU32(b, size_at, 0xfffffff0u);
    writeBytes(path, b);
    BagReader r(path);
    EXPECT_FALSE(r.indexed()) << toString(c);
    EXPECT_NE(r.recoveryReason().find("byte " + std::to_string(chunk_pos) + ": chunk of " +
                                      "4294967280 bytes"),
              std::string::npos)
        << r.recoveryReason();
    // Recovery stops at the same chunk with a BagReadError, not an allocation of 4 GiB.
    BagMessage m;
    try {
      while (r.next(m)) {
      }
      FAIL() << "no damage reported for " << toString(c);
    } catch (const BagReadError& e) {
      EXPECT_NE(std::string(e.what()).find(path + ": corrupt chunk record at byte " +
                                           std::to_string(chunk_pos)),
                std::string::npos)
          << e.what();
    }
  }
}

TEST(BagStructureCheck, AnIndexEntryOutsideItsChunkIsCaughtBeforeRosbagReadsIt) {
  const std::string dir = test::makeTempDir("bag_check_entry");
  const std::string path = writeBag(dir, Compression::None);
  auto b = readBytes(path);
  std::size_t index_data = 0;
  for (const RecordAt& r : records(b))
    if (r.op == 0x04) {
      index_data = r.pos;
      break;
    }
  ASSERT_GT(index_data, 0u);
  // Data of the index record: entries of u64 time + u32 offset; corrupt the first offset.
  const std::uint32_t hl = getU32(b, index_data);
  putU32(b, index_data + 8 + hl + 8, 0x00ffffffu);
  writeBytes(path, b);
  BagReader r(path);
  EXPECT_FALSE(r.indexed());
  EXPECT_NE(r.recoveryReason().find("byte " + std::to_string(index_data) +
                                    ": index entry 0 (offset 16777215"),
            std::string::npos)
      << r.recoveryReason();
  EXPECT_GT(countMessages(r), 0u);  // the chunk itself is intact
}
