#include "bag/bag_chunk_scanner.h"

#include <rosbag/chunked_file.h>
#include <rosbag/exceptions.h>

#include <cstring>
#include <filesystem>

#include "rgbdi/bag/bag_reader.h"

namespace rgbdi::bag::detail {
namespace {

constexpr std::uint8_t kOpMessageData = 0x02, kOpFileHeader = 0x03, kOpChunk = 0x05,
                       kOpConnection = 0x07;
const std::string kMagic = "#ROSBAG V2.0\n";

std::uint32_t u32(const std::uint8_t* p) {
  return static_cast<std::uint32_t>(p[0]) | static_cast<std::uint32_t>(p[1]) << 8 |
         static_cast<std::uint32_t>(p[2]) << 16 | static_cast<std::uint32_t>(p[3]) << 24;
}

template <typename T>
bool field(const std::map<std::string, std::string>& f, const std::string& name, T& out) {
  const auto it = f.find(name);
  if (it == f.end() || it->second.size() != sizeof(T)) return false;
  std::memcpy(&out, it->second.data(), sizeof(T));  // little-endian like the file
  return true;
}

}  // namespace

BagChunkScanner::BagChunkScanner(const std::string& path, const BagLimits& limits)
    : path_(path), limits_(limits) {
  std::error_code ec;
  file_size_ = std::filesystem::file_size(path, ec);
  if (ec) throw BagError(path + ": cannot read: " + ec.message());
  in_.open(path, std::ios::binary);
  if (!in_) throw BagError(path + ": cannot open for reading");
  std::string magic(kMagic.size(), '\0');
  in_.read(magic.data(), static_cast<std::streamsize>(magic.size()));
  if (in_.gcount() != static_cast<std::streamsize>(magic.size()) || magic != kMagic)
    throw BagError(path + ": not a ROS1 bag in format 2.0 (no \"#ROSBAG V2.0\" line)");
  pos_ = kMagic.size();
}

void BagChunkScanner::fail(const std::string& what) {
  done_ = true;
  in_chunk_ = false;
  throw BagReadError(path_ + ": " + what);
}

BagChunkScanner::Fields BagChunkScanner::parseFields(const std::uint8_t* p, std::uint32_t size,
                                                     const std::string& where) const {
  Fields f;
  std::uint32_t off = 0;
  while (off < size) {
    if (size - off < 4) throw BagReadError(path_ + ": corrupt record header " + where);
    const std::uint32_t len = u32(p + off);
    off += 4;
    if (len > size - off) throw BagReadError(path_ + ": corrupt record header " + where);
    const char* s = reinterpret_cast<const char*>(p + off);
    const void* eq = std::memchr(s, '=', len);
    if (!eq) throw BagReadError(path_ + ": corrupt record header field " + where);
    const std::size_t name_len = static_cast<std::size_t>(static_cast<const char*>(eq) - s);
    f[std::string(s, name_len)] = std::string(s + name_len + 1, len - name_len - 1);
    off += len;
  }
  return f;
}

void BagChunkScanner::registerConnection(const Fields& header, const std::uint8_t* data,
                                         std::uint32_t size, const std::string& where) {
  ScannedConnection c;
  if (!field(header, "conn", c.id))
    throw BagReadError(path_ + ": connection record without id " + where);
  const Fields def = parseFields(data, size, where);
  const auto get = [&](const char* k) {
    const auto it = def.find(k);
    return it == def.end() ? std::string() : it->second;
  };
  const auto topic = header.find("topic");
  c.topic = topic != header.end() ? topic->second : get("topic");
  c.datatype = get("type");
  c.md5sum = get("md5sum");
  connections_.emplace(c.id, c);
}

bool BagChunkScanner::nextInChunk(Message& out) {
  while (chunk_off_ < chunk_.size()) {
    const std::string where = "in the chunk at byte " + std::to_string(chunk_pos_) +
                              " (record at offset " + std::to_string(chunk_off_) + ")";
    const std::size_t left = chunk_.size() - chunk_off_;
    const std::uint8_t* p = chunk_.data() + chunk_off_;
    std::uint32_t header_len = 0, data_len = 0;
    bool complete = left >= 4;
    if (complete) {
      header_len = u32(p);
      complete = header_len <= limits_.max_record_header_bytes && left - 4 >= header_len + 4ull;
    }
    if (complete) {
      data_len = u32(p + 4 + header_len);
      complete = left - 8 - header_len >= data_len;
    }
    if (!complete) {
      if (!pending_error_.empty()) break;  // the cut chunk: its complete records are used up
      fail("corrupt chunk: record " + where + " overruns the chunk");
    }
    const Fields header = parseFields(p + 4, header_len, where);
    const std::uint8_t* data = p + 8 + header_len;
    chunk_off_ += 8ull + header_len + data_len;
    std::uint8_t op = 0;
    if (!field(header, "op", op)) fail("corrupt chunk: record without op " + where);
    if (op == kOpConnection) {
      registerConnection(header, data, data_len, where);
    } else if (op == kOpMessageData) {
      std::uint32_t conn = 0;
      std::uint64_t stamp = 0;
      if (!field(header, "conn", conn) || !field(header, "time", stamp))
        fail("corrupt message record " + where);
      if (!connections_.count(conn))
        fail("message record " + where + " uses connection " + std::to_string(conn) +
             " that was never defined");
      out.connection = conn;
      out.time = static_cast<double>(stamp & 0xffffffffu) + 1e-9 * static_cast<double>(stamp >> 32);
      out.data = data;
      out.size = data_len;
      out.position = chunk_pos_;
      return true;
    }
  }
  in_chunk_ = false;
  if (!pending_error_.empty()) {
    const std::string e = pending_error_;
    pending_error_.clear();
    fail(e);
  }
  return false;
}

bool BagChunkScanner::readTopLevelRecord() {
  const std::uint64_t record_pos = pos_;
  const std::uint64_t left = file_size_ - pos_;
  const std::string where = "at byte " + std::to_string(record_pos);
  if (left < 4) fail("truncated: the file ends inside the record header " + where);
  std::uint8_t len_bytes[4];
  in_.read(reinterpret_cast<char*>(len_bytes), 4);
  const std::uint32_t header_len = u32(len_bytes);
  if (header_len > limits_.max_record_header_bytes)
    fail("corrupt record " + where + " (header length " + std::to_string(header_len) + ")");
  if (left < 8ull + header_len) fail("truncated: the file ends inside the record header " + where);
  std::vector<std::uint8_t> header_bytes(header_len + 4);
  in_.read(reinterpret_cast<char*>(header_bytes.data()), header_len + 4);
  if (!in_) fail("cannot read the record " + where);
  const Fields header = parseFields(header_bytes.data(), header_len, where);
  const std::uint32_t data_len = u32(header_bytes.data() + header_len);
  const std::uint64_t data_pos = record_pos + 8 + header_len;
  const std::uint64_t present = std::min<std::uint64_t>(data_len, file_size_ - data_pos);
  pos_ = data_pos + present;
  std::uint8_t op = 0;
  if (!field(header, "op", op)) fail("corrupt record " + where + " (no op field)");

  if (op == kOpChunk) {
    std::string compression = "none";
    if (header.count("compression")) compression = header.at("compression");
    std::uint32_t size = 0;
    if (!field(header, "size", size)) fail("corrupt chunk record " + where + " (no size field)");
    if (size > limits_.max_chunk_bytes || data_len > limits_.max_chunk_bytes)
      fail("corrupt chunk record " + where + " (" + std::to_string(size) + " bytes, " +
           std::to_string(data_len) + " stored; limit " + std::to_string(limits_.max_chunk_bytes) +
           ")");
    raw_.resize(present);
    in_.read(reinterpret_cast<char*>(raw_.data()), static_cast<std::streamsize>(present));
    if (!in_) fail("cannot read the chunk " + where);
    chunk_pos_ = record_pos;
    chunk_off_ = 0;
    if (present < data_len) {
      const std::string cut = "truncated: the file ends inside the chunk " + where + " (" +
                              std::to_string(present) + " of " + std::to_string(data_len) +
                              " bytes present)";
      if (compression != "none")
        fail(cut + "; its " + compression + "-compressed messages are lost");
      // An uncompressed chunk still holds its complete records: deliver those first.
      pending_error_ = cut;
      chunk_.swap(raw_);
      in_chunk_ = true;
      return true;
    }
    if (compression == "none") {
      chunk_.swap(raw_);
    } else if (compression == "bz2" || compression == "lz4") {
      chunk_.resize(size);
      try {
        rosbag::ChunkedFile decompressor;
        decompressor.decompress(
            compression == "bz2" ? rosbag::compression::BZ2 : rosbag::compression::LZ4,
            chunk_.data(), size, raw_.data(), data_len);
      } catch (const std::exception& e) {
        fail("corrupt " + compression + " chunk " + where + ": " + e.what());
      }
    } else {
      fail("chunk " + where + " uses unknown compression '" + compression + "'");
    }
    in_chunk_ = true;
    return true;
  }
  if (present < data_len) fail("truncated: the file ends inside the record " + where);
  if (op == kOpFileHeader) {
    field(header, "index_pos", index_pos_);
  } else if (op == kOpConnection) {
    std::vector<std::uint8_t> data(data_len);
    in_.read(reinterpret_cast<char*>(data.data()), data_len);
    if (!in_) fail("cannot read the connection record " + where);
    std::uint32_t id = 0;
    if (field(header, "conn", id) && !connections_.count(id))
      registerConnection(header, data.data(), data_len, where);
    return true;
  }
  in_.seekg(static_cast<std::streamoff>(pos_));  // index data, chunk info, file header padding
  return true;
}

bool BagChunkScanner::next(Message& out) {
  if (done_) return false;
  try {
    while (true) {
      if (in_chunk_ && nextInChunk(out)) return true;
      if (pos_ >= file_size_) {
        done_ = true;
        return false;
      }
      readTopLevelRecord();
    }
  } catch (const BagReadError&) {
    done_ = true;
    in_chunk_ = false;
    throw;
  }
}

}  // namespace rgbdi::bag::detail
