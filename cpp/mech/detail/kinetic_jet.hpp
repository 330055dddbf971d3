// Internal: KineticJet<N>, the forward-mode AD scalar that gives M, h and ∂T/∂q of a kinetic
// energy with N (compile-time) coordinates in ONE sweep. Used by autodiff_model.hpp for models
// that declare kCoordinates; not for direct use.
//
// The jet carries, for a function T(q, q̇, t) evaluated along (q, q̇, t) + ε (q̇, 0, 1):
//   v  = T                    g  = ∂T/∂q̇ (N)         e  = ∂T/∂ε
//   gq = ∂T/∂q (N)            H  = ∂²T/∂q̇² (packed upper triangle, N(N+1)/2)
//   ge = ∂²T/∂q̇∂ε (N)
// and is closed under the chain rule: each component's rule needs only tracked components
// (H needs g; ge needs g and e), so second derivatives in q, in ε², and mixed q-ε terms are not
// carried. With T quadratic in q̇: M = H, h = ge − gq (h_j = (∂p_j/∂q) q̇ + ∂p_j/∂t − ∂T/∂q_j).
// Two flags skip zero blocks: `dq` (g, H, ge may be non-zero: the value depends on q̇) and
// `quad` (H may be non-zero). In a kinetic energy most operations are on functions of (q, t)
// alone (sin θ, constants), which then cost N + 2 numbers instead of ~N²/2.
// Functions: + − × ÷, sin, cos, tan, exp, log, sqrt (each checked against Eigen's nested
// AutoDiffScalar in tests/mech/test_autodiff.cpp); a model needing more fails to compile here.
#pragma once

#include <cmath>
#include <limits>

#include <Eigen/Core>

