// Which generated runs revisit a place (loop-closure tests need both kinds): a camera pose is a
// revisit of an earlier one when it is within 1 m and its viewing direction within 45 deg,
// after at least 3 m of travel in between. Runs shorter than one lap never revisit.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "rgbdi/common/sensor_options.h"
#include "rgbdi/sim/profiles.h"

namespace rgbdi::sim {
namespace {

struct Revisit {
  bool found = false;
  double closest_m = std::numeric_limits<double>::infinity();  ///< nearest similar view
};

Revisit findRevisit(ProfileKind kind, double duration_s) {
  ProfileOptions po;
  po.kind = kind;
  po.duration_s = duration_s;
  const Eigen::Isometry3d T_body_cam = ExtrinsicOptions().T_body_cam;
  const MotionProfile prof = makeMotionProfile(po, T_body_cam);
  struct View {
    Eigen::Vector3d p, dir;
    double travelled;
  };
  std::vector<View> views;
  double travelled = 0.0;
  Eigen::Vector3d last = prof.trajectory->pose(0.0).translation();
  for (double t = 0.0; t <= prof.trajectory->duration(); t += 0.1) {
    const Eigen::Isometry3d T_world_cam = prof.trajectory->pose(t) * T_body_cam;
    travelled += (T_world_cam.translation() - last).norm();
    last = T_world_cam.translation();
    views.push_back({T_world_cam.translation(), T_world_cam.linear().col(2), travelled});
  }
  Revisit r;
  const double cos45 = std::cos(45.0 * M_PI / 180.0);
  for (std::size_t j = 0; j < views.size(); ++j)
    for (std::size_t i = 0; i < j; ++i) {
      if (views[j].travelled - views[i].travelled < 3.0) break;  // i increases: travel shrinks
      if (views[i].dir.dot(views[j].dir) < cos45) continue;
      const double d = (views[i].p - views[j].p).norm();
      r.closest_m = std::min(r.closest_m, d);
      if (d < 1.0) r.found = true;
    }
  return r;
}

TEST(ProfileRevisits, AHandheldRunShorterThanOneLapNeverRevisits) {
  // One lap of the handheld path is 14.9 m (~21 s of walking after 2 s of rest).
  for (double duration : {12.0, 18.0}) {
    const Revisit r = findRevisit(ProfileKind::Handheld, duration);
    EXPECT_FALSE(r.found) << duration << " s: closest similar view " << r.closest_m << " m";
  }
}

TEST(ProfileRevisits, WheeledRunsShorterThanOneLapNeverRevisit) {
  // wheeled_circle: 12.6 m per lap at 0.4 m/s.
  EXPECT_FALSE(findRevisit(ProfileKind::WheeledCircle, 25.0).found);
  EXPECT_FALSE(findRevisit(ProfileKind::WheeledSlopes, 30.0).found);
  EXPECT_FALSE(findRevisit(ProfileKind::TrackedSlopes, 40.0).found);
}

TEST(ProfileRevisits, FullLengthRunsRevisit) {
  // The check can fail: the default runs go round more than once.
  EXPECT_TRUE(findRevisit(ProfileKind::Handheld, 0.0).found);
  EXPECT_TRUE(findRevisit(ProfileKind::WheeledCircle, 0.0).found);
  EXPECT_TRUE(findRevisit(ProfileKind::TrackedSlopes, 0.0).found);
}

}  // namespace
}  // namespace rgbdi::sim
