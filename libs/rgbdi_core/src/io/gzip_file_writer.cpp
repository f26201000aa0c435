#include "rgbdi/io/gzip_file_writer.h"

#include <libdeflate.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "rgbdi/common/atomic_file.h"

namespace rgbdi::io {

GzipFileWriter::GzipFileWriter(const std::string& path, int level, std::size_t member_bytes)
    : path_(path) {
  if (level < 1 || level > 12)
    throw std::invalid_argument("GzipFileWriter: compression level " + std::to_string(level) +
                                " outside 1..12");
  if (member_bytes == 0) throw std::invalid_argument("GzipFileWriter: member size 0");
  compressor_ = libdeflate_alloc_compressor(level);
  if (!compressor_) throw std::bad_alloc();
  file_ = std::fopen(path.c_str(), "wb");
  if (!file_) {
    libdeflate_free_compressor(static_cast<libdeflate_compressor*>(compressor_));
    throw IoError(path + ": cannot create the file: " + std::strerror(errno));
  }
  buffer_.resize(member_bytes);
}

GzipFileWriter::~GzipFileWriter() {
  try {
    close();  // closes the file whether or not writing succeeds
  } catch (...) {
    // A destructor cannot report it; close() does.
  }
  libdeflate_free_compressor(static_cast<libdeflate_compressor*>(compressor_));
}

void GzipFileWriter::writeMember() {
  if (used_ == 0) return;
  auto* c = static_cast<libdeflate_compressor*>(compressor_);
  compressed_.resize(libdeflate_gzip_compress_bound(c, used_));
  const std::size_t n =
      libdeflate_gzip_compress(c, buffer_.data(), used_, compressed_.data(), compressed_.size());
  if (n == 0) throw IoError(path_ + ": gzip compression failed");  // the bound was too small
  if (std::fwrite(compressed_.data(), 1, n, file_) != n)
    throw IoError(path_ + ": write failed: " + std::strerror(errno));
  used_ = 0;
}

size_t GzipFileWriter::Write(const void* buffer, size_t count) {
  if (!file_) throw IoError(path_ + ": written after close()");
  const auto* in = static_cast<const std::uint8_t*>(buffer);
  size_t left = count;
  while (left > 0) {
    const size_t take = std::min(left, buffer_.size() - used_);
    std::memcpy(buffer_.data() + used_, in, take);
    used_ += take;
    in += take;
    left -= take;
    if (used_ == buffer_.size()) writeMember();
  }
  written_ += count;
  return count;
}

void GzipFileWriter::close() {
  if (!file_) return;
  std::FILE* f = file_;
  try {
    writeMember();
  } catch (...) {
    file_ = nullptr;
    std::fclose(f);
    throw;
  }
  file_ = nullptr;
  if (std::fclose(f) != 0) throw IoError(path_ + ": closing failed: " + std::strerror(errno));
}

size_t GzipFileWriter::Read(void*, size_t) {
  throw std::logic_error("GzipFileWriter: " + path_ + " is write-only");
}

uint64_t GzipFileWriter::Seek(int64_t offset, TSeekOrigin origin) {
  const bool here = (origin == sFromCurrent && offset == 0) ||
                    (origin == sFromBeginning && offset >= 0 && uint64_t(offset) == written_);
  if (!here) throw std::logic_error("GzipFileWriter: " + path_ + " cannot seek");
  return written_;
}

}  // namespace rgbdi::io
