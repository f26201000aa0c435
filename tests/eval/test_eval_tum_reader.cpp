// readTum: accepted syntax (comments, blank lines, commas, CRLF) and one test per rejected input,
// each checking that the message names the file, the line and what is wrong.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "rgbdi/eval/eval_error.h"
#include "rgbdi/eval/tum_reader.h"
#include "testing/fixtures.h"

namespace rgbdi::eval {
namespace {

std::string writeTemp(const std::string& name, const std::string& text) {
  const std::string path = test::makeTempDir("eval_tum") + "/" + name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

// Expects readTum to throw an EvalError whose message contains every fragment.
void expectError(const std::string& text, const std::vector<std::string>& fragments) {
  const std::string path = writeTemp("bad.tum", text);
  try {
    readTum(path);
    FAIL() << "no error for:\n" << text;
  } catch (const EvalError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find(path), std::string::npos) << msg;
    for (const auto& f : fragments)
      EXPECT_NE(msg.find(f), std::string::npos) << "'" << f << "' not in: " << msg;
  }
}

TEST(TumReader, ReadsCommentsBlankLinesCommasAndCrlf) {
  const std::string path = writeTemp("ok.tum",
                                     "# timestamp tx ty tz qx qy qz qw\n"
                                     "\n"
                                     "1.5 1 2 3 0 0 0 1\n"
                                     "  # indented comment\r\n"
                                     "2.25,4,5,6,0,0,1,0\r\n"
                                     "3.0, -1e-3 , +2 , 3.5e1, 0.5, 0.5, 0.5, 0.5\n");
  const Trajectory t = readTum(path);
  ASSERT_EQ(t.size(), 3u);
  EXPECT_EQ(t[0].t, 1.5);
  EXPECT_EQ(t[0].p, Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(t[0].q.w(), 1.0);
  EXPECT_EQ(t[1].t, 2.25);
  EXPECT_EQ(t[1].q.z(), 1.0);  // file order qx qy qz qw
  EXPECT_EQ(t[1].q.w(), 0.0);
  EXPECT_EQ(t[2].p, Eigen::Vector3d(-1e-3, 2, 35));
  EXPECT_DOUBLE_EQ(t[2].q.x(), 0.5);
}

TEST(TumReader, NormalisesSlightlyOffQuaternions) {
  const Trajectory t = readTum(writeTemp("q.tum", "0 0 0 0 0 0 0 1.004\n"));
  EXPECT_DOUBLE_EQ(t[0].q.norm(), 1.0);
  EXPECT_DOUBLE_EQ(t[0].q.w(), 1.0);
}

TEST(TumReader, KeepsFullTimestampPrecision) {
  const Trajectory t = readTum(writeTemp("p.tum", "1403715529.262140036 0 0 0 0 0 0 1\n"));
  EXPECT_EQ(t[0].t, 1403715529.262140036);
}

TEST(TumReader, RejectsWrongColumnCount) {
  expectError("# c\n1 0 0 0 0 0 0 1\n2 0 0 0 0 0 1\n", {":3:", "expected 8 values", "found 7"});
  expectError("1 0 0 0 0 0 0 1 9\n", {":1:", "found 9"});
}

TEST(TumReader, RejectsEmptyCommaField) { expectError("1,0,,0,0,0,0,1\n", {":1:", "empty field"}); }

TEST(TumReader, RejectsNonNumbers) {
  expectError("1 0 0 x 0 0 0 1\n", {":1:", "value 4 'x' is not a number"});
  expectError("1 0 0 0.5.5 0 0 0 1\n", {":1:", "not a number"});
}

TEST(TumReader, RejectsNanAndInf) {
  expectError("1 0 0 0 0 0 0 1\n2 nan 0 0 0 0 0 1\n", {":2:", "not finite"});
  expectError("1 0 inf 0 0 0 0 1\n", {":1:", "not finite"});
}

TEST(TumReader, RejectsNonUnitQuaternion) {
  expectError("1 0 0 0 0 0 0 2\n", {":1:", "quaternion norm 2"});
  expectError("1 0 0 0 0 0 0 0\n", {":1:", "quaternion norm 0"});
}

TEST(TumReader, RejectsNonIncreasingTimestamps) {
  expectError("1 0 0 0 0 0 0 1\n# c\n3 0 0 0 0 0 0 1\n2 0 0 0 0 0 0 1\n",
              {":4:", "not larger than 3 on line 3"});
  expectError("1 0 0 0 0 0 0 1\n1 0 0 0 0 0 0 1\n", {":2:", "on line 1"});
}

TEST(TumReader, RejectsFilesWithoutPoses) {
  expectError("", {"no poses"});
  expectError("# only\n\n# comments\n", {"no poses"});
}

TEST(TumReader, RejectsMissingFile) {
  try {
    readTum("/nonexistent/dir/traj.tum");
    FAIL();
  } catch (const EvalError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/dir/traj.tum: cannot open"),
              std::string::npos);
  }
}

TEST(TumReader, ReadsRealFixtures) {
  const std::string gt = test::fixturePath("eval/freiburg1_xyz-groundtruth.txt");
  RGBDI_REQUIRE_FIXTURE(gt);
  const Trajectory t = readTum(gt);
  ASSERT_EQ(t.size(), 3000u);  // 3003 lines, 3 comments
  EXPECT_DOUBLE_EQ(t.front().t, 1305031098.6659);
  EXPECT_DOUBLE_EQ(t.front().p.x(), 1.3563);
  const Trajectory e = readTum(test::fixturePath("eval/euroc_v102_stamped_estimate0.txt"));
  EXPECT_EQ(e.size(), 264u);
}

}  // namespace
}  // namespace rgbdi::eval
