// ImuFactor: analytic Jacobians vs numeric differentiation through the right perturbation,
// whitening, and a small Ceres solve with a pose manifold whose PlusJacobian is [I6; 0].
#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <memory>
#include <random>

#include "imu/synthetic_motion.h"
#include "rgbdi/common/so3.h"
#include "rgbdi/imu/imu_factor.h"

using namespace rgbdi;
using namespace rgbdi::imu;

namespace {

const Eigen::Vector3d& kGravity = test::kTestGravity;
ImuNoise testNoise() { return test::simImuNoise(); }

using Pose = std::array<double, 7>;
using SpeedBias = std::array<double, 9>;

Pose makePose(const Eigen::Vector3d& p, const Eigen::Quaterniond& q) {
  return {p.x(), p.y(), p.z(), q.x(), q.y(), q.z(), q.w()};
}

SpeedBias makeSpeedBias(const Eigen::Vector3d& v, const Eigen::Vector3d& ba,
                        const Eigen::Vector3d& bg) {
  return {v.x(), v.y(), v.z(), ba.x(), ba.y(), ba.z(), bg.x(), bg.y(), bg.z()};
}

// The perturbation the lead's PoseManifold applies: p <- p + dp, q <- q * Exp(dtheta).
Pose perturbPose(const Pose& x, int k, double h) {
  Pose y = x;
  if (k < 3) {
    y[static_cast<size_t>(k)] += h;
    return y;
  }
  Eigen::Vector3d dth = Eigen::Vector3d::Zero();
  dth[k - 3] = h;
  const Eigen::Quaterniond q =
      (Eigen::Quaterniond(x[6], x[3], x[4], x[5]) * expQuat(dth)).normalized();
  y[3] = q.x();
  y[4] = q.y();
  y[5] = q.z();
  y[6] = q.w();
  return y;
}

// Test copy of the estimator's pose manifold (ambient 7, tangent 6, PlusJacobian [I6; 0]).
class TestPoseManifold : public ceres::Manifold {
 public:
  int AmbientSize() const override { return 7; }
  int TangentSize() const override { return 6; }
  bool Plus(const double* x, const double* delta, double* x_plus_delta) const override {
    const Eigen::Map<const Eigen::Vector3d> p(x);
    const Eigen::Map<const Eigen::Quaterniond> q(x + 3);
    Eigen::Map<Eigen::Vector3d> p_out(x_plus_delta);
    Eigen::Map<Eigen::Quaterniond> q_out(x_plus_delta + 3);
    p_out = p + Eigen::Map<const Eigen::Vector3d>(delta);
    q_out = (q * expQuat(Eigen::Map<const Eigen::Vector3d>(delta + 3))).normalized();
    return true;
  }
  bool PlusJacobian(const double*, double* jacobian) const override {
    Eigen::Map<Eigen::Matrix<double, 7, 6, Eigen::RowMajor>> J(jacobian);
    J.setZero();
    J.topRows<6>().setIdentity();
    return true;
  }
  bool Minus(const double* y, const double* x, double* y_minus_x) const override {
    const Eigen::Map<const Eigen::Quaterniond> qx(x + 3), qy(y + 3);
    Eigen::Map<Eigen::Matrix<double, 6, 1>> d(y_minus_x);
    d.head<3>() = Eigen::Map<const Eigen::Vector3d>(y) - Eigen::Map<const Eigen::Vector3d>(x);
    d.tail<3>() = logSO3((qx.inverse() * qy).toRotationMatrix());
    return true;
  }
  bool MinusJacobian(const double*, double* jacobian) const override {
    Eigen::Map<Eigen::Matrix<double, 6, 7, Eigen::RowMajor>> J(jacobian);
    J.setZero();
    J.leftCols<6>().setIdentity();
    return true;
  }
};

struct Scenario {
  std::unique_ptr<Preintegration> pre;
  Pose pose_i, pose_j;
  SpeedBias sb_i, sb_j;
};

// A pre-integration over 0.3 s of noisy synthetic motion and two random states near consistency.
Scenario randomScenario(std::mt19937_64& rng) {
  std::normal_distribution<double> n01(0.0, 1.0);
  auto rvec = [&](double s) { return Eigen::Vector3d(s * n01(rng), s * n01(rng), s * n01(rng)); };
  const test::SyntheticMotion motion(kGravity);
  const Eigen::Vector3d ba_lin = rvec(0.1), bg_lin = rvec(0.01);
  Scenario sc;
  sc.pre = std::make_unique<Preintegration>(ba_lin, bg_lin, testNoise());
  const double t0 = 1.0 + std::uniform_real_distribution<double>(0.0, 2.0)(rng);
  for (const auto& s : motion.samples(t0, t0 + 0.3, 200.0, ba_lin, bg_lin)) {
    sc.pre->push(s.t, s.acc + rvec(0.05), s.gyr + rvec(0.005));
  }
  const Eigen::Vector3d Pi = rvec(3.0), Vi = rvec(1.0);
  const Eigen::Quaterniond Qi = expQuat(rvec(1.5));
  Eigen::Vector3d Pj, Vj;
  Eigen::Quaterniond Qj;
  sc.pre->predict(Pi, Qi, Vi, kGravity, Pj, Qj, Vj);
  sc.pose_i = makePose(Pi, Qi);
  sc.pose_j = makePose(Pj + rvec(0.05), Qj * expQuat(rvec(0.05)));
  sc.sb_i = makeSpeedBias(Vi, ba_lin + rvec(0.05), bg_lin + rvec(0.005));
  sc.sb_j = makeSpeedBias(Vj + rvec(0.05), ba_lin + rvec(0.05), bg_lin + rvec(0.005));
  return sc;
}

using Residual = Eigen::Matrix<double, 15, 1>;

Residual evaluate(const ImuFactor& f, const Pose& pi, const SpeedBias& si, const Pose& pj,
                  const SpeedBias& sj) {
  const double* params[] = {pi.data(), si.data(), pj.data(), sj.data()};
  Residual r;
  EXPECT_TRUE(f.Evaluate(params, r.data(), nullptr));
  return r;
}

}  // namespace

