// Keyframe store: ordering, pose updates, and the versioned binary file (bit-exact round trip,
// clear errors for every kind of damage, never a crash).
#include <dirent.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "rgbdi/common/atomic_file.h"
#include "rgbdi/mapping/keyframe_store.h"
#include "testing/fixtures.h"

using namespace rgbdi::mapping;

namespace {

Keyframe randomKeyframe(std::mt19937_64& rng, std::uint64_t id) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_int_distribution<int> byte(0, 255);
  Keyframe k;
  k.id = id;
  k.frame_index = 1000 + 3 * id;
  k.t = 1.7e9 + 0.1 * static_cast<double>(id) + 1e-7;
  k.T_world_cam.linear() =
      Eigen::AngleAxisd(3.0 * u(rng), Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized())
          .toRotationMatrix();
  k.T_world_cam.translation() = Eigen::Vector3d(u(rng), u(rng), u(rng)) * 50.0;
  for (int i = 0; i < 40; ++i) {
    KeyframeFeature f;
    f.id = 100000 + static_cast<std::uint64_t>(i) * 7 + id;
    f.uv = Eigen::Vector2d(320 + 300 * u(rng), 240 + 200 * u(rng)).cast<float>();
    f.has_position = i % 3 != 0;
    if (f.has_position) f.p_cam = Eigen::Vector3d(u(rng), u(rng), 2.0 + u(rng)).cast<float>();
    k.features.push_back(f);
  }
  k.descriptors.type = "BRIEF-256";
  k.descriptors.bytes_per_descriptor = 32;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (int i = 0; i < 25; ++i) {
    k.descriptors.keypoints_uv.emplace_back(static_cast<float>(320 + 300 * u(rng)),
                                            static_cast<float>(240 + 200 * u(rng)));
    for (int b = 0; b < 32; ++b) k.descriptors.data.push_back(static_cast<std::uint8_t>(byte(rng)));
    // Every fourth keypoint has no depth (NaN), the others a point.
    k.descriptors.keypoints_p_cam.push_back(
        i % 4 == 0 ? Eigen::Vector3f(nan, nan, nan)
                   : Eigen::Vector3d(u(rng), u(rng), 2.0 + u(rng)).cast<float>());
  }
  for (int i = 0; i < 500; ++i) {
    MapPoint p;
    p.p_cam = Eigen::Vector3d(u(rng), u(rng), 3.0 + u(rng)).cast<float>();
    p.rgb = {static_cast<std::uint8_t>(byte(rng)), static_cast<std::uint8_t>(byte(rng)),
             static_cast<std::uint8_t>(byte(rng))};
    k.points.push_back(p);
  }
  return k;
}

void expectIdentical(const Keyframe& a, const Keyframe& b) {
  EXPECT_EQ(a.id, b.id);
  EXPECT_EQ(a.frame_index, b.frame_index);
  EXPECT_EQ(a.t, b.t);
  EXPECT_EQ(a.T_world_cam.matrix(), b.T_world_cam.matrix());
  ASSERT_EQ(a.features.size(), b.features.size());
  for (std::size_t i = 0; i < a.features.size(); ++i) {
    EXPECT_EQ(a.features[i].id, b.features[i].id);
    EXPECT_EQ(a.features[i].uv, b.features[i].uv);
    EXPECT_EQ(a.features[i].has_position, b.features[i].has_position);
    EXPECT_EQ(a.features[i].p_cam, b.features[i].p_cam);
  }
  EXPECT_EQ(a.descriptors.type, b.descriptors.type);
  EXPECT_EQ(a.descriptors.bytes_per_descriptor, b.descriptors.bytes_per_descriptor);
  EXPECT_EQ(a.descriptors.keypoints_uv, b.descriptors.keypoints_uv);
  EXPECT_EQ(a.descriptors.data, b.descriptors.data);
  ASSERT_EQ(a.descriptors.keypoints_p_cam.size(), b.descriptors.keypoints_p_cam.size());
  for (std::size_t i = 0; i < a.descriptors.keypoints_p_cam.size(); ++i) {
    // Bit-exact, NaN (no depth) included.
    EXPECT_EQ(std::memcmp(a.descriptors.keypoints_p_cam[i].data(),
                          b.descriptors.keypoints_p_cam[i].data(), sizeof(Eigen::Vector3f)),
              0)
        << "keypoint point " << i;
    EXPECT_EQ(a.descriptors.hasPoint(i), b.descriptors.hasPoint(i));
  }
  ASSERT_EQ(a.points.size(), b.points.size());
  for (std::size_t i = 0; i < a.points.size(); ++i) {
    EXPECT_EQ(a.points[i].p_cam, b.points[i].p_cam);
    EXPECT_EQ(a.points[i].rgb, b.points[i].rgb);
  }
}

