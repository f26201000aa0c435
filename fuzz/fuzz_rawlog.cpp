// Fuzz target: MRPT rawlog records read by io::RawlogSource (both layouts, gzip, ordering and
// data checks). Documented refusal: RawlogError (at open or at the damaged record).
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <new>

#include "fuzz_target.h"
#include "rgbdi/io/rawlog_source.h"
#include "rgbdi/io/rawlog_writer.h"

// Open finding 1 (doc/robustness.md): MRPT's CArchive allocates what a corrupt size field says
// before it reads the data (a class-name string, a deque of CActionCollection entries). In
// rgbdi-slam a request beyond the machine ends as std::bad_alloc, which RawlogSource turns into
// its documented refusal ("FILE record N: corrupt record (std::bad_alloc)"). Under ASan,
// operator new aborts the process on a request it cannot serve (allocator_may_return_null
// only covers malloc), and libFuzzer stops at the first such input, so nothing behind it was
// fuzzed. In THIS binary only (the libFuzzer target and its replay), operator new / new[]
// refuse requests above kAllocationCap with std::bad_alloc, the way an exhausted heap does, so
// the reader's refusal path runs and fuzzing goes on. malloc/aligned_alloc and free serve
// them, so every new/delete pair stays consistent. The aligned forms are capped too (fuzz_rawlog,
// 2026-12-03 night: MRPT's vector of CPose2D asked for 206 GB through `operator new(size_t,
// align_val_t)`, and ASan aborted).
namespace {
constexpr std::size_t kAllocationCap = std::size_t{64} << 20;  // 64 MiB: 2.5x a 3840x2160 RGB image

void* cappedNew(std::size_t size) {
  if (size > kAllocationCap) throw std::bad_alloc();
  void* p = std::malloc(size == 0 ? 1 : size);
  if (p == nullptr) throw std::bad_alloc();
  return p;
}

void* cappedAlignedNew(std::size_t size, std::align_val_t alignment) {
  const auto a = static_cast<std::size_t>(alignment);
  if (size > kAllocationCap) throw std::bad_alloc();
  // aligned_alloc wants a size that is a multiple of the alignment.
  void* p = std::aligned_alloc(a, size == 0 ? a : (size + a - 1) / a * a);
  if (p == nullptr) throw std::bad_alloc();
  return p;
}
}  // namespace

void* operator new(std::size_t size) { return cappedNew(size); }
void* operator new[](std::size_t size) { return cappedNew(size); }
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  return size > kAllocationCap ? nullptr : std::malloc(size == 0 ? 1 : size);
}
void* operator new[](std::size_t size, const std::nothrow_t& t) noexcept {
  return operator new(size, t);
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }
void* operator new(std::size_t size, std::align_val_t a) { return cappedAlignedNew(size, a); }
void* operator new[](std::size_t size, std::align_val_t a) { return cappedAlignedNew(size, a); }
void* operator new(std::size_t size, std::align_val_t a, const std::nothrow_t&) noexcept {
  try {
    return cappedAlignedNew(size, a);
  } catch (const std::bad_alloc&) {
    return nullptr;
  }
}
void* operator new[](std::size_t size, std::align_val_t a, const std::nothrow_t& t) noexcept {
  return operator new(size, a, t);
}
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t, const std::nothrow_t&) noexcept { std::free(p); }

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace rgbdi::io;
  const std::string path = rgbdi::fuzz::writeScratchFile("rawlog.rawlog", data, size);
  try {
    StreamConfig cfg;
    cfg.stream.max_listed_issues = 2;
    RawlogSource src(path, cfg);
    src.logging_enable_console_output = false;
    rgbdi::io::Measurement m;
    while (src.next(m)) {
    }
    (void)src.diagnostics().report();
  } catch (const RawlogError& e) {
    if (std::getenv("RGBDI_FUZZ_TRACE")) std::cerr << "  refused: " << e.what() << "\n";
  }
  return 0;
}

namespace rgbdi::fuzz {

std::vector<std::string> rgbdiFuzzSeeds() {
  using io::RawlogWriter;
  using io::RawlogWriterOptions;
  const std::string dir = scratchDir("rawlog_seeds");
  std::vector<std::string> seeds;
  int n = 0;
  for (const auto layout :
       {RawlogWriterOptions::Layout::Observations, RawlogWriterOptions::Layout::SensoryFrames})
    for (const bool gzip : {false, true}) {
      RawlogWriterOptions o;
      o.layout = layout;
      o.gzip = gzip;
      const std::string path = dir + "/s" + std::to_string(n++) + (gzip ? ".rawlog.gz" : ".rawlog");
      RawlogWriter w(path, o);
      for (int i = 0; i < 8; ++i) {
        ImuSample s;
        s.t = 100.0 + 0.005 * i;
        s.acc = Eigen::Vector3d(0.1, 0.0, 9.8);
        s.gyr = Eigen::Vector3d(0.0, 0.01, 0.0);
        w.write(s);
        if (i % 4 == 1) {
          RgbdFrame f;
          f.t = s.t;
          f.rgb = cv::Mat(6, 8, CV_8UC3, cv::Scalar(20, 40, 60));
          f.rgb.at<cv::Vec3b>(1, 1) = cv::Vec3b(200, 10, 0);
          f.depth = cv::Mat(6, 8, CV_16UC1, cv::Scalar(1200));
          f.depth_unit_m = 1e-3;
          f.cam_color.width = f.cam_depth.width = 8;
          f.cam_color.height = f.cam_depth.height = 6;
          f.cam_color.fx = f.cam_color.fy = f.cam_depth.fx = f.cam_depth.fy = 10.0;
          f.cam_color.cx = f.cam_depth.cx = 4.0;
          f.cam_color.cy = f.cam_depth.cy = 3.0;
          f.depth_aligned_to_color = true;
          w.write(f);
        }
      }
      w.close();
      seeds.push_back(readFileBytes(path));
    }
  std::filesystem::remove_all(dir);
  return seeds;
}

}  // namespace rgbdi::fuzz
