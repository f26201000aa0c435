// Weighting of the 4-DOF pose graph's odometry edges: a random walk in path length (position and
// yaw) and in the angle turned (yaw), the overlapping edges of a keyframe sharing the odometry's
// information. Known answers: the sigmas of edges over a bent path, and the closed-form
// solution of a chain closed by one loop, where the correction of node k is the end
// discrepancy times the share of the chain's variance accumulated up to k.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "rgbdi/loop/four_dof.h"
#include "rgbdi/loop/pose_graph.h"

using namespace rgbdi::loop;
using Eigen::Isometry3d;
using Eigen::Vector3d;

namespace {

constexpr double kDeg = M_PI / 180.0;

Isometry3d poseOf(const Vector3d& p, double yaw) {
  Isometry3d T = Isometry3d::Identity();
  T.linear() = rotZ(yaw);
  T.translation() = p;
  return T;
}

/// Options for a problem solved to machine precision.
PoseGraphOptions tight(PoseGraphOptions o) {
  o.function_tolerance = 1e-15;
  o.gradient_tolerance = 1e-15;
  o.parameter_tolerance = 1e-15;
  return o;
}

}  // namespace

TEST(PoseGraphWeighting, EdgeSigmasGrowWithThePathAndTheTurnBetweenTheirKeyframes) {
  PoseGraphOptions o;
  o.sequential_edges = 2;  // every step is spanned by 1 + 2 = 3 edges
  o.odom_pos_sigma_floor_m = 0.002;
  o.odom_pos_sigma_per_sqrt_m = 0.01;
  o.odom_yaw_sigma_floor_deg = 0.02;
  o.odom_yaw_sigma_per_sqrt_m_deg = 0.1;
  o.odom_yaw_sigma_per_sqrt_rad_deg = 0.3;
  PoseGraph4Dof g(o);
  // 1 m along x, then 1 m along y after turning left by 90 deg at node 1.
  g.addNode(0, 0, poseOf(Vector3d(0, 0, 0), 0.0));
  g.addNode(1, 0, poseOf(Vector3d(1, 0, 0), M_PI / 2));
  g.addNode(2, 0, poseOf(Vector3d(1, 1, 0), M_PI / 2));
  EXPECT_DOUBLE_EQ(g.nodes()[1].odom_path_m, 1.0);
  EXPECT_DOUBLE_EQ(g.nodes()[2].odom_path_m, 2.0);
  EXPECT_NEAR(g.nodes()[1].odom_rotation_rad, M_PI / 2, 1e-12);
  EXPECT_NEAR(g.nodes()[2].odom_rotation_rad, M_PI / 2, 1e-12);

  ASSERT_EQ(g.edges().size(), 3u);  // 0->1, then 0->2 and 1->2
  const GraphEdge& e01 = g.edges()[0];
  const GraphEdge& e02 = g.edges()[1];
  const GraphEdge& e12 = g.edges()[2];
  EXPECT_EQ(e02.from, 0u);
  EXPECT_EQ(e02.to, 2u);
  // 0->2 spans the bent path of 2 m (the straight distance is sqrt(2) m) and the 90 deg turn.
  EXPECT_NEAR(e02.sigma_pos_m, std::sqrt(3.0 * (0.002 * 0.002 + 0.01 * 0.01 * 2.0)), 1e-15);
  const double var_yaw02 = std::pow(0.02 * kDeg, 2) + std::pow(0.1 * kDeg, 2) * 2.0 +
                           std::pow(0.3 * kDeg, 2) * (M_PI / 2);
  EXPECT_NEAR(e02.sigma_yaw_rad, std::sqrt(3.0 * var_yaw02), 1e-12);
  // 0->1: 1 m and the turn; 1->2: 1 m, no turn.
  EXPECT_NEAR(e01.sigma_pos_m, std::sqrt(3.0 * (0.002 * 0.002 + 0.01 * 0.01 * 1.0)), 1e-15);
  EXPECT_NEAR(e12.sigma_pos_m, e01.sigma_pos_m, 1e-15);
  const double var_yaw12 = std::pow(0.02 * kDeg, 2) + std::pow(0.1 * kDeg, 2) * 1.0;
  EXPECT_NEAR(e12.sigma_yaw_rad, std::sqrt(3.0 * var_yaw12), 1e-12);
  EXPECT_NEAR(e01.sigma_yaw_rad, std::sqrt(3.0 * (var_yaw12 + std::pow(0.3 * kDeg, 2) * M_PI / 2)),
              1e-12);
  // The same figures from the static helper.
  const auto [sp, sy] = PoseGraph4Dof::sequentialSigmas(o, 2.0, M_PI / 2);
  EXPECT_EQ(sp, e02.sigma_pos_m);
  EXPECT_NEAR(sy, e02.sigma_yaw_rad, 1e-15);
}

