// C++ port of fortran/radau_lu.f: the small dense LU (partial pivoting, zero multipliers and
// zero pivot-row entries skipped) for Radau's real and complex iteration matrices, with the
// same operations in the same order as the Fortran routines, so both kernels round alike.
// Column-major storage with leading dimension lda; pivots 1-based as in Fortran/LAPACK.
#pragma once

namespace pcsim::radau_lu {

/// RADLUD: P A = L U of the n x n matrix a (in place; the diagonal holds 1/u_kk). iwl: n ints
/// of workspace.
/// Returns 0, or k > 0 if the pivot of column k is exactly zero (factorization unusable).
int factor(int n, double* a, int lda, int* ipiv, int* iwl);

/// RADLUS: solves A x = b in place with the factors of factor().
void solve(int n, const double* a, int lda, const int* ipiv, double* b);

/// RADLZD: the same for A = ar + i ai (real and imaginary parts apart).
int factor_complex(int n, double* ar, double* ai, int lda, int* ipiv, int* iwl);

/// RADLZS: solves A x = b, b = br + i bi, in place.
void solve_complex(int n, const double* ar, const double* ai, int lda, const int* ipiv,
                   double* br, double* bi);

}  // namespace pcsim::radau_lu
