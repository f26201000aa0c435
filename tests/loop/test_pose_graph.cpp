// PoseGraph4Dof on synthetic routes with exact ground truth: a square driven with known yaw,
// scale and height drift, closed by loops measured from the truth; wrong loops, odometry
// segments, determinism and argument checks.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "rgbdi/loop/four_dof.h"
#include "rgbdi/loop/pose_graph.h"
#include "rgbdi/loop/yaw_manifold.h"

using namespace rgbdi::loop;
using Eigen::Isometry3d;
using Eigen::Vector3d;

namespace {

constexpr double kDeg = M_PI / 180.0;

Isometry3d poseOf(const Vector3d& p, double yaw, double pitch, double roll) {
  Isometry3d T = Isometry3d::Identity();
  T.linear() =
      (Eigen::AngleAxisd(yaw, Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Vector3d::UnitY()) *
       Eigen::AngleAxisd(roll, Vector3d::UnitX()))
          .toRotationMatrix();
  T.translation() = p;
  return T;
}

/// True body poses on a square of side `side_m` driven `laps` times counter-clockwise, starting
/// at heading `heading0`, `steps_per_side` keyframes per side; node laps * 4 * steps_per_side
/// is back on node 0. Height and tilt wobble (height repeats every lap, tilt does not).
std::vector<Isometry3d> squareRoute(double side_m, int steps_per_side, int laps,
                                    double heading0 = 0.0) {
  const int per_lap = 4 * steps_per_side;
  const double step = side_m / steps_per_side;
  std::vector<Isometry3d> out;
  for (int k = 0; k <= laps * per_lap; ++k) {
    const int s = k % per_lap;
    const int side = s / steps_per_side;
    Vector3d p = Vector3d::Zero();
    for (int c = 0; c < side; ++c)
      p += side_m * Vector3d(std::cos(c * M_PI / 2), std::sin(c * M_PI / 2), 0);
    p += (s % steps_per_side) * step *
         Vector3d(std::cos(side * M_PI / 2), std::sin(side * M_PI / 2), 0);
    p = rotZ(heading0) * p;
    p.z() = 0.1 * std::sin(2.0 * M_PI * s / per_lap);
    out.push_back(poseOf(p, wrapAngle(heading0 + side * M_PI / 2), 0.03 * std::sin(0.7 * k),
                         0.02 * std::cos(0.3 * k)));
  }
  return out;
}

/// Odometry of `truth` with a yaw error per keyframe step, a scale error and a height drift per
/// step; roll and pitch are the truth's (gravity observes them).
std::vector<Isometry3d> driftedOdometry(const std::vector<Isometry3d>& truth, double yaw_per_step,
                                        double scale, double z_per_step) {
  std::vector<Isometry3d> odom{truth[0]};
  double yaw = yawOf(truth[0].linear());
  Vector3d p = truth[0].translation();
  for (std::size_t k = 0; k + 1 < truth.size(); ++k) {
    const double yaw_t = yawOf(truth[k].linear());
    const Vector3d dp =
        rotZ(yaw_t).transpose() * (truth[k + 1].translation() - truth[k].translation());
    const double dyaw = wrapAngle(yawOf(truth[k + 1].linear()) - yaw_t);
    p += rotZ(yaw) * dp * scale + Vector3d(0, 0, z_per_step);
    yaw = wrapAngle(yaw + dyaw + yaw_per_step);
    Isometry3d T = Isometry3d::Identity();
    T.linear() = rotZ(yaw) * tiltOf(truth[k + 1].linear());
    T.translation() = p;
    odom.push_back(T);
  }
  return odom;
}

/// Graph options for the drift of these routes (0.05 deg of yaw and 1 % of scale per 0.4 m
/// keyframe step, 4 deg and 0.32 m per 32 m lap: ten times the simulator's odometry the defaults
/// describe), so that loops measured from the truth are within the graph's sigmas.
PoseGraphOptions routeOptions() {
  PoseGraphOptions o;
  o.odom_pos_sigma_per_sqrt_m = 0.06;
  o.odom_yaw_sigma_per_sqrt_m_deg = 0.5;
  o.odom_yaw_sigma_per_sqrt_rad_deg = 0.1;  // their yaw drifts per step, not per turn
  return o;
}

Isometry3d relative(const std::vector<Isometry3d>& truth, std::size_t a, std::size_t b) {
  return truth[a].inverse() * truth[b];
}

double yawError(const Isometry3d& a, const Isometry3d& b) {
  return std::abs(wrapAngle(yawOf(a.linear()) - yawOf(b.linear())));
}

double positionError(const Isometry3d& a, const Isometry3d& b) {
  return (a.translation() - b.translation()).norm();
}

void addAll(PoseGraph4Dof& g, const std::vector<Isometry3d>& odom, std::uint64_t first_id = 0,
            int segment = 0) {
  for (std::size_t k = 0; k < odom.size(); ++k) g.addNode(first_id + k, segment, odom[k]);
}

// One lap of an 8 m square, keyframes every 0.4 m, 0.05 deg yaw drift per keyframe (4 deg per
// lap), 1 % scale error and 1 mm height drift per keyframe.
struct SquareLap {
  std::vector<Isometry3d> truth = squareRoute(8.0, 20, 1);
  std::vector<Isometry3d> odom = driftedOdometry(truth, 0.05 * kDeg, 1.01, 0.001);
};

// Three laps of the same square with loops to the first lap every 10 keyframes.
struct ThreeLaps {
  std::vector<Isometry3d> truth = squareRoute(8.0, 20, 3);
  std::vector<Isometry3d> odom = driftedOdometry(truth, 0.05 * kDeg, 1.01, 0.001);
  void addGoodLoops(PoseGraph4Dof& g) const {
    for (std::size_t lap = 1; lap <= 3; ++lap)
      for (std::size_t j = 0; j < 80; j += 10) {
        const std::size_t k = lap * 80 + j;
        if (k < truth.size()) g.addLoopEdge(k, j, relative(truth, k, j));
      }
  }
};

}  // namespace

