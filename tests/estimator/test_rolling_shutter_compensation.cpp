// Rolling-shutter compensation: observations moved from their row's time to the image's
// reference time along their image velocity (rgbdi/estimator/rolling_shutter_compensation.h).
#include <gtest/gtest.h>

#include <vector>

#include "rgbdi/common/so3.h"
#include "rgbdi/estimator/feature_manager.h"
#include "rgbdi/estimator/rolling_shutter_compensation.h"

using namespace rgbdi;
using namespace rgbdi::estimator;

namespace {

RollingShutter d435iLike() {
  RollingShutter rs;
  rs.readout_s = 0.033;
  rs.rows = 480;  // top to bottom, stamped at the middle row y_ref = 239.5
  return rs;
}

frontend::FeatureObservation feature(double x, double y, double row, double vx, double vy) {
  frontend::FeatureObservation f;
  f.xn = Eigen::Vector2d(x, y);
  f.uv = Eigen::Vector2d(320.0, row);
  f.velocity_xn = Eigen::Vector2d(vx, vy);
  return f;
}

/// Normalised projection of p_w for a camera yawing about its own y axis at `yaw_rate` [rad/s]
/// from the identity pose, at time t.
Eigen::Vector2d projectYawing(double t, double yaw_rate, const Eigen::Vector3d& p_w) {
  const Eigen::Vector3d p_c = expSO3(Eigen::Vector3d(0.0, yaw_rate * t, 0.0)).transpose() * p_w;
  return p_c.head<2>() / p_c.z();
}

}  // namespace

TEST(RollingShutterCompensation, MovesAlongTheVelocityByTheRowsShareOfTheReadout) {
  std::vector<frontend::FeatureObservation> f = {feature(0.1, 0.2, 359.5, 0.5, -0.2),
                                                 feature(-0.3, -0.1, 0.0, -1.0, 0.4),
                                                 feature(0.0, 0.0, 239.5, 2.0, 2.0)};
  moveToReferenceTime(f, d435iLike());
  // Row 359.5: 120 rows after the middle, 120 * 0.033 / 480 = 8.25 ms later.
  EXPECT_NEAR(f[0].xn.x(), 0.1 - 0.00825 * 0.5, 1e-15);
  EXPECT_NEAR(f[0].xn.y(), 0.2 + 0.00825 * 0.2, 1e-15);
  // Row 0: 239.5 rows before the middle, 16.465625 ms earlier.
  EXPECT_NEAR(f[1].xn.x(), -0.3 - 0.016465625, 1e-15);
  EXPECT_NEAR(f[1].xn.y(), -0.1 + 0.016465625 * 0.4, 1e-15);
  // The reference row is exposed at the stamp: unchanged.
  EXPECT_EQ(f[2].xn, Eigen::Vector2d(0.0, 0.0));
}

TEST(RollingShutterCompensation, BottomToTopReadsTheLastRowFirst) {
  RollingShutter rs = d435iLike();
  rs.bottom_to_top = true;
  rs.reference_middle = false;  // stamped at the first row read: the bottom one, y = 479
  std::vector<frontend::FeatureObservation> f = {feature(0.1, 0.2, 0.0, 0.5, 0.0)};
  moveToReferenceTime(f, rs);
  // Row 0 is read last, 479 rows (32.93125 ms) after the stamp.
  EXPECT_NEAR(f[0].xn.x(), 0.1 - 0.03293125 * 0.5, 1e-15);
  EXPECT_EQ(f[0].xn.y(), 0.2);
}

