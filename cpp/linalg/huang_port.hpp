// The C++ (Eigen) port of the Huang kernels PCHUAN and PCHNUL of fortran/huang.f: same arguments,
// same argument checks (INFO = -i for the same i), same algorithm and order of operations.
#pragma once

namespace pcsim::huang_port {

/// Port of PCHUAN: A x = b by the modified (meth 0, 1) or plain (meth 2) Huang algorithm; x in:
/// start vector, out: solution nearest to it. Column-major arrays with leading dimensions, as in
/// bridge/pcsim_huang.h. Returns INFO (0 ok, -i bad argument i, i > 0 row i inconsistent).
int solve(int meth, int m, int n, const double* a, int lda, const double* b, double* x, double tol,
          double* h, int ldh, int* rank, int* idep, double* work, int lwork);

/// Port of PCHNUL: orthonormal basis D (n x (n - rank)) of range(H), deterministic pivoting.
/// Returns INFO (0 ok, -i bad argument i, k > 0 column k of D could not be formed).
int null_basis(int n, int rank, const double* h, int ldh, double* d, int ldd, double* work,
               int lwork);

/// Port of PCHNRM: ||v||_2 as amax * sqrt(sum (v_k / amax)^2), in that order.
double norm2(int n, const double* v, int incv);

}  // namespace pcsim::huang_port