TEST(PoseGraph4Dof, CorrectsASquareLoopWithKnownDrift) {
  const SquareLap lap;
  PoseGraph4Dof g(routeOptions());
  addAll(g, lap.odom);
  // The odometry is far off where the square closes.
  EXPECT_GT(positionError(lap.odom[80], lap.truth[80]), 0.35);
  EXPECT_GT(yawError(lap.odom[80], lap.truth[80]), 3.9 * kDeg);

  const int e0 = g.addLoopEdge(80, 0, relative(lap.truth, 80, 0));
  const int e1 = g.addLoopEdge(80, 1, relative(lap.truth, 80, 1));
  const PoseGraphSolveReport r = g.solve();
  EXPECT_TRUE(r.converged);
  EXPECT_EQ(r.solver_runs, 1);
  EXPECT_GT(r.iterations, 1);
  EXPECT_LT(r.final_cost, r.initial_cost);
  EXPECT_EQ(r.nodes, 81u);
  EXPECT_EQ(r.free_nodes, 80u);
  EXPECT_EQ(r.active_loop_edges, (std::vector<int>{e0, e1}));
  EXPECT_TRUE(r.rolled_back_loop_edges.empty());

  // The loop keyframe is back on its true pose (a tenth of the yaw drift is left: the loop
  // edge has a 1 deg sigma, the chain of 80 odometry edges about 4 deg) and both ends of the
  // loop agree.
  EXPECT_LT(positionError(g.pose(80), lap.truth[80]), 0.01);
  EXPECT_LT(yawError(g.pose(80), lap.truth[80]), 0.4 * kDeg);
  const Isometry3d loop_measured = relative(lap.truth, 80, 0);
  const Isometry3d loop_solved = g.pose(80).inverse() * g.pose(0);
  EXPECT_LT((loop_solved.translation() - loop_measured.translation()).norm(), 0.02);
  EXPECT_LT(std::abs(wrapAngle(yawOf(loop_solved.linear()) - yawOf(loop_measured.linear()))),
            0.4 * kDeg);
  EXPECT_LT(g.edges()[static_cast<std::size_t>(e0)].normalised_residual, 1.0);
  // The first node is the gauge: exactly its odometry pose.
  EXPECT_EQ(g.nodes()[0].p_world_body_m(), lap.odom[0].translation());
  // The whole lap is closer to the truth (what is left is mostly the 1 % scale error, which a
  // loop at the start point cannot observe).
  double worst = 0.0, worst_odom = 0.0, sq = 0.0, sq_odom = 0.0;
  for (std::size_t k = 0; k < lap.truth.size(); ++k) {
    const double e = positionError(g.pose(k), lap.truth[k]);
    const double e_odom = positionError(lap.odom[k], lap.truth[k]);
    worst = std::max(worst, e);
    worst_odom = std::max(worst_odom, e_odom);
    sq += e * e;
    sq_odom += e_odom * e_odom;
  }
  EXPECT_LT(worst, 0.3 * worst_odom);
  EXPECT_LT(std::sqrt(sq), 0.4 * std::sqrt(sq_odom));
  // drift() is the correction of the newest node.
  const Isometry3d C = g.drift(0);
  EXPECT_TRUE((C * lap.odom[80]).translation().isApprox(g.pose(80).translation(), 1e-12));
}

