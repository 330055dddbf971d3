/* C interface to the Huang (ABS) kernels (fortran/huang.f through bridge/huang_bridge.f90).
 * Arguments are those of PCHUAN / PCHNUL in the same order, so INFO = -i names the same
 * argument i on both sides; the Fortran headers document every argument and INFO value.
 * All matrices are column-major with the given leading dimension; nothing is transposed.
 * Scalars are passed by value; outputs through pointers. */
#ifndef PCSIM_HUANG_H
#define PCSIM_HUANG_H

#ifdef __cplusplus
extern "C" {
#endif

/* Solves A x = b (A m x n, any rank) by the modified (meth 0 or 1) or plain (meth 2) Huang
 * algorithm from the start vector x (in: x1, out: solution nearest to x1).
 *   a    [lda x n]  input,  lda >= max(1, m)
 *   b    [m]        input
 *   x    [n]        in/out
 *   tol  relative dependence tolerance, < 1; <= 0 selects 100 * max(m, n) * 2^-52
 *   h    [ldh x n]  output: orthogonal projector onto null(A), ldh >= max(1, n)
 *   rank            output
 *   idep [m]        output: 0 independent, 1 dependent (consistent), 2 inconsistent,
 *                   -1 not examined
 *   work [lwork]    workspace, lwork >= max(1, 2 n), or lwork = -1: query (work[0])
 *   info            output: 0 ok, -i argument i invalid, i > 0 row i inconsistent */
void pcsim_huang_solve(int meth, int m, int n, const double* a, int lda, const double* b,
                       double* x, double tol, double* h, int ldh, int* rank, int* idep,
                       double* work, int lwork, int* info);

/* Orthonormal basis D of range(H) = null(A), n x (n - rank), deterministic (QR of H with relaxed
 * column pivoting: first column within a factor 2 of the largest norm).
 *   h    [ldh x n]         input, ldh >= max(1, n)
 *   d    [ldd x (n-rank)]  output, ldd >= max(1, n)
 *   work [lwork]           workspace, lwork >= max(1, n*n + n), or -1: query (work[0])
 *   info                   output: 0 ok, -i argument i invalid, k > 0 column k not formed
 *                          (H is not a projector of rank >= n - rank) */
void pcsim_huang_null_basis(int n, int rank, const double* h, int ldh, double* d, int ldd,
                            double* work, int lwork, int* info);

#ifdef __cplusplus
}
#endif

#endif /* PCSIM_HUANG_H */
