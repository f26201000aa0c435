// Fuzz target: ROS1 bag files (records, chunks: uncompressed, bz2, lz4; the index, or recovery
// by scanning the chunks) read by bag::BagReader, every message delivered. Documented refusal:
// BagError (and its BagReadError at damage).
#include <filesystem>

#include "fuzz_target.h"
#include "rgbdi/bag/bag_reader.h"
#include "rgbdi/bag/bag_writer.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace rgbdi::bag;
  const std::string path = rgbdi::fuzz::writeScratchFile("bag.bag", data, size);
  try {
    BagReader reader(path);
    (void)reader.topics();
    BagMessage m;
    std::uint64_t sum = 0;
    while (reader.next(m)) {
      for (std::uint32_t i = 0; i < m.size; ++i) sum += m.data[i];  // touch every byte
    }
    (void)sum;
  } catch (const BagError&) {
  }
  return 0;
}

namespace rgbdi::fuzz {

std::vector<std::string> rgbdiFuzzSeeds() {
  using namespace bag;
  const std::string dir = scratchDir("bag_seeds");
  std::vector<std::string> seeds;
  for (const Compression c : {Compression::None, Compression::Bz2, Compression::Lz4}) {
    const std::string path = dir + "/s" + toString(c) + ".bag";
    BagWriter w(path, c);
    for (int i = 0; i < 6; ++i) {
      ImuSample s;
      s.t = 100.0 + 0.005 * i;
      s.acc = Eigen::Vector3d(0.1, 0.0, 9.8);
      s.gyr = Eigen::Vector3d(0.0, 0.01, 0.0);
      w.writeImu(s);
    }
    RgbdFrame f;
    f.t = 100.01;
    f.rgb = cv::Mat(4, 6, CV_8UC3, cv::Scalar(20, 40, 60));
    f.depth = cv::Mat(4, 6, CV_16UC1, cv::Scalar(1200));
    f.depth_unit_m = 1e-3;
    f.cam_color.width = f.cam_depth.width = 6;
    f.cam_color.height = f.cam_depth.height = 4;
    f.cam_color.fx = f.cam_color.fy = f.cam_depth.fx = f.cam_depth.fy = 10.0;
    f.depth_aligned_to_color = true;
    w.writeRgbd(f);
    w.writePose(100.02, Eigen::Isometry3d::Identity());
    w.close();
    seeds.push_back(readFileBytes(path));
  }
  std::filesystem::remove_all(dir);
  return seeds;
}

}  // namespace rgbdi::fuzz
