// A gzip file written as a sequence of gzip members, each compressed whole by libdeflate from a
// fixed-size buffer: what MRPT's CFileGZOutputStream writes (one zlib stream) costs about twice
// the CPU, and the serialized maps and scenes written at the end of a run are mostly float
// coordinates that compress little. gzip readers treat the members as one stream (RFC 1952;
// zlib's gzread, and so MRPT's CFileGZInputStream, gunzip, zcat), so the file reads back
// exactly as the one zlib would have written.
#pragma once

#include <mrpt/io/CStream.h>

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace rgbdi::io {

class GzipFileWriter : public mrpt::io::CStream {
 public:
  /// Creates (truncates) `path`. `level`: libdeflate's compression level (1 fastest, 12 best);
  /// `member_bytes`: uncompressed bytes per gzip member (the buffer held). Throws IoError naming
  /// the file when it cannot be created, std::invalid_argument for a level outside 1..12 or
  /// member_bytes 0.
  explicit GzipFileWriter(const std::string& path, int level = 1,
                          std::size_t member_bytes = std::size_t{1} << 20);
  /// Closes the file if close() was not called (errors are lost then: call close()).
  ~GzipFileWriter() override;
  GzipFileWriter(const GzipFileWriter&) = delete;
  GzipFileWriter& operator=(const GzipFileWriter&) = delete;

  /// Compresses what is buffered, writes it and closes the file; throws IoError naming the file
  /// when anything could not be written.
  void close();

  /// Buffers `count` bytes (writing a member whenever the buffer is full); throws IoError on a
  /// write error or after close().
  size_t Write(const void* buffer, size_t count) override;
  /// Not readable: throws std::logic_error.
  size_t Read(void* buffer, size_t count) override;
  /// Only the current position can be "sought" (serialization asks); anything else throws
  /// std::logic_error.
  uint64_t Seek(int64_t offset, TSeekOrigin origin = sFromBeginning) override;
  /// Uncompressed bytes written so far.
  uint64_t getTotalBytesCount() const override { return written_; }
  uint64_t getPosition() const override { return written_; }

 private:
  void writeMember();

  std::string path_;
  std::FILE* file_ = nullptr;
  void* compressor_ = nullptr;  ///< libdeflate_compressor
  std::vector<std::uint8_t> buffer_, compressed_;
  std::size_t used_ = 0;
  std::uint64_t written_ = 0;
};

}  // namespace rgbdi::io
