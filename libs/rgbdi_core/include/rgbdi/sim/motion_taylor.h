// Truncated Taylor series in one variable (time), used to differentiate the simulator's analytic
// motion exactly. A Taylor<K> holds the normalised coefficients c_k = f^(k)(t0) / k! of a function
// around one instant, k = 0..K. Arithmetic and elementary functions propagate them with the
// classic recurrences of Taylor-mode automatic differentiation, so velocities, accelerations and
// angular rates of a trajectory written as ordinary formulas come out to machine precision
// (no finite differences, no step-size trade-off).
#pragma once

#include <array>
#include <cmath>

namespace rgbdi::sim {

template <int K>
class Taylor {
  static_assert(K >= 0, "Taylor order must be non-negative");

 public:
  static constexpr int kOrder = K;

  Taylor() { c_.fill(0.0); }
  /// A constant (all derivatives zero).
  explicit Taylor(double value) {
    c_.fill(0.0);
    c_[0] = value;
  }
  /// The independent variable itself at `value`: f(t) = t.
  static Taylor variable(double value) {
    Taylor x(value);
    if (K >= 1) x.c_[1] = 1.0;
    return x;
  }

  double value() const { return c_[0]; }
  /// Normalised coefficient k (f^(k) / k!).
  double coeff(int k) const { return c_[static_cast<size_t>(k)]; }
  double& coeff(int k) { return c_[static_cast<size_t>(k)]; }
  /// k-th derivative with respect to the variable.
  double derivative(int k) const {
    double f = 1.0;
    for (int i = 2; i <= k; ++i) f *= i;
    return c_[static_cast<size_t>(k)] * f;
  }

  /// d/dt of the series; one order is lost.
  Taylor<(K > 0 ? K - 1 : 0)> differentiated() const {
    static_assert(K >= 1, "cannot differentiate a Taylor<0>");
    Taylor<(K > 0 ? K - 1 : 0)> d;
    for (int k = 0; k < K; ++k) d.coeff(k) = (k + 1) * c_[static_cast<size_t>(k + 1)];
    return d;
  }
  /// The antiderivative that takes `value` at the expansion point; one order is gained.
  Taylor<K + 1> integrated(double value) const {
    Taylor<K + 1> r(value);
    for (int k = 0; k <= K; ++k) r.coeff(k + 1) = c_[static_cast<size_t>(k)] / (k + 1);
    return r;
  }
  /// Drops coefficients above order J.
  template <int J>
  Taylor<J> truncated() const {
    static_assert(J <= K, "truncation can only lower the order");
    Taylor<J> r;
    for (int k = 0; k <= J; ++k) r.coeff(k) = c_[static_cast<size_t>(k)];
    return r;
  }

  Taylor& operator+=(const Taylor& o) {
    for (int k = 0; k <= K; ++k) c_[static_cast<size_t>(k)] += o.c_[static_cast<size_t>(k)];
    return *this;
  }
  Taylor& operator-=(const Taylor& o) {
    for (int k = 0; k <= K; ++k) c_[static_cast<size_t>(k)] -= o.c_[static_cast<size_t>(k)];
    return *this;
  }
  Taylor& operator*=(double s) {
    for (double& v : c_) v *= s;
    return *this;
  }
  Taylor& operator+=(double s) {
    c_[0] += s;
    return *this;
  }