TEST(RollingShutterCompensation, GlobalShutterAndNewFeaturesAreUntouched) {
  const std::vector<frontend::FeatureObservation> before = {feature(0.1, 0.2, 400.0, 0.5, -0.2),
                                                            feature(0.3, 0.1, 10.0, 0.0, 0.0)};
  std::vector<frontend::FeatureObservation> global = before;
  moveToReferenceTime(global, RollingShutter{});
  EXPECT_EQ(global[0].xn, before[0].xn);  // bit-identical: readout 0 changes no output
  std::vector<frontend::FeatureObservation> rolling = before;
  moveToReferenceTime(rolling, d435iLike());
  EXPECT_EQ(rolling[1].xn, before[1].xn);  // no velocity (newly detected): stays
  TrackObservation o;
  o.meas.xn = Eigen::Vector3d(0.1, 0.2, 1.0);
  o.meas.velocity = Eigen::Vector2d(1.0, 1.0);
  o.xn_row = Eigen::Vector2d(0.5, 0.5);
  o.compensateRollingShutter();  // row_time_s 0: the observation is kept as it is
  EXPECT_EQ(o.meas.xn, Eigen::Vector3d(0.1, 0.2, 1.0));
  o.row_time_s = 0.01;
  o.compensateRollingShutter();
  EXPECT_NEAR(o.meas.xn.x(), 0.49, 1e-15);
  EXPECT_NEAR(o.meas.xn.y(), 0.49, 1e-15);
  EXPECT_EQ(o.meas.xn.z(), 1.0);
}

TEST(RollingShutterCompensation, RecoversThePositionAtTheStampUnderAYaw) {
  // A camera yawing at 1 rad/s sees a point at 2 m in row 450: the observation is made 14.5 ms
  // after the stamp. Moved back along the image
  // velocity at that time it lands where the point projects at the stamp, up to the second-order
  // term (the velocity changes with x), while the uncompensated one is ~9 px off.
  const double yaw_rate = 1.0;
  const Eigen::Vector3d p_w(0.3, 0.4, 2.0);
  const RollingShutter rs = d435iLike();
  const double row = 450.0, t_row = rs.rowTime(row);
  ASSERT_NEAR(t_row, 210.5 * 0.033 / 480, 1e-15);
  const double h = 1e-6;
  std::vector<frontend::FeatureObservation> f(1);
  f[0].uv = Eigen::Vector2d(320.0, row);
  f[0].xn = projectYawing(t_row, yaw_rate, p_w);
  f[0].velocity_xn =
      (projectYawing(t_row + h, yaw_rate, p_w) - projectYawing(t_row - h, yaw_rate, p_w)) / (2 * h);
  const Eigen::Vector2d at_stamp = projectYawing(0.0, yaw_rate, p_w);
  const double fx = 612.0;
  EXPECT_GT(fx * (f[0].xn - at_stamp).norm(), 8.0);  // the skew to compensate [px]
  moveToReferenceTime(f, rs);
  EXPECT_LT(fx * (f[0].xn - at_stamp).norm(), 0.05);  // [px]
}

TEST(RollingShutterCompensation, MovesAKeypointToItsPixelAtTheStamp) {
  // Loop closing's keypoints have no tracked velocity: pixelAtReferenceTime takes the motion
  // field of the camera's rate. A camera yawing at 1 rad/s about its y axis sees the point in
  // row ~420, 5 px from where it is at the stamp; moved back it lands there (second-order residue).
  PinholeCamera cam;
  cam.width = 640;
  cam.height = 480;
  cam.fx = cam.fy = 600.0;
  cam.cx = 320.0;
  cam.cy = 240.0;
  const RollingShutter rs = d435iLike();
  const double yaw_rate = 1.0;
  const Eigen::Vector3d p_w(0.3, 0.4, 2.0);
  auto pixel = [&](double t) {
    const Eigen::Vector2d xn = projectYawing(t, yaw_rate, p_w);
    return Eigen::Vector2d(cam.fx * xn.x() + cam.cx, cam.fy * xn.y() + cam.cy);
  };
  // The row the point is seen in and the time it is seen at (fixed point).
  Eigen::Vector2d seen = pixel(0.0);
  for (int k = 0; k < 5; ++k) seen = pixel(rs.rowTime(seen.y()));
  const Eigen::Vector2d at_stamp = pixel(0.0);
  const Eigen::Vector3d omega(0.0, yaw_rate, 0.0), v(0.0, 0.0, 0.0);
  EXPECT_GT((seen - at_stamp).norm(), 4.0);  // [px] the skew to compensate
  EXPECT_LT((pixelAtReferenceTime(seen, cam, rs, omega, v, 0.0) - at_stamp).norm(), 0.1);
  // A global shutter leaves it where it is.
  RollingShutter global = rs;
  global.readout_s = 0.0;
  EXPECT_EQ(pixelAtReferenceTime(seen, cam, global, omega, v, 2.0), seen);
}