namespace pcsim::mech::detail {

template <int N> struct KineticJet {
  static constexpr int kP = N * (N + 1) / 2;
  double v = 0, e = 0;
  double g[N] = {}, gq[N] = {}, ge[N] = {}, H[kP] = {};
  bool dq = false, quad = false;

  KineticJet() = default;
  KineticJet(double value) : v(value) {}  // NOLINT: implicit, a constant (as AutoDiffScalar)

  KineticJet& operator+=(const KineticJet& b) { return *this = *this + b; }
  KineticJet& operator-=(const KineticJet& b) { return *this = *this - b; }
  KineticJet& operator*=(const KineticJet& b) { return *this = *this * b; }
  KineticJet& operator/=(const KineticJet& b) { return *this = *this / b; }
  KineticJet& operator+=(double b) { v += b; return *this; }
  KineticJet& operator-=(double b) { v -= b; return *this; }
  KineticJet& operator*=(double b) { return *this = *this * b; }
  KineticJet& operator/=(double b) { return *this = *this * (1.0 / b); }

  // ---- arithmetic ----------------------------------------------------------------------------
  friend KineticJet operator+(const KineticJet& a, const KineticJet& b) {
    KineticJet r;
    r.v = a.v + b.v;
    r.e = a.e + b.e;
    for (int k = 0; k < N; ++k) r.gq[k] = a.gq[k] + b.gq[k];
    r.dq = a.dq || b.dq;
    r.quad = a.quad || b.quad;
    if (r.dq) {
      for (int k = 0; k < N; ++k) {
        r.g[k] = a.g[k] + b.g[k];
        r.ge[k] = a.ge[k] + b.ge[k];
      }
    }
    if (r.quad)
      for (int k = 0; k < kP; ++k) r.H[k] = a.H[k] + b.H[k];
    return r;
  }
  friend KineticJet operator-(const KineticJet& a) { return a * -1.0; }
  friend KineticJet operator-(const KineticJet& a, const KineticJet& b) { return a + b * -1.0; }
  friend KineticJet operator+(KineticJet a, double b) { a.v += b; return a; }
  friend KineticJet operator+(double b, KineticJet a) { a.v += b; return a; }
  friend KineticJet operator-(KineticJet a, double b) { a.v -= b; return a; }
  friend KineticJet operator-(double b, const KineticJet& a) { return (a * -1.0) + b; }

  friend KineticJet operator*(const KineticJet& a, double s) {
    KineticJet r;
    r.v = a.v * s;
    r.e = a.e * s;
    for (int k = 0; k < N; ++k) r.gq[k] = a.gq[k] * s;
    r.dq = a.dq;
    r.quad = a.quad;
    if (r.dq) {
      for (int k = 0; k < N; ++k) {
        r.g[k] = a.g[k] * s;
        r.ge[k] = a.ge[k] * s;
      }
    }
    if (r.quad)
      for (int k = 0; k < kP; ++k) r.H[k] = a.H[k] * s;
    return r;
  }
  friend KineticJet operator*(double s, const KineticJet& a) { return a * s; }
  friend KineticJet operator/(const KineticJet& a, double s) { return a * (1.0 / s); }
  friend KineticJet operator/(double s, const KineticJet& b) { return s * inverse(b); }
  friend KineticJet operator/(const KineticJet& a, const KineticJet& b) { return a * inverse(b); }

  friend KineticJet operator*(const KineticJet& a, const KineticJet& b) {
    KineticJet r;
    r.v = a.v * b.v;
    r.e = a.v * b.e + b.v * a.e;
    for (int k = 0; k < N; ++k) r.gq[k] = a.v * b.gq[k] + b.v * a.gq[k];
    r.dq = a.dq || b.dq;
    if (!r.dq) return r;
    for (int k = 0; k < N; ++k) {
      r.g[k] = a.v * b.g[k] + b.v * a.g[k];
      r.ge[k] = a.v * b.ge[k] + b.v * a.ge[k] + a.g[k] * b.e + b.g[k] * a.e;
    }
    r.quad = a.quad || b.quad || (a.dq && b.dq);
    if (!r.quad) return r;
    if (a.dq && b.dq) {
      int p = 0;
      for (int j = 0; j < N; ++j)
        for (int k = j; k < N; ++k, ++p)
          r.H[p] = a.v * b.H[p] + b.v * a.H[p] + a.g[j] * b.g[k] + b.g[j] * a.g[k];
    } else {
      for (int p = 0; p < kP; ++p) r.H[p] = a.v * b.H[p] + b.v * a.H[p];
    }
    return r;
  }

  /// f(a) with f = f(a.v), f1 = f'(a.v), f2 = f''(a.v).
  static KineticJet chain(const KineticJet& a, double f, double f1, double f2) {
    KineticJet r;
    r.v = f;
    r.e = f1 * a.e;
    for (int k = 0; k < N; ++k) r.gq[k] = f1 * a.gq[k];
    r.dq = a.dq;
    if (!a.dq) return r;
    for (int k = 0; k < N; ++k) {
      r.g[k] = f1 * a.g[k];
      r.ge[k] = f1 * a.ge[k] + f2 * a.g[k] * a.e;
    }
    r.quad = true;
    int p = 0;
    for (int j = 0; j < N; ++j)
      for (int k = j; k < N; ++k, ++p) r.H[p] = f1 * a.H[p] + f2 * a.g[j] * a.g[k];
    return r;
  }
  friend KineticJet inverse(const KineticJet& a) {
    const double i = 1.0 / a.v;
    return chain(a, i, -i * i, 2 * i * i * i);
  }

  // ---- functions (found by ADL after `using std::sin;`) --------------------------------------
  friend KineticJet sin(const KineticJet& a) {
    const double s = std::sin(a.v), c = std::cos(a.v);
    return chain(a, s, c, -s);
  }
  friend KineticJet cos(const KineticJet& a) {
    const double s = std::sin(a.v), c = std::cos(a.v);
    return chain(a, c, -s, -c);
  }
  friend KineticJet tan(const KineticJet& a) {
    const double t = std::tan(a.v), d = 1 + t * t;
    return chain(a, t, d, 2 * t * d);
  }
  friend KineticJet exp(const KineticJet& a) {
    const double x = std::exp(a.v);
    return chain(a, x, x, x);
  }
  friend KineticJet log(const KineticJet& a) {
    const double i = 1.0 / a.v;
    return chain(a, std::log(a.v), i, -i * i);
  }
  friend KineticJet sqrt(const KineticJet& a) {
    const double s = std::sqrt(a.v);
    return chain(a, s, 0.5 / s, -0.25 / (s * a.v));
  }
  friend bool operator<(const KineticJet& a, const KineticJet& b) { return a.v < b.v; }
  friend bool operator>(const KineticJet& a, const KineticJet& b) { return a.v > b.v; }
  friend bool operator<=(const KineticJet& a, const KineticJet& b) { return a.v <= b.v; }
  friend bool operator>=(const KineticJet& a, const KineticJet& b) { return a.v >= b.v; }
};

}  // namespace pcsim::mech::detail

namespace Eigen {
template <int N> struct NumTraits<pcsim::mech::detail::KineticJet<N>> : NumTraits<double> {
  using Real = pcsim::mech::detail::KineticJet<N>;
  using NonInteger = Real;
  using Nested = Real;
  using Literal = Real;
  enum { RequireInitialization = 1, ReadCost = 1, AddCost = 2, MulCost = 4 };
};
}  // namespace Eigen