 private:
  std::array<double, K + 1> c_;
};

template <int K>
Taylor<K> operator+(Taylor<K> a, const Taylor<K>& b) {
  return a += b;
}
template <int K>
Taylor<K> operator-(Taylor<K> a, const Taylor<K>& b) {
  return a -= b;
}
template <int K>
Taylor<K> operator-(Taylor<K> a) {
  return a *= -1.0;
}
template <int K>
Taylor<K> operator+(Taylor<K> a, double s) {
  return a += s;
}
template <int K>
Taylor<K> operator+(double s, Taylor<K> a) {
  return a += s;
}
template <int K>
Taylor<K> operator-(Taylor<K> a, double s) {
  return a += -s;
}
template <int K>
Taylor<K> operator-(double s, const Taylor<K>& a) {
  return (-a) += s;
}
template <int K>
Taylor<K> operator*(Taylor<K> a, double s) {
  return a *= s;
}
template <int K>
Taylor<K> operator*(double s, Taylor<K> a) {
  return a *= s;
}
template <int K>
Taylor<K> operator/(Taylor<K> a, double s) {
  return a *= 1.0 / s;
}

/// Cauchy product of the coefficient sequences.
template <int K>
Taylor<K> operator*(const Taylor<K>& a, const Taylor<K>& b) {
  Taylor<K> r;
  for (int k = 0; k <= K; ++k) {
    double s = 0.0;
    for (int j = 0; j <= k; ++j) s += a.coeff(j) * b.coeff(k - j);
    r.coeff(k) = s;
  }
  return r;
}

template <int K>
Taylor<K> operator/(const Taylor<K>& a, const Taylor<K>& b) {
  Taylor<K> q;
  for (int k = 0; k <= K; ++k) {
    double s = a.coeff(k);
    for (int j = 1; j <= k; ++j) s -= b.coeff(j) * q.coeff(k - j);
    q.coeff(k) = s / b.coeff(0);
  }
  return q;
}

/// sin and cos together (their recurrences are coupled).
template <int K>
void sincos(const Taylor<K>& a, Taylor<K>& s, Taylor<K>& c) {
  s = Taylor<K>(std::sin(a.value()));
  c = Taylor<K>(std::cos(a.value()));
  for (int k = 1; k <= K; ++k) {
    double ss = 0.0, cc = 0.0;
    for (int j = 1; j <= k; ++j) {
      ss += j * a.coeff(j) * c.coeff(k - j);
      cc -= j * a.coeff(j) * s.coeff(k - j);
    }
    s.coeff(k) = ss / k;
    c.coeff(k) = cc / k;
  }
}

template <int K>
Taylor<K> sin(const Taylor<K>& a) {
  Taylor<K> s, c;
  sincos(a, s, c);
  return s;
}

template <int K>
Taylor<K> cos(const Taylor<K>& a) {
  Taylor<K> s, c;
  sincos(a, s, c);
  return c;
}

/// Square root; the value must be positive.
template <int K>
Taylor<K> sqrt(const Taylor<K>& a) {
  Taylor<K> r(std::sqrt(a.value()));
  for (int k = 1; k <= K; ++k) {
    double s = a.coeff(k);
    for (int j = 1; j < k; ++j) s -= r.coeff(j) * r.coeff(k - j);
    r.coeff(k) = s / (2.0 * r.value());
  }
  return r;
}

/// Arc tangent, from u' (1 + a^2) = a'.
template <int K>
Taylor<K> atan(const Taylor<K>& a) {
  const Taylor<K> d = 1.0 + a * a;
  Taylor<K> u(std::atan(a.value()));
  for (int m = 0; m < K; ++m) {
    // Coefficient m of u' d equals coefficient m of a': (m+1) a_{m+1}.
    double s = (m + 1) * a.coeff(m + 1);
    for (int j = 0; j < m; ++j) s -= (j + 1) * u.coeff(j + 1) * d.coeff(m - j);
    u.coeff(m + 1) = s / ((m + 1) * d.value());
  }
  return u;
}

/// Polynomial sum_i p[i] x^i by Horner's rule.
template <int K, size_t N>
Taylor<K> polynomial(const std::array<double, N>& p, const Taylor<K>& x) {
  Taylor<K> r(p[N - 1]);
  for (size_t i = N - 1; i-- > 0;) r = r * x + p[i];
  return r;
}

/// A 3-vector of Taylor series (position, velocity or angular-rate expansions).
template <int K>
using TaylorVec3 = std::array<Taylor<K>, 3>;

template <int K>
TaylorVec3<K> operator+(const TaylorVec3<K>& a, const TaylorVec3<K>& b) {
  return {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
}

/// Rotates a Taylor vector about coordinate axis `axis` (0 = x, 1 = y, 2 = z) by `angle`
/// (right-handed): returns R_axis(angle) * v.
template <int K>
TaylorVec3<K> rotateAboutAxis(int axis, const Taylor<K>& angle, const TaylorVec3<K>& v) {
  Taylor<K> s, c;
  sincos(angle, s, c);
  const int i = (axis + 1) % 3, j = (axis + 2) % 3;
  TaylorVec3<K> r = v;
  r[static_cast<size_t>(i)] = c * v[static_cast<size_t>(i)] - s * v[static_cast<size_t>(j)];
  r[static_cast<size_t>(j)] = s * v[static_cast<size_t>(i)] + c * v[static_cast<size_t>(j)];
  return r;
}

}  // namespace rgbdi::sim
