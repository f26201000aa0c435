#include "io/cimage_guard.h"

#include <algorithm>
#include <cstring>
#include <limits>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <stdexcept>
#include <string_view>

#include "rgbdi/io/image_decode.h"

namespace rgbdi::io {
namespace {

std::uint32_t le32(const std::uint8_t* p) {
  return static_cast<std::uint32_t>(p[0]) | static_cast<std::uint32_t>(p[1]) << 8 |
         static_cast<std::uint32_t>(p[2]) << 16 | static_cast<std::uint32_t>(p[3]) << 24;
}

/// Why OpenCV cannot decode the JPEG (empty: it decodes).
std::string jpegProblem(const std::uint8_t* data, std::size_t n) {
  if (n > static_cast<std::size_t>(std::numeric_limits<int>::max())) return "too large";
  // Only JPEG data go to cv::imdecode, which would try every codec OpenCV has (fuzzing finding
  // 20: OpenEXR allocating what a damaged attribute size says).
  if (!isJpegData(data, n)) return "it is no JPEG (no start-of-image marker)";
  try {
    const cv::Mat bytes(1, static_cast<int>(n), CV_8UC1, const_cast<std::uint8_t*>(data));
    if (cv::imdecode(bytes, cv::IMREAD_UNCHANGED).empty()) return "it does not decode";
    return {};
  } catch (const cv::Exception& e) {
    return e.err;
  } catch (const std::exception& e) {
    return e.what();
  }
}

}  // namespace

bool storedClassIs(const std::uint8_t* name, std::size_t size, const std::string& cls) {
  // MRPT 2 stores "mrpt::img::CImage", MRPT 1 "CImage"; MRPT finds the class by the part after
  // the namespace, whatever precedes it (fuzz_rawlog, 2026-12-03: "mr\x90\x8b\xc5\xbcimg::CImage"
  // was read as a CImage), so this compares that part only.
  // MRPT also takes the stored name as a C string: it ends at the first NUL byte (fuzz_rawlog,
  // 2026-12-03 night: "=rpt::obs::CActionCollection\0\0\0" was read as a CActionCollection).
  const auto* chars = reinterpret_cast<const char*>(name);
  const std::string_view n(chars,
                           static_cast<std::size_t>(std::find(chars, chars + size, '\0') - chars));
  return n == cls ||
         (n.size() > cls.size() + 1 && n.compare(n.size() - cls.size(), cls.size(), cls) == 0 &&
          n.compare(n.size() - cls.size() - 2, 2, "::") == 0);
}

void CImageGuard::refuse(const std::string& why) {
  step_ = Step::Idle;
  error_ = why;
  throw std::runtime_error(why);
}

void CImageGuard::beforeRead(std::size_t count) {
  if (step_ == Step::V0Data) {
    // CImage version 0: the data read goes into the width x height x channels bytes allocated
    // from the stored sizes (8-bit pixels).
    const std::uint64_t pixels = static_cast<std::uint64_t>(width_) *
                                 static_cast<std::uint64_t>(height_) *
                                 static_cast<std::uint64_t>(channels_);
    if (count != length_ || length_ != pixels)
      refuse("embedded image (version 0) stores " + std::to_string(length_) + " bytes for " +
             std::to_string(width_) + "x" + std::to_string(height_) + " pixels of " +
             std::to_string(channels_) + " channels (" + std::to_string(pixels) + " bytes)");
  }
}

void CImageGuard::startPayload(int version) {
  version_ = version;
  if (!nested_container_.empty()) {
    // RawlogSource reads top-level sensory frames and action collections itself. Inside another
    // object MRPT reads them: it resizes their element list to the stored count before it reads
    // any element (a damaged count: gigabytes of empty entries, finding 1), and a version-0
    // frame writes its stamp through every element pointer, also null ones (finding 10).
    refuse(nested_container_ + " inside another object is not read (MRPT allocates " +
           "its stored element count before reading any element)");
  }
  if (version == 0) {
    step_ = Step::V0Width;
  } else if (version == 1) {
    step_ = Step::JpegLength;
  } else if (version >= 2 && version <= 9) {
    step_ = version >= 6 ? Step::External : Step::HasColor;
  } else {
    step_ = Step::Idle;  // 100 (external file only) or unknown: MRPT decides
  }
}

void CImageGuard::watchHeader(const std::uint8_t* data, std::size_t n, std::size_t count) {
  // MRPT 2 stores the class name with its namespace, MRPT 1 without. The name's length is stored
  // in one byte (0x80 | length) or in four whose upper three are zero (the two cases below), so a
  // longer read is no class name: pixel and range data (a megabyte per frame when embedded) are
  // not searched for one.
  constexpr std::size_t kMaxStoredNameBytes = 255;
  const bool name_sized = n == count && count <= kMaxStoredNameBytes;
  const bool image = name_sized && storedClassIs(data, n, "CImage");
  const bool frame = name_sized && storedClassIs(data, n, "CSensoryFrame");
  const bool actions = name_sized && storedClassIs(data, n, "CActionCollection");
  if (image || frame || actions) {
    nested_container_ = frame ? "a sensory frame" : actions ? "an action collection" : "";
    if (last_count_ == 1 && last_bytes_ == (0x80u | count)) {
      step_ = Step::Version8;
    } else if (last_count_ == 3 && last_bytes_ == 0 && before_last_count_ == 1 &&
               before_last_bytes_ == count) {
      step_ = Step::Version32;
    }
  }
  before_last_count_ = last_count_;
  before_last_bytes_ = last_bytes_;
  last_count_ = count;
  last_bytes_ = 0;
  for (std::size_t i = 0; i < n && i < 4; ++i)
    last_bytes_ |= static_cast<std::uint32_t>(data[i]) << (8 * i);
}

void CImageGuard::afterRead(const std::uint8_t* data, std::size_t n, std::size_t count) {
  const Step step = step_;
  // A read the layout does not expect (or a short one: the archive throws next) ends the check.
  const auto expect = [&](std::size_t size) {
    if (count == size && n == size) return true;
    step_ = Step::Idle;
    return false;
  };
  switch (step) {
    case Step::Idle:
      break;
    case Step::Version8:
      if (expect(1)) startPayload(data[0]);
      break;
    case Step::Version32:
      if (expect(4)) startPayload(static_cast<int>(le32(data)));
      break;
    case Step::V0Width:
      if (expect(4)) width_ = le32(data), step_ = Step::V0Height;
      break;
    case Step::V0Height:
      if (expect(4)) height_ = le32(data), step_ = Step::V0Channels;
      break;
    case Step::V0Channels:
      if (expect(4)) channels_ = le32(data), step_ = Step::V0Origin;
      break;
    case Step::V0Origin:
      if (expect(1)) step_ = Step::V0Length;
      break;
    case Step::V0Length:
      if (expect(4)) {
        length_ = le32(data);
        step_ = length_ == 0 ? Step::Idle : Step::V0Data;  // nothing is read for 0 bytes
      }
      break;
    case Step::V0Data:
      step_ = Step::Idle;
      break;
    case Step::External:
      if (expect(1)) step_ = data[0] != 0 ? Step::Idle : Step::HasColor;
      break;
    case Step::HasColor:
      if (expect(1))
        step_ = data[0] == 0 ? Step::Idle : version_ >= 7 ? Step::ColorWidth : Step::JpegLength;
      break;
    case Step::ColorWidth:
      if (expect(4)) width_ = static_cast<std::int32_t>(le32(data)), step_ = Step::ColorHeight;
      break;
    case Step::ColorHeight:
      if (expect(4)) {
        height_ = static_cast<std::int32_t>(le32(data));
        step_ = width_ >= 1 && height_ >= 1 ? Step::JpegLength : Step::Idle;
      }
      break;
    case Step::JpegLength:
      if (expect(4)) length_ = le32(data), step_ = Step::JpegData;
      break;
    case Step::JpegData:
      step_ = Step::Idle;
      // MRPT's CArchive::ReadBuffer returns a short read without an error, and CImage decodes
      // its whole buffer anyway, the unread part uninitialised (fuzz_rawlog, 2026-12-03, after
      // 28 999 runs: libjpeg's exit(1) on such a buffer): the file ended inside the image.
      if (count == length_ && n < count)
        refuse("the data ends inside an embedded JPEG image (" + std::to_string(n) + " of " +
               std::to_string(count) + " bytes)");
      if (count == length_) {
        const std::string problem = jpegProblem(data, n);
        if (!problem.empty())
          refuse("embedded JPEG image (" + std::to_string(n) + " bytes) is damaged: " + problem);
      }
      break;
  }
  if (step == Step::Idle || step_ == Step::Idle) watchHeader(data, n, count);
}

}  // namespace rgbdi::io
