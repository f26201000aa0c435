// Sequential reader of the records of a ROS1 2.0 bag, in file order, without its index: what
// BagReader falls back to when rosbag cannot read the index (truncated or unindexed bags).
//
// Layout (ROS bag format 2.0): the line "#ROSBAG V2.0\n", then records of
//   uint32 header_len, header = fields (uint32 len, "name=value"), uint32 data_len, data.
// Chunk records (op 0x05) hold compressed connection (0x07) and message data (0x02) records;
// index data (0x04), chunk info (0x06) and repeated connection records follow the chunks.
#pragma once

#include <cstdint>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "rgbdi/bag/bag_reader.h"

namespace rgbdi::bag::detail {

struct ScannedConnection {
  std::uint32_t id = 0;
  std::string topic, datatype, md5sum;
};

class BagChunkScanner {
 public:
  struct Message {
    std::uint32_t connection = 0;
    double time = 0.0;
    const std::uint8_t* data = nullptr;
    std::uint32_t size = 0;
    std::uint64_t position = 0;  ///< file offset of the chunk (or record) holding the message
  };

  /// Opens the file and checks the format line; throws BagError otherwise. Record headers and
  /// chunks above `limits` are damage (BagReadError), not allocations.
  explicit BagChunkScanner(const std::string& path, const BagLimits& limits = {});

  /// Next message record (connection records are registered on the way). False at the end of
  /// the file; throws BagReadError naming the file and byte offset at damage, once.
  bool next(Message& out);

  const std::map<std::uint32_t, ScannedConnection>& connections() const { return connections_; }
  std::uint64_t position() const { return pos_; }
  std::uint64_t fileSize() const { return file_size_; }
  /// index_pos of the file header record (0 until read or when the bag was never indexed).
  std::uint64_t indexPosition() const { return index_pos_; }

 private:
  using Fields = std::map<std::string, std::string>;
  bool readTopLevelRecord();
  bool nextInChunk(Message& out);
  void registerConnection(const Fields& header, const std::uint8_t* data, std::uint32_t size,
                          const std::string& where);
  Fields parseFields(const std::uint8_t* p, std::uint32_t size, const std::string& where) const;
  [[noreturn]] void fail(const std::string& what);

  std::string path_;
  BagLimits limits_;
  std::ifstream in_;
  std::uint64_t file_size_ = 0, pos_ = 0, index_pos_ = 0;
  std::map<std::uint32_t, ScannedConnection> connections_;
  // Current chunk: decompressed bytes, read offset, file offset, and the error to raise once its
  // complete records are used up (a chunk cut by the end of the file).
  std::vector<std::uint8_t> chunk_, raw_;
  std::size_t chunk_off_ = 0;
  std::uint64_t chunk_pos_ = 0;
  bool in_chunk_ = false;
  std::string pending_error_;
  bool done_ = false;
};

}  // namespace rgbdi::bag::detail
