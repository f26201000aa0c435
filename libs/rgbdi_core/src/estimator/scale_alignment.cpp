#include "rgbdi/estimator/scale_alignment.h"

#include <Eigen/Dense>
#include <cmath>
#include <exception>

#include "rgbdi/common/so3.h"
#include "rgbdi/imu/imu_init.h"
#include "rgbdi/imu/preintegration.h"

namespace rgbdi::estimator {

namespace {

// Smallest / largest eigenvalue of the column-scaled normal matrix below which the system is
// rank-deficient (singular-value ratio 1e-6: well above the ~1e-8 rounding floor of squaring).
constexpr double kMinEigenvalueRatio = 1e-12;

/// One frame-to-frame constraint, with everything the linear rows need.
struct Interval {
  Eigen::Matrix3d R_bk_c0;  // R_c0_bk^T: rows are expressed in body k, like the deltas
  double dt = 0.0;
  Eigen::Vector3d dp_sfm;         // p_c0_c(k+1) - p_c0_ck in SfM units
  Eigen::Vector3d dlever;         // change of -R_c0_b p_body_cam (metric, scale-free)
  Eigen::Vector3d dP, dV;         // pre-integrated deltas
  Eigen::Matrix<double, 6, 6> C;  // covariance of [dP, dV]
};

/// Unknowns [v_0..v_n (c0), gravity (3, or the 2-DOF tangent step around *g0), s]. Rows, per
/// interval (from the pre-integration definitions in preintegration.h):
///   R^T dt v_k + 0.5 R^T dt^2 g - s R^T dp_sfm = R^T dlever - dP
///   R^T v_k - R^T v_{k+1} + R^T dt g          = -dV
void buildRows(const std::vector<Interval>& iv, const Eigen::Vector3d* g0, Eigen::MatrixXd* A,
               Eigen::VectorXd* b) {
  const int n = static_cast<int>(iv.size()) + 1;
  const int cols = 3 * n + (g0 ? 2 : 3) + 1;
  A->setZero(6 * (n - 1), cols);
  b->resize(6 * (n - 1));
  const Eigen::Matrix<double, 3, 2> B =
      g0 ? sphereTangentBasis(*g0) : Eigen::Matrix<double, 3, 2>();
  for (int k = 0; k + 1 < n; ++k) {
    const Interval& I = iv[static_cast<size_t>(k)];
    const int r = 6 * k;
    Eigen::Matrix<double, 6, 3> G;  // d(rows)/d(g)
    G << 0.5 * I.dt * I.dt * I.R_bk_c0, I.dt * I.R_bk_c0;
    A->block<3, 3>(r, 3 * k) = I.dt * I.R_bk_c0;
    A->block<3, 3>(r + 3, 3 * k) = I.R_bk_c0;
    A->block<3, 3>(r + 3, 3 * (k + 1)) = -I.R_bk_c0;
    A->block<3, 1>(r, cols - 1) = -I.R_bk_c0 * I.dp_sfm;
    b->segment<6>(r) << I.R_bk_c0 * I.dlever - I.dP, -I.dV;
    if (g0) {
      A->block<6, 2>(r, 3 * n) = G * B;
      b->segment<6>(r) -= G * (*g0);
    } else {
      A->block<6, 3>(r, 3 * n) = G;
    }
  }
}

/// Covariance of all rows: the pre-integration noise plus independent camera-position noise of
/// variance var_cam [m^2] per axis, which enters the position rows through p_(k+1) - p_k and so
/// also correlates consecutive intervals.
Eigen::MatrixXd rowCovariance(const std::vector<Interval>& iv, double var_cam) {
  const int m = 6 * static_cast<int>(iv.size());
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(m, m);
  for (size_t k = 0; k < iv.size(); ++k) {
    const int r = 6 * static_cast<int>(k);
    S.block<6, 6>(r, r) = iv[k].C;
    S.block<3, 3>(r, r).diagonal().array() += 2.0 * var_cam;
    if (k + 1 < iv.size()) {
      const Eigen::Matrix3d X = -var_cam * iv[k].R_bk_c0 * iv[k + 1].R_bk_c0.transpose();
      S.block<3, 3>(r, r + 6) = X;
      S.block<3, 3>(r + 6, r) = X.transpose();
    }
  }
  return S;
}

struct LinearSolution {
  Eigen::VectorXd x;
  double scale_sigma = 0.0;  // 1-sigma of the last unknown under the row covariance
  double chi2 = 0.0;         // whitened squared residual
};

/// Generalised least squares for A x = b with row covariance S.
std::optional<LinearSolution> solveGls(const Eigen::MatrixXd& A, const Eigen::VectorXd& b,
                                       const Eigen::MatrixXd& S) {
  const Eigen::LLT<Eigen::MatrixXd> llt(S);
  if (llt.info() != Eigen::Success) return std::nullopt;
  const Eigen::MatrixXd Aw = llt.matrixL().solve(A);
  const Eigen::VectorXd bw = llt.matrixL().solve(b);
  // Equilibrate the columns (velocities, gravity and scale have unrelated magnitudes) so the
  // rank test is meaningful; then x = D y with y from the eigen-decomposition of the normal
  // matrix of Aw D (small and symmetric: much cheaper than an SVD of Aw, and this runs inside
  // the noise-level search).
  const Eigen::VectorXd norms = Aw.colwise().norm();
  if (!(norms.minCoeff() > 0.0) || !norms.allFinite()) return std::nullopt;
  const Eigen::VectorXd D = norms.cwiseInverse();
  const Eigen::MatrixXd M = Aw * D.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(M.transpose() * M);
  if (eig.info() != Eigen::Success) return std::nullopt;
  const Eigen::VectorXd ev = eig.eigenvalues();  // ascending
  if (!(ev(0) > kMinEigenvalueRatio * ev(ev.size() - 1))) return std::nullopt;
  const Eigen::MatrixXd& V = eig.eigenvectors();
  LinearSolution sol;
  sol.x = D.asDiagonal() * (V * (V.transpose() * (M.transpose() * bw)).cwiseQuotient(ev));
  if (!sol.x.allFinite()) return std::nullopt;
  // Whitened rows: Cov(x) = D V E^-1 V^T D; only the scale entry is needed.
  const Eigen::Index last = A.cols() - 1;
  sol.scale_sigma = D(last) * std::sqrt(V.row(last).cwiseAbs2().dot(ev.cwiseInverse()));
  sol.chi2 = (Aw * sol.x - bw).squaredNorm();
  return sol;
}

/// Camera-position noise variance [m^2] for which the whitened residual matches its degrees of
/// freedom (chi2 = rows - unknowns). The SfM poses are far noisier than the pre-integration, and
/// weighting the position rows by the IMU noise alone would trust them blindly: the noise in
/// dp_sfm, which multiplies s, then pulls the scale towards zero. chi2 only falls as var_cam
/// grows, so a bisection on log(var_cam) finds it; 0 when the IMU noise already explains all.
double cameraNoiseVariance(const std::vector<Interval>& iv, const Eigen::MatrixXd& A,
                           const Eigen::VectorXd& b) {
  const double dof = static_cast<double>(A.rows() - A.cols());
  auto excess = [&](double var) {
    const auto sol = solveGls(A, b, rowCovariance(iv, var));
    return sol ? sol->chi2 - dof : -1.0;
  };
  if (dof <= 0.0 || excess(0.0) <= 0.0) return 0.0;
  double lo = 1e-14, hi = 1e-8;  // [m^2]
  while (excess(hi) > 0.0) {
    lo = hi;
    hi *= 100.0;
    if (hi > 1e4) return hi;  // metres of noise: alignment will be rejected anyway
  }
  for (int it = 0; it < 12; ++it) {  // brackets a factor 100: ends within 0.1 %
    const double mid = std::sqrt(lo * hi);
    (excess(mid) > 0.0 ? lo : hi) = mid;
  }
  return hi;
}

/// Gyro bias from the visual body rotations; repropagates every pre-integration with it.
bool estimateGyroBias(const std::vector<Eigen::Matrix3d>& R_c0_b,
                      const std::vector<imu::Preintegration*>& preint, Eigen::Vector3d* bg) {
  std::vector<imu::GyroBiasPair> pairs;
  for (size_t k = 1; k < R_c0_b.size(); ++k)
    pairs.emplace_back(Eigen::Quaterniond(R_c0_b[k - 1].transpose() * R_c0_b[k]), preint[k]);
  *bg = preint[1]->biasGyr();
  // Two Gauss-Newton passes: the bias Jacobian is a linearisation, the second pass removes what
  // is left after re-integrating with the first estimate.
  for (int pass = 0; pass < 2; ++pass) {
    try {
      *bg += imu::solveGyroBias(pairs);
    } catch (const std::exception&) {
      return false;
    }
    if (!bg->allFinite()) return false;
    for (size_t k = 1; k < preint.size(); ++k) preint[k]->repropagate(Eigen::Vector3d::Zero(), *bg);
  }
  return true;
}

}  // namespace

std::optional<ScaleAlignmentResult> alignWithScale(const std::vector<Eigen::Isometry3d>& T_c0_c,
                                                   const Eigen::Isometry3d& T_body_cam,
                                                   const std::vector<imu::Preintegration*>& preint,
                                                   double g_norm, double max_scale_rel_sigma) {
  const size_t n = T_c0_c.size();
  // 6 (n - 1) equations for 3 n + 4 unknowns: three frames are one equation short.
  if (n < 4 || preint.size() != n) return std::nullopt;
  for (size_t k = 1; k < n; ++k)
    if (preint[k] == nullptr || !(preint[k]->dt() > 0.0)) return std::nullopt;
  const Eigen::Matrix3d R_cam_body = T_body_cam.rotation().transpose();
  std::vector<Eigen::Matrix3d> R_c0_b(n);
  for (size_t k = 0; k < n; ++k) R_c0_b[k] = T_c0_c[k].rotation() * R_cam_body;

  ScaleAlignmentResult res;
  const Eigen::Vector3d bg_before = preint[1]->biasGyr();
  Eigen::Vector3d bg;
  if (!estimateGyroBias(R_c0_b, preint, &bg)) return std::nullopt;
  res.bg_correction = bg - bg_before;

  std::vector<Interval> iv(n - 1);
  for (size_t k = 0; k + 1 < n; ++k) {
    const imu::Preintegration& P = *preint[k + 1];
    Interval& I = iv[k];
    I.R_bk_c0 = R_c0_b[k].transpose();
    I.dt = P.dt();
    I.dp_sfm = T_c0_c[k + 1].translation() - T_c0_c[k].translation();
    I.dlever = -(R_c0_b[k + 1] - R_c0_b[k]) * T_body_cam.translation();
    I.dP = P.deltaP();
    I.dV = P.deltaV();
    const int idx[6] = {imu::kIdxP, imu::kIdxP + 1, imu::kIdxP + 2,
                        imu::kIdxV, imu::kIdxV + 1, imu::kIdxV + 2};
    Eigen::Matrix<double, 6, 6> C;
    for (int i = 0; i < 6; ++i)
      for (int j = 0; j < 6; ++j) C(i, j) = P.covariance()(idx[i], idx[j]);
    // A tiny floor keeps the factorisation defined for a noise-free IMU model.
    C.diagonal().array() += 1e-9 * C.trace() / 6.0 + 1e-24;
    I.C = C;
  }

  const int nv = 3 * static_cast<int>(n);
  Eigen::MatrixXd A;
  Eigen::VectorXd b;
  buildRows(iv, nullptr, &A, &b);
  const double var_cam = cameraNoiseVariance(iv, A, b);
  res.camera_position_sigma_m = std::sqrt(var_cam);
  const Eigen::MatrixXd S = rowCovariance(iv, var_cam);
  auto sol = solveGls(A, b, S);
  if (!sol) return std::nullopt;
  Eigen::Vector3d g = sol->x.segment<3>(nv);
  // Far from |g|: the visual and inertial data disagree (wrong extrinsics, bad SfM, time offset).
  if (!(std::abs(g.norm() - g_norm) <= 0.25 * g_norm)) return std::nullopt;
  // Known magnitude: linearise the sphere constraint around the current direction, step in its
  // tangent plane and renormalise; a few passes converge since the first solve is already close.
  g = g.normalized() * g_norm;
  for (int it = 0; it < 4; ++it) {
    buildRows(iv, &g, &A, &b);
    sol = solveGls(A, b, S);
    if (!sol) return std::nullopt;
    g = (g + sphereTangentBasis(g) * sol->x.segment<2>(nv)).normalized() * g_norm;
  }
  res.scale = sol->x(sol->x.size() - 1);
  if (!std::isfinite(res.scale) || !(res.scale > 0.0) || !g.allFinite()) return std::nullopt;
  res.scale_rel_sigma = sol->scale_sigma / res.scale;
  if (!(res.scale_rel_sigma <= max_scale_rel_sigma)) return std::nullopt;
  res.g_ref = g;
  res.residual_rms = std::sqrt(sol->chi2 / static_cast<double>(b.size()));
  for (size_t k = 0; k < n; ++k) res.v_ref.push_back(sol->x.segment<3>(3 * static_cast<int>(k)));
  return res;
}

}  // namespace rgbdi::estimator
