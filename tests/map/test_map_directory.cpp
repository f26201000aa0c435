// The saved map directory: bit-exact round trip of every field, the tools' files read back by
// MRPT / OctoMap / a PLY header, every refusal case with its message, the replacement of an
// earlier version, and crash safety (a saving process killed with SIGKILL at every step and at
// random moments leaves a directory that loads as the old or the new map).
#include <gtest/gtest.h>
#include <mrpt/graphs/CNetworkOfPoses.h>
#include <octomap/OcTree.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "rgbdi/map/map_directory.h"
#include "testing/fixtures.h"

using namespace rgbdi;
using namespace rgbdi::map;

namespace {

Eigen::Isometry3d randomPose(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(3.0 * u(rng), Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized())
                   .toRotationMatrix();
  T.translation() = Eigen::Vector3d(u(rng), u(rng), u(rng)) * 20.0;
  return T;
}

mapping::DescriptorSet randomDescriptors(std::mt19937_64& rng, int n, bool with_points) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_int_distribution<int> byte(0, 255);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  mapping::DescriptorSet d;
  d.type = "ORB-256";
  d.bytes_per_descriptor = 32;
  for (int i = 0; i < n; ++i) {
    d.keypoints_uv.emplace_back(static_cast<float>(320 + 300 * u(rng)),
                                static_cast<float>(240 + 200 * u(rng)));
    for (int b = 0; b < 32; ++b) d.data.push_back(static_cast<std::uint8_t>(byte(rng)));
    if (with_points)
      d.keypoints_p_cam.push_back(i % 5 == 0
                                      ? Eigen::Vector3f(nan, nan, nan)
                                      : Eigen::Vector3d(u(rng), u(rng), 2 + u(rng)).cast<float>());
  }
  return d;
}

/// A map with two segments, active and rolled-back loops, places with and without keypoint
/// points, a place without keypoints, store keyframes with features and kept points.
MapData syntheticMap(std::uint64_t seed, int places = 9, int keypoints = 30) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  MapData m;
  MapManifest& mf = m.manifest;
  mf.camera.width = 640;
  mf.camera.height = 480;
  mf.camera.fx = 615.123456789012;
  mf.camera.fy = 614.987654321098;
  mf.camera.cx = 319.5 + 1e-9;
  mf.camera.cy = 241.25;
  mf.camera.dist = {0.1234567890123, -0.25, 1e-4, -2e-4, 0.0123};
  mf.T_body_cam = randomPose(rng);
  mf.has_groundtruth_alignment = true;
  mf.T_groundtruth_world = randomPose(rng);
  mf.descriptor_type = "ORB-256";
  mf.descriptor_bytes = 32;
  mf.next_segment = 2;
  mf.sessions = 1;
  mf.index_parameters = "place_min_score = 0.05\nplace_candidates = 4\n";
  double travelled = 0.0;
  for (int i = 0; i < places; ++i) {
    loop::LoopKeyframe p;
    p.id = 3 + 7 * static_cast<std::uint64_t>(i);
    p.segment = i < places / 2 ? 0 : 1;
    p.t = 1.7e9 + 0.4 * i + 1e-7;
    p.T_world_body_odom = randomPose(rng);
    p.T_world_body = randomPose(rng);
    travelled += 0.3 + 0.1 * u(rng);
    p.travelled_m = travelled;
    if (i == 2) {
      p.descriptors.type = "ORB-256";  // a keyframe without colour: no keypoints
      p.descriptors.bytes_per_descriptor = 32;
    } else {
      p.descriptors = randomDescriptors(rng, keypoints, i != 4);
    }
    m.places.push_back(p);
  }
  mf.next_keyframe_id = m.places.back().id + 5;
  for (int i = 0; i + 4 < places; i += 2) {
    MapLoopEdge e;
    e.from_id = m.places[static_cast<std::size_t>(i)].id;
    e.to_id = m.places[static_cast<std::size_t>(i + 4)].id;
    e.T_from_to = randomPose(rng);
    e.active = i != 2;
    m.loops.push_back(e);
  }
  for (int i = 0; i < places + 2; ++i) {
    mapping::Keyframe k;
    k.id = 3 + 7 * static_cast<std::uint64_t>(i) / 2 * 2;  // some ids shared with places
    if (m.keyframes.contains(k.id)) continue;
    k.frame_index = 10 * static_cast<std::uint64_t>(i);
    k.t = 1.7e9 + 0.2 * i;
    k.T_world_cam = randomPose(rng);
    for (int f = 0; f < 20; ++f) {
      mapping::KeyframeFeature kf;
      kf.id = 1000 + static_cast<std::uint64_t>(f);
      kf.uv = Eigen::Vector2d(300 + 200 * u(rng), 200 + 150 * u(rng)).cast<float>();
      kf.has_position = f % 3 != 0;
      if (kf.has_position) kf.p_cam = Eigen::Vector3d(u(rng), u(rng), 2 + u(rng)).cast<float>();
      k.features.push_back(kf);
    }
    for (int q = 0; q < 50; ++q) {
      mapping::MapPoint mp;
      mp.p_cam = Eigen::Vector3d(u(rng), u(rng), 3 + u(rng)).cast<float>();
      mp.rgb = {static_cast<std::uint8_t>(q), static_cast<std::uint8_t>(2 * q), 7};
      k.points.push_back(mp);
    }
    if (i == 1) k.descriptors = randomDescriptors(rng, 10, true);
    m.keyframes.add(k);
  }
  mf.next_keyframe_id = std::max(mf.next_keyframe_id, m.keyframes.keyframes().back().id + 1);
  return m;
}

