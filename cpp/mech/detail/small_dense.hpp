// Internal: the engine's hot-path dense kernels for the small symmetric positive definite
// systems of the reaction solve (M, n x n, and g M⁻¹ gᵀ, s x s): Cholesky factorization and
// solves in plain loops on column-major storage. For the sizes of mechanical models (n up to a
// few dozen) they cost a fraction of Eigen's dynamic-size LLT, whose blocked machinery is made
// for large matrices. Results agree with Eigen's LLT to rounding (test_reactions).
#pragma once

#include <cmath>

namespace pcsim::mech::detail {

/// Factors the SPD matrix a (n x n, column-major, leading dimension lda) in place into its lower
/// Cholesky factor L (the strict upper triangle is not referenced or changed), and inv_diag (n)
/// into 1 / L_kk, so the solves multiply instead of divide. Returns false if
/// a pivot is not positive or the pivot ratio min(L_kk²)/max(L_kk²) is below `ratio` (an
/// ill-conditioned or singular matrix), as the engine's mass-matrix check demands.
template <int N = 0>
inline bool cholesky_lower(double* a, int n_runtime, int lda, double ratio, double* inv_diag) {
  const int n = N > 0 ? N : n_runtime;
  double dmin = INFINITY, dmax = 0.0;
  for (int j = 0; j < n; ++j) {
    double* aj = a + j * lda;
    double d = aj[j];
    for (int k = 0; k < j; ++k) {
      const double l = a[k * lda + j];
      d -= l * l;
    }
    if (!(d > 0.0)) return false;
    const double ljj = std::sqrt(d);
    aj[j] = ljj;
    dmin = d < dmin ? d : dmin;
    dmax = d > dmax ? d : dmax;
    const double inv = 1.0 / ljj;
    inv_diag[j] = inv;
    for (int i = j + 1; i < n; ++i) {
      double v = aj[i];
      for (int k = 0; k < j; ++k) v -= a[k * lda + i] * a[k * lda + j];
      aj[i] = v * inv;
    }
  }
  return dmin > ratio * dmax;
}

/// (N > 0: the size known at compile time, so the compiler unrolls the loops; n is then N.)
///
/// Solves L Lᵀ x = b in place (b overwritten by x), L and inv_diag from cholesky_lower.
template <int N = 0>
inline void cholesky_solve(const double* l, const double* inv_diag, int n_runtime, int lda,
                           double* b) {
  const int n = N > 0 ? N : n_runtime;
  for (int i = 0; i < n; ++i) {  // L y = b
    double v = b[i];
    for (int k = 0; k < i; ++k) v -= l[k * lda + i] * b[k];
    b[i] = v * inv_diag[i];
  }
  for (int i = n - 1; i >= 0; --i) {  // Lᵀ x = y
    double v = b[i];
    const double* li = l + i * lda;
    for (int k = i + 1; k < n; ++k) v -= li[k] * b[k];
    b[i] = v * inv_diag[i];
  }
}

}  // namespace pcsim::mech::detail
