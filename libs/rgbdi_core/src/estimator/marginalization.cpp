#include "rgbdi/estimator/marginalization.h"

#include <Eigen/Eigenvalues>
#include <map>

#include "rgbdi/estimator/pose_manifold.h"

namespace rgbdi::estimator {
namespace {

// Eigenvalues below this are treated as unobservable directions (gauge freedom) when inverting.
constexpr double kEigenEps = 1e-8;

Eigen::VectorXd tangentDelta(const double* x, const Eigen::VectorXd& x0, int size) {
  if (size == 7) {
    Eigen::VectorXd d(6);
    PoseManifold().Minus(x, x0.data(), d.data());
    return d;
  }
  return Eigen::Map<const Eigen::VectorXd>(x, size) - x0;
}

}  // namespace

bool MarginalizationInfo::marginalize(const std::set<const double*>& remove,
                                      const std::set<const double*>& constant) {
  // 1. Order variables: removed first, then kept; record sizes and values.
  std::map<const double*, int> size_of;
  std::vector<double*> order_removed, order_kept;
  for (const auto& r : residuals_) {
    const auto& sizes = r.cost->parameter_block_sizes();
    for (size_t k = 0; k < r.blocks.size(); ++k) {
      double* b = r.blocks[k];
      if (constant.count(b) || size_of.count(b)) continue;
      size_of[b] = sizes[k];
      (remove.count(b) ? order_removed : order_kept).push_back(b);
    }
  }
  std::map<const double*, int> offset;
  int m = 0;
  for (double* b : order_removed) {
    offset[b] = m;
    m += tangentSize(size_of[b]);
  }
  int n = 0;
  for (double* b : order_kept) {
    offset[b] = m + n;
    n += tangentSize(size_of[b]);
  }
  if (n == 0) return false;

  // 2. Accumulate H and b of the linearised residuals (robust loss applied as in Ceres' corrector).
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(m + n, m + n);
  Eigen::VectorXd g = Eigen::VectorXd::Zero(m + n);
  for (const auto& r : residuals_) {
    const int nres = r.cost->num_residuals();
    const auto& sizes = r.cost->parameter_block_sizes();
    std::vector<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> J(
        r.blocks.size());
    std::vector<double*> jac_ptrs(r.blocks.size());
    for (size_t k = 0; k < r.blocks.size(); ++k) {
      J[k].resize(nres, sizes[k]);
      jac_ptrs[k] = J[k].data();
    }
    Eigen::VectorXd res(nres);
    std::vector<const double*> params(r.blocks.begin(), r.blocks.end());
    if (!r.cost->Evaluate(params.data(), res.data(), jac_ptrs.data())) continue;
    if (r.loss) {
      const double sq = res.squaredNorm();
      double rho[3];
      r.loss->Evaluate(sq, rho);
      const double sqrt_rho1 = std::sqrt(rho[1]);
      double alpha = 0.0;
      if (sq != 0.0 && rho[2] > 0.0) {
        const double D = 1.0 + 2.0 * sq * rho[2] / rho[1];
        alpha = 1.0 - std::sqrt(D);
      }
      // Residual and Jacobian scaling of Ceres' Corrector (Triggs correction).
      for (size_t k = 0; k < r.blocks.size(); ++k) {
        if (sq == 0.0) {
          J[k] *= sqrt_rho1;
        } else {
          J[k] = sqrt_rho1 * (J[k] - alpha / sq * res * (res.transpose() * J[k]));
        }
      }
      res *= sqrt_rho1 / (1.0 - alpha);
    }
    for (size_t a = 0; a < r.blocks.size(); ++a) {
      if (!offset.count(r.blocks[a])) continue;
      const int oa = offset[r.blocks[a]];
      const int ta = tangentSize(sizes[a]);
      const Eigen::MatrixXd Ja = J[a].leftCols(ta);
      g.segment(oa, ta) += Ja.transpose() * res;
      for (size_t c = a; c < r.blocks.size(); ++c) {
        if (!offset.count(r.blocks[c])) continue;
        const int oc = offset[r.blocks[c]];
        const int tc = tangentSize(sizes[c]);
        const Eigen::MatrixXd Hac = Ja.transpose() * J[c].leftCols(tc);
        H.block(oa, oc, ta, tc) += Hac;
        if (c != a) H.block(oc, oa, tc, ta) += Hac.transpose();
      }
    }
  }

  // 3. Schur complement onto the kept variables.
  Eigen::MatrixXd A;
  Eigen::VectorXd bvec;
  if (m > 0) {
    const Eigen::MatrixXd Hmm = 0.5 * (H.topLeftCorner(m, m) + H.topLeftCorner(m, m).transpose());
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(Hmm);
    const Eigen::VectorXd inv_vals =
        (es.eigenvalues().array() > kEigenEps).select(es.eigenvalues().array().inverse(), 0.0);
    const Eigen::MatrixXd Hmm_inv =
        es.eigenvectors() * inv_vals.asDiagonal() * es.eigenvectors().transpose();
    const Eigen::MatrixXd Hrm = H.block(m, 0, n, m);
    A = H.bottomRightCorner(n, n) - Hrm * Hmm_inv * H.block(0, m, m, n);
    bvec = g.tail(n) - Hrm * Hmm_inv * g.head(m);
  } else {
    A = H;
    bvec = g;
  }

  // 4. Factor A = J^T J and b = J^T r (pseudo-inverse square roots on the observable subspace).
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(0.5 * (A + A.transpose()));
  const Eigen::VectorXd S =
      (es.eigenvalues().array() > kEigenEps).select(es.eigenvalues().array(), 0.0);
  const Eigen::VectorXd S_inv =
      (es.eigenvalues().array() > kEigenEps).select(es.eigenvalues().array().inverse(), 0.0);
  lin_jacobian_ = S.cwiseSqrt().asDiagonal() * es.eigenvectors().transpose();
  lin_residual_ = S_inv.cwiseSqrt().asDiagonal() * es.eigenvectors().transpose() * bvec;

  kept_blocks_ = order_kept;
  kept_sizes_.clear();
  kept_values_.clear();
  for (double* b : order_kept) {
    kept_sizes_.push_back(size_of[b]);
    kept_values_.push_back(Eigen::Map<const Eigen::VectorXd>(b, size_of[b]));
  }
  residuals_.clear();  // the linearised prior is all that is needed from now on
  return true;
}

void MarginalizationInfo::remapBlocks(const std::unordered_map<const double*, double*>& remap) {
  for (auto& b : kept_blocks_) {
    const auto it = remap.find(b);
    if (it != remap.end()) b = it->second;
  }
}

MarginalizationFactor::MarginalizationFactor(std::shared_ptr<const MarginalizationInfo> info)
    : info_(std::move(info)) {
  int rows = 0;
  for (int s : info_->keptSizes()) {
    mutable_parameter_block_sizes()->push_back(s);
    rows += MarginalizationInfo::tangentSize(s);
  }
  set_num_residuals(rows);
}

bool MarginalizationFactor::Evaluate(double const* const* parameters, double* residuals,
                                     double** jacobians) const {
  const auto& sizes = info_->keptSizes();
  const int n = num_residuals();
  Eigen::VectorXd dx(n);
  int off = 0;
  for (size_t k = 0; k < sizes.size(); ++k) {
    const int t = MarginalizationInfo::tangentSize(sizes[k]);
    dx.segment(off, t) = tangentDelta(parameters[k], info_->keptValues()[k], sizes[k]);
    off += t;
  }
  Eigen::Map<Eigen::VectorXd>(residuals, n) = info_->residual() + info_->jacobian() * dx;
  if (!jacobians) return true;
  off = 0;
  for (size_t k = 0; k < sizes.size(); ++k) {
    const int t = MarginalizationInfo::tangentSize(sizes[k]);
    if (jacobians[k]) {
      Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> J(
          jacobians[k], n, sizes[k]);
      J.setZero();
      J.leftCols(t) = info_->jacobian().middleCols(off, t);
    }
    off += t;
  }
  return true;
}

}  // namespace rgbdi::estimator
