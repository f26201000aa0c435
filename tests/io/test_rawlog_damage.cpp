// Damaged rawlogs that crashed or ended the reader before its documented refusal (fuzzing
// findings 9-11 and 13, doc/robustness.md): each input is crafted here from a valid record, and
// the reader must refuse it as damage naming the file and the record, or report and skip the
// damaged part, and go on living.
#include <gtest/gtest.h>
#include <mrpt/core/aligned_allocator.h>
#include <mrpt/img/CImage.h>
#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/serialization/CArchive.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <new>
#include <string>
#include <vector>

#include "rgbdi/io/mrpt_conversions.h"
#include "rgbdi/io/rawlog_source.h"
#include "rgbdi/io/rawlog_writer.h"
#include "testing/fixtures.h"

#if defined(__SANITIZE_ADDRESS__)
#define RGBDI_TEST_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define RGBDI_TEST_ASAN 1
#endif
#endif

namespace rgbdi::io {
namespace {

namespace fs = std::filesystem;
using Bytes = std::vector<std::uint8_t>;

constexpr double kT0 = 1700000000.0;

#ifdef RGBDI_TEST_ASAN
/// ASan aborts on allocation requests it cannot serve unless allocator_may_return_null=1; the
/// tests of failing allocations need the heap's ordinary answer (nullptr from aligned_alloc), so
/// this executable asks for it (ASAN_OPTIONS from the environment still overrides it).
extern "C" const char* __asan_default_options() { return "allocator_may_return_null=1"; }
#endif

/// False only under ASan told by ASAN_OPTIONS not to return null (it would abort on the request).
bool allocationFailuresAreReported() {
#ifdef RGBDI_TEST_ASAN
  const char* o = std::getenv("ASAN_OPTIONS");
  return o == nullptr || std::string(o).find("allocator_may_return_null=0") == std::string::npos;
#else
  return true;
#endif
}

ImuSample imuAt(double t) {
  ImuSample s;
  s.t = t;
  s.acc = Eigen::Vector3d(0.01, -0.02, 9.805);
  s.gyr = Eigen::Vector3d(0.001, 0.002, -0.003);
  return s;
}

/// A 9x7 frame: sizes that appear nowhere else in a record.
RgbdFrame smallFrame(double t) {
  RgbdFrame f;
  f.t = t;
  f.rgb = cv::Mat(7, 9, CV_8UC3, cv::Scalar(10, 200, 30));
  f.rgb.at<cv::Vec3b>(0, 0) = cv::Vec3b(90, 20, 130);
  f.depth = cv::Mat(7, 9, CV_16UC1, cv::Scalar(1500));
  f.depth_unit_m = 1e-3;
  PinholeCamera c;
  c.width = 9;
  c.height = 7;
  c.fx = c.fy = 30.0;
  c.cx = 4.5;
  c.cy = 3.5;
  f.cam_color = f.cam_depth = c;
  f.depth_aligned_to_color = true;
  return f;
}

Bytes readBytes(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return Bytes(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
}

void writeBytes(const std::string& path, const Bytes& b) {
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  f.write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
}

void putLe32(Bytes& b, std::size_t at, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) b[at + static_cast<std::size_t>(i)] = (v >> (8 * i)) & 0xff;
}

/// The only offset of `pattern` in `b` (fails the test if there is not exactly one).
std::size_t findOnce(const Bytes& b, const Bytes& pattern) {
  std::vector<std::size_t> hits;
  for (auto it = b.begin();
       (it = std::search(it, b.end(), pattern.begin(), pattern.end())) != b.end(); ++it)
    hits.push_back(static_cast<std::size_t>(it - b.begin()));
  EXPECT_EQ(hits.size(), 1u);
  return hits.empty() ? 0 : hits.front();
}

/// A rawlog of 40 IMU samples (records 0-39) and one 9x7 frame (record 40), then 10 more IMU
/// samples (records 41-50); plain (not gzip), observations layout.
std::string writeFrameRawlog(const std::string& dir) {
  const std::string path = dir + "/frame.rawlog";
  RawlogWriterOptions o;
  o.T_body_cam = StreamConfig().extrinsic.T_body_cam;
  RawlogWriter w(path, o);
  for (int i = 0; i < 40; ++i) w.write(imuAt(kT0 + 0.005 * i));
  w.write(smallFrame(kT0 + 0.1));
  for (int i = 40; i < 50; ++i) w.write(imuAt(kT0 + 0.005 * i));
  w.close();
  return path;
}

struct ReadResult {
  std::size_t imu = 0, frames = 0;
  std::string error;  ///< RawlogError text, empty if reading ended normally
  StreamDiagnostics diagnostics;
};

ReadResult readAll(const std::string& path) {
  ReadResult r;
  RawlogSource src(path);
  src.logging_enable_console_output = false;
  Measurement m;
  try {
    while (src.next(m)) (isImu(m) ? r.imu : r.frames)++;
  } catch (const RawlogError& e) {
    r.error = e.what();
  }
  r.diagnostics = src.diagnostics();
  return r;
}

class RawlogDamage : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = test::makeTempDir("rgbdi_rawlog_damage"); }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  std::string dir_;
};