TEST(PoseGraph4Dof, APreciseLoopPutsTheLoopKeyframeOntoItsTruePose) {
  const SquareLap lap;
  PoseGraphOptions o = routeOptions();
  o.loop_sigma_pos_m = 0.005;
  o.loop_sigma_yaw_deg = 0.1;
  PoseGraph4Dof g(o);
  addAll(g, lap.odom);
  g.addLoopEdge(80, 0, relative(lap.truth, 80, 0));
  g.addLoopEdge(80, 1, relative(lap.truth, 80, 1));
  const PoseGraphSolveReport r = g.solve();
  EXPECT_TRUE(r.rolled_back_loop_edges.empty());
  EXPECT_LT(positionError(g.pose(80), lap.truth[80]), 0.0005);
  EXPECT_LT(yawError(g.pose(80), lap.truth[80]), 0.01 * kDeg);
}

TEST(PoseGraph4Dof, WithoutLoopsThePosesEqualTheOdometryExactly) {
  const SquareLap lap;
  PoseGraph4Dof g(routeOptions());
  addAll(g, lap.odom);
  const PoseGraphSolveReport r = g.solve();
  EXPECT_EQ(r.solver_runs, 0);
  for (std::size_t k = 0; k < lap.odom.size(); ++k) {
    EXPECT_EQ(g.nodes()[k].p_world_body_m(), lap.odom[k].translation());
    EXPECT_EQ(g.nodes()[k].yaw_rad(), yawOf(lap.odom[k].linear()));
    EXPECT_TRUE(g.pose(k).isApprox(lap.odom[k], 1e-14));
  }
  EXPECT_TRUE(g.drift(0).isApprox(Isometry3d::Identity(), 0.0));
}

TEST(PoseGraph4Dof, RollAndPitchNeverChange) {
  const SquareLap lap;
  PoseGraph4Dof g(routeOptions());
  addAll(g, lap.odom);
  g.addLoopEdge(80, 0, relative(lap.truth, 80, 0));
  g.solve();
  double max_yaw_change = 0.0;
  for (std::size_t k = 0; k < lap.odom.size(); ++k) {
    const Eigen::Matrix3d R = g.pose(k).linear();
    EXPECT_LT((tiltOf(R) - tiltOf(lap.odom[k].linear())).cwiseAbs().maxCoeff(), 1e-12) << k;
    // The body z axis keeps its angle to gravity.
    EXPECT_NEAR(R(2, 2), lap.odom[k].linear()(2, 2), 1e-12);
    max_yaw_change = std::max(max_yaw_change, yawError(g.pose(k), lap.odom[k]));
  }
  EXPECT_GT(max_yaw_change, 3.0 * kDeg);  // the yaw did move
}

