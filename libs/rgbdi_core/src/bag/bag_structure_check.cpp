#include "bag/bag_structure_check.h"

#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <vector>

namespace rgbdi::bag::detail {
namespace {

constexpr std::uint8_t kOpFileHeader = 0x03, kOpIndexData = 0x04, kOpChunk = 0x05,
                       kOpChunkInfo = 0x06, kOpConnection = 0x07;
constexpr std::uint32_t kIndexEntryBytes = 12;     // u64 time + u32 offset
constexpr std::uint32_t kChunkInfoEntryBytes = 8;  // u32 connection + u32 count
constexpr std::uint32_t kRecordLengthBytes = 4;    // every length field of the format
const std::string kMagic = "#ROSBAG V2.0\n";

std::uint32_t u32(const std::uint8_t* p) {
  return static_cast<std::uint32_t>(p[0]) | static_cast<std::uint32_t>(p[1]) << 8 |
         static_cast<std::uint32_t>(p[2]) << 16 | static_cast<std::uint32_t>(p[3]) << 24;
}

using Fields = std::map<std::string, std::string>;

template <typename T>
bool field(const Fields& f, const std::string& name, T& out) {
  const auto it = f.find(name);
  if (it == f.end() || it->second.size() != sizeof(T)) return false;
  std::memcpy(&out, it->second.data(), sizeof(T));  // little-endian like the file
  return true;
}

struct Record {
  std::uint64_t pos = 0;
  std::uint8_t op = 0;
  Fields header;
  std::uint64_t data_pos = 0;
  std::uint32_t data_len = 0;
};

struct Chunk {
  std::uint32_t size = 0;  ///< [bytes] decompressed
  bool uncompressed = false;
  std::uint64_t data_pos = 0;
};

class StructureWalk {
 public:
  StructureWalk(const std::string& path, const BagLimits& limits) : path_(path), limits_(limits) {
    std::error_code ec;
    file_size_ = std::filesystem::file_size(path, ec);
    if (ec) throw BagError(path + ": cannot read: " + ec.message());
    in_.open(path, std::ios::binary);
    if (!in_) throw BagError(path + ": cannot open for reading");
  }

  void run() {
    std::string magic(kMagic.size(), '\0');
    read(0, magic.data(), magic.size());
    if (magic != kMagic) fail(0, "not a ROS1 bag in format 2.0 (no \"#ROSBAG V2.0\" line)");
    std::vector<Record> records;
    for (std::uint64_t pos = kMagic.size(); pos < file_size_;) {
      Record r = readRecord(pos);
      checkRecord(r, records.empty());
      pos = r.data_pos + r.data_len;
      r.header.clear();  // positions and ops are all the index check needs
      records.push_back(std::move(r));
    }
    if (records.empty()) fail(kMagic.size(), "no file header record");
    checkIndex(records);
  }

 private:
  [[noreturn]] void fail(std::uint64_t at, const std::string& what) const {
    throw BagReadError(path_ + ": byte " + std::to_string(at) + ": " + what);
  }

  void read(std::uint64_t pos, void* out, std::size_t n) {
    in_.clear();
    in_.seekg(static_cast<std::streamoff>(pos));
    in_.read(static_cast<char*>(out), static_cast<std::streamsize>(n));
    if (in_.gcount() != static_cast<std::streamsize>(n)) fail(pos, "cannot read the record");
  }

  std::uint32_t readU32(std::uint64_t pos) {
    std::uint8_t b[kRecordLengthBytes];
    read(pos, b, sizeof(b));
    return u32(b);
  }

  /// The fields (u32 length, "name=value") of a header of `len` bytes at `h`, each inside it.
  Fields headerFields(const std::uint8_t* h, std::uint32_t len, std::uint64_t pos,
                      const std::string& what) {
    Fields fields;
    for (std::uint32_t off = 0; off < len;) {
      const std::uint32_t n = len - off >= kRecordLengthBytes ? u32(h + off) : 0;
      off += kRecordLengthBytes;
      if (off > len || n > len - off) fail(pos, "corrupt " + what + " field");
      const char* s = reinterpret_cast<const char*>(h + off);
      const void* eq = std::memchr(s, '=', n);
      if (!eq) fail(pos, what + " field without '='");
      const std::size_t name_len = static_cast<std::size_t>(static_cast<const char*>(eq) - s);
      fields[std::string(s, name_len)] = std::string(s + name_len + 1, n - name_len - 1);
      off += n;
    }
    return fields;
  }