TEST(PoseGraphWeighting, ALoopSpreadsThePositionCorrectionInProportionToThePathLength) {
  // A straight chain along x with uneven keyframe spacing; the odometry over-measures every
  // step and climbs 2 mm per step. One loop from the last keyframe to the first gives the true
  // relative pose. Position residuals are then linear in the positions (the yaw stays 0): the
  // least-squares solution is c_k = D * V_k / (V + s^2), with V_k the summed variances of the
  // edges up to node k, V the chain's, s the loop's sigma and D the end discrepancy.
  PoseGraphOptions o;
  o.sequential_edges = 1;
  o.odom_pos_sigma_floor_m = 0.003;
  o.odom_pos_sigma_per_sqrt_m = 0.02;
  o = tight(o);
  const std::vector<double> step = {0.2, 0.5, 0.1, 0.8, 0.4};
  std::vector<Vector3d> truth{Vector3d::Zero()}, odom{Vector3d::Zero()};
  for (double d : step) {
    truth.push_back(truth.back() + Vector3d(d, 0, 0));
    odom.push_back(odom.back() + Vector3d(1.03 * d, 0, 0.002));
  }
  PoseGraph4Dof g(o);
  for (std::size_t k = 0; k < odom.size(); ++k) g.addNode(k, 0, poseOf(odom[k], 0.0));
  const double s_loop = 0.01;
  const std::size_t last = odom.size() - 1;
  g.addLoopEdge(last, 0, poseOf(truth[0] - truth[last], 0.0), s_loop, 0.1 * kDeg);
  const PoseGraphSolveReport r = g.solve();
  ASSERT_TRUE(r.converged);
  EXPECT_TRUE(r.rolled_back_loop_edges.empty());

  std::vector<double> V{0.0};
  for (std::size_t k = 1; k < odom.size(); ++k)
    V.push_back(V.back() + o.odom_pos_sigma_floor_m * o.odom_pos_sigma_floor_m +
                o.odom_pos_sigma_per_sqrt_m * o.odom_pos_sigma_per_sqrt_m *
                    (odom[k] - odom[k - 1]).norm());
  const Vector3d D = truth[last] - odom[last];  // discrepancy at the loop keyframe
  for (std::size_t k = 0; k < odom.size(); ++k) {
    const Vector3d expected = odom[k] + D * V[k] / (V.back() + s_loop * s_loop);
    EXPECT_NEAR(g.nodes()[k].xyz_yaw.x(), expected.x(), 1e-9) << k;
    EXPECT_NEAR(g.nodes()[k].xyz_yaw.y(), 0.0, 1e-12) << k;
    EXPECT_NEAR(g.nodes()[k].xyz_yaw.z(), expected.z(), 1e-9) << k;
    EXPECT_NEAR(g.nodes()[k].yaw_rad(), 0.0, 1e-12) << k;
  }
  // The long step (0.8 m) takes more of the correction than the short ones.
  const double c3 = g.nodes()[3].xyz_yaw.x() - odom[3].x();
  const double c4 = g.nodes()[4].xyz_yaw.x() - odom[4].x();
  const double c2 = g.nodes()[2].xyz_yaw.x() - odom[2].x();
  EXPECT_GT(std::abs(c4 - c3), 4.0 * std::abs(c3 - c2));
}