TEST(PoseGraph4Dof, YawWrapsAroundPlusMinusPi) {
  // The first side heads just below +pi and the drift carries it across.
  const std::vector<Isometry3d> truth = squareRoute(8.0, 20, 1, M_PI - 0.01);
  const std::vector<Isometry3d> odom = driftedOdometry(truth, 0.05 * kDeg, 1.01, 0.001);
  PoseGraph4Dof g(routeOptions());
  addAll(g, odom);
  g.addLoopEdge(80, 0, relative(truth, 80, 0));
  g.addLoopEdge(80, 1, relative(truth, 80, 1));
  const PoseGraphSolveReport r = g.solve();
  EXPECT_TRUE(r.converged);
  EXPECT_TRUE(r.rolled_back_loop_edges.empty());
  bool crossed = false;
  for (std::size_t k = 0; k < odom.size(); ++k) {
    const double yaw = g.nodes()[k].yaw_rad();
    EXPECT_GE(yaw, -M_PI);
    EXPECT_LT(yaw, M_PI);
    crossed = crossed || yaw < -M_PI / 2;
  }
  EXPECT_TRUE(crossed);
  EXPECT_LT(positionError(g.pose(80), truth[80]), 0.01);
  EXPECT_LT(yawError(g.pose(80), truth[80]), 0.4 * kDeg);
  // Same correction as the same square driven at heading 0, turned by the heading.
  const SquareLap lap0;
  PoseGraph4Dof g0(routeOptions());
  addAll(g0, lap0.odom);
  g0.addLoopEdge(80, 0, relative(lap0.truth, 80, 0));
  g0.addLoopEdge(80, 1, relative(lap0.truth, 80, 1));
  g0.solve();
  for (std::size_t k = 0; k < odom.size(); k += 7) {
    const Vector3d err = g.pose(k).translation() - truth[k].translation();
    const Vector3d err0 = g0.pose(k).translation() - lap0.truth[k].translation();
    EXPECT_LT((rotZ(-(M_PI - 0.01)) * err - err0).norm(), 1e-6) << k;
  }
}

TEST(PoseGraph4Dof, AWrongLoopAmongGoodOnesIsRolledBack) {
  const ThreeLaps route;
  PoseGraph4Dof with_wrong(routeOptions()), reference(routeOptions());
  addAll(with_wrong, route.odom);
  addAll(reference, route.odom);
  route.addGoodLoops(with_wrong);
  route.addGoodLoops(reference);
  // Perceptual aliasing: node 180 (second lap, second corner) "recognises" node 60 (fourth
  // corner, 11 m away) as the same place seen from 0.3 m.
  Isometry3d alias = Isometry3d::Identity();
  alias.translation() << 0.3, 0.0, 0.0;
  const int wrong = with_wrong.addLoopEdge(180, 60, alias);

  const PoseGraphSolveReport r = with_wrong.solve();
  const PoseGraphSolveReport r_ref = reference.solve();
  EXPECT_EQ(r.rolled_back_loop_edges, std::vector<int>{wrong});
  EXPECT_EQ(r.solver_runs, 2);
  EXPECT_FALSE(with_wrong.edges()[static_cast<std::size_t>(wrong)].active);
  EXPECT_GT(with_wrong.edges()[static_cast<std::size_t>(wrong)].normalised_residual, 10.0);
  EXPECT_TRUE(r_ref.rolled_back_loop_edges.empty());
  EXPECT_EQ(r.active_loop_edges, r_ref.active_loop_edges);
  EXPECT_EQ(r.active_loop_edges.size(), 17u);  // 8 + 8 + 1 good loops
  for (std::size_t k = 0; k < route.odom.size(); ++k) {
    EXPECT_LT(positionError(with_wrong.pose(k), reference.pose(k)), 1e-6) << k;
    EXPECT_LT(yawError(with_wrong.pose(k), reference.pose(k)), 1e-6) << k;
  }
  // And the kept solution is the good one (the odometry is 1.2 m off after three laps).
  EXPECT_GT(positionError(route.odom.back(), route.truth.back()), 1.0);
  for (std::size_t k = 0; k < route.odom.size(); ++k)
    EXPECT_LT(positionError(with_wrong.pose(k), route.truth[k]), 0.15) << k;
}

TEST(PoseGraph4Dof, TheCauchyLossRollsTheWrongLoopBackToo) {
  const ThreeLaps route;
  PoseGraphOptions o = routeOptions();
  o.loss = RobustLoss::kCauchy;
  PoseGraph4Dof with_wrong(o), reference(o);
  for (PoseGraph4Dof* g : {&with_wrong, &reference}) {
    addAll(*g, route.odom);
    route.addGoodLoops(*g);
  }
  const int wrong = with_wrong.addLoopEdge(180, 60, Isometry3d::Identity());
  EXPECT_EQ(with_wrong.solve().rolled_back_loop_edges, std::vector<int>{wrong});
  EXPECT_TRUE(reference.solve().rolled_back_loop_edges.empty());
  for (std::size_t k = 0; k < route.odom.size(); ++k)
    EXPECT_LT(positionError(with_wrong.pose(k), reference.pose(k)), 1e-6) << k;
}