  Record readRecord(std::uint64_t pos) {
    Record r;
    r.pos = pos;
    if (file_size_ - pos < kRecordLengthBytes)
      fail(pos, "the file ends inside a record's header length");
    const std::uint32_t header_len = readU32(pos);
    if (header_len > limits_.max_record_header_bytes)
      fail(pos, "record header of " + std::to_string(header_len) + " bytes (limit " +
                    std::to_string(limits_.max_record_header_bytes) + ")");
    if (file_size_ - pos - kRecordLengthBytes < header_len + std::uint64_t{kRecordLengthBytes})
      fail(pos, "record header of " + std::to_string(header_len) +
                    " bytes runs past the end of the file (" + std::to_string(file_size_) +
                    " bytes)");
    std::vector<std::uint8_t> h(header_len + kRecordLengthBytes);
    read(pos + kRecordLengthBytes, h.data(), h.size());
    r.header = headerFields(h.data(), header_len, pos, "record header");
    if (!field(r.header, "op", r.op)) fail(pos, "record without an op field");
    r.data_len = u32(h.data() + header_len);
    r.data_pos = pos + 2ull * kRecordLengthBytes + header_len;
    if (r.data_len > file_size_ - r.data_pos)
      fail(pos, "record data of " + std::to_string(r.data_len) +
                    " bytes runs past the end of the file (" + std::to_string(file_size_) +
                    " bytes)");
    return r;
  }

  void checkRecord(const Record& r, bool first) {
    if (first != (r.op == kOpFileHeader))
      fail(r.pos,
           first ? "the first record is not the file header" : "a second file header record");
    switch (r.op) {
      case kOpFileHeader:
        if (!field(r.header, "index_pos", index_pos_) ||
            !field(r.header, "conn_count", conn_count_) ||
            !field(r.header, "chunk_count", chunk_count_))
          fail(r.pos, "file header without index_pos, conn_count or chunk_count");
        break;
      case kOpChunk:
        checkChunk(r);
        break;
      case kOpIndexData:
        checkIndexData(r);
        break;
      case kOpChunkInfo: {
        std::uint32_t count = 0;
        std::uint64_t chunk_pos = 0;
        if (!field(r.header, "count", count) || !field(r.header, "chunk_pos", chunk_pos))
          fail(r.pos, "chunk info without count or chunk_pos");
        if (r.data_len != std::uint64_t{kChunkInfoEntryBytes} * count)
          fail(r.pos, "chunk info of " + std::to_string(count) + " connections has " +
                          std::to_string(r.data_len) + " data bytes");
        chunk_info_targets_.emplace_back(r.pos, chunk_pos);
        break;
      }
      case kOpConnection: {
        // Its data is the connection header (topic, type, md5sum, definition), which rosbag
        // parses with ros::Header::parse: that copies each field by its stored length without
        // checking it against the header (fuzz_bag 2026-12-03 night: heap-buffer-overflow in
        // Bag::readConnectionRecord). Every field must lie inside the data.
        if (r.data_len > limits_.max_record_header_bytes)
          fail(r.pos, "connection header of " + std::to_string(r.data_len) + " bytes (limit " +
                          std::to_string(limits_.max_record_header_bytes) + ")");
        std::vector<std::uint8_t> data(r.data_len);
        read(r.data_pos, data.data(), data.size());
        headerFields(data.data(), static_cast<std::uint32_t>(r.data_len), r.pos,
                     "connection header");
        break;
      }
      default:
        break;  // messages: sizes checked by readRecord is all rosbag needs
    }
  }