// Central differences with step 1e-6 through the right perturbation; the agreement is limited by
// the O(h^2) truncation and round-off, so 1e-6 of each block's magnitude is a real check.
TEST(ImuFactor, AnalyticJacobiansMatchNumericDifferentiation) {
  std::mt19937_64 rng(20240601);
  double worst = 0.0;
  for (int trial = 0; trial < 20; ++trial) {
    const Scenario sc = randomScenario(rng);
    const ImuFactor factor(sc.pre.get(), kGravity);
    const double* params[] = {sc.pose_i.data(), sc.sb_i.data(), sc.pose_j.data(), sc.sb_j.data()};
    Residual r;
    Eigen::Matrix<double, 15, 7, Eigen::RowMajor> J0, J2;
    Eigen::Matrix<double, 15, 9, Eigen::RowMajor> J1, J3;
    double* jacs[] = {J0.data(), J1.data(), J2.data(), J3.data()};
    ASSERT_TRUE(factor.Evaluate(params, r.data(), jacs));
    ASSERT_LT((r - evaluate(factor, sc.pose_i, sc.sb_i, sc.pose_j, sc.sb_j)).norm(), 1e-12);

    const double h = 1e-6;
    Eigen::Matrix<double, 15, 6> N0, N2;
    Eigen::Matrix<double, 15, 9> N1, N3;
    for (int k = 0; k < 6; ++k) {
      N0.col(k) = (evaluate(factor, perturbPose(sc.pose_i, k, h), sc.sb_i, sc.pose_j, sc.sb_j) -
                   evaluate(factor, perturbPose(sc.pose_i, k, -h), sc.sb_i, sc.pose_j, sc.sb_j)) /
                  (2 * h);
      N2.col(k) = (evaluate(factor, sc.pose_i, sc.sb_i, perturbPose(sc.pose_j, k, h), sc.sb_j) -
                   evaluate(factor, sc.pose_i, sc.sb_i, perturbPose(sc.pose_j, k, -h), sc.sb_j)) /
                  (2 * h);
    }
    for (int k = 0; k < 9; ++k) {
      auto plus = [&](SpeedBias s, double d) {
        s[static_cast<size_t>(k)] += d;
        return s;
      };
      N1.col(k) = (evaluate(factor, sc.pose_i, plus(sc.sb_i, h), sc.pose_j, sc.sb_j) -
                   evaluate(factor, sc.pose_i, plus(sc.sb_i, -h), sc.pose_j, sc.sb_j)) /
                  (2 * h);
      N3.col(k) = (evaluate(factor, sc.pose_i, sc.sb_i, sc.pose_j, plus(sc.sb_j, h)) -
                   evaluate(factor, sc.pose_i, sc.sb_i, sc.pose_j, plus(sc.sb_j, -h))) /
                  (2 * h);
    }
    auto check = [&](const Eigen::MatrixXd& ana, const Eigen::MatrixXd& num, const char* name) {
      const double scale = std::max(1.0, ana.cwiseAbs().maxCoeff());
      const double err = (ana - num).cwiseAbs().maxCoeff() / scale;
      worst = std::max(worst, err);
      EXPECT_LT(err, 1e-6) << name << " trial " << trial << "\nanalytic\n"
                           << ana << "\nnumeric\n"
                           << num;
    };
    check(J0.leftCols<6>(), N0, "pose_i");
    check(J1, N1, "speed_bias_i");
    check(J2.leftCols<6>(), N2, "pose_j");
    check(J3, N3, "speed_bias_j");
    EXPECT_EQ(J0.col(6).norm(), 0.0);
    EXPECT_EQ(J2.col(6).norm(), 0.0);
  }
  std::printf("worst relative Jacobian error: %.3e\n", worst);
}