TEST(PoseGraph4Dof, WithNoRollbacksAllowedTheWrongLoopStaysAndDistortsTheGraph) {
  const ThreeLaps route;
  PoseGraphOptions o = routeOptions();
  o.max_rollbacks_per_solve = 0;
  PoseGraph4Dof g(o);
  addAll(g, route.odom);
  route.addGoodLoops(g);
  const int wrong = g.addLoopEdge(180, 60, Isometry3d::Identity());
  const PoseGraphSolveReport r = g.solve();
  EXPECT_TRUE(r.rolled_back_loop_edges.empty());
  EXPECT_EQ(r.solver_runs, 1);
  EXPECT_TRUE(g.edges()[static_cast<std::size_t>(wrong)].active);
  EXPECT_GT(g.edges()[static_cast<std::size_t>(wrong)].normalised_residual, 3.0);
  PoseGraph4Dof reference(o);
  addAll(reference, route.odom);
  route.addGoodLoops(reference);
  reference.solve();
  // The robust loss bounds the damage (2 cm here), but it is there.
  EXPECT_GT(positionError(g.pose(180), reference.pose(180)), 0.01);
}

TEST(PoseGraph4Dof, AWrongLoopThatJoinsASegmentFirstIsRolledBackToo) {
  // Segment 1 (second and third laps after a reset, in a frame of its own) is joined to segment
  // 0 by a wrong loop added before the good ones, so the wrong loop also places it first.
  const ThreeLaps route;
  Isometry3d G = Isometry3d::Identity();
  G.linear() = rotZ(1.0);
  G.translation() << 5.0, 2.0, 0.0;
  PoseGraph4Dof with_wrong(routeOptions()), reference(routeOptions());
  for (PoseGraph4Dof* g : {&with_wrong, &reference}) {
    for (std::size_t k = 0; k < 80; ++k) g->addNode(k, 0, route.odom[k]);
    for (std::size_t k = 80; k < route.odom.size(); ++k)
      g->addNode(k, 1, G.inverse() * route.odom[k]);
  }
  Isometry3d alias = Isometry3d::Identity();
  alias.translation() << 0.3, 0.0, 0.0;
  const int wrong = with_wrong.addLoopEdge(180, 60, alias);
  for (PoseGraph4Dof* g : {&with_wrong, &reference})
    for (std::size_t k = 80; k < route.odom.size(); k += 10)
      g->addLoopEdge(k, k % 80, relative(route.truth, k, k % 80));
  const PoseGraphSolveReport r = with_wrong.solve();
  const PoseGraphSolveReport r_ref = reference.solve();
  EXPECT_EQ(r.rolled_back_loop_edges, std::vector<int>{wrong});
  EXPECT_TRUE(r_ref.rolled_back_loop_edges.empty());
  EXPECT_EQ(r.separate_segments, 0);
  EXPECT_TRUE(with_wrong.connected(0, 1));
  for (std::size_t k = 0; k < route.odom.size(); ++k) {
    EXPECT_LT(positionError(with_wrong.pose(k), reference.pose(k)), 1e-6) << k;
    EXPECT_LT(yawError(with_wrong.pose(k), reference.pose(k)), 1e-6) << k;
    EXPECT_LT(positionError(with_wrong.pose(k), route.truth[k]), 0.15) << k;
  }
}

TEST(PoseGraph4Dof, SegmentsHaveNoSequentialEdgeAcrossAReset) {
  const ThreeLaps route;
  PoseGraph4Dof g(routeOptions());
  for (std::size_t k = 0; k < 100; ++k) g.addNode(k, k < 50 ? 0 : 1, route.odom[k]);
  int into_50 = 0, into_51 = 0, into_60 = 0;
  for (const GraphEdge& e : g.edges()) {
    ASSERT_EQ(e.kind, EdgeKind::kSequential);
    EXPECT_EQ(g.nodes()[e.from_index].segment, g.nodes()[e.to_index].segment)
        << e.from << " -> " << e.to;
    into_50 += e.to == 50;
    into_51 += e.to == 51;
    into_60 += e.to == 60;
  }
  EXPECT_EQ(into_50, 0);
  EXPECT_EQ(into_51, 1);
  EXPECT_EQ(into_60, 4);
  EXPECT_EQ(g.edges().size(), 2u * (1 + 2 + 3 + 4 * 46));
}

