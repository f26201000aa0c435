#include "rgbdi/io/rawlog_writer.h"

#include <mrpt/img/CImage.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CObservation3DRangeScan.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/serialization/CArchive.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <mutex>

#include "io/rawlog_naming.h"
#include "rgbdi/common/atomic_file.h"
#include "rgbdi/io/mrpt_conversions.h"
#include "rgbdi/io/mrpt_image_path.h"

namespace rgbdi::io {

namespace fs = std::filesystem;

struct RawlogWriter::Stream {
  std::unique_ptr<mrpt::io::CStream> file;
  std::unique_ptr<mrpt::serialization::CArchive> archive;
};

RawlogWriter::RawlogWriter(const std::string& path, const RawlogWriterOptions& options)
    : path_(path), options_(options), stream_(std::make_unique<Stream>()) {
  // MRPT's convention, which RawlogSource (rawlogImagesDirectory) follows: "<dir>/<name>_Images".
  const fs::path p(path);
  images_dir_ = (p.parent_path() / (rawlogBaseName(p) + "_Images")).string();
  // As rgbdi-slam --out and rgbdi-sim --out: 'rawlog-convert BAG -o /new/dir/x.rawlog' works.
  if (!p.parent_path().empty()) {
    std::error_code ec;
    fs::create_directories(p.parent_path(), ec);
    if (ec)
      throw IoError(p.parent_path().string() +
                    ": cannot create the rawlog's directory: " + ec.message());
  }
  if (options_.external_images) {
    std::error_code ec;
    fs::create_directories(images_dir_, ec);
    if (ec) throw IoError(images_dir_ + ": cannot create image directory: " + ec.message());
  }
  tmp_path_ = path + ".tmp." + std::to_string(::getpid());
  bool ok = false;
  if (options_.gzip) {
    auto f = std::make_unique<mrpt::io::CFileGZOutputStream>();
    ok = f->open(tmp_path_);
    stream_->file = std::move(f);
  } else {
    auto f = std::make_unique<mrpt::io::CFileOutputStream>();
    ok = f->open(tmp_path_);
    stream_->file = std::move(f);
  }
  if (!ok) throw IoError(path + ": cannot create rawlog (temporary " + tmp_path_ + ")");
  stream_->archive =
      std::make_unique<mrpt::serialization::CArchiveStreamBase<mrpt::io::CStream>>(*stream_->file);
}

RawlogWriter::~RawlogWriter() {
  if (stream_) {
    stream_.reset();
    std::remove(tmp_path_.c_str());
  }
}

void RawlogWriter::writeRaw(const mrpt::serialization::CSerializable& obj) {
  if (!stream_) throw IoError(path_ + ": write after close()");
  try {
    stream_->archive->WriteObject(&obj);
  } catch (const std::exception& e) {
    throw IoError(path_ + ": cannot write record " + std::to_string(records_) + ": " + e.what());
  }
  ++records_;
}

void RawlogWriter::writeObservation(const mrpt::obs::CObservation::Ptr& obs) {
  if (options_.layout == RawlogWriterOptions::Layout::Observations) {
    writeRaw(*obs);
    return;
  }
  mrpt::obs::CActionCollection actions;
  mrpt::obs::CSensoryFrame sf;
  sf.insert(obs);
  writeRaw(actions);
  writeRaw(sf);
}

void RawlogWriter::write(const ImuSample& imu) {
  writeObservation(toMrpt(imu, options_.imu_label));
}

void RawlogWriter::write(const WheelOdometrySample& wheel) {
  writeObservation(toMrpt(wheel, options_.wheel_label));
}

void RawlogWriter::write(const RgbdFrame& frame) {
  auto obs = toMrpt(frame, options_.T_body_cam, options_.camera_label);
  if (options_.external_images) {
    const std::string stem = options_.camera_label + "_" + std::to_string(frames_);
    if (obs->hasIntensityImage) {
      const std::string name = stem + "_color.png";
      if (!obs->intensityImage.saveToFile(images_dir_ + "/" + name))
        throw IoError(images_dir_ + "/" + name + ": cannot write colour image");
      obs->intensityImage.setExternalStorage(name);  // relative to the image directory
    }
    if (obs->hasRangeImage) {
      try {
        // MRPT swaps its process-wide image directory while it writes the depth file.
        std::lock_guard<std::mutex> lock(mrptImagePathMutex());
        obs->rangeImage_convertToExternalStorage(stem + "_depth.bin", images_dir_);
      } catch (const std::exception& e) {
        throw IoError(images_dir_ + "/" + stem + "_depth.bin: cannot write depth: " + e.what());
      }
    }
  }
  ++frames_;
  writeObservation(obs);
}

void RawlogWriter::close() {
  if (!stream_) return;
  stream_->archive.reset();
  stream_->file.reset();  // flushes and closes
  stream_.reset();
  std::error_code ec;
  fs::rename(tmp_path_, path_, ec);
  if (ec) {
    std::remove(tmp_path_.c_str());
    throw IoError(path_ + ": cannot rename " + tmp_path_ + ": " + ec.message());
  }
}

}  // namespace rgbdi::io