TEST(ImuFactor, ResidualIsWhitenedPreintegrationResidual) {
  std::mt19937_64 rng(7);
  const Scenario sc = randomScenario(rng);
  const ImuFactor factor(sc.pre.get(), kGravity);
  const Residual r = evaluate(factor, sc.pose_i, sc.sb_i, sc.pose_j, sc.sb_j);
  auto v3 = [](const double* d) { return Eigen::Vector3d(d[0], d[1], d[2]); };
  auto q = [](const Pose& p) { return Eigen::Quaterniond(p[6], p[3], p[4], p[5]); };
  const Residual raw = sc.pre->residual(v3(sc.pose_i.data()), q(sc.pose_i), v3(sc.sb_i.data()),
                                        v3(sc.sb_i.data() + 3), v3(sc.sb_i.data() + 6),
                                        v3(sc.pose_j.data()), q(sc.pose_j), v3(sc.sb_j.data()),
                                        v3(sc.sb_j.data() + 3), v3(sc.sb_j.data() + 6), kGravity);
  EXPECT_LT((r - sc.pre->sqrtInformation() * raw).norm(), 1e-9 * r.norm());
  // The squared norm is the Mahalanobis distance under the pre-integration covariance.
  EXPECT_NEAR(r.squaredNorm(), raw.dot(sc.pre->covariance().ldlt().solve(raw)),
              1e-8 * r.squaredNorm());
}