TEST(PoseGraph4Dof, AnUnconnectedSegmentKeepsItsOdometryPoses) {
  const ThreeLaps route;
  PoseGraph4Dof g(routeOptions());
  // Segment 0: the first lap, closed by a loop. Segment 1: the second lap after a reset, in a
  // frame of its own (its odometry restarted), never linked to segment 0.
  for (std::size_t k = 0; k <= 80; ++k) g.addNode(k, 0, route.odom[k]);
  std::vector<Isometry3d> seg1;
  const Isometry3d restart = route.odom[81].inverse();
  for (std::size_t k = 81; k < 161; ++k) seg1.push_back(restart * route.odom[k]);
  for (std::size_t k = 81; k < 161; ++k) g.addNode(k, 1, seg1[k - 81]);
  g.addLoopEdge(80, 0, relative(route.truth, 80, 0));
  g.addLoopEdge(160, 81, relative(route.truth, 160, 81));  // a loop inside segment 1 only

  const PoseGraphSolveReport r = g.solve();
  EXPECT_EQ(r.separate_segments, 1);
  EXPECT_FALSE(g.connected(0, 1));
  EXPECT_TRUE(g.connected(1, 1));
  EXPECT_FALSE(g.connected(0, 7));
  const std::vector<SegmentState> s = g.segments();
  ASSERT_EQ(s.size(), 2u);
  EXPECT_TRUE(s[0].connected_to_origin);
  EXPECT_FALSE(s[1].connected_to_origin);
  EXPECT_EQ(s[1].component, 1);
  EXPECT_EQ(s[1].first_id, 81u);
  EXPECT_EQ(s[1].last_id, 160u);
  EXPECT_EQ(s[1].nodes, 80u);
  // Segment 1 is corrected by its own loop but stays anchored at its first odometry pose.
  EXPECT_EQ(g.nodes()[81].p_world_body_m(), seg1[0].translation());
  EXPECT_EQ(g.nodes()[81].yaw_rad(), yawOf(seg1[0].linear()));
  EXPECT_GT(positionError(g.pose(160), seg1.back()), 0.3);

  // Without any loop of its own, segment 1 is exactly its odometry.
  PoseGraph4Dof h(routeOptions());
  for (std::size_t k = 0; k <= 80; ++k) h.addNode(k, 0, route.odom[k]);
  for (std::size_t k = 81; k < 161; ++k) h.addNode(k, 1, seg1[k - 81]);
  h.addLoopEdge(80, 0, relative(route.truth, 80, 0));
  h.solve();
  for (std::size_t k = 81; k < 161; ++k) {
    EXPECT_EQ(h.nodes()[k].p_world_body_m(), seg1[k - 81].translation());
    EXPECT_EQ(h.nodes()[k].yaw_rad(), yawOf(seg1[k - 81].linear()));
  }
  EXPECT_GT(positionError(h.pose(80), route.odom[80]), 0.35);  // segment 0 did move
}

TEST(PoseGraph4Dof, ALoopJoiningASegmentMovesItOntoTheOrigin) {
  // No drift: segment 1's odometry is the truth seen from a frame G away (yaw 0.7 rad and a
  // translation), so one exact loop places it exactly.
  const std::vector<Isometry3d> truth = squareRoute(8.0, 20, 2);
  Isometry3d G = Isometry3d::Identity();
  G.linear() = rotZ(0.7);
  G.translation() << 3.0, -2.0, 0.5;
  PoseGraph4Dof g(routeOptions());
  for (std::size_t k = 0; k < 80; ++k) g.addNode(k, 0, truth[k]);
  for (std::size_t k = 80; k < truth.size(); ++k) g.addNode(k, 1, G.inverse() * truth[k]);
  g.solve();
  EXPECT_FALSE(g.connected(0, 1));
  EXPECT_TRUE(g.pose(100).isApprox(G.inverse() * truth[100], 1e-12));

  g.addLoopEdge(120, 40, relative(truth, 120, 40));
  EXPECT_TRUE(g.connected(0, 1));
  const PoseGraphSolveReport r = g.solve();
  EXPECT_EQ(r.separate_segments, 0);
  EXPECT_TRUE(g.segments()[1].connected_to_origin);
  EXPECT_EQ(r.free_nodes, truth.size() - 1);
  for (std::size_t k = 0; k < truth.size(); ++k) {
    EXPECT_LT(positionError(g.pose(k), truth[k]), 1e-9) << k;
    EXPECT_LT(yawError(g.pose(k), truth[k]), 1e-9) << k;
  }
  const Isometry3d D = g.drift(1);
  EXPECT_TRUE(D.isApprox(G, 1e-9)) << D.matrix();
  // A node added to segment 1 later starts at the segment's correction.
  const Isometry3d next = G.inverse() * truth[5];
  g.addNode(1000, 1, next);
  EXPECT_TRUE(g.pose(1000).isApprox(D * next, 1e-12));
}