bool sameBits(const Eigen::Vector3f& a, const Eigen::Vector3f& b) {
  return std::memcmp(a.data(), b.data(), sizeof a) == 0;
}

void expectSameDescriptors(const mapping::DescriptorSet& a, const mapping::DescriptorSet& b) {
  EXPECT_EQ(a.type, b.type);
  EXPECT_EQ(a.bytes_per_descriptor, b.bytes_per_descriptor);
  EXPECT_EQ(a.keypoints_uv, b.keypoints_uv);
  EXPECT_EQ(a.data, b.data);
  ASSERT_EQ(a.keypoints_p_cam.size(), b.keypoints_p_cam.size());
  for (std::size_t i = 0; i < a.keypoints_p_cam.size(); ++i)
    EXPECT_TRUE(sameBits(a.keypoints_p_cam[i], b.keypoints_p_cam[i])) << "keypoint point " << i;
}

void expectSameMap(const MapData& a, const MapData& b) {
  const MapManifest &x = a.manifest, &y = b.manifest;
  EXPECT_EQ(x.format_version, y.format_version);
  EXPECT_EQ(x.camera.width, y.camera.width);
  EXPECT_EQ(x.camera.height, y.camera.height);
  EXPECT_EQ(x.camera.fx, y.camera.fx);
  EXPECT_EQ(x.camera.fy, y.camera.fy);
  EXPECT_EQ(x.camera.cx, y.camera.cx);
  EXPECT_EQ(x.camera.cy, y.camera.cy);
  EXPECT_EQ(x.camera.dist, y.camera.dist);
  EXPECT_EQ(x.T_body_cam.matrix(), y.T_body_cam.matrix());
  EXPECT_EQ(x.has_groundtruth_alignment, y.has_groundtruth_alignment);
  EXPECT_EQ(x.T_groundtruth_world.matrix(), y.T_groundtruth_world.matrix());
  EXPECT_EQ(x.descriptor_type, y.descriptor_type);
  EXPECT_EQ(x.descriptor_bytes, y.descriptor_bytes);
  EXPECT_EQ(x.next_keyframe_id, y.next_keyframe_id);
  EXPECT_EQ(x.next_segment, y.next_segment);
  EXPECT_EQ(x.sessions, y.sessions);
  EXPECT_EQ(x.index_parameters, y.index_parameters);
  EXPECT_EQ(x.world_frame, y.world_frame);
  EXPECT_EQ(x.pose_convention, y.pose_convention);

  ASSERT_EQ(a.places.size(), b.places.size());
  for (std::size_t i = 0; i < a.places.size(); ++i) {
    SCOPED_TRACE("place " + std::to_string(i));
    const loop::LoopKeyframe &p = a.places[i], &q = b.places[i];
    EXPECT_EQ(p.id, q.id);
    EXPECT_EQ(p.segment, q.segment);
    EXPECT_EQ(p.t, q.t);
    EXPECT_EQ(p.T_world_body_odom.matrix(), q.T_world_body_odom.matrix());
    EXPECT_EQ(p.T_world_body.matrix(), q.T_world_body.matrix());
    EXPECT_EQ(p.travelled_m, q.travelled_m);
    expectSameDescriptors(p.descriptors, q.descriptors);
  }
  ASSERT_EQ(a.loops.size(), b.loops.size());
  for (std::size_t i = 0; i < a.loops.size(); ++i) {
    EXPECT_EQ(a.loops[i].from_id, b.loops[i].from_id);
    EXPECT_EQ(a.loops[i].to_id, b.loops[i].to_id);
    EXPECT_EQ(a.loops[i].T_from_to.matrix(), b.loops[i].T_from_to.matrix());
    EXPECT_EQ(a.loops[i].active, b.loops[i].active);
  }
  ASSERT_EQ(a.keyframes.size(), b.keyframes.size());
  for (std::size_t i = 0; i < a.keyframes.size(); ++i) {
    SCOPED_TRACE("store keyframe " + std::to_string(i));
    const mapping::Keyframe &k = a.keyframes.at(i), &l = b.keyframes.at(i);
    EXPECT_EQ(k.id, l.id);
    EXPECT_EQ(k.frame_index, l.frame_index);
    EXPECT_EQ(k.t, l.t);
    EXPECT_EQ(k.T_world_cam.matrix(), l.T_world_cam.matrix());
    ASSERT_EQ(k.features.size(), l.features.size());
    for (std::size_t f = 0; f < k.features.size(); ++f) {
      EXPECT_EQ(k.features[f].id, l.features[f].id);
      EXPECT_EQ(k.features[f].uv, l.features[f].uv);
      EXPECT_EQ(k.features[f].has_position, l.features[f].has_position);
      EXPECT_EQ(k.features[f].p_cam, l.features[f].p_cam);
    }
    expectSameDescriptors(k.descriptors, l.descriptors);
    ASSERT_EQ(k.points.size(), l.points.size());
    for (std::size_t q = 0; q < k.points.size(); ++q) {
      EXPECT_EQ(k.points[q].p_cam, l.points[q].p_cam);
      EXPECT_EQ(k.points[q].rgb, l.points[q].rgb);
    }
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

/// FNV-1a 64 written here independently of the library (known answers checked below).
std::uint64_t fnv1a64(const std::vector<char>& bytes) {
  std::uint64_t h = 14695981039346656037ull;
  for (char c : bytes) {
    h ^= static_cast<unsigned char>(c);
    h *= 1099511628211ull;
  }
  return h;
}

std::string hex(std::uint64_t v) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(v));
  return buf;
}