// Finding 9 (2026-12-03): mrpt::aligned_malloc returned nullptr for a request the heap could not
// serve, and MRPT's matrices wrote through it (SIGSEGV in Release rgbdi-slam). rgbdi's
// definition throws std::bad_alloc; MRPT's own aligned_calloc calls it through the PLT, so this
// also checks that the definition is the one MRPT's libraries use.
TEST(MrptAlignedMalloc, AFailedAllocationThrowsInsteadOfReturningNull) {
  if (!allocationFailuresAreReported())
    GTEST_SKIP() << "ASan with allocator_may_return_null=0 aborts on the request itself";
  EXPECT_THROW((void)mrpt::aligned_calloc(std::size_t{1} << 62, 16), std::bad_alloc);
  EXPECT_THROW((void)mrpt::aligned_malloc(std::size_t{1} << 62, 16), std::bad_alloc);
  void* p = mrpt::aligned_malloc(100, 32);  // rounded up to 128 bytes, aligned: as MRPT's own
  ASSERT_NE(p, nullptr);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(p) % 32, 0u);
  std::memset(p, 1, 128);
  mrpt::aligned_free(p);
}

TEST_F(RawlogDamage, RangeImageSizeBeyondMemoryIsRefusedNamingTheRecord) {
  if (!allocationFailuresAreReported())
    GTEST_SKIP() << "ASan with allocator_may_return_null=0 aborts on the request itself";
  const std::string path = writeFrameRawlog(dir_);
  Bytes b = readBytes(path);
  // The range image is stored as rows, cols (uint32) and the values: 2^30 x 2^30 values ask
  // MRPT's CMatrix_u16 for 2 EiB.
  // (after rangeUnits, 0.001f).
  const std::size_t at = findOnce(b, {0x6f, 0x12, 0x83, 0x3a, 7, 0, 0, 0, 9, 0, 0, 0}) + 4;
  putLe32(b, at, 1u << 30);
  putLe32(b, at + 4, 1u << 30);
  writeBytes(path, b);
  const ReadResult r = readAll(path);
  EXPECT_EQ(r.error, path + " record 40: corrupt record (std::bad_alloc)");
  EXPECT_EQ(r.imu, 40u);
  EXPECT_EQ(r.frames, 0u);
}

/// A top-level object header as CArchive writes it (new format).
void putHeader(Bytes& b, const std::string& class_name, int version) {
  b.push_back(static_cast<std::uint8_t>(0x80 | class_name.size()));
  b.insert(b.end(), class_name.begin(), class_name.end());
  if (version >= 0) b.push_back(static_cast<std::uint8_t>(version));
}

void appendLe32(Bytes& b, std::uint32_t v) {
  b.resize(b.size() + 4, 0);
  putLe32(b, b.size() - 4, v);
}

/// A top-level container (a sensory frame of version 2 or an action collection) whose one
/// element is the container `inner` of `inner_version` claiming 4 billion elements, none stored.
void putNestedContainer(Bytes& b, const std::string& outer, const std::string& inner,
                        int inner_version) {
  putHeader(b, outer, outer == "mrpt::obs::CSensoryFrame" ? 2 : 0);
  appendLe32(b, 1);
  putHeader(b, inner, inner_version);
  if (inner_version == 1) appendLe32(b, 0);  // a frame's ID
  appendLe32(b, 0xfffffff0u);
}

/// The refusal of a container (`what`: "a sensory frame", "an action collection") that MRPT
/// would read inside another object, record 30 of `path`.
std::string nestedContainerRefusal(const std::string& path, const std::string& what) {
  return path + " record 30: corrupt record (" + what +
         " inside another object is not read (MRPT allocates its stored element count before "
         "reading any element))";
}