TEST(ImuFactor, CeresRecoversTheStateThePreintegrationPredicts) {
  std::mt19937_64 rng(99);
  Scenario sc = randomScenario(rng);
  const ImuFactor* factor = new ImuFactor(sc.pre.get(), kGravity);
  // State i fixed with biases at the linearisation point: the optimum of state j is predict().
  const Eigen::Vector3d ba = sc.pre->biasAcc(), bg = sc.pre->biasGyr();
  Eigen::Vector3d Pj, Vj;
  Eigen::Quaterniond Qj;
  const Eigen::Vector3d Pi(sc.pose_i[0], sc.pose_i[1], sc.pose_i[2]);
  const Eigen::Quaterniond Qi(sc.pose_i[6], sc.pose_i[3], sc.pose_i[4], sc.pose_i[5]);
  const Eigen::Vector3d Vi(sc.sb_i[0], sc.sb_i[1], sc.sb_i[2]);
  sc.sb_i = makeSpeedBias(Vi, ba, bg);
  sc.pre->predict(Pi, Qi, Vi, kGravity, Pj, Qj, Vj);

  ceres::Problem problem;
  problem.AddResidualBlock(const_cast<ImuFactor*>(factor), nullptr, sc.pose_i.data(),
                           sc.sb_i.data(), sc.pose_j.data(), sc.sb_j.data());
  problem.SetManifold(sc.pose_i.data(), new TestPoseManifold);
  problem.SetManifold(sc.pose_j.data(), new TestPoseManifold);
  problem.SetParameterBlockConstant(sc.pose_i.data());
  problem.SetParameterBlockConstant(sc.sb_i.data());
  ceres::Solver::Options options;
  options.max_num_iterations = 20;
  options.function_tolerance = 1e-16;
  options.gradient_tolerance = 1e-16;
  options.parameter_tolerance = 1e-16;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  ASSERT_TRUE(summary.IsSolutionUsable()) << summary.FullReport();
  EXPECT_LT(summary.final_cost, 1e-12);
  EXPECT_LT((Eigen::Vector3d(sc.pose_j[0], sc.pose_j[1], sc.pose_j[2]) - Pj).norm(), 1e-8);
  EXPECT_LT(Eigen::Quaterniond(sc.pose_j[6], sc.pose_j[3], sc.pose_j[4], sc.pose_j[5])
                .angularDistance(Qj),
            1e-8);
  EXPECT_LT((Eigen::Vector3d(sc.sb_j[0], sc.sb_j[1], sc.sb_j[2]) - Vj).norm(), 1e-8);
  EXPECT_LT((Eigen::Vector3d(sc.sb_j[3], sc.sb_j[4], sc.sb_j[5]) - ba).norm(), 1e-8);
  EXPECT_LT((Eigen::Vector3d(sc.sb_j[6], sc.sb_j[7], sc.sb_j[8]) - bg).norm(), 1e-8);
}

TEST(ImuFactor, RejectsNullAndDegeneratePreintegration) {
  EXPECT_THROW(ImuFactor(nullptr, kGravity), std::invalid_argument);
  Preintegration one(Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), testNoise());
  one.push(0.0, -kGravity, Eigen::Vector3d::Zero());
  EXPECT_THROW(ImuFactor(&one, kGravity), std::runtime_error);
  Preintegration noiseless(Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), ImuNoise{});
  noiseless.push(0.0, -kGravity, Eigen::Vector3d::Zero());
  noiseless.push(0.005, -kGravity, Eigen::Vector3d::Zero());
  EXPECT_THROW(ImuFactor(&noiseless, kGravity), std::runtime_error);
}

TEST(ImuFactor, FollowsARepropagatedPreintegration) {
  std::mt19937_64 rng(5);
  Scenario sc = randomScenario(rng);
  const ImuFactor factor(sc.pre.get(), kGravity);
  const Residual before = evaluate(factor, sc.pose_i, sc.sb_i, sc.pose_j, sc.sb_j);
  // Move the linearisation point to the biases of state i, as the estimator does.
  sc.pre->repropagate(Eigen::Vector3d(sc.sb_i[3], sc.sb_i[4], sc.sb_i[5]),
                      Eigen::Vector3d(sc.sb_i[6], sc.sb_i[7], sc.sb_i[8]));
  const Residual after = evaluate(factor, sc.pose_i, sc.sb_i, sc.pose_j, sc.sb_j);
  const ImuFactor fresh(sc.pre.get(), kGravity);
  EXPECT_EQ(after, evaluate(fresh, sc.pose_i, sc.sb_i, sc.pose_j, sc.sb_j));
  EXPECT_GT((after - before).norm(), 1e-6 * before.norm()) << "repropagation changed nothing";
}
