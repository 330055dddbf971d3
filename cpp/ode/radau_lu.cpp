// Port of fortran/radau_lu.f (RADLUD, RADLUS, RADLZD, RADLZS), line for line; see there for the
// mathematics. Indices are 0-based here, pivots 1-based (as the Fortran stores them).
#include "ode/radau_lu.hpp"

#include <cmath>

namespace pcsim::radau_lu {

namespace {
inline double& at(double* a, int lda, int i, int j) { return a[i + static_cast<long>(lda) * j]; }
inline double at(const double* a, int lda, int i, int j) {
  return a[i + static_cast<long>(lda) * j];
}
}  // namespace

int factor(int n, double* a, int lda, int* ipiv, int* iwl) {
  for (int k = 0; k < n; ++k) {
    int p = k;
    double amax = std::abs(at(a, lda, k, k));
    for (int i = k + 1; i < n; ++i)
      if (std::abs(at(a, lda, i, k)) > amax) {
        amax = std::abs(at(a, lda, i, k));
        p = i;
      }
    ipiv[k] = p + 1;
    if (amax == 0.0) return k + 1;
    if (p != k)
      for (int j = 0; j < n; ++j) {
        const double t = at(a, lda, k, j);
        at(a, lda, k, j) = at(a, lda, p, j);
        at(a, lda, p, j) = t;
      }
    const double piv = at(a, lda, k, k);
    at(a, lda, k, k) = 1.0 / piv;
    int nl = 0;
    for (int i = k + 1; i < n; ++i)
      if (at(a, lda, i, k) != 0.0) {
        at(a, lda, i, k) = at(a, lda, i, k) / piv;
        iwl[nl++] = i;
      }
    if (nl == 0) continue;
    for (int j = k + 1; j < n; ++j) {
      const double u = at(a, lda, k, j);
      if (u != 0.0)
        for (int l = 0; l < nl; ++l) {
          const int i = iwl[l];
          at(a, lda, i, j) = at(a, lda, i, j) - at(a, lda, i, k) * u;
        }
    }
  }
  return 0;
}

void solve(int n, const double* a, int lda, const int* ipiv, double* b) {
  for (int k = 0; k < n; ++k) {
    const int p = ipiv[k] - 1;
    if (p != k) {
      const double t = b[k];
      b[k] = b[p];
      b[p] = t;
    }
  }
  for (int k = 0; k < n; ++k) {
    const double t = b[k];
    if (t != 0.0)
      for (int i = k + 1; i < n; ++i) b[i] = b[i] - at(a, lda, i, k) * t;
  }
  for (int k = n - 1; k >= 0; --k) {
    if (b[k] != 0.0) {
      b[k] = b[k] * at(a, lda, k, k);
      const double t = b[k];
      for (int i = 0; i < k; ++i) b[i] = b[i] - at(a, lda, i, k) * t;
    }
  }
}

int factor_complex(int n, double* ar, double* ai, int lda, int* ipiv, int* iwl) {
  for (int k = 0; k < n; ++k) {
    int p = k;
    double amax = std::abs(at(ar, lda, k, k)) + std::abs(at(ai, lda, k, k));
    for (int i = k + 1; i < n; ++i) {
      const double s = std::abs(at(ar, lda, i, k)) + std::abs(at(ai, lda, i, k));
      if (s > amax) {
        amax = s;
        p = i;
      }
    }
    ipiv[k] = p + 1;
    if (amax == 0.0) return k + 1;
    if (p != k)
      for (int j = 0; j < n; ++j) {
        const double tr = at(ar, lda, k, j);
        at(ar, lda, k, j) = at(ar, lda, p, j);
        at(ar, lda, p, j) = tr;
        const double ti = at(ai, lda, k, j);
        at(ai, lda, k, j) = at(ai, lda, p, j);
        at(ai, lda, p, j) = ti;
      }
    const double pr = at(ar, lda, k, k), pim = at(ai, lda, k, k);
    double rr, ri;
    if (std::abs(pr) >= std::abs(pim)) {
      const double q = pim / pr;
      const double d = pr + pim * q;
      rr = 1.0 / d;
      ri = -q / d;
    } else {
      const double q = pr / pim;
      const double d = pim + pr * q;
      rr = q / d;
      ri = -1.0 / d;
    }
    at(ar, lda, k, k) = rr;
    at(ai, lda, k, k) = ri;
    int nl = 0;
    for (int i = k + 1; i < n; ++i)
      if (at(ar, lda, i, k) != 0.0 || at(ai, lda, i, k) != 0.0) {
        const double xr = at(ar, lda, i, k), xi = at(ai, lda, i, k);
        at(ar, lda, i, k) = xr * rr - xi * ri;
        at(ai, lda, i, k) = xr * ri + xi * rr;
        iwl[nl++] = i;
      }
    if (nl == 0) continue;
    for (int j = k + 1; j < n; ++j) {
      const double ur = at(ar, lda, k, j), ui = at(ai, lda, k, j);
      if (ur != 0.0 || ui != 0.0)
        for (int l = 0; l < nl; ++l) {
          const int i = iwl[l];
          at(ar, lda, i, j) =
              at(ar, lda, i, j) - (at(ar, lda, i, k) * ur - at(ai, lda, i, k) * ui);
          at(ai, lda, i, j) =
              at(ai, lda, i, j) - (at(ar, lda, i, k) * ui + at(ai, lda, i, k) * ur);
        }
    }
  }
  return 0;
}

void solve_complex(int n, const double* ar, const double* ai, int lda, const int* ipiv,
                   double* br, double* bi) {
  for (int k = 0; k < n; ++k) {
    const int p = ipiv[k] - 1;
    if (p != k) {
      double t = br[k];
      br[k] = br[p];
      br[p] = t;
      t = bi[k];
      bi[k] = bi[p];
      bi[p] = t;
    }
  }
  for (int k = 0; k < n; ++k) {
    const double tr = br[k], ti = bi[k];
    if (tr != 0.0 || ti != 0.0)
      for (int i = k + 1; i < n; ++i) {
        br[i] = br[i] - (at(ar, lda, i, k) * tr - at(ai, lda, i, k) * ti);
        bi[i] = bi[i] - (at(ar, lda, i, k) * ti + at(ai, lda, i, k) * tr);
      }
  }
  for (int k = n - 1; k >= 0; --k) {
    const double xr = br[k], xi = bi[k];
    if (xr != 0.0 || xi != 0.0) {
      // times the reciprocal of u(k,k) that factor_complex stored on the diagonal
      const double tr = xr * at(ar, lda, k, k) - xi * at(ai, lda, k, k);
      const double ti = xr * at(ai, lda, k, k) + xi * at(ar, lda, k, k);
      br[k] = tr;
      bi[k] = ti;
      for (int i = 0; i < k; ++i) {
        br[i] = br[i] - (at(ar, lda, i, k) * tr - at(ai, lda, i, k) * ti);
        bi[i] = bi[i] - (at(ar, lda, i, k) * ti + at(ai, lda, i, k) * tr);
      }
    }
  }
}

}  // namespace pcsim::radau_lu