TEST(PoseGraph4Dof, TwoSegmentsJoinedOnlyToEachOtherKeepTheLowerOnesAnchor) {
  const std::vector<Isometry3d> truth = squareRoute(8.0, 20, 2);
  Isometry3d G1 = Isometry3d::Identity(), G2 = Isometry3d::Identity();
  G1.linear() = rotZ(-1.2);
  G1.translation() << -4.0, 1.0, 0.0;
  G2.linear() = rotZ(2.9);
  G2.translation() << 10.0, 5.0, -1.0;
  PoseGraph4Dof g(routeOptions());
  for (std::size_t k = 0; k < 40; ++k) g.addNode(k, 0, truth[k]);
  for (std::size_t k = 40; k < 100; ++k) g.addNode(k, 1, G1.inverse() * truth[k]);
  for (std::size_t k = 100; k < truth.size(); ++k) g.addNode(k, 2, G2.inverse() * truth[k]);
  g.addLoopEdge(130, 50, relative(truth, 130, 50));
  const PoseGraphSolveReport r = g.solve();
  EXPECT_EQ(r.separate_segments, 2);
  EXPECT_TRUE(g.connected(1, 2));
  EXPECT_FALSE(g.connected(0, 2));
  EXPECT_EQ(g.segments()[2].component, 1);
  // Segment 1 holds its odometry, segment 2 is placed in segment 1's frame.
  for (std::size_t k = 40; k < truth.size(); ++k)
    EXPECT_LT(positionError(g.pose(k), G1.inverse() * truth[k]), 1e-9) << k;
}

TEST(PoseGraph4Dof, TheSameCallsGiveTheSameResult) {
  const ThreeLaps route;
  PoseGraph4Dof a(routeOptions()), b(routeOptions());
  for (PoseGraph4Dof* g : {&a, &b}) {
    addAll(*g, route.odom);
    route.addGoodLoops(*g);
    g->addLoopEdge(180, 60, Isometry3d::Identity());
  }
  const PoseGraphSolveReport ra = a.solve(), rb = b.solve();
  EXPECT_EQ(ra.iterations, rb.iterations);
  EXPECT_EQ(ra.final_cost, rb.final_cost);
  EXPECT_EQ(ra.rolled_back_loop_edges, rb.rolled_back_loop_edges);
  for (std::size_t k = 0; k < route.odom.size(); ++k) {
    EXPECT_EQ(a.nodes()[k].p_world_body_m(), b.nodes()[k].p_world_body_m());
    EXPECT_EQ(a.nodes()[k].yaw_rad(), b.nodes()[k].yaw_rad());
  }
}