nlohmann::json readManifest(const std::string& dir) {
  const std::vector<char> b = readBytes(dir + "/manifest.json");
  return nlohmann::json::parse(std::string(b.begin(), b.end()));
}

void writeManifest(const std::string& dir, const nlohmann::json& j) {
  const std::string s = j.dump(2);
  writeBytes(dir + "/manifest.json", std::vector<char>(s.begin(), s.end()));
}

/// After editing a data file on purpose: the manifest's size and checksum follow, so that the
/// file's own checks (signature, counts, ...) are what loadMap reports.
void resealFile(const std::string& dir, const std::string& name) {
  nlohmann::json j = readManifest(dir);
  const std::vector<char> b = readBytes(dir + "/" + name);
  j["files"][name]["bytes"] = b.size();
  j["files"][name]["fnv1a64"] = hex(fnv1a64(b));
  writeManifest(dir, j);
}

std::string loadError(const std::string& dir) {
  try {
    loadMap(dir);
  } catch (const MapError& e) {
    return e.what();
  }
  return "(no error)";
}

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

std::vector<std::string> entriesOf(const std::string& dir) {
  std::vector<std::string> names;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace

TEST(MapDirectory, RoundTripOfASyntheticMapIsExactInEveryField) {
  const MapData m = syntheticMap(1);
  const std::string dir = test::makeTempDir("rgbdi_map") + "/map";
  saveMap(dir, m);
  const MapData r = loadMap(dir);
  expectSameMap(m, r);
  // An empty map (a run that never made a keyframe) round-trips too.
  MapData empty;
  empty.manifest = m.manifest;
  empty.manifest.next_keyframe_id = 0;
  empty.manifest.next_segment = 0;
  saveMap(dir, empty);
  expectSameMap(empty, loadMap(dir));
}

TEST(MapDirectory, ManifestRecordsEveryFieldCountsAndTheSizeAndChecksumOfEveryFile) {
  // Known answers of FNV-1a 64 (the test's own implementation).
  EXPECT_EQ(fnv1a64({}), 0xcbf29ce484222325ull);
  EXPECT_EQ(fnv1a64({'a'}), 0xaf63dc4c8601ec8cull);
  EXPECT_EQ(fnv1a64({'f', 'o', 'o', 'b', 'a', 'r'}), 0x85944171f73967e8ull);

  const MapData m = syntheticMap(2);
  const std::string dir = test::makeTempDir("rgbdi_map") + "/map";
  saveMap(dir, m);
  const nlohmann::json j = readManifest(dir);
  EXPECT_EQ(j["format"], "rgbdi-map");
  EXPECT_EQ(j["format_version"], kMapFormatVersion);
  EXPECT_EQ(j["descriptor_type"], "ORB-256");
  EXPECT_EQ(j["descriptor_bytes"], 32);
  EXPECT_EQ(j["camera"]["fx"].get<double>(), m.manifest.camera.fx);
  EXPECT_EQ(j["counts"]["places"], 9);
  EXPECT_EQ(j["counts"]["place_keypoints"], 8 * 30);
  EXPECT_EQ(j["counts"]["loops"], m.loops.size());
  EXPECT_EQ(j["counts"]["keyframes"], m.keyframes.size());
  EXPECT_EQ(j["counts"]["keyframe_points"], m.keyframes.pointCount());
  std::vector<std::string> listed;
  for (auto it = j["files"].begin(); it != j["files"].end(); ++it) {
    listed.push_back(it.key());
    const std::vector<char> b = readBytes(dir + "/" + it.key());
    EXPECT_EQ(it.value()["bytes"].get<std::uint64_t>(), b.size()) << it.key();
    EXPECT_EQ(it.value()["fnv1a64"].get<std::string>(), hex(fnv1a64(b))) << it.key();
  }
  EXPECT_EQ(listed, (std::vector<std::string>{"keyframes.bin", "loops.txt", "places.bin",
                                              "pose_graph.graph"}));
  EXPECT_EQ(entriesOf(dir), (std::vector<std::string>{"keyframes.bin", "loops.txt", "manifest.json",
                                                      "places.bin", "pose_graph.graph"}));
  // loops.txt: documented header, one line per edge.
  const std::vector<char> lb = readBytes(dir + "/loops.txt");
  const std::string loops(lb.begin(), lb.end());
  EXPECT_EQ(loops.rfind("# rgbdi map loop edges, version 1\n", 0), 0u) << loops;
  EXPECT_EQ(static_cast<std::size_t>(std::count(loops.begin(), loops.end(), '\n')),
            4 + m.loops.size());
  EXPECT_TRUE(contains(loops, "\n" + std::to_string(m.loops[1].from_id) + " " +
                                  std::to_string(m.loops[1].to_id) + " 0 "))
      << loops;
}

TEST(MapDirectory, ToolsFilesAreWrittenAndReadBackByMrptOctomapAndAPlyReader) {
  MapData m = syntheticMap(3);
  mapping::MappingOptions mo;
  mapping::PointMap points(mo);
  mapping::OccupancyMap occupancy(mo);
  for (const mapping::Keyframe& k : m.keyframes.keyframes()) {
    points.insertPoints(k.points, k.T_world_cam);
    occupancy.insertPoints(k.points, k.T_world_cam);
  }
  ASSERT_GT(points.pointCount(), 100u);
  MapExtras extras;
  extras.point_map = &points;
  extras.occupancy = &occupancy;
  extras.odometry_information = Eigen::Matrix<double, 6, 6>::Identity() * 1e4;
  extras.loop_information = Eigen::Matrix<double, 6, 6>::Identity() * 400.0;
  const std::string dir = test::makeTempDir("rgbdi_map") + "/map";
  saveMap(dir, m, extras);

  // pose_graph.graph in MRPT: one node per place, odometry edges within segments, active loops.
  mrpt::graphs::CNetworkOfPoses3DInf g;
  g.loadFromTextFile(dir + "/pose_graph.graph", false);
  EXPECT_EQ(g.nodes.size(), m.places.size());
  std::size_t active = 0;
  for (const MapLoopEdge& e : m.loops) active += e.active;
  const std::size_t odometry = (m.places.size() - 1) - 1;  // one segment change
  EXPECT_EQ(g.edges.size(), odometry + active);
  for (const loop::LoopKeyframe& p : m.places) {
    ASSERT_TRUE(g.nodes.count(p.id)) << p.id;
    const mrpt::poses::CPose3D& n = g.nodes.at(p.id);
    EXPECT_NEAR(n.x(), p.T_world_body.translation().x(), 1e-9);
    EXPECT_NEAR(n.z(), p.T_world_body.translation().z(), 1e-9);
  }
  const output::PoseGraph ours = output::readPoseGraph(dir + "/pose_graph.graph");
  ASSERT_EQ(ours.edges.size(), odometry + active);
  const output::PoseGraphEdge& e01 = ours.edges.front();
  EXPECT_EQ(e01.from, m.places[0].id);
  EXPECT_EQ(e01.to, m.places[1].id);
  EXPECT_TRUE(e01.T_from_to.isApprox(
      m.places[0].T_world_body_odom.inverse() * m.places[1].T_world_body_odom, 1e-12));
  EXPECT_NEAR(e01.information(0, 0), 1e4, 1e-6);

  // map.bt in OctoMap with the same leaves.
  octomap::OcTree tree(0.1);
  ASSERT_TRUE(tree.readBinary(dir + "/map.bt"));
  EXPECT_EQ(tree.getNumLeafNodes(), occupancy.tree().getNumLeafNodes());

  // points.ply: the header announces every point of the map, the body holds them.
  const std::vector<char> ply = readBytes(dir + "/points.ply");
  const std::string text(ply.begin(), ply.end());
  const std::size_t end = text.find("end_header\n");
  ASSERT_NE(end, std::string::npos);
  EXPECT_EQ(text.rfind("ply\nformat binary_little_endian 1.0\n", 0), 0u);
  EXPECT_TRUE(contains(text.substr(0, end),
                       "element vertex " + std::to_string(points.pointCount()) + "\n"));
  EXPECT_EQ(ply.size() - (end + 11), points.pointCount() * 15);

  // The tools' files are listed with size and checksum but not needed by loadMap.
  const nlohmann::json j = readManifest(dir);
  EXPECT_TRUE(j["files"].contains("points.ply"));
  EXPECT_TRUE(j["files"].contains("map.bt"));
  expectSameMap(m, loadMap(dir));
}

TEST(MapDirectory, RefusesAnotherFormatVersionNamingTheManifest) {
  const std::string dir = test::makeTempDir("rgbdi_map") + "/map";
  saveMap(dir, syntheticMap(4));
  nlohmann::json j = readManifest(dir);
  j["format_version"] = kMapFormatVersion + 1;
  j.erase("camera");  // another version may have other keys: the version is checked first
  writeManifest(dir, j);
  const std::string e = loadError(dir);
  EXPECT_TRUE(contains(e, "manifest.json")) << e;
  EXPECT_TRUE(contains(e, "map format version " + std::to_string(kMapFormatVersion + 1) +
                              ", this build reads version " + std::to_string(kMapFormatVersion)))
      << e;
}

TEST(MapDirectory, RefusesManifestNumbersBeyondTheirTypeNamingTheKey) {
  // doc/robustness.md finding 22 (fuzz_map_files): a number beyond double's range made the JSON
  // parser throw out_of_range, which escaped loadMap (the process ended in std::terminate).
  const std::string dir = test::makeTempDir("rgbdi_map") + "/map";
  saveMap(dir, syntheticMap(7));
  const std::vector<char> original = readBytes(dir + "/manifest.json");
  std::string text(original.begin(), original.end());
  const std::string width = "\"width\": 640";
  ASSERT_NE(text.find(width), std::string::npos) << text;
  text.replace(text.find(width), width.size(), "\"width\": 1.0e2815");
  writeBytes(dir + "/manifest.json", std::vector<char>(text.begin(), text.end()));
  std::string e = loadError(dir);
  EXPECT_TRUE(contains(e, "manifest.json: not valid JSON (")) << e;
  EXPECT_TRUE(contains(e, "number overflow parsing '1.0e2815'")) << e;

  // Found beside it: an integer beyond the key's type was converted silently (4294967936 read as
  // an int is 640, the saved width).
  nlohmann::json j = nlohmann::json::parse(std::string(original.begin(), original.end()));
  j["camera"]["width"] = 4294967936ULL;
  writeManifest(dir, j);
  e = loadError(dir);
  EXPECT_TRUE(contains(e,
                       "manifest.json: camera key \"width\": 4294967936 is out of range "
                       "(-2147483648 to 2147483647)"))
      << e;
  j["camera"]["width"] = -7;  // in range: refused later, by what checks camera sizes (if any)
  j["format_version"] = -4294967296LL;
  writeManifest(dir, j);
  e = loadError(dir);
  EXPECT_TRUE(contains(e, "key \"format_version\": -4294967296 is out of range")) << e;
}

TEST(MapDirectory, RefusesAMissingManifest) {
  const std::string dir = test::makeTempDir("rgbdi_map") + "/map";
  saveMap(dir, syntheticMap(5));
  ASSERT_EQ(std::remove((dir + "/manifest.json").c_str()), 0);
  const std::string e = loadError(dir);
  EXPECT_TRUE(contains(e, "manifest.json: missing manifest")) << e;
  const std::string none = loadError(dir + "/../nothing_here");
  EXPECT_TRUE(contains(none, "nothing_here: no map directory here")) << none;
}

TEST(MapDirectory, RefusesATruncatedPlacesFileNamingIt) {
  const std::string dir = test::makeTempDir("rgbdi_map") + "/map";
  saveMap(dir, syntheticMap(6));
  std::vector<char> b = readBytes(dir + "/places.bin");
  const std::size_t full = b.size();
  b.resize(full - 100);
  writeBytes(dir + "/places.bin", b);
  std::string e = loadError(dir);
  EXPECT_TRUE(contains(e, "places.bin: " + std::to_string(full - 100) +
                              " bytes, manifest.json says " + std::to_string(full) +
                              " (truncated or replaced file)"))
      << e;
  // With the manifest agreeing (e.g. both edited), the file's own reader still refuses it.
  resealFile(dir, "places.bin");
  e = loadError(dir);
  EXPECT_TRUE(contains(e, "places.bin: place record 8")) << e;
  EXPECT_TRUE(contains(e, "truncated")) << e;
}

TEST(MapDirectory, RefusesAFlippedByteInTheKeyframeFileByItsChecksum) {
  const std::string dir = test::makeTempDir("rgbdi_map") + "/map";
  saveMap(dir, syntheticMap(7));
  std::vector<char> b = readBytes(dir + "/keyframes.bin");
  b[b.size() / 2] = static_cast<char>(b[b.size() / 2] ^ 0x10);
  writeBytes(dir + "/keyframes.bin", b);
  const std::string e = loadError(dir);
  EXPECT_TRUE(contains(e, "keyframes.bin: checksum (FNV-1a 64)")) << e;
  EXPECT_TRUE(contains(e, "(corrupt file)")) << e;
}

TEST(MapDirectory, RefusesMissingDataFilesBadSignaturesAndCountsThatDisagree) {
  const std::string root = test::makeTempDir("rgbdi_map");
  const std::string dir = root + "/map";
  saveMap(dir, syntheticMap(8));
  const std::vector<char> places = readBytes(dir + "/places.bin");
  const nlohmann::json manifest = readManifest(dir);

  ASSERT_EQ(std::remove((dir + "/loops.txt").c_str()), 0);
  std::string e = loadError(dir);
  EXPECT_TRUE(contains(e, "loops.txt: missing (listed in manifest.json)")) << e;
  saveMap(dir, syntheticMap(8));

  std::vector<char> bad = places;
  bad[0] = 'X';
  writeBytes(dir + "/places.bin", bad);
  resealFile(dir, "places.bin");
  e = loadError(dir);
  EXPECT_TRUE(contains(e, "places.bin: header: not an rgbdi places file")) << e;

  writeBytes(dir + "/places.bin", places);
  nlohmann::json j = manifest;
  j["counts"]["places"] = 10;
  writeManifest(dir, j);
  e = loadError(dir);
  EXPECT_TRUE(contains(e, "places.bin: the manifest says 10 places, the file holds 9")) << e;

  j = manifest;
  j["counts"]["keyframe_points"] = 1;
  writeManifest(dir, j);
  e = loadError(dir);
  EXPECT_TRUE(contains(e, "keyframes.bin: the manifest says 1 kept points")) << e;

  j = manifest;
  j["files"].erase("places.bin");
  writeManifest(dir, j);
  e = loadError(dir);
  EXPECT_TRUE(contains(e, "manifest.json: does not list the data file places.bin")) << e;

  writeBytes(dir + "/manifest.json", {'{', '"'});
  e = loadError(dir);
  EXPECT_TRUE(contains(e, "manifest.json: not valid JSON")) << e;

  j = manifest;
  j.erase("next_segment");
  writeManifest(dir, j);
  e = loadError(dir);
  EXPECT_TRUE(contains(e, "manifest.json: manifest missing key \"next_segment\"")) << e;
}

TEST(MapDirectory, RefusesDescriptorsInconsistentWithTheManifest) {
  const std::string dir = test::makeTempDir("rgbdi_map") + "/map";
  saveMap(dir, syntheticMap(9));
  nlohmann::json j = readManifest(dir);
  j["descriptor_bytes"] = 16;
  writeManifest(dir, j);
  std::string e = loadError(dir);
  EXPECT_TRUE(contains(e,
                       "places.bin: place 3: descriptors \"ORB-256\" (32 bytes) but the "
                       "manifest says \"ORB-256\" (16 bytes)"))
      << e;
  j["descriptor_bytes"] = 32;
  j["descriptor_type"] = "BRIEF-256";
  writeManifest(dir, j);
  e = loadError(dir);
  EXPECT_TRUE(contains(e, "manifest says \"BRIEF-256\" (32 bytes)")) << e;

  // saveMap refuses to write such a map in the first place.
  MapData m = syntheticMap(9);
  m.places[3].descriptors.type = "BRIEF-256";
  try {
    saveMap(dir, m);
    FAIL() << "saved a map with mixed descriptor types";
  } catch (const MapError& err) {
    EXPECT_TRUE(contains(err.what(), "cannot save the map: place 24: descriptors \"BRIEF-256\""))
        << err.what();
  }
  MapData loose = syntheticMap(9);
  loose.loops.front().to_id = 4;
  EXPECT_THROW(saveMap(dir, loose), MapError);
  MapData ids = syntheticMap(9);
  ids.manifest.next_keyframe_id = 10;
  EXPECT_THROW(saveMap(dir, ids), MapError);
}

TEST(MapDirectory, CheckCompatibleNamesEveryDifferenceWithBothValues) {
  const MapData m = syntheticMap(10);
  const MapManifest& mf = m.manifest;
  EXPECT_NO_THROW(checkCompatible(mf, mf.camera, mf.T_body_cam, "ORB-256", "/maps/a"));
  // Below the tolerance (1e-6): compatible.
  PinholeCamera near = mf.camera;
  near.fx += 1e-8;
  Eigen::Isometry3d T_near = mf.T_body_cam;
  T_near.translation().x() += 1e-7;
  EXPECT_NO_THROW(checkCompatible(mf, near, T_near, "ORB-256", "/maps/a"));

  PinholeCamera other = mf.camera;
  other.fx = 600.0;
  other.dist[1] = -0.5;
  Eigen::Isometry3d T_other = mf.T_body_cam;
  T_other.translation().y() += 1e-5;
  try {
    checkCompatible(mf, other, T_other, "ORB-256", "/maps/a");
    FAIL();
  } catch (const MapError& e) {
    const std::string s = e.what();
    EXPECT_EQ(s.rfind("/maps/a: the map was built with another calibration", 0), 0u) << s;
    EXPECT_TRUE(contains(s, "fx 615.1234567890")) << s;
    EXPECT_TRUE(contains(s, "(map) vs 600 (this run)")) << s;
    EXPECT_TRUE(contains(s, "k2 -0.25 (map) vs -0.5 (this run)")) << s;
    EXPECT_TRUE(contains(s, "T_body_cam(1,3)")) << s;
    EXPECT_FALSE(contains(s, "fy")) << s;
    EXPECT_FALSE(contains(s, "descriptor type \"")) << s;
  }
  PinholeCamera small = mf.camera;
  small.width = 424;
  small.height = 240;
  try {
    checkCompatible(mf, small, mf.T_body_cam, "ORB-256", "/maps/a");
    FAIL();
  } catch (const MapError& e) {
    EXPECT_TRUE(contains(e.what(), "image size 640x480 (map) vs 424x240 (this run)")) << e.what();
  }
  try {
    checkCompatible(mf, mf.camera, mf.T_body_cam, "BRIEF-256", "/maps/a");
    FAIL();
  } catch (const MapError& e) {
    EXPECT_TRUE(contains(e.what(), "descriptor type \"ORB-256\" (map) vs \"BRIEF-256\" (this run)"))
        << e.what();
  }
}

TEST(MapDirectory, ANewSaveReplacesTheOldVersionAndLeavesOnlyTheLink) {
  const std::string root = test::makeTempDir("rgbdi_map");
  const std::string dir = root + "/map";
  MapData first = syntheticMap(11);
  saveMap(dir, first);
  EXPECT_EQ(entriesOf(root), (std::vector<std::string>{"map", "map.1"}));
  MapData second = syntheticMap(12, 12);
  second.manifest.sessions = 2;
  saveMap(dir + "/", second);  // a trailing slash names the same map
  EXPECT_EQ(entriesOf(root), (std::vector<std::string>{"map", "map.2"}));
  struct stat st {};
  ASSERT_EQ(lstat(dir.c_str(), &st), 0);
  EXPECT_TRUE(S_ISLNK(st.st_mode));
  EXPECT_EQ(std::filesystem::read_symlink(dir).string(), "map.2");  // relative: DIR can move
  expectSameMap(second, loadMap(dir));
  std::filesystem::rename(root, root + "-moved");
  expectSameMap(second, loadMap(root + "-moved/map"));
  // Something else beside the map is never touched.
  std::filesystem::create_directory(root + "-moved/map.notes");
  saveMap(root + "-moved/map", first);
  EXPECT_EQ(entriesOf(root + "-moved"), (std::vector<std::string>{"map", "map.3", "map.notes"}));
}

TEST(MapDirectory, RefusesToReplaceAPlainDirectoryAndAMissingParent) {
  const std::string root = test::makeTempDir("rgbdi_map");
  std::filesystem::create_directory(root + "/map");
  std::ofstream(root + "/map/keep.txt") << "user data\n";
  try {
    saveMap(root + "/map", syntheticMap(13));
    FAIL();
  } catch (const MapError& e) {
    EXPECT_TRUE(contains(e.what(),
                         "/map: exists and is not a map published by rgbdi (a plain "
                         "directory"))
        << e.what();
  }
  EXPECT_EQ(entriesOf(root), std::vector<std::string>{"map"});
  EXPECT_EQ(entriesOf(root + "/map"), std::vector<std::string>{"keep.txt"});
  EXPECT_THROW(saveMap(root + "/no/such/map", syntheticMap(13)), MapError);

  // A plain copy of a published map (cp -rL) loads, but cannot be saved over.
  const MapData m = syntheticMap(14);
  saveMap(root + "/published", m);
  std::filesystem::copy(root + "/published.1", root + "/copy",
                        std::filesystem::copy_options::recursive);
  expectSameMap(m, loadMap(root + "/copy"));
  EXPECT_THROW(saveMap(root + "/copy", m), MapError);
  expectSameMap(m, loadMap(root + "/copy"));
}

// A child process saves map B over map A and SIGKILLs itself right after step k, for every step
// of the save: the directory then loads as A before the link is replaced, as B from then on, and
// the next save cleans up whatever the killed one left.
TEST(MapDirectory, AProcessKilledAtAnyStepOfASaveLeavesTheOldOrTheNewMap) {
  const MapData a = syntheticMap(20);
  MapData b = syntheticMap(21, 11);
  b.manifest.sessions = 2;
  mapping::MappingOptions mo;
  mapping::PointMap points(mo);
  mapping::OccupancyMap occupancy(mo);
  for (const mapping::Keyframe& k : b.keyframes.keyframes()) {
    points.insertPoints(k.points, k.T_world_cam);
    occupancy.insertPoints(k.points, k.T_world_cam);
  }
  MapExtras extras;
  extras.point_map = &points;
  extras.occupancy = &occupancy;

  std::vector<std::string> steps;
  {
    MapExtras record = extras;
    record.after_step = [&](const std::string& s) { steps.push_back(s); };
    saveMap(test::makeTempDir("rgbdi_map") + "/map", b, record);
  }
  const std::vector<std::string> expected = {
      "staged", "keyframes.bin", "places.bin", "loops.txt", "pose_graph.graph", "points.ply",
      "map.bt", "manifest.json", "fsync",      "renamed",   "published",        "cleaned"};
  ASSERT_EQ(steps, expected);

  for (bool old_exists : {true, false}) {
    for (std::size_t k = 0; k < steps.size(); ++k) {
      SCOPED_TRACE("killed after step " + steps[k] + (old_exists ? "" : ", no earlier map"));
      const std::string root = test::makeTempDir("rgbdi_map_kill");
      const std::string dir = root + "/map";
      if (old_exists) saveMap(dir, a);
      const pid_t pid = fork();
      ASSERT_GE(pid, 0);
      if (pid == 0) {
        MapExtras kill = extras;
        kill.after_step = [&](const std::string& s) {
          if (s == steps[k]) std::raise(SIGKILL);
        };
        try {
          saveMap(dir, b, kill);
        } catch (...) {
          _exit(3);
        }
        _exit(0);
      }
      int status = 0;
      ASSERT_EQ(waitpid(pid, &status, 0), pid);
      ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGKILL) << status;
      const bool published = k >= 10;
      if (published) {
        expectSameMap(b, loadMap(dir));
      } else if (old_exists) {
        expectSameMap(a, loadMap(dir));
      } else {
        EXPECT_TRUE(contains(loadError(dir), "no map directory here"));
      }
      // The next save works and removes the leftovers.
      saveMap(dir, a);
      expectSameMap(a, loadMap(dir));
      const std::vector<std::string> left = entriesOf(root);
      ASSERT_EQ(left.size(), 2u) << left.back();
      EXPECT_EQ(left[0], "map");
    }
  }
}

