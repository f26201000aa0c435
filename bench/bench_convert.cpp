// bench_convert: throughput of rawlog-convert on ROS1 bags in the VINS-RGBD dataset layout.
//
// Writes bags with BagWriter (640x480 colour + aligned depth at 30 Hz, IMU and ground truth at
// 200 Hz; image content: smooth texture plus sensor-like noise, so compressors and JPEG see
// camera-like data), then times, per chunk compression:
//   read+decode  BagConverter into a sink that discards everything (bag reading, decompression,
//                deserialisation, image decoding, pairing)
//   convert      the full conversion into a rawlog with the images inside (MRPT 2.5 stores colour
//                raw: CImage::DISABLE_JPEG_COMPRESSION defaults to true), as rawlog-convert does
//   convert-ext  the same with --external-images (colour PNG files, depth MRPT range files)
// and prints MB/s of bag input and the time a 1.3 GB bag would take at that rate.
//
// Usage: bench_convert [MB of the uncompressed and lz4 bags, default 300] [MB of the bz2 bag,
//        default 60]
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <string>

#include "rgbdi/bag/bag_converter.h"
#include "rgbdi/bag/bag_writer.h"
#include "rgbdi/convert/dataset_conversion.h"

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double seconds(Clock::time_point a) {
  return std::chrono::duration<double>(Clock::now() - a).count();
}

struct NullSink : rgbdi::bag::ConversionSink {
  std::size_t n = 0;
  void imu(const rgbdi::ImuSample&) override { ++n; }
  void accelerometer(double, const Eigen::Vector3d&) override { ++n; }
  void frame(const rgbdi::RgbdFrame&) override { ++n; }
  void groundTruth(const rgbdi::StampedPose&) override { ++n; }
};

/// A few distinct camera-like frames, cycled.
std::vector<rgbdi::RgbdFrame> makeFrames() {
  std::vector<rgbdi::RgbdFrame> frames;
  std::mt19937_64 rng(1);
  std::normal_distribution<double> noise(0.0, 2.0);
  for (int k = 0; k < 6; ++k) {
    rgbdi::RgbdFrame f;
    f.rgb = cv::Mat(480, 640, CV_8UC3);
    f.depth = cv::Mat(480, 640, CV_16UC1);
    for (int r = 0; r < 480; ++r)
      for (int c = 0; c < 640; ++c) {
        const double base = 128 + 60 * std::sin(0.03 * c + 0.5 * k) * std::cos(0.02 * r) +
                            30 * ((r / 40 + c / 40 + k) % 2);
        for (int ch = 0; ch < 3; ++ch)
          f.rgb.at<cv::Vec3b>(r, c)[ch] = cv::saturate_cast<uchar>(base + 20 * ch + noise(rng));
        f.depth.at<std::uint16_t>(r, c) =
            (r * 7 + c * 3 + k) % 97 == 0
                ? 0
                : cv::saturate_cast<std::uint16_t>(1500 + 2 * r + std::abs(noise(rng)) * 4);
      }
    frames.push_back(f);
  }
  return frames;
}

void writeBag(const std::string& path, rgbdi::bag::Compression comp, double megabytes,
              const std::vector<rgbdi::RgbdFrame>& frames) {
  rgbdi::bag::BagWriter w(path, comp);
  const int n_frames = static_cast<int>(std::ceil(megabytes * 1e6 / (640.0 * 480 * 5)));
  const double t0 = 1.6e9;
  int frame = 0;
  for (int k = 0; frame < n_frames; ++k) {
    rgbdi::ImuSample s;
    s.t = t0 + 0.005 * k;
    s.acc = Eigen::Vector3d(0.1, -0.2, 9.81);
    s.gyr = Eigen::Vector3d(0.01, 0.02, 0.03);
    w.writeImu(s);
    w.writePose(s.t, Eigen::Isometry3d::Identity());
    if (k == 0 || (k * 30) / 200 != ((k - 1) * 30) / 200) {  // 30 Hz frames on the 200 Hz clock
      rgbdi::RgbdFrame f = frames[static_cast<std::size_t>(frame) % frames.size()];
      f.t = s.t;
      f.index = static_cast<std::uint64_t>(frame);
      w.writeRgbd(f);
      ++frame;
    }
  }
  w.close();
}

}  // namespace

int main(int argc, char** argv) {
  const double mb = argc > 1 ? std::atof(argv[1]) : 300.0;
  const double mb_bz2 = argc > 2 ? std::atof(argv[2]) : 60.0;
  const std::string dir =
      (fs::temp_directory_path() / ("bench_convert_" + std::to_string(::getpid()))).string();
  fs::create_directories(dir);
  const std::vector<rgbdi::RgbdFrame> frames = makeFrames();

  rgbdi::convert::ConversionSettings settings;  // built-in calibration: the 640x480 D435i
  std::printf("bench_convert: 640x480 colour + depth at 30 Hz, IMU + ground truth at 200 Hz\n");
  std::printf("%-5s %8s %8s | %-12s %8s %9s | %-12s %8s %9s | %-12s %8s %9s\n", "bag", "MB",
              "frames", "read+decode", "MB/s", "1.3GB [s]", "convert", "MB/s", "1.3GB [s]",
              "convert-ext", "MB/s", "1.3GB [s]");
  for (const auto comp : {rgbdi::bag::Compression::None, rgbdi::bag::Compression::Lz4,
                          rgbdi::bag::Compression::Bz2}) {
    const std::string name = rgbdi::bag::toString(comp);
    const std::string bag = dir + "/" + name + ".bag";
    writeBag(bag, comp, comp == rgbdi::bag::Compression::Bz2 ? mb_bz2 : mb, frames);
    const double bag_mb = static_cast<double>(fs::file_size(bag)) / 1e6;

    Clock::time_point start = Clock::now();
    rgbdi::bag::BagConverter reader(bag, settings.options, {}, settings.calibration);
    NullSink sink;
    const rgbdi::bag::ConversionReport decoded = reader.run(sink);
    const double t_read = seconds(start);

    double t_conv[2] = {0, 0};
    for (int ext = 0; ext < 2; ++ext) {
      rgbdi::convert::ConversionRequest q;
      q.input = bag;
      q.output = dir + "/" + name + (ext ? "_ext" : "") + ".rawlog";
      q.settings = settings;
      q.external_images = ext == 1;
      start = Clock::now();
      const rgbdi::bag::ConversionReport r = rgbdi::convert::convertDataset(q);
      t_conv[ext] = seconds(start);
      if (!r.ok()) std::fprintf(stderr, "bench_convert: %s\n", r.error.c_str());
      fs::remove_all(dir + "/" + name + "_ext_Images");
      fs::remove(q.output);
      fs::remove(dir + "/" + name + (ext ? "_ext" : "") + "_groundtruth.tum");
    }
    const auto rate = [&](double t) { return bag_mb / t; };
    std::printf("%-5s %8.1f %8zu | %-12s %8.1f %9.1f | %-12s %8.1f %9.1f | %-12s %8.1f %9.1f\n",
                name.c_str(), bag_mb, decoded.pairing.pairs, "", rate(t_read),
                1300.0 / rate(t_read), "", rate(t_conv[0]), 1300.0 / rate(t_conv[0]), "",
                rate(t_conv[1]), 1300.0 / rate(t_conv[1]));
    std::fflush(stdout);
    fs::remove(bag);
  }
  fs::remove_all(dir);
  return 0;
}