Bytes serialised(const mrpt::serialization::CSerializable& o, const std::string& dir) {
  const std::string tmp = dir + "/object.bin";
  {
    mrpt::io::CFileOutputStream f(tmp);
    auto a = mrpt::serialization::archiveFrom(f);
    a << o;
  }
  return readBytes(tmp);
}

/// 30 serialised IMU records at 200 Hz from kT0 (records 0-29 of a crafted rawlog).
Bytes imuRecords(const std::string& dir) {
  Bytes b;
  for (int i = 0; i < 30; ++i) {
    const Bytes imu = serialised(*toMrpt(imuAt(kT0 + 0.005 * i), "IMU"), dir);
    b.insert(b.end(), imu.begin(), imu.end());
  }
  return b;
}

// Finding 10 (2026-12-03): MRPT's CSensoryFrame::serializeFrom (version 0) sets the frame's
// stamp through every element pointer, also an empty one or one of an object that is no
// observation (SIGSEGV). rgbdi reads sensory frames itself; such elements are reported as damage
// of the record and skipped, the observations of the frame are used.
TEST_F(RawlogDamage, SensoryFrameElementsThatAreNoObservationAreReportedAndSkipped) {
  for (const int version : {0, 1, 2}) {
    SCOPED_TRACE("CSensoryFrame version " + std::to_string(version));
    Bytes b = imuRecords(dir_);
    putHeader(b, version == 1 ? "CSensoryFrame" : "mrpt::obs::CSensoryFrame", version);
    const std::size_t n_at = b.size() + (version == 0 ? 12 : version == 1 ? 4 : 0);
    b.resize(n_at + 4, 0);
    if (version == 0) {  // ID, then the frame's stamp (MRPT time: 100 ns since 1601)
      const auto stamp = fromSeconds(kT0 + 0.2).time_since_epoch().count();
      for (int i = 0; i < 8; ++i)
        b[n_at - 8 + static_cast<std::size_t>(i)] =
            (static_cast<std::uint64_t>(stamp) >> (8 * i)) & 0xff;
    }
    putLe32(b, n_at, 3);
    const Bytes imu = serialised(*toMrpt(imuAt(kT0 + 0.2), "IMU"), dir_);
    b.insert(b.end(), imu.begin(), imu.end());
    putHeader(b, "nullptr", -1);  // a null element: no version, its end flag
    b.push_back(0x88);
    const Bytes pose = serialised(mrpt::poses::CPose3D(), dir_);
    b.insert(b.end(), pose.begin(), pose.end());
    b.push_back(0x88);  // the frame's end flag
    const std::string path = dir_ + "/sf" + std::to_string(version) + ".rawlog";
    writeBytes(path, b);

    const ReadResult r = readAll(path);
    EXPECT_EQ(r.error, "");
    EXPECT_EQ(r.imu, 31u);
    EXPECT_EQ(r.diagnostics.unusable, 2u);
    const std::string warnings = [&] {
      std::string s;
      for (const auto& w : r.diagnostics.warnings) s += w + "\n";
      return s;
    }();
    EXPECT_NE(warnings.find(path + " record 30: sensory frame element 1 of 3 is empty (stored as "
                                   "a null object); skipped"),
              std::string::npos)
        << warnings;
    EXPECT_NE(warnings.find(path + " record 30: sensory frame element 2 of 3 is a "
                                   "mrpt::poses::CPose3D, not an observation; skipped"),
              std::string::npos)
        << warnings;
  }
}

// The same inside another object, where MRPT reads the frame: a version-0 frame nested in a
// top-level one, with a null element (before: SIGSEGV).
TEST_F(RawlogDamage, NestedSensoryFrameOfVersion0IsACorruptRecord) {
  Bytes b = imuRecords(dir_);
  putHeader(b, "mrpt::obs::CSensoryFrame", 2);
  appendLe32(b, 1);
  putHeader(b, "mrpt::obs::CSensoryFrame", 0);  // ID, stamp, 1 element: null
  b.resize(b.size() + 16, 0);
  putLe32(b, b.size() - 4, 1);
  putHeader(b, "nullptr", -1);
  b.push_back(0x88);
  b.push_back(0x88);  // nested frame's end flag
  b.push_back(0x88);  // top-level frame's end flag
  const std::string path = dir_ + "/sf_nested.rawlog";
  writeBytes(path, b);
  const ReadResult r = readAll(path);
  EXPECT_EQ(r.error, nestedContainerRefusal(path, "a sensory frame"));
  EXPECT_EQ(r.imu, 30u);
}