  void checkChunk(const Record& r) {
    const auto compression = r.header.find("compression");
    Chunk c;
    if (compression == r.header.end() || !field(r.header, "size", c.size))
      fail(r.pos, "chunk without compression or size");
    const std::string& kind = compression->second;
    if (kind != "none" && kind != "bz2" && kind != "lz4")
      fail(r.pos, "chunk with unknown compression '" + kind + "'");
    if (c.size > limits_.max_chunk_bytes || r.data_len > limits_.max_chunk_bytes)
      fail(r.pos, "chunk of " + std::to_string(c.size) + " bytes (" + std::to_string(r.data_len) +
                      " stored; limit " + std::to_string(limits_.max_chunk_bytes) + ")");
    c.uncompressed = kind == "none";
    if (c.uncompressed && c.size != r.data_len)
      fail(r.pos, "uncompressed chunk says " + std::to_string(c.size) + " bytes but stores " +
                      std::to_string(r.data_len));
    c.data_pos = r.data_pos;
    chunks_[r.pos] = c;
    last_chunk_ = &chunks_[r.pos];
  }

  void checkIndexData(const Record& r) {
    std::uint32_t count = 0;
    if (!field(r.header, "count", count)) fail(r.pos, "index data without count");
    if (r.data_len != std::uint64_t{kIndexEntryBytes} * count)
      fail(r.pos, "index data of " + std::to_string(count) + " entries has " +
                      std::to_string(r.data_len) + " data bytes");
    if (!last_chunk_) fail(r.pos, "index data before any chunk");
    const Chunk& c = *last_chunk_;
    std::vector<std::uint8_t> data(r.data_len);
    read(r.data_pos, data.data(), data.size());
    for (std::uint32_t i = 0; i < count; ++i) {
      const std::uint64_t offset = u32(data.data() + i * kIndexEntryBytes + 8);
      const std::string entry = "index entry " + std::to_string(i) + " (offset " +
                                std::to_string(offset) + " in a chunk of " +
                                std::to_string(c.size) + " bytes)";
      if (offset + 2 * kRecordLengthBytes > c.size) fail(r.pos, entry + " is outside its chunk");
      if (!c.uncompressed) continue;  // its records are known only after decompression
      const std::uint64_t header_len = readU32(c.data_pos + offset);
      const std::uint64_t data_at = offset + kRecordLengthBytes + header_len;
      if (data_at + kRecordLengthBytes > c.size)
        fail(r.pos, entry + ": its message record's header overruns the chunk");
      const std::uint64_t data_len = readU32(c.data_pos + data_at);
      if (data_at + kRecordLengthBytes + data_len > c.size)
        fail(r.pos, entry + ": its message record overruns the chunk");
    }
  }

  /// What rosbag reads at open: conn_count connection records at index_pos, then chunk_count
  /// chunk infos, each pointing at a chunk.
  void checkIndex(const std::vector<Record>& records) {
    const std::uint64_t header_pos = records.front().pos;
    if (index_pos_ == 0) fail(header_pos, "the bag was never indexed (index_pos 0)");
    std::size_t i = 0;
    while (i < records.size() && records[i].pos != index_pos_) ++i;
    if (i == records.size())
      fail(header_pos, "index_pos " + std::to_string(index_pos_) + " is not the start of a record");
    for (std::uint64_t k = 0; k < conn_count_; ++k, ++i)
      if (i == records.size() || records[i].op != kOpConnection)
        fail(i == records.size() ? file_size_ : records[i].pos,
             "the index holds fewer than the file header's " + std::to_string(conn_count_) +
                 " connection records");
    for (std::uint64_t k = 0; k < chunk_count_; ++k, ++i)
      if (i == records.size() || records[i].op != kOpChunkInfo)
        fail(i == records.size() ? file_size_ : records[i].pos,
             "the index holds fewer than the file header's " + std::to_string(chunk_count_) +
                 " chunk info records");
    for (const auto& [info_pos, chunk_pos] : chunk_info_targets_)
      if (!chunks_.count(chunk_pos))
        fail(info_pos, "chunk info points at byte " + std::to_string(chunk_pos) +
                           ", which is no chunk record");
  }

  std::string path_;
  BagLimits limits_;
  std::ifstream in_;
  std::uint64_t file_size_ = 0, index_pos_ = 0;
  std::uint32_t conn_count_ = 0, chunk_count_ = 0;
  std::map<std::uint64_t, Chunk> chunks_;
  const Chunk* last_chunk_ = nullptr;
  std::vector<std::pair<std::uint64_t, std::uint64_t>> chunk_info_targets_;  // info, chunk pos
};

}  // namespace

void checkBagStructure(const std::string& path, const BagLimits& limits) {
  StructureWalk(path, limits).run();
}

}  // namespace rgbdi::bag::detail
