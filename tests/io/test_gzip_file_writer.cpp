// GzipFileWriter: gzip members written by libdeflate read back by MRPT's gzip stream (zlib) as
// one stream, byte for byte, also through MRPT serialization; errors name the file.
#include <gtest/gtest.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/serialization/CArchive.h>
#include <unistd.h>

#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "rgbdi/common/atomic_file.h"
#include "rgbdi/io/gzip_file_writer.h"

namespace fs = std::filesystem;
using rgbdi::io::GzipFileWriter;

namespace {

std::string tempDir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / (name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d.string();
}

std::vector<std::uint8_t> readGz(const std::string& path) {
  mrpt::io::CFileGZInputStream in(path);
  std::vector<std::uint8_t> out;
  std::uint8_t chunk[4096];
  for (size_t n; (n = in.Read(chunk, sizeof chunk)) > 0;) out.insert(out.end(), chunk, chunk + n);
  return out;
}

}  // namespace

TEST(GzipFileWriter, MembersReadBackAsOneStream) {
  const std::string dir = tempDir("rgbdi_gzip_writer");
  std::mt19937 rng(3);
  std::vector<std::uint8_t> data(100000);
  for (std::size_t i = 0; i < data.size(); ++i)  // half noise, half runs: both kinds of block
    data[i] = i < data.size() / 2 ? static_cast<std::uint8_t>(rng()) : std::uint8_t(i / 1000);
  for (const std::size_t member : {std::size_t{1}, std::size_t{777}, std::size_t{1} << 20})
    for (const int level : {1, 6}) {
      const std::string path = dir + "/data.gz";
      GzipFileWriter out(path, level, member);
      // Uneven writes: across member boundaries and within them.
      std::size_t at = 0, step = 1;
      while (at < data.size()) {
        const std::size_t n = std::min(step, data.size() - at);
        EXPECT_EQ(out.Write(data.data() + at, n), n);
        at += n;
        step = step * 3 % 5003 + 1;
      }
      EXPECT_EQ(out.getTotalBytesCount(), data.size());
      out.close();
      EXPECT_EQ(readGz(path), data) << "member " << member << ", level " << level;
    }
  // Nothing written: a valid empty gzip file (no member at all reads as empty).
  {
    GzipFileWriter out(dir + "/empty.gz");
    out.close();
  }
  EXPECT_TRUE(readGz(dir + "/empty.gz").empty());
  fs::remove_all(dir);
}

TEST(GzipFileWriter, SerializedObjectsReadBackThroughMrpt) {
  const std::string dir = tempDir("rgbdi_gzip_serial");
  const mrpt::poses::CPose3D pose(1.5, -2.0, 0.25, 0.1, -0.2, 0.3);
  {
    GzipFileWriter out(dir + "/pose.gz", 1, 16);  // a member every 16 bytes
    auto archive = mrpt::serialization::archiveFrom(out);
    archive << pose << pose;
    out.close();
  }
  mrpt::io::CFileGZInputStream in(dir + "/pose.gz");
  auto archive = mrpt::serialization::archiveFrom(in);
  mrpt::poses::CPose3D a, b;
  archive >> a >> b;
  EXPECT_EQ(a, pose);
  EXPECT_EQ(b, pose);
  fs::remove_all(dir);
}

TEST(GzipFileWriter, ErrorsNameTheFile) {
  try {
    GzipFileWriter out("/nonexistent_dir_rgbdi/x.gz");
    FAIL() << "a file in a missing directory was opened";
  } catch (const rgbdi::IoError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent_dir_rgbdi/x.gz"), std::string::npos);
  }
  EXPECT_THROW(GzipFileWriter("/tmp/x.gz", 0), std::invalid_argument);
  EXPECT_THROW(GzipFileWriter("/tmp/x.gz", 13), std::invalid_argument);
  EXPECT_THROW(GzipFileWriter("/tmp/x.gz", 1, 0), std::invalid_argument);
  const std::string dir = tempDir("rgbdi_gzip_errors");
  GzipFileWriter out(dir + "/y.gz");
  std::uint8_t byte = 7;
  out.Write(&byte, 1);
  EXPECT_EQ(out.Seek(0, mrpt::io::CStream::sFromCurrent), 1u);
  EXPECT_THROW(out.Seek(0), std::logic_error);
  EXPECT_THROW(out.Read(&byte, 1), std::logic_error);
  out.close();
  EXPECT_THROW(out.Write(&byte, 1), rgbdi::IoError);
  if (fs::exists("/dev/full")) {  // a device that refuses every write
    GzipFileWriter full("/dev/full", 1, 4);
    std::uint8_t bytes[4] = {1, 2, 3, 4};
    try {
      full.Write(bytes, 4);  // fills a member: written now (the C library may buffer it)
      full.close();
      FAIL() << "writing to /dev/full succeeded";
    } catch (const rgbdi::IoError& e) {
      EXPECT_NE(std::string(e.what()).find("/dev/full"), std::string::npos) << e.what();
    }
  }
  fs::remove_all(dir);
}