TEST(PoseGraphWeighting, ALoopPutsTheHeadingCorrectionWhereTheOdometryTurned) {
  // A robot turning on the spot (no path): the yaw drift can only come from the turns, so the
  // loop's heading correction goes to the edges in proportion to the angle turned, and the
  // edge that did not turn keeps its odometry (only the floor variance).
  PoseGraphOptions o;
  o.sequential_edges = 1;
  o.odom_yaw_sigma_floor_deg = 0.001;
  o.odom_yaw_sigma_per_sqrt_rad_deg = 0.2;
  o = tight(o);
  const std::vector<double> turn = {0.2, 0.0, 0.6, 0.4};  // [rad] true turns
  const double drift = 0.001;                             // [rad] odometry error per turn, if any
  std::vector<double> yaw_true{0.0}, yaw_odom{0.0};
  for (double t : turn) {
    yaw_true.push_back(yaw_true.back() + t);
    yaw_odom.push_back(yaw_odom.back() + t + (t > 0.0 ? drift : 0.0));
  }
  PoseGraph4Dof g(o);
  for (std::size_t k = 0; k < turn.size() + 1; ++k)
    g.addNode(k, 0, poseOf(Vector3d(1.0, -2.0, 0.5), yaw_odom[k]));
  const std::size_t last = turn.size();
  const double s_loop = 0.05 * kDeg;
  g.addLoopEdge(last, 0, poseOf(Vector3d::Zero(), yaw_true[0] - yaw_true[last]), 0.01, s_loop);
  ASSERT_TRUE(g.solve().converged);

  const double f = o.odom_yaw_sigma_floor_deg * kDeg, q = o.odom_yaw_sigma_per_sqrt_rad_deg * kDeg;
  std::vector<double> V{0.0};
  for (std::size_t k = 1; k <= last; ++k)
    V.push_back(V.back() + f * f + q * q * std::abs(yaw_odom[k] - yaw_odom[k - 1]));
  const double D = yaw_true[last] - yaw_odom[last];
  for (std::size_t k = 0; k <= last; ++k) {
    EXPECT_NEAR(g.nodes()[k].yaw_rad(), yaw_odom[k] + D * V[k] / (V.back() + s_loop * s_loop),
                1e-10)
        << k;
    EXPECT_NEAR((g.nodes()[k].p_world_body_m() - Vector3d(1.0, -2.0, 0.5)).norm(), 0.0, 1e-12);
  }
  // Nothing moved across the edge that did not turn (beyond the floor's share, < 1e-5 rad).
  EXPECT_LT(
      std::abs((g.nodes()[2].yaw_rad() - yaw_odom[2]) - (g.nodes()[1].yaw_rad() - yaw_odom[1])),
      1e-5);
}

TEST(PoseGraphWeighting, LoopEdgesTakeTheirOwnSigmasOrTheOptionsDefaults) {
  PoseGraphOptions o;
  PoseGraph4Dof g(o);
  g.addNode(0, 0, Isometry3d::Identity());
  g.addNode(1, 0, poseOf(Vector3d(1, 0, 0), 0.0));
  const int a = g.addLoopEdge(1, 0, poseOf(Vector3d(-1, 0, 0), 0.0));
  const int b = g.addLoopEdge(1, 0, poseOf(Vector3d(-1, 0, 0), 0.0), 0.004, 0.002);
  EXPECT_EQ(g.edges()[static_cast<std::size_t>(a)].sigma_pos_m, o.loop_sigma_pos_m);
  EXPECT_NEAR(g.edges()[static_cast<std::size_t>(a)].sigma_yaw_rad, o.loop_sigma_yaw_deg * kDeg,
              1e-15);
  EXPECT_EQ(g.edges()[static_cast<std::size_t>(b)].sigma_pos_m, 0.004);
  EXPECT_EQ(g.edges()[static_cast<std::size_t>(b)].sigma_yaw_rad, 0.002);
  EXPECT_THROW(g.addLoopEdge(1, 0, Isometry3d::Identity(), 0.0, 0.01), std::invalid_argument);
  EXPECT_THROW(g.addLoopEdge(1, 0, Isometry3d::Identity(), 0.01, std::nan("")),
               std::invalid_argument);
}

