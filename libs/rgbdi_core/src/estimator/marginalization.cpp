#include "rgbdi/estimator/marginalization.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "estimator/dense_kernels.h"
#include "estimator/robust_correction.h"
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
  // 1. Variables in first-seen order. Removed scalar blocks that no residual couples with another
  // removed scalar (a feature's inverse depth: each reprojection residual holds one) form a
  // diagonal part of H_mm and are eliminated one by one; the other removed blocks (the frame's
  // pose and speed/bias) stay dense: the eigen-decomposition is then only over those.
  struct Var {
    int size = 0;     ///< ambient
    int tangent = 0;  ///< columns
    bool removed = false;
    bool diagonal = false;
    int index = 0;  ///< column offset (dense) or row of the diagonal part
  };
  std::unordered_map<const double*, int> var_of;
  std::vector<Var> vars;
  std::vector<double*> var_block;
  for (const auto& r : residuals_) {
    const auto& sizes = r.cost->parameter_block_sizes();
    for (size_t k = 0; k < r.blocks.size(); ++k) {
      double* b = r.blocks[k];
      if (constant.count(b) || var_of.count(b)) continue;
      Var v;
      v.size = sizes[k];
      v.tangent = tangentSize(sizes[k]);
      v.removed = remove.count(b) > 0;
      v.diagonal = v.removed && v.tangent == 1;
      var_of.emplace(b, static_cast<int>(vars.size()));
      vars.push_back(v);
      var_block.push_back(b);
    }
  }
  // Residual -> its variables (-1: constant), and the diagonal test.
  std::vector<std::vector<int>> res_vars(residuals_.size());
  for (size_t i = 0; i < residuals_.size(); ++i) {
    int n_diag = 0;
    for (double* b : residuals_[i].blocks) {
      const auto it = var_of.find(b);
      res_vars[i].push_back(it == var_of.end() ? -1 : it->second);
      if (it != var_of.end() && vars[static_cast<size_t>(it->second)].diagonal) ++n_diag;
    }
    if (n_diag > 1)
      for (int v : res_vars[i])
        if (v >= 0) vars[static_cast<size_t>(v)].diagonal = false;
  }
  int m = 0, n = 0, nd = 0;
  for (auto& v : vars)
    if (v.removed && !v.diagonal) {
      v.index = m;
      m += v.tangent;
    }
  for (auto& v : vars) {
    if (v.diagonal) {
      v.index = nd++;
    } else if (!v.removed) {
      v.index = m + n;
      n += v.tangent;
    }
  }
  if (n == 0) return false;

  // 2. Accumulate H and g of the linearised residuals (robust loss applied as in Ceres'
  // corrector): the dense part over [removed dense | kept], and for each diagonal variable its
  // scalar Hessian, gradient and coupling row to the dense part.
  const int nx = m + n;
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(nx, nx);
  Eigen::VectorXd g = Eigen::VectorXd::Zero(nx);
  Eigen::VectorXd h_diag = Eigen::VectorXd::Zero(nd), g_diag = Eigen::VectorXd::Zero(nd);
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  RowMajor coupling = RowMajor::Zero(nd, nx);                      ///< row d: contiguous
  std::vector<std::vector<int>> coupled(static_cast<size_t>(nd));  ///< dense vars per diagonal
  // H += J^T J (formed when the prior was made), g += J^T r of a previous prior; false (nothing
  // added) when one of its blocks is an eliminated scalar.
  std::vector<int> prior_offsets;
  auto addPrior = [&](const MarginalizationInfo& p, const std::vector<double*>& blocks,
                      const std::vector<int>& rv) {
    prior_offsets.clear();
    for (int v : rv) {
      if (v >= 0 && vars[static_cast<size_t>(v)].diagonal) return false;
      prior_offsets.push_back(v >= 0 ? vars[static_cast<size_t>(v)].index : -1);
    }
    p.addNormalEquations(blocks.data(), prior_offsets, false, H, g);
    return true;
  };
  std::vector<double> jac_storage, res_storage, row_storage;
  std::vector<double*> jac_ptrs;
  std::vector<const double*> params;
  for (size_t i = 0; i < residuals_.size(); ++i) {
    const auto& r = residuals_[i];
    // A previous prior adds its constant J^T J and J^T r directly (its Jacobian is dense: the
    // generic products below would form J^T J again over ~150 rows).
    if (const auto* prior = dynamic_cast<const MarginalizationFactor*>(r.cost.get());
        prior && !r.loss && addPrior(prior->info(), r.blocks, res_vars[i])) {
      continue;
    }
    const int nres = r.cost->num_residuals();
    const auto& sizes = r.cost->parameter_block_sizes();
    const size_t nb = r.blocks.size();
    int total_cols = 0;
    for (size_t k = 0; k < nb; ++k) total_cols += sizes[k];
    // Buffers grow to the largest residual and are reused (no allocation per residual).
    if (jac_storage.size() < static_cast<size_t>(nres * total_cols))
      jac_storage.resize(static_cast<size_t>(nres * total_cols));
    if (res_storage.size() < static_cast<size_t>(nres))
      res_storage.resize(static_cast<size_t>(nres));
    jac_ptrs.resize(nb);
    for (size_t k = 0, off = 0; k < nb; ++k) {
      jac_ptrs[k] = jac_storage.data() + off;
      off += static_cast<size_t>(nres * sizes[k]);
    }
    params.assign(r.blocks.begin(), r.blocks.end());
    if (!r.cost->Evaluate(params.data(), res_storage.data(), jac_ptrs.data())) continue;
    Eigen::Map<Eigen::VectorXd> res(res_storage.data(), nres);
    if (r.loss) {
      detail::applyRobustLoss(*r.loss, nres, res_storage.data(), jac_ptrs.data(), sizes.data(),
                              static_cast<int>(nb), row_storage);
    }
    const auto& rv = res_vars[i];
    // The eliminated (diagonal) variable of this residual, if any: its Jacobian column.
    const double* Jd = nullptr;
    int d = -1;
    for (size_t a = 0; a < nb; ++a)
      if (rv[a] >= 0 && vars[static_cast<size_t>(rv[a])].diagonal) {
        Jd = jac_ptrs[a];
        d = vars[static_cast<size_t>(rv[a])].index;
      }
    if (Jd) {
      for (int k = 0; k < nres; ++k) {
        h_diag[d] += Jd[k] * Jd[k];
        g_diag[d] += Jd[k] * res[k];
      }
    }
    for (size_t a = 0; a < nb; ++a) {
      if (rv[a] < 0) continue;
      const Var& va = vars[static_cast<size_t>(rv[a])];
      if (va.diagonal) continue;
      const double* Ja = jac_ptrs[a];
      detail::addJtv(g.data() + va.index, Ja, sizes[a], va.tangent, res.data(), nres);
      if (Jd) {
        detail::addJtv(coupling.row(d).data() + va.index, Ja, sizes[a], va.tangent, Jd, nres);
        auto& list = coupled[static_cast<size_t>(d)];
        if (std::find(list.begin(), list.end(), rv[a]) == list.end()) list.push_back(rv[a]);
      }
      for (size_t c = a; c < nb; ++c) {
        if (rv[c] < 0) continue;
        const Var& vc = vars[static_cast<size_t>(rv[c])];
        if (vc.diagonal) continue;
        detail::addJtJ(H.data(), nx, va.index, vc.index, Ja, sizes[a], va.tangent, jac_ptrs[c],
                       sizes[c], vc.tangent, nres);
        if (c != a)
          detail::addJtJ(H.data(), nx, vc.index, va.index, jac_ptrs[c], sizes[c], vc.tangent, Ja,
                         sizes[a], va.tangent, nres);
      }
    }
  }

  // 3a. Eliminate the diagonal variables: H -= c c^T / h, g -= c g_d / h for each, where c is
  // its coupling row (non-zero only on the blocks it shares a residual with). A variable
  // without information (h below the eigenvalue threshold) is an unobservable direction and
  // contributes nothing, as the pseudo-inverse of the dense elimination does.
  for (int d = 0; d < nd; ++d) {
    const double h = h_diag[d];
    if (!(h > kEigenEps)) continue;
    const double* c = coupling.row(d).data();
    for (int p : coupled[static_cast<size_t>(d)]) {
      const Var& vp = vars[static_cast<size_t>(p)];
      for (int i = 0; i < vp.tangent; ++i) g[vp.index + i] -= c[vp.index + i] * (g_diag[d] / h);
      for (int q : coupled[static_cast<size_t>(d)]) {
        const Var& vq = vars[static_cast<size_t>(q)];
        detail::subtractOuter(H.data(), nx, c, vp.index, vp.tangent, vq.index, vq.tangent, h);
      }
    }
  }

  // 3b. Schur complement of the remaining (dense) removed variables onto the kept ones.
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
  lin_hessian_ = lin_jacobian_.transpose() * lin_jacobian_;

  kept_blocks_.clear();
  kept_sizes_.clear();
  kept_values_.clear();
  for (size_t k = 0; k < vars.size(); ++k) {
    if (vars[k].removed) continue;
    kept_blocks_.push_back(var_block[k]);
    kept_sizes_.push_back(vars[k].size);
    kept_values_.push_back(Eigen::Map<const Eigen::VectorXd>(var_block[k], vars[k].size));
  }
  residuals_.clear();  // the linearised prior is all that is needed from now on
  return true;
}