// SIGKILL from outside at random moments while a child saves larger maps again and again.
TEST(MapDirectory, AProcessKilledAtRandomMomentsLeavesALoadableMap) {
  const std::string root = test::makeTempDir("rgbdi_map_kill");
  const std::string dir = root + "/map";
  MapData m = syntheticMap(30, 200, 400);
  m.manifest.sessions = 0;
  saveMap(dir, m);
  const auto t0 = std::chrono::steady_clock::now();
  saveMap(dir, m);
  const double save_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  std::mt19937 rng(4);
  int last_known = 0, changed = 0;
  for (int round = 0; round < 12; ++round) {
    const pid_t pid = fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
      // Each save carries a new session number: the parent knows which one it may see.
      MapData mine = m;
      for (int s = 1;; ++s) {
        mine.manifest.sessions = last_known + s;
        try {
          saveMap(dir, mine);
        } catch (...) {
          _exit(3);
        }
      }
    }
    std::uniform_real_distribution<double> delay(0.2 * save_s, 3.0 * save_s);
    std::this_thread::sleep_for(std::chrono::duration<double>(delay(rng)));
    kill(pid, SIGKILL);
    int status = 0;
    ASSERT_EQ(waitpid(pid, &status, 0), pid);
    ASSERT_TRUE(WIFSIGNALED(status)) << "the saving child ended by itself: " << status;
    MapData r;
    ASSERT_NO_THROW(r = loadMap(dir)) << "round " << round;
    EXPECT_GE(r.manifest.sessions, last_known);
    changed += r.manifest.sessions != last_known;
    last_known = r.manifest.sessions;
    r.manifest.sessions = m.manifest.sessions;
    if (round % 4 == 0) expectSameMap(m, r);
  }
  EXPECT_GT(changed, 0) << "no save was ever published before the kill";
}