TEST(PoseGraphWeighting, AnImuOnlyStretchIsAWeakEdgeThatTakesTheLoopCorrection) {
  // A straight chain along x; the step from node 2 to node 3 was carried by the IMU alone for
  // 1.5 s (blind frames) and is 6 cm too long, the other steps are exact. Its edge gets the
  // IMU-only variance on top (position sigma 0.1 m * 1.5^1.5, yaw 0.5 deg * 1.5), and one loop
  // from the last node to the first puts nearly all of the correction there: the closed form
  // c_k = D * V_k / (V + s^2) of the chain, V_k the summed edge variances up to node k.
  PoseGraphOptions o;
  o.sequential_edges = 1;
  o.odom_pos_sigma_floor_m = 0.002;
  o.odom_pos_sigma_per_sqrt_m = 0.01;
  o.odom_bridge_pos_sigma_m = 0.1;
  o.odom_bridge_yaw_sigma_deg = 0.5;
  o = tight(o);
  const std::vector<double> step = {0.3, 0.3, 0.6, 0.3};
  const std::vector<double> bridged = {0.0, 0.0, 1.5, 0.0};
  std::vector<Vector3d> truth{Vector3d::Zero()}, odom{Vector3d::Zero()};
  for (std::size_t k = 0; k < step.size(); ++k) {
    truth.push_back(truth.back() + Vector3d(step[k], 0, 0));
    odom.push_back(odom.back() + Vector3d(step[k] + (bridged[k] > 0.0 ? 0.06 : 0.0), 0, 0));
  }
  PoseGraph4Dof g(o);
  g.addNode(0, 0, poseOf(odom[0], 0.0));
  for (std::size_t k = 1; k < odom.size(); ++k)
    g.addNode(k, 0, poseOf(odom[k], 0.0), bridged[k - 1]);
  EXPECT_DOUBLE_EQ(g.nodes()[3].odom_bridged_s, 1.5);
  EXPECT_DOUBLE_EQ(g.nodes()[4].odom_bridged_s, 1.5);

  // The edge sigmas: known answers.
  ASSERT_EQ(g.edges().size(), 4u);
  const double bridge_pos = 0.1 * std::pow(1.5, 1.5);
  const double step_var = 0.002 * 0.002 + 0.01 * 0.01 * 0.3;
  EXPECT_NEAR(g.edges()[0].sigma_pos_m, std::sqrt(step_var), 1e-15);
  const double var_bridged = 0.002 * 0.002 + 0.01 * 0.01 * 0.66 + bridge_pos * bridge_pos;
  EXPECT_NEAR(g.edges()[2].sigma_pos_m, std::sqrt(var_bridged), 1e-12);
  const auto [sp, sy] = PoseGraph4Dof::sequentialSigmas(o, 0.66, 0.0, 1.5);
  EXPECT_EQ(sp, g.edges()[2].sigma_pos_m);
  const double var_yaw = std::pow(o.odom_yaw_sigma_floor_deg * kDeg, 2) +
                         std::pow(o.odom_yaw_sigma_per_sqrt_m_deg * kDeg, 2) * 0.66 +
                         std::pow(0.5 * kDeg * 1.5, 2);
  EXPECT_NEAR(sy, std::sqrt(var_yaw), 1e-15);

  const double s_loop = 0.01;
  const std::size_t last = odom.size() - 1;
  g.addLoopEdge(last, 0, poseOf(truth[0] - truth[last], 0.0), s_loop, 0.1 * kDeg);
  const PoseGraphSolveReport r = g.solve();
  ASSERT_TRUE(r.converged);
  std::vector<double> V{0.0};
  for (std::size_t k = 1; k < odom.size(); ++k)
    V.push_back(
        V.back() +
        PoseGraph4Dof::sequentialSigmas(o, (odom[k] - odom[k - 1]).norm(), 0.0, bridged[k - 1])
                .first *
            PoseGraph4Dof::sequentialSigmas(o, (odom[k] - odom[k - 1]).norm(), 0.0, bridged[k - 1])
                .first);
  const Vector3d D = truth[last] - odom[last];
  for (std::size_t k = 0; k < odom.size(); ++k) {
    const Vector3d expected = odom[k] + D * V[k] / (V.back() + s_loop * s_loop);
    EXPECT_NEAR(g.nodes()[k].xyz_yaw.x(), expected.x(), 1e-9) << k;
  }
  // The nodes before the blind stretch stay within 3 mm of the truth, the ones after within 6.
  EXPECT_NEAR(g.nodes()[2].xyz_yaw.x(), truth[2].x(), 0.003);
  EXPECT_NEAR(g.nodes()[3].xyz_yaw.x(), truth[3].x(), 0.006);

  // An IMU-only time that is negative or not finite is refused, naming the node.
  PoseGraph4Dof h(o);
  h.addNode(0, 0, poseOf(odom[0], 0.0));
  EXPECT_THROW(h.addNode(1, 0, poseOf(odom[1], 0.0), -0.1), std::invalid_argument);
  EXPECT_THROW(h.addNode(1, 0, poseOf(odom[1], 0.0), std::nan("")), std::invalid_argument);
}
