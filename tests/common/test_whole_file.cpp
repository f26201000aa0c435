// readWholeFile: exact content for sizes around its probe buffer, capacity reuse, files whose
// reported size is wrong, and the failing step with its errno.
#include <gtest/gtest.h>

#include <cerrno>
#include <fstream>
#include <string>
#include <vector>

#include "rgbdi/common/whole_file.h"
#include "testing/fixtures.h"

namespace rgbdi {
namespace {

std::vector<std::uint8_t> pattern(std::size_t n) {
  std::vector<std::uint8_t> v(n);
  for (std::size_t i = 0; i < n; ++i) v[i] = static_cast<std::uint8_t>((i * 131 + i / 256) & 0xFF);
  return v;
}

std::string writeBytes(const std::string& path, const std::vector<std::uint8_t>& b) {
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
  return path;
}

TEST(WholeFile, ReadsEveryByteForSizesAroundItsBuffers) {
  const std::string dir = test::makeTempDir("whole_file");
  std::vector<std::uint8_t> out(7, 0xAA);  // previous content must not survive
  for (std::size_t n : {0u, 1u, 4095u, 4096u, 4097u, 8193u, (1u << 20) + 3u}) {
    const auto expected = pattern(n);
    const std::string f = writeBytes(dir + "/f" + std::to_string(n), expected);
    ASSERT_EQ(readWholeFile(f, out), FileReadError::kNone) << n;
    EXPECT_EQ(out, expected) << n;
    std::vector<char> chars;
    ASSERT_EQ(readWholeFile(f, chars), FileReadError::kNone) << n;
    ASSERT_EQ(chars.size(), n);
    EXPECT_TRUE(
        std::equal(chars.begin(), chars.end(), expected.begin(),
                   [](char c, std::uint8_t b) { return static_cast<std::uint8_t>(c) == b; }));
  }
}

TEST(WholeFile, ReusesTheCapacityOfItsOutput) {
  const std::string dir = test::makeTempDir("whole_file_reuse");
  const std::string big = writeBytes(dir + "/big", pattern(100000));
  const std::string small = writeBytes(dir + "/small", pattern(10));
  std::vector<std::uint8_t> out;
  ASSERT_EQ(readWholeFile(big, out), FileReadError::kNone);
  const std::uint8_t* buffer = out.data();
  ASSERT_EQ(readWholeFile(small, out), FileReadError::kNone);
  EXPECT_EQ(out, pattern(10));
  ASSERT_EQ(readWholeFile(big, out), FileReadError::kNone);
  EXPECT_EQ(out.data(), buffer);  // no new allocation
}

TEST(WholeFile, FileLargerThanItsReportedSizeIsReadToItsEnd) {
  // /proc files report size 0 but have content.
  std::vector<std::uint8_t> out;
  ASSERT_EQ(readWholeFile("/proc/self/status", out), FileReadError::kNone);
  const std::string text(out.begin(), out.end());
  EXPECT_NE(text.find("Name:"), std::string::npos);
  EXPECT_NE(text.find("VmRSS:"), std::string::npos);
}

TEST(WholeFile, FailuresSayWhichStepFailedWithItsErrno) {
  const std::string dir = test::makeTempDir("whole_file_fail");
  std::vector<std::uint8_t> out;
  errno = 0;
  EXPECT_EQ(readWholeFile(dir + "/missing", out), FileReadError::kOpen);
  EXPECT_EQ(errno, ENOENT);
  errno = 0;
  EXPECT_EQ(readWholeFile(dir, out), FileReadError::kRead);  // a directory opens but cannot be read
  EXPECT_EQ(errno, EISDIR);
}

}  // namespace
}  // namespace rgbdi
