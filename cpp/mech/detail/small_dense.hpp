// Internal: the engine's hot-path dense kernels for the small symmetric positive definite
// systems of the reaction solve (M, n x n, and g M⁻¹ gᵀ, s x s): Cholesky factorization and
// solves in plain loops on column-major storage. For the sizes of mechanical models (n up to a
// few dozen) they cost a fraction of Eigen's dynamic-size LLT, whose blocked machinery is made
// for large matrices. Results agree with Eigen's LLT to rounding (test_reactions).
//
// The factor is A = Uᵀ U with U upper triangular, stored in the upper triangle of A's own
// column-major storage, so every inner loop runs down a column (contiguous memory). N > 0 fixes
// the order at compile time (the compiler then unrolls); n is N then.
#pragma once

// Full unrolling of the short loops when the order is known at compile time (gcc and clang).
#if defined(__clang__)
#define PCSIM_UNROLL _Pragma("unroll")
#elif defined(__GNUC__)
#define PCSIM_UNROLL _Pragma("GCC unroll 16")
#else
#define PCSIM_UNROLL
#endif

#include <cmath>

namespace pcsim::mech::detail {

/// Factors the SPD matrix a (n x n, column-major, leading dimension lda) in place: its upper
/// triangle becomes U (A = Uᵀ U; the strict lower triangle is not referenced), and inv_diag (n)
/// 1 / U_kk, so the solves multiply instead of divide. Returns false if a pivot is not positive
/// or the pivot ratio min(U_kk²)/max(U_kk²) is below `ratio` (an ill-conditioned or singular
/// matrix), as the engine's mass-matrix check demands.
template <int N = 0>
inline bool cholesky_upper(double* a, int n_runtime, int lda, double ratio, double* inv_diag) {
  const int n = N > 0 ? N : n_runtime;
  double dmin = INFINITY, dmax = 0.0;
  PCSIM_UNROLL
  for (int j = 0; j < n; ++j) {
    double* uj = a + j * lda;  // column j: U(0..j, j)
    PCSIM_UNROLL
    for (int i = 0; i < j; ++i) {
      const double* ui = a + i * lda;  // column i: U(0..i, i)
      double v = uj[i];
      PCSIM_UNROLL
      for (int k = 0; k < i; ++k) v -= ui[k] * uj[k];
      uj[i] = v * inv_diag[i];
    }
    double d = uj[j];
    PCSIM_UNROLL
    for (int k = 0; k < j; ++k) d -= uj[k] * uj[k];
    if (!(d > 0.0)) return false;
    const double ujj = std::sqrt(d);
    uj[j] = ujj;
    inv_diag[j] = 1.0 / ujj;
    dmin = d < dmin ? d : dmin;
    dmax = d > dmax ? d : dmax;
  }
  return dmin > ratio * dmax;
}

/// Solves Uᵀ U x = b in place (b overwritten by x), U and inv_diag from cholesky_upper.
template <int N = 0>
inline void cholesky_solve(const double* u, const double* inv_diag, int n_runtime, int lda,
                           double* b) {
  const int n = N > 0 ? N : n_runtime;
  PCSIM_UNROLL
  for (int i = 0; i < n; ++i) {  // Uᵀ y = b: y_i = (b_i - Σ_{k<i} U(k,i) y_k) / U(i,i)
    const double* ui = u + i * lda;
    double v = b[i];
    PCSIM_UNROLL
    for (int k = 0; k < i; ++k) v -= ui[k] * b[k];
    b[i] = v * inv_diag[i];
  }
  PCSIM_UNROLL
  for (int i = n - 1; i >= 0; --i) {  // U x = y, by columns: x_i = y_i / U(i,i), then
    const double* ui = u + i * lda;   // y_k -= U(k,i) x_i for k < i
    const double xi = b[i] * inv_diag[i];
    b[i] = xi;
    PCSIM_UNROLL
    for (int k = 0; k < i; ++k) b[k] -= ui[k] * xi;
  }
}

}  // namespace pcsim::mech::detail