TEST(PoseGraph4Dof, IdsOutOfOrderAndBadArgumentsAreRejected) {
  PoseGraph4Dof g(routeOptions());
  g.addNode(5, 0, Isometry3d::Identity());
  auto message = [](auto&& call) -> std::string {
    try {
      call();
    } catch (const std::exception& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_THROW(g.addNode(5, 0, Isometry3d::Identity()), std::invalid_argument);
  const std::string m = message([&] { g.addNode(4, 0, Isometry3d::Identity()); });
  EXPECT_NE(m.find("node 4"), std::string::npos) << m;
  EXPECT_NE(m.find("5"), std::string::npos) << m;
  g.addNode(6, 1, Isometry3d::Identity());
  EXPECT_THROW(g.addNode(7, 0, Isometry3d::Identity()), std::invalid_argument);  // segment back
  EXPECT_THROW(g.addNode(8, -1, Isometry3d::Identity()), std::invalid_argument);
  Isometry3d bad = Isometry3d::Identity();
  bad.linear() *= 2.0;
  EXPECT_THROW(g.addNode(9, 1, bad), std::invalid_argument);
  bad = Isometry3d::Identity();
  bad.translation().x() = std::nan("");
  EXPECT_THROW(g.addNode(9, 1, bad), std::invalid_argument);
  EXPECT_EQ(g.nodes().size(), 2u);  // nothing added by the failed calls

  const std::string m2 = message([&] { g.addLoopEdge(6, 42, Isometry3d::Identity()); });
  EXPECT_NE(m2.find("42"), std::string::npos) << m2;
  EXPECT_THROW(g.addLoopEdge(6, 6, Isometry3d::Identity()), std::invalid_argument);
  EXPECT_THROW(g.pose(42), std::out_of_range);
  EXPECT_THROW(g.drift(3), std::out_of_range);
  EXPECT_TRUE(g.hasNode(6));
  EXPECT_FALSE(g.hasNode(7));
}

TEST(PoseGraph4Dof, MemoryGrowsWithNodesAndEdges) {
  const SquareLap lap;
  PoseGraph4Dof g(routeOptions());
  const std::size_t empty = g.memoryBytes();
  addAll(g, lap.odom);
  EXPECT_GE(g.memoryBytes(), empty + 81 * sizeof(GraphNode) + g.edges().size() * sizeof(GraphEdge));
  const std::size_t before = g.memoryBytes();
  for (int k = 0; k < 200; ++k) g.addLoopEdge(80, 0, relative(lap.truth, 80, 0));
  EXPECT_GT(g.memoryBytes(), before);
  EXPECT_GE(g.memoryBytes(), empty + 81 * sizeof(GraphNode) + g.edges().size() * sizeof(GraphEdge));
}

TEST(PoseGraph4Dof, ALoadedMapStaysFixedAndALaterRunIsMovedIntoItsFrame) {
  // Segment 0: a map (fixed nodes at their true poses). Segment 1: a new run with drift, in a
  // frame G away. Two loops to the map put the run into the map frame; no map node moves.
  const std::vector<Isometry3d> truth = squareRoute(8.0, 20, 2);
  Isometry3d G = Isometry3d::Identity();
  G.linear() = rotZ(-1.1);
  G.translation() << -4.0, 2.0, 0.3;
  std::vector<Isometry3d> run(truth.begin() + 80, truth.end());
  const std::vector<Isometry3d> run_odom = driftedOdometry(run, 0.05 * kDeg, 1.01, 0.001);
  PoseGraph4Dof g(routeOptions());
  for (std::size_t k = 0; k < 80; ++k) g.addFixedNode(k, 0, truth[k]);
  for (std::size_t k = 0; k < run_odom.size(); ++k) g.addNode(80 + k, 1, G.inverse() * run_odom[k]);
  EXPECT_EQ(g.nodes()[0].fixed, true);
  EXPECT_EQ(g.nodes()[80].fixed, false);
  // No odometry edge among the map's nodes nor into the map.
  for (const GraphEdge& e : g.edges()) EXPECT_GE(e.from, 80u);

  g.addLoopEdge(10, 90, relative(truth, 10, 90));
  g.addLoopEdge(70, 150, relative(truth, 70, 150));
  const PoseGraphSolveReport r = g.solve();
  EXPECT_TRUE(r.rolled_back_loop_edges.empty());
  EXPECT_TRUE(g.segments()[1].connected_to_origin);
  EXPECT_EQ(r.free_nodes, run_odom.size());
  for (std::size_t k = 0; k < 80; ++k) EXPECT_TRUE(g.pose(k).isApprox(truth[k], 1e-12)) << k;
  // The loop keyframes land on their true poses within the loops' weight against the drift.
  EXPECT_LT(positionError(g.pose(90), truth[90]), 0.02);
  EXPECT_LT(positionError(g.pose(150), truth[150]), 0.02);
  for (std::size_t k = 80; k < truth.size(); ++k)
    EXPECT_LT(positionError(g.pose(k), truth[k]), 0.10) << k;

  // Order and mixing rules.
  EXPECT_THROW(g.addFixedNode(1000, 1, truth[0]), std::invalid_argument);  // after free nodes
  PoseGraph4Dof h(routeOptions());
  h.addFixedNode(0, 0, truth[0]);
  EXPECT_THROW(h.addNode(1, 0, truth[1]), std::invalid_argument);  // same segment, free
  EXPECT_NO_THROW(h.addNode(1, 1, truth[1]));
}