TEST_F(RawlogDamage, SensoryFrameWithoutItsEndFlagIsACorruptRecord) {
  Bytes b = imuRecords(dir_);
  putHeader(b, "mrpt::obs::CSensoryFrame", 2);
  appendLe32(b, 1);
  const Bytes imu = serialised(*toMrpt(imuAt(kT0 + 0.2), "IMU"), dir_);
  b.insert(b.end(), imu.begin(), imu.end());
  b.push_back(0x77);  // not the end flag
  b.insert(b.end(), imu.begin(), imu.end());
  const std::string path = dir_ + "/sf_end.rawlog";
  writeBytes(path, b);
  const ReadResult r = readAll(path);
  EXPECT_EQ(r.error, path + " record 30: corrupt record (the sensory frame's end flag is missing)");
  EXPECT_EQ(r.imu, 30u);  // the damaged frame's observation is not used
}

/// The rawlog of writeFrameRawlog() with the colour image stored as an embedded JPEG.
std::string writeJpegFrameRawlog(const std::string& dir) {
  const bool was_disabled = mrpt::img::CImage::DISABLE_JPEG_COMPRESSION();
  mrpt::img::CImage::DISABLE_JPEG_COMPRESSION(false);
  const std::string path = writeFrameRawlog(dir);
  mrpt::img::CImage::DISABLE_JPEG_COMPRESSION(was_disabled);
  return path;
}

// Finding 11 (2026-12-03): MRPT decodes an embedded JPEG with libjpeg's default error handler,
// which calls exit(1) on a damaged one: rgbdi-slam ended with libjpeg's message ("Not a JPEG
// file: starts with 0x00 0x00") instead of exit 3 naming the file and record. The JPEG is
// decoded by OpenCV first, and a damaged one makes the record corrupt.
TEST_F(RawlogDamage, DamagedEmbeddedJpegIsACorruptRecordNotAnExit) {
  {
    // The undamaged JPEG frame is read (so the check does not refuse good images).
    const std::string path = writeJpegFrameRawlog(dir_);
    const Bytes b = readBytes(path);
    findOnce(b, {0xff, 0xd8, 0xff});
    const ReadResult r = readAll(path);
    EXPECT_EQ(r.error, "");
    EXPECT_EQ(r.frames, 1u);
    EXPECT_EQ(r.imu, 50u);
  }
  const std::string path = writeJpegFrameRawlog(dir_);
  Bytes b = readBytes(path);
  const std::size_t soi = findOnce(b, {0xff, 0xd8, 0xff});
  b[soi] = b[soi + 1] = 0;
  writeBytes(path, b);
  const ReadResult r = readAll(path);
  EXPECT_EQ(r.error.rfind(path + " record 40: corrupt record (embedded JPEG image (", 0), 0u)
      << r.error;
  EXPECT_NE(r.error.find("bytes) is damaged"), std::string::npos) << r.error;
  EXPECT_EQ(r.imu, 40u);
}

// Finding 11, third input (fuzz_rawlog, 2026-12-03, after 12 990 runs of the fifth run): the
// namespace part of the stored class name damaged ("mr\x90\x8b\xc5\xbcimg::CImage"). MRPT finds
// the class by the part after "::" and decoded the JPEG; the check did not know the name.
TEST_F(RawlogDamage, DamagedJpegUnderADamagedNamespaceIsACorruptRecordNotAnExit) {
  const std::string path = writeJpegFrameRawlog(dir_);
  Bytes b = readBytes(path);
  const std::string name = "mrpt::img::CImage";
  const std::size_t at = findOnce(b, Bytes(name.begin(), name.end()));
  b[at + 2] = 0x90;
  b[at + 3] = 0x8b;
  const std::size_t soi = findOnce(b, {0xff, 0xd8, 0xff});
  b[soi] = b[soi + 1] = 0;
  writeBytes(path, b);
  const ReadResult r = readAll(path);
  EXPECT_EQ(r.error.rfind(path + " record 40: corrupt record (embedded JPEG image (", 0), 0u)
      << r.error;
  EXPECT_EQ(r.imu, 40u);
}