std::vector<char> readBytes(const std::string& path) {
  std::ifstream is(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(is), std::istreambuf_iterator<char>()};
}

void writeBytes(const std::string& path, const std::vector<char>& bytes) {
  std::ofstream os(path, std::ios::binary | std::ios::trunc);
  os.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

std::string loadError(const std::string& path) {
  try {
    KeyframeStore::load(path);
  } catch (const KeyframeFileError& e) {
    return e.what();
  }
  return "";
}

std::vector<std::string> filesIn(const std::string& dir) {
  std::vector<std::string> names;
  if (DIR* d = opendir(dir.c_str())) {
    while (dirent* e = readdir(d))
      if (std::string(e->d_name) != "." && std::string(e->d_name) != "..")
        names.push_back(e->d_name);
    closedir(d);
  }
  return names;
}

}  // namespace

TEST(KeyframeStore, KeepsKeyframesOrderedByIdAndRejectsInvalidOnes) {
  KeyframeStore store;
  for (std::uint64_t id : {5u, 2u, 9u, 7u}) {
    Keyframe k;
    k.id = id;
    k.t = static_cast<double>(id);
    store.add(k);
  }
  ASSERT_EQ(store.size(), 4u);
  EXPECT_EQ(store.at(0).id, 2u);
  EXPECT_EQ(store.at(1).id, 5u);
  EXPECT_EQ(store.at(2).id, 7u);
  EXPECT_EQ(store.at(3).id, 9u);
  EXPECT_TRUE(store.contains(7));
  EXPECT_FALSE(store.contains(6));
  EXPECT_EQ(store.get(9).t, 9.0);
  EXPECT_THROW(store.get(6), std::out_of_range);

  Keyframe dup;
  dup.id = 5;
  EXPECT_THROW(store.add(dup), std::invalid_argument);
  Keyframe scaled;
  scaled.id = 11;
  scaled.T_world_cam.linear() *= 2.0;
  EXPECT_THROW(store.add(scaled), std::invalid_argument);
  Keyframe bad_desc;
  bad_desc.id = 12;
  bad_desc.descriptors.bytes_per_descriptor = 32;
  bad_desc.descriptors.keypoints_uv.resize(2);
  bad_desc.descriptors.data.resize(63);
  try {
    store.add(bad_desc);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("keyframe 12"), std::string::npos) << e.what();
  }
  EXPECT_EQ(store.size(), 4u);
}

TEST(KeyframeStore, PoseUpdatesAreCountedAndValidated) {
  KeyframeStore store;
  Keyframe k;
  k.id = 3;
  store.add(k);
  EXPECT_EQ(store.poseRevision(), 0u);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(1, 2, 3);
  store.setPose(3, T);
  EXPECT_EQ(store.poseRevision(), 1u);
  EXPECT_EQ(store.get(3).T_world_cam.translation(), Eigen::Vector3d(1, 2, 3));
  EXPECT_THROW(store.setPose(4, T), std::out_of_range);
  T.translation().x() = std::nan("");
  EXPECT_THROW(store.setPose(3, T), std::invalid_argument);
  EXPECT_EQ(store.poseRevision(), 1u);
  const rgbdi::Trajectory traj = store.cameraTrajectory();
  ASSERT_EQ(traj.size(), 1u);
  EXPECT_EQ(traj[0].p, Eigen::Vector3d(1, 2, 3));
}

