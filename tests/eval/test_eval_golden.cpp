// Golden values of ../shared/data/README.md section eval/ (TUM fr1/xyz and EuRoC V1_02), reproduced
// to 1e-6 relative.
#include <gtest/gtest.h>

#include "rgbdi/eval/association.h"
#include "rgbdi/eval/evaluate.h"
#include "rgbdi/eval/tum_reader.h"
#include "testing/fixtures.h"

namespace rgbdi::eval {
namespace {

constexpr double kRel = 1e-6;

void expectRel(double actual, double expected, const char* what) {
  EXPECT_NEAR(actual, expected, kRel * std::abs(expected)) << what;
}

struct Fixture {
  Trajectory gt;
  Trajectory est;
};

Fixture loadPair(const std::string& gt_name, const std::string& est_name) {
  Fixture f;
  f.gt = readTum(test::fixturePath("eval/" + gt_name));
  f.est = readTum(test::fixturePath("eval/" + est_name));
  return f;
}

EvalResult run(const Fixture& f, AlignMode mode) {
  EvalOptions opt;
  opt.align = mode;
  return evaluate(f.gt, f.est, opt);
}

TEST(EvalGolden, Fr1XyzSe3) {
  RGBDI_REQUIRE_FIXTURE(test::fixturePath("eval/freiburg1_xyz-groundtruth.txt"));
  const Fixture f = loadPair("freiburg1_xyz-groundtruth.txt", "freiburg1_xyz-rgbdslam.txt");
  EXPECT_EQ(associate(f.gt, f.est, 0.02).size(), 786u);
  const EvalResult r = run(f, AlignMode::Se3);
  EXPECT_EQ(r.pairs, 786u);
  expectRel(r.ate.rmse, 0.0134734678, "ATE rmse");
  expectRel(r.ate.mean, 0.0120294764, "ATE mean");
  expectRel(r.ate.median, 0.0111757511, "ATE median");
  expectRel(r.ate.max, 0.0347272017, "ATE max");
  EXPECT_EQ(r.alignment.scale, 1.0);
  EXPECT_EQ(r.rpe.pairs, 753u);
  expectRel(r.rpe.trans_rmse_m, 0.0212174441, "RPE translation rmse");
  expectRel(r.rpe.rot_rmse_deg, 0.9344804594, "RPE rotation rmse");
}

TEST(EvalGolden, Fr1XyzSim3) {
  RGBDI_REQUIRE_FIXTURE(test::fixturePath("eval/freiburg1_xyz-groundtruth.txt"));
  const Fixture f = loadPair("freiburg1_xyz-groundtruth.txt", "freiburg1_xyz-rgbdslam.txt");
  const EvalResult r = run(f, AlignMode::Sim3);
  EXPECT_EQ(r.pairs, 786u);
  expectRel(r.ate.rmse, 0.0133940549, "Sim(3) ATE rmse");
  expectRel(r.alignment.scale, 1.00792367, "Sim(3) scale");
}

TEST(EvalGolden, EurocV102AllAlignments) {
  RGBDI_REQUIRE_FIXTURE(test::fixturePath("eval/euroc_v102_stamped_groundtruth.txt"));
  const Fixture f =
      loadPair("euroc_v102_stamped_groundtruth.txt", "euroc_v102_stamped_estimate0.txt");
  EXPECT_EQ(associate(f.gt, f.est, 0.02).size(), 264u);
  const EvalResult posyaw = run(f, AlignMode::PosYaw);
  EXPECT_EQ(posyaw.pairs, 264u);
  expectRel(posyaw.ate.rmse, 0.0219557305, "posyaw ATE rmse");
  expectRel(run(f, AlignMode::Se3).ate.rmse, 0.0216520907, "SE(3) ATE rmse");
  const EvalResult sim3 = run(f, AlignMode::Sim3);
  expectRel(sim3.ate.rmse, 0.0131862625, "Sim(3) ATE rmse");
  expectRel(sim3.alignment.scale, 1.00977752, "Sim(3) scale");
  // A yaw-only rotation leaves the vertical axis fixed.
  EXPECT_NEAR((posyaw.alignment.R * Eigen::Vector3d::UnitZ() - Eigen::Vector3d::UnitZ()).norm(),
              0.0, 1e-12);
}

}  // namespace
}  // namespace rgbdi::eval
