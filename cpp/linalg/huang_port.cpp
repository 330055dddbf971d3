// C++ port of fortran/huang.f on Eigen maps of the caller's arrays. Element-wise operations
// (axpy, scaling, rank-one updates) are Eigen column expressions, which vectorize and round
// exactly like the Fortran loops; reductions (dot products, norms) are explicit left-to-right
// loops, because Eigen's vectorized reductions and GEMV would reorder the sums. So both paths
// round identically in practice. The mathematics and every argument are documented in the
// Fortran headers.
#include "linalg/huang_port.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Core>

namespace pcsim::huang_port {

namespace {
using ConstMat = Eigen::Map<const Eigen::MatrixXd, 0, Eigen::OuterStride<>>;
using Mat = Eigen::Map<Eigen::MatrixXd, 0, Eigen::OuterStride<>>;
}  // namespace

double norm2(int n, const double* v, int incv) {
  double amax = 0.0;
  for (int k = 0; k < n; ++k) {
    if (std::abs(v[k * incv]) > amax) amax = std::abs(v[k * incv]);
  }
  if (amax == 0.0) return 0.0;
  double s = 0.0;
  for (int k = 0; k < n; ++k) {
    const double t = v[k * incv] / amax;
    s = s + t * t;
  }
  return amax * std::sqrt(s);
}

int solve(int meth, int m, int n, const double* a, int lda, const double* b, double* x, double tol,
          double* h, int ldh, int* rank, int* idep, double* work, int lwork) {
  const int minwrk = std::max(1, 2 * n);
  if (meth < 0 || meth > 2) return -1;
  if (m < 0) return -2;
  if (n < 0) return -3;
  if (lda < std::max(1, m)) return -5;
  if (tol != tol || tol >= 1.0) return -8;
  if (ldh < std::max(1, n)) return -10;
  if (lwork < minwrk && lwork != -1) return -14;
  if (lwork == -1) {
    work[0] = static_cast<double>(minwrk);
    return 0;
  }

  const bool modif = meth != 2;
  double told = tol;
  if (told <= 0.0) {
    told = 100.0 * static_cast<double>(std::max(m, n)) * std::numeric_limits<double>::epsilon();
  }
  const ConstMat A(a, m, n, Eigen::OuterStride<>(lda));
  Mat H(h, n, n, Eigen::OuterStride<>(ldh));
  double* u = work;
  double* p = work + n;
  Eigen::Map<Eigen::VectorXd> U(u, n), P(p, n), X(x, n);

  H.setIdentity();
  for (int i = 0; i < m; ++i) idep[i] = -1;
  *rank = 0;
  double grow = 1.0;  // G_i: the error-amplification estimate of the consistency test

  for (int i = 0; i < m; ++i) {
    // u = H a_i, column by column of H.
    U.setZero();
    for (int k = 0; k < n; ++k) U += H.col(k) * A(i, k);
    const double anrm = n > 0 ? norm2(n, &a[i], lda) : 0.0;
    const double unrm = norm2(n, u, 1);
    double r = 0.0;
    for (int k = 0; k < n; ++k) r = r + A(i, k) * x[k];
    r = r - b[i];

    bool dependent = unrm <= told * anrm;
    if (!dependent) {
      // p = H u (modified) or u (plain).
      if (modif) {
        P.setZero();
        for (int k = 0; k < n; ++k) P += H.col(k) * u[k];
      } else {
        P = U;
      }
      const double pnrm = norm2(n, p, 1);
      double alpha = 0.0;
      if (pnrm != 0.0) {
        P /= pnrm;
        for (int j = 0; j < n; ++j) alpha = alpha + A(i, j) * p[j];
      }
      dependent = pnrm == 0.0 || alpha == 0.0;
      if (!dependent) {
        X -= (r / alpha) * P;
        for (int k = 0; k < n; ++k) H.col(k) -= P * p[k];
        grow = grow + anrm / std::abs(alpha);
        *rank += 1;
        idep[i] = 0;
        if (*rank == n) H.setZero();  // null(A) = {0}: no rounding residue (see the Fortran)
        continue;
      }
    }
    // Row i depends on rows 0..i-1: consistent or not.
    const double xnrm = norm2(n, x, 1);
    if (std::abs(r) > told * (grow * anrm * xnrm + std::abs(b[i]))) {
      idep[i] = 2;
      return i + 1;
    }
    idep[i] = 1;
  }
  return 0;
}

int null_basis(int n, int rank, const double* h, int ldh, double* d, int ldd, double* work,
               int lwork) {
  const int minwrk = std::max(1, n * n + n);
  if (n < 0) return -1;
  if (rank < 0 || rank > n) return -2;
  if (ldh < std::max(1, n)) return -4;
  if (ldd < std::max(1, n)) return -6;
  if (lwork < minwrk && lwork != -1) return -8;
  if (lwork == -1) {
    work[0] = static_cast<double>(minwrk);
    return 0;
  }
  if (rank == n) return 0;

  const ConstMat H(h, n, n, Eigen::OuterStride<>(ldh));
  Mat D(d, n, n - rank, Eigen::OuterStride<>(ldd));
  Eigen::Map<Eigen::MatrixXd> W(work, n, n);  // leading dimension n, as in the Fortran
  double* wnorm = work + n * n;
  W = H;

  for (int k = 0; k < n - rank; ++k) {
    // Column norms of W and the relaxed pivot (first column within a factor 2 of the largest).
    double wmax = 0.0;
    for (int j = 0; j < n; ++j) {
      wnorm[j] = norm2(n, &W(0, j), 1);
      if (wnorm[j] > wmax) wmax = wnorm[j];
    }
    if (wmax < 0.5 / std::sqrt(static_cast<double>(n))) return k + 1;
    int jk = -1;
    for (int j = n - 1; j >= 0; --j) {
      if (wnorm[j] >= 0.5 * wmax) jk = j;
    }
    // d = W(:,jk) / ||W(:,jk)||, re-orthogonalized once against D(:,0:k-1), normalized again.
    D.col(k) = W.col(jk) / wnorm[jk];
    for (int j = 0; j < k; ++j) {
      double c = 0.0;
      for (int l = 0; l < n; ++l) c = c + D(l, j) * D(l, k);
      D.col(k) -= c * D.col(j);
    }
    D.col(k) /= norm2(n, &D(0, k), 1);
    // W <- W - d (d' W); the pivot column is set to zero exactly.
    for (int j = 0; j < n; ++j) {
      if (j == jk) {
        W.col(j).setZero();
      } else {
        double c = 0.0;
        for (int l = 0; l < n; ++l) c = c + D(l, k) * W(l, j);
        W.col(j) -= c * D.col(k);
      }
    }
  }
  return 0;
}

}  // namespace pcsim::huang_port