// Finding 11, second input (fuzz_rawlog, 2026-12-03, after 28 999 runs): a JPEG byte count
// beyond the end of the file. MRPT's ReadBuffer returns the short read without an error and
// CImage decodes the buffer anyway (libjpeg: "Not a JPEG file: starts with 0xff 0xff", exit 1).
TEST_F(RawlogDamage, FileEndingInsideAnEmbeddedJpegIsACorruptRecordNotAnExit) {
  const std::string path = writeJpegFrameRawlog(dir_);
  Bytes b = readBytes(path);
  const std::size_t soi = findOnce(b, {0xff, 0xd8, 0xff});
  b.resize(soi + 20);  // 20 bytes of the JPEG remain
  writeBytes(path, b);
  const ReadResult r = readAll(path);
  EXPECT_EQ(r.error.rfind(path + " record 40: corrupt record (the data ends inside an embedded "
                                 "JPEG image (20 of ",
                          0),
            0u)
      << r.error;
  EXPECT_EQ(r.imu, 40u);
}

// Finding 13 (2026-12-03, read in MRPT's CImage::serializeFrom while fixing 11): version 0 of a
// CImage reads a stored byte count into the buffer it allocated from the stored width, height
// and channels, without comparing them (a heap overflow by the difference). The count must match.
TEST_F(RawlogDamage, ImageVersion0WithMoreBytesThanPixelsIsACorruptRecord) {
  Bytes b = imuRecords(dir_);
  putHeader(b, "mrpt::img::CImage", 0);
  const std::size_t at = b.size();
  b.resize(at + 17, 0);
  putLe32(b, at, 2);                      // width
  putLe32(b, at + 4, 2);                  // height
  putLe32(b, at + 8, 1);                  // channels
  putLe32(b, at + 13, 1u << 20);          // bytes stored (after the origin byte): 1 MiB
  b.resize(b.size() + (1u << 20), 0x41);  // the bytes
  b.push_back(0x88);
  const std::string path = dir_ + "/img0.rawlog";
  writeBytes(path, b);
  const ReadResult r = readAll(path);
  EXPECT_EQ(r.error, path +
                         " record 30: corrupt record (embedded image (version 0) stores 1048576 "
                         "bytes for 2x2 pixels of 1 channels (4 bytes))");
  EXPECT_EQ(r.imu, 30u);
}

/// Reads the rawlog at `path` with the stored byte of its scan's "range image is external" flag
/// set to `value` (after the sensor label "RGBD": points external (bool) + file (""), range
/// external (bool) + file).
ReadResult readWithRangeExternalFlag(const std::string& path, std::uint8_t value) {
  Bytes b = readBytes(path);
  const std::size_t at =
      findOnce(b, {4, 0, 0, 0, 'R', 'G', 'B', 'D', 0, 0, 0, 0, 0, 0, 0, 0, 0, 0});
  b[at + 13] = value;
  writeBytes(path, b);
  return readAll(path);
}

// Finding 14 (2026-12-03, fuzz_rawlog after 5 326 runs): a range image marked as stored in an
// external file with an empty file name made MRPT's lazy_load_absolute_path assert
// (std::logic_error) while rgbdi looked the file up, outside the conversion's error handling: the
// exception left RawlogSource::next as something else than RawlogError (std::terminate in the
// fuzz target). The observation is reported as unusable and skipped, the rest is read.
TEST_F(RawlogDamage, ExternalRangeImageWithoutAFileNameIsReportedAndSkipped) {
  const std::string path = writeFrameRawlog(dir_);
  const ReadResult r = readWithRangeExternalFlag(path, 1);
  EXPECT_EQ(r.error, "");
  EXPECT_EQ(r.imu, 50u);
  EXPECT_EQ(r.frames, 0u);
  EXPECT_EQ(r.diagnostics.unusable, 1u);
  ASSERT_FALSE(r.diagnostics.warnings.empty());
  EXPECT_EQ(
      r.diagnostics.warnings[0].rfind(
          path + " record 40: cannot load the observation's images: Assert condition failed", 0),
      0u)
      << r.diagnostics.warnings[0];
}

// Finding 15 (fuzz_rawlog, 2026-12-03 evening, after 17 359 runs): the external-storage flag of
// a scan's range image, a bool MRPT reads as the stored byte, held 8; rgbdi loaded it as bool
// (UBSan "load of value 8, which is not a valid value for type 'bool'", undefined behaviour: the
// flag may be taken as set and as not set). Like the public flags of finding 8, such bytes are
// refused as damage of the observation.
TEST_F(RawlogDamage, ExternalStorageFlagThatIsNoBoolIsRefusedAsDamage) {
  const std::string path = writeFrameRawlog(dir_);
  const ReadResult r = readWithRangeExternalFlag(path, 8);
  EXPECT_EQ(r.error, "");
  EXPECT_EQ(r.imu, 50u);
  EXPECT_EQ(r.frames, 0u);
  EXPECT_EQ(r.diagnostics.unusable, 1u);
  ASSERT_FALSE(r.diagnostics.warnings.empty());
  EXPECT_EQ(r.diagnostics.warnings[0],
            path +
                " record 40: the range image's external flag is stored as 8, which is no bool "
                "(0 or 1): the record is damaged; skipped");
}

