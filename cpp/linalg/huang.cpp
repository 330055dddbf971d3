// The public Huang API (linalg/huang.hpp): marshals Eigen objects to the kernel's column-major
// argument list and dispatches to the Fortran kernel (through the bridge) or to the C++ port.
#include "linalg/huang.hpp"

#include <algorithm>

#include "linalg/huang_port.hpp"
#include "pcsim_kernels.h"

namespace pcsim {

namespace {
// Kernel method code: 0 = modified Huang (re-projection), 2 = plain Huang.
int method_code(const HuangOptions& options) { return options.reproject ? 0 : 2; }

// A valid address for an empty array (the kernels never read it, but Fortran dummies should not
// be associated with a null pointer).
double* data_or(double* p, double* fallback) { return p != nullptr ? p : fallback; }
const double* data_or(const double* p, const double* fallback) {
  return p != nullptr ? p : fallback;
}
// Grows (never shrinks) the scratch vector, so alternating solve / null-basis calls reuse it.
void grow(Eigen::VectorXd& work, int size) {
  if (work.size() < size) work.resize(size);
}
}  // namespace

int huang_solve(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, const Eigen::VectorXd& x1,
                const HuangOptions& options, HuangWorkspace& workspace, HuangResult& result) {
  const int m = static_cast<int>(A.rows());
  const int n = static_cast<int>(A.cols());
  result.rank = 0;
  result.row_dependent.assign(static_cast<std::size_t>(m), false);
  if (b.size() != A.rows()) return result.info = -6;
  if (x1.size() != A.cols()) return result.info = -7;

  result.x = x1;
  result.H.resize(n, n);
  grow(workspace.work, std::max(1, 2 * n));
  if (workspace.idep.size() < static_cast<std::size_t>(std::max(1, m))) {
    workspace.idep.resize(static_cast<std::size_t>(std::max(1, m)));
  }
  double dummy[1] = {0.0};
  const double* a = data_or(A.data(), dummy);
  const double* bb = data_or(b.data(), dummy);
  double* x = data_or(result.x.data(), dummy);
  double* h = data_or(result.H.data(), dummy);
  const int lda = std::max(1, m);
  const int ldh = std::max(1, n);
  const int lwork = static_cast<int>(workspace.work.size());
  int info = 0;
  if (options.kernel == Kernel::fortran) {
    pcsim_huang_solve(method_code(options), m, n, a, lda, bb, x, options.tol, h, ldh,
                      &result.rank, workspace.idep.data(), workspace.work.data(), lwork, &info);
  } else {
    info = huang_port::solve(method_code(options), m, n, a, lda, bb, x, options.tol, h, ldh,
                             &result.rank, workspace.idep.data(), workspace.work.data(), lwork);
  }
  result.info = info;
  if (info < 0) result.H.setZero();  // the kernel returned before writing H: no garbage out
  if (info >= 0) {
    for (int i = 0; i < m; ++i) result.row_dependent[static_cast<std::size_t>(i)] =
        workspace.idep[static_cast<std::size_t>(i)] > 0;
  }
  return info;
}

HuangResult huang_solve(const Eigen::MatrixXd& A, const Eigen::VectorXd& b,
                        const Eigen::VectorXd& x1, const HuangOptions& options) {
  HuangWorkspace workspace;
  HuangResult result;
  huang_solve(A, b, x1, options, workspace, result);
  return result;
}

HuangResult huang_solve(const Eigen::MatrixXd& A, const Eigen::VectorXd& b,
                        const HuangOptions& options) {
  return huang_solve(A, b, Eigen::VectorXd::Zero(A.cols()), options);
}

int huang_null_basis(const Eigen::MatrixXd& H, int rank, const HuangOptions& options,
                     HuangWorkspace& workspace, NullBasisResult& result) {
  const int n = static_cast<int>(H.cols());
  if (H.rows() != H.cols()) {
    result.D.resize(0, 0);
    return result.info = -3;
  }
  if (rank < 0 || rank > n) {
    result.D.resize(0, 0);
    return result.info = -2;
  }
  result.D.resize(n, n - rank);
  grow(workspace.work, std::max(1, n * n + n));
  double dummy[1] = {0.0};
  const double* h = data_or(H.data(), dummy);
  double* d = data_or(result.D.data(), dummy);
  const int ld = std::max(1, n);
  const int lwork = static_cast<int>(workspace.work.size());
  int info = 0;
  if (options.kernel == Kernel::fortran) {
    pcsim_huang_null_basis(n, rank, h, ld, d, ld, workspace.work.data(), lwork, &info);
  } else {
    info = huang_port::null_basis(n, rank, h, ld, d, ld, workspace.work.data(), lwork);
  }
  return result.info = info;
}

NullBasisResult huang_null_basis(const Eigen::MatrixXd& H, int rank,
                                 const HuangOptions& options) {
  HuangWorkspace workspace;
  NullBasisResult result;
  huang_null_basis(H, rank, options, workspace, result);
  return result;
}

}  // namespace pcsim