void MarginalizationInfo::tangentDelta(double const* const* parameters, Eigen::VectorXd& dx) const {
  dx.resize(lin_jacobian_.cols());
  int off = 0;
  for (size_t k = 0; k < kept_sizes_.size(); ++k) {
    const int t = tangentSize(kept_sizes_[k]);
    dx.segment(off, t) = estimator::tangentDelta(parameters[k], kept_values_[k], kept_sizes_[k]);
    off += t;
  }
}

double MarginalizationInfo::evaluate(double const* const* parameters,
                                     Eigen::VectorXd* gradient) const {
  Eigen::VectorXd dx;
  tangentDelta(parameters, dx);
  Eigen::VectorXd r;
  r.noalias() = lin_residual_ + lin_jacobian_ * dx;
  if (gradient) *gradient = lin_jacobian_.transpose() * r;
  return 0.5 * r.squaredNorm();
}

double MarginalizationInfo::addNormalEquations(double const* const* parameters,
                                               const std::vector<int>& offsets, bool lower_only,
                                               Eigen::MatrixXd& H, Eigen::VectorXd& g) const {
  Eigen::VectorXd Jtr;
  const double cost = evaluate(parameters, &Jtr);
  for (std::size_t a = 0, oa = 0; a < kept_sizes_.size(); ++a) {
    const int ta = tangentSize(kept_sizes_[a]);
    if (offsets[a] >= 0) {
      g.segment(offsets[a], ta) += Jtr.segment(static_cast<Eigen::Index>(oa), ta);
      for (std::size_t c = 0, oc = 0; c < kept_sizes_.size(); ++c) {
        const int tc = tangentSize(kept_sizes_[c]);
        if (offsets[c] >= 0 && (!lower_only || offsets[c] <= offsets[a]))
          H.block(offsets[a], offsets[c], ta, tc) += lin_hessian_.block(
              static_cast<Eigen::Index>(oa), static_cast<Eigen::Index>(oc), ta, tc);
        oc += static_cast<std::size_t>(tc);
      }
    }
    oa += static_cast<std::size_t>(ta);
  }
  return cost;
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
  Eigen::VectorXd dx;
  info_->tangentDelta(parameters, dx);
  Eigen::Map<Eigen::VectorXd>(residuals, n) = info_->residual() + info_->jacobian() * dx;
  if (!jacobians) return true;
  int off = 0;
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