// Open finding 1, the action-collection case (fuzz_rawlog, 2026-12-03 evening, out of memory
// after 24 226 runs of the seventh run): MRPT's CActionCollection resizes a deque to the stored
// element count before reading any element (4 billion entries: gigabytes). rgbdi reads action
// collections itself, element by element; a damaged count ends where the data does.
TEST_F(RawlogDamage, ActionCollectionCountBeyondTheDataEndsAtTheData) {
  Bytes b = imuRecords(dir_);
  putHeader(b, "mrpt::obs::CActionCollection", 0);
  appendLe32(b, 0xffffffffu);  // 4 294 967 295 actions, none stored
  const std::string path = dir_ + "/actions.rawlog";
  writeBytes(path, b);
  const ReadResult r = readAll(path);
  EXPECT_EQ(r.error.rfind(path + " record 30: truncated", 0), 0u) << r.error;
  EXPECT_EQ(r.imu, 30u);
}

// Open finding 1, the nested case (fuzz_rawlog, 2026-12-03 evening: the seventh run's input had
// its action collection inside another object, where MRPT reads it). Every container MRPT sizes
// by its stored count, nested at any depth in a top-level frame or action collection, is
// refused as damage of that record before MRPT allocates anything.
TEST_F(RawlogDamage, NestedContainerWithACountBeyondTheDataIsRefusedBeforeMrptAllocatesIt) {
  struct Case {
    std::string outer, inner, what;
    int inner_version;
  };
  for (const Case& c :
       {Case{"mrpt::obs::CSensoryFrame", "mrpt::obs::CActionCollection", "an action collection", 0},
        Case{"mrpt::obs::CActionCollection", "mrpt::obs::CActionCollection", "an action collection",
             0},
        Case{"mrpt::obs::CSensoryFrame", "mrpt::obs::CSensoryFrame", "a sensory frame", 2},
        Case{"mrpt::obs::CActionCollection", "CSensoryFrame", "a sensory frame", 1}}) {
    SCOPED_TRACE(c.inner + " in " + c.outer);
    Bytes b = imuRecords(dir_);
    putNestedContainer(b, c.outer, c.inner, c.inner_version);
    const Bytes imu = serialised(*toMrpt(imuAt(kT0 + 0.2), "IMU"), dir_);
    b.insert(b.end(), imu.begin(), imu.end());
    const std::string path = dir_ + "/nested.rawlog";
    writeBytes(path, b);
    const ReadResult r = readAll(path);
    EXPECT_EQ(r.error, nestedContainerRefusal(path, c.what));
    EXPECT_EQ(r.imu, 30u);
  }
}

// Finding 1 once more (fuzz_rawlog, 2026-12-03 night, out of memory after 2 129 runs): MRPT takes
// a stored class name as a C string, so "=rpt::obs::CActionCollection" followed by NUL bytes is
// an action collection to MRPT, and was none to rgbdi's checks, which compared every stored
// byte. Top level (rgbdi reads it) and nested (refused) with NUL-padded names.
TEST_F(RawlogDamage, ClassNamesEndAtTheirFirstNulByteAsForMrpt) {
  {
    Bytes b = imuRecords(dir_);
    putHeader(b, std::string("=rpt::obs::CActionCollection\0\0\0", 31), 0);
    appendLe32(b, 0xfffffff0u);
    const std::string path = dir_ + "/nul_top.rawlog";
    writeBytes(path, b);
    const ReadResult r = readAll(path);
    EXPECT_EQ(r.error.rfind(path + " record 30: truncated", 0), 0u) << r.error;
    EXPECT_EQ(r.imu, 30u);
  }
  {
    Bytes b = imuRecords(dir_);
    putNestedContainer(b, "mrpt::obs::CSensoryFrame",
                       std::string("mrpt::obs::CActionCollection\0x", 30), 0);
    const std::string path = dir_ + "/nul_nested.rawlog";
    writeBytes(path, b);
    const ReadResult r = readAll(path);
    EXPECT_EQ(r.error, nestedContainerRefusal(path, "an action collection"));
    EXPECT_EQ(r.imu, 30u);
  }
}

}  // namespace
}  // namespace rgbdi::io