TEST(KeyframeStore, SaveLoadRoundTripIsBitExact) {
  std::mt19937_64 rng(5);
  KeyframeStore store;
  for (std::uint64_t id = 0; id < 12; ++id) store.add(randomKeyframe(rng, id * 4 + 1));
  Keyframe no_depth = randomKeyframe(rng, 900);  // descriptors without any 3-D information
  no_depth.descriptors.keypoints_p_cam.clear();
  store.add(no_depth);
  Keyframe empty;  // no features, descriptors or points
  empty.id = 1000;
  store.add(empty);
  const std::string dir = rgbdi::test::makeTempDir("rgbdi_kfs");
  const std::string path = dir + "/keyframes.rgbdikf";
  store.save(path);
  EXPECT_EQ(filesIn(dir), std::vector<std::string>{"keyframes.rgbdikf"});  // no temporary left
  const KeyframeStore loaded = KeyframeStore::load(path);
  ASSERT_EQ(loaded.size(), store.size());
  for (std::size_t s = 0; s < store.size(); ++s) expectIdentical(store.at(s), loaded.at(s));
  EXPECT_FALSE(loaded.at(0).descriptors.hasPoint(0));  // the NaN marks survived
  EXPECT_TRUE(loaded.at(0).descriptors.hasPoint(1));
  EXPECT_TRUE(loaded.get(900).descriptors.keypoints_p_cam.empty());
  EXPECT_EQ(loaded.pointCount(), store.pointCount());
  // An empty store round-trips too.
  KeyframeStore().save(path);
  EXPECT_TRUE(KeyframeStore::load(path).empty());
}

TEST(KeyframeStore, DamagedFilesAreReportedWithFileRecordAndReason) {
  std::mt19937_64 rng(9);
  KeyframeStore store;
  for (std::uint64_t id = 0; id < 3; ++id) store.add(randomKeyframe(rng, id));
  const std::string dir = rgbdi::test::makeTempDir("rgbdi_kfs_bad");
  const std::string good = dir + "/good.kf", bad = dir + "/bad.kf";
  store.save(good);
  const std::vector<char> bytes = readBytes(good);

  EXPECT_NE(loadError(dir + "/missing.kf").find("missing.kf: cannot open"), std::string::npos);

  std::vector<char> b = bytes;
  b[0] = 'X';
  writeBytes(bad, b);
  EXPECT_NE(loadError(bad).find("signature"), std::string::npos) << loadError(bad);

  // A version-1 file (no keypoint points) is refused with the version this build reads.
  b = bytes;
  b[8] = 1;  // version field
  writeBytes(bad, b);
  EXPECT_NE(loadError(bad).find("unsupported format version 1 (this build reads version 2)"),
            std::string::npos)
      << loadError(bad);

  b = bytes;
  b.push_back('x');
  writeBytes(bad, b);
  EXPECT_NE(loadError(bad).find("1 unexpected bytes"), std::string::npos) << loadError(bad);

  // Cutting the file anywhere gives a KeyframeFileError naming the file (never a crash or a
  // huge allocation); a cut inside the second record names that record.
  const std::size_t record_bytes = (bytes.size() - 20) / 3;
  for (std::size_t n = 0; n < bytes.size(); n += (n < 200 ? 1 : 499)) {
    writeBytes(bad, std::vector<char>(bytes.begin(), bytes.begin() + static_cast<long>(n)));
    const std::string e = loadError(bad);
    ASSERT_NE(e.find(bad), std::string::npos) << "cut at " << n << ": " << e;
  }
  writeBytes(bad, std::vector<char>(bytes.begin(),
                                    bytes.begin() + static_cast<long>(20 + record_bytes + 200)));
  const std::string cut = loadError(bad);
  EXPECT_NE(cut.find("keyframe record 1 (id 1)"), std::string::npos) << cut;
  EXPECT_NE(cut.find("truncated"), std::string::npos) << cut;

  // A corrupt count must be reported, not allocated: set keyframe 0's feature count to 2^32-1.
  b = bytes;
  const std::size_t nf_offset = 20 + 4 + 8 + 8 + 8 + 96;
  for (int i = 0; i < 4; ++i) b[nf_offset + static_cast<std::size_t>(i)] = static_cast<char>(0xFF);
  writeBytes(bad, b);
  EXPECT_NE(loadError(bad).find("features announced"), std::string::npos) << loadError(bad);

  // The keypoint point count must be 0 or the keypoint count; a point must be finite or all
  // NaN. Offsets of keyframe 0's descriptor section: type "BRIEF-256" (9 bytes), 25 keypoints.
  const std::size_t n3_offset =
      nf_offset + 4 + 40 * (8 + 16 + 1 + 24) + 4 + 9 + 4 + 4 + 25 * 8 + 25 * 32;
  std::uint32_t n3;
  std::memcpy(&n3, &bytes[n3_offset], 4);
  ASSERT_EQ(n3, 25u);  // the layout assumed above
  b = bytes;
  b[n3_offset] = 7;
  writeBytes(bad, b);
  EXPECT_NE(loadError(bad).find("keyframe record 0 (id 0): 7 keypoint points for 25 keypoints"),
            std::string::npos)
      << loadError(bad);
  b = bytes;
  const float inf = std::numeric_limits<float>::infinity();
  std::memcpy(&b[n3_offset + 4 + 12 + 4], &inf, 4);  // keypoint 1's y
  writeBytes(bad, b);
  EXPECT_NE(loadError(bad).find("neither finite nor absent"), std::string::npos) << loadError(bad);
  b = bytes;
  const float half_nan = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(&b[n3_offset + 4 + 12], &half_nan, 4);  // keypoint 1's x only
  writeBytes(bad, b);
  EXPECT_NE(loadError(bad).find("neither finite nor absent"), std::string::npos) << loadError(bad);

  // A non-rigid pose (scaled rotation) is refused with the record's id.
  b = bytes;
  double scaled;
  std::memcpy(&scaled, &b[20 + 4 + 8 + 8 + 8], 8);
  scaled *= 3.0;
  std::memcpy(&b[20 + 4 + 8 + 8 + 8], &scaled, 8);
  writeBytes(bad, b);
  EXPECT_NE(loadError(bad).find("keyframe record 0 (id 0): pose is not a finite rigid transform"),
            std::string::npos)
      << loadError(bad);
}

