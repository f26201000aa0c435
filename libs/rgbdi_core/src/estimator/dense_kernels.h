// Small dense kernels shared by the window solver and the marginalisation: the Gauss-Newton
// products of one residual block's row-major Jacobians, written as plain loops over raw memory
// (Eigen's dynamic-size blocks of 2-15 rows spent more on their dispatch than on arithmetic).
#pragma once

#include <cstddef>

namespace rgbdi::estimator::detail {

/// H(rows oa.., cols oc..) += Ja^T Jc for row-major Jacobians of n rows (row strides sa, sc;
/// their first ta, tc columns are used); H is column-major with leading dimension ld.
inline void addJtJ(double* H, int ld, int oa, int oc, const double* Ja, int sa, int ta,
                   const double* Jc, int sc, int tc, int n) {
  for (int j = 0; j < tc; ++j) {
    double* __restrict col = H + static_cast<std::ptrdiff_t>(oc + j) * ld + oa;
    for (int r = 0; r < n; ++r) {
      const double cj = Jc[r * sc + j];
      const double* __restrict ja = Ja + r * sa;
      for (int i = 0; i < ta; ++i) col[i] += ja[i] * cj;
    }
  }
}

/// out[0..t) += Ja^T v for a row-major Jacobian of n rows (row stride sa, first t columns).
inline void addJtv(double* out, const double* Ja, int sa, int t, const double* v, int n) {
  for (int r = 0; r < n; ++r)
    for (int k = 0; k < t; ++k) out[k] += Ja[r * sa + k] * v[r];
}

/// A(rows op.., cols oq..) -= c[op..op+tp) c[oq..oq+tq)^T / h: one eliminated scalar's rank-one
/// Schur update on a column-major A with leading dimension ld (c: its coupling row).
inline void subtractOuter(double* A, int ld, const double* c, int op, int tp, int oq, int tq,
                          double h) {
  for (int j = 0; j < tq; ++j) {
    const double cj = c[oq + j] / h;
    double* __restrict col = A + static_cast<std::ptrdiff_t>(oq + j) * ld + op;
    const double* __restrict cp = c + op;
    for (int i = 0; i < tp; ++i) col[i] -= cp[i] * cj;
  }
}

}  // namespace rgbdi::estimator::detail