TEST(KeyframeStore, MemoryHoldsPointsAndFeaturesButNoImages) {
  std::mt19937_64 rng(1);
  KeyframeStore store;
  const std::size_t empty_bytes = store.memoryBytes();
  store.add(randomKeyframe(rng, 0));
  const std::size_t one = store.memoryBytes() - empty_bytes;
  // 500 points x 16 B + 40 features + 25 descriptors of 32 B: a few tens of kB, while a
  // 640x480 colour + depth pair is 1.5 MB.
  EXPECT_GE(one, 500 * sizeof(MapPoint) + 40 * sizeof(KeyframeFeature) + 25 * 32);
  EXPECT_LT(one, 20000u);
  std::vector<MapPoint> fewer(store.at(0).points.begin(), store.at(0).points.begin() + 100);
  store.replacePoints(0, fewer);
  EXPECT_EQ(store.pointCount(), 100u);
}

TEST(KeyframeStore, StoredKeyframesKeepNoSpareCapacity) {
  Keyframe kf;
  kf.id = 3;
  for (int i = 0; i < 150; ++i) kf.features.push_back(KeyframeFeature{});  // capacity 256
  for (int i = 0; i < 300; ++i) kf.points.push_back(MapPoint{});           // capacity 512
  ASSERT_GT(kf.features.capacity(), 150u);
  KeyframeStore store;
  store.add(kf);
  EXPECT_EQ(store.at(0).features.capacity(), 150u);
  EXPECT_EQ(store.at(0).points.capacity(), 300u);
  EXPECT_EQ(store.memoryBytes() - KeyframeStore().memoryBytes() - sizeof(Keyframe) -
                store.at(0).descriptors.type.capacity(),  // the empty string's inline buffer
            150 * sizeof(KeyframeFeature) + 300 * sizeof(MapPoint));
}

TEST(KeyframeStore, SaveIntoAMissingDirectoryFailsWithThePath) {
  KeyframeStore store;
  try {
    store.save("/nonexistent_dir_rgbdi/keyframes.kf");
    FAIL();
  } catch (const rgbdi::IoError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent_dir_rgbdi/keyframes.kf"), std::string::npos);
  }
}
