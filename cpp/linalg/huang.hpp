// Public C++ API of the modified Huang (ABS class) solver for A x = b, A m x n of any shape and
// rank, and of the null-space basis extraction. Two implementations behind one interface: the
// Fortran-77 kernel through the bridge (Kernel::fortran) and the C++ port (Kernel::cpp).
#pragma once

#include <vector>

#include <Eigen/Dense>

#include "common/kernel.hpp"

namespace pcsim {

struct HuangOptions {
  Kernel kernel = Kernel::fortran;
  /// Relative linear-dependence tolerance; <= 0 selects the documented default (see the
  /// Fortran header of the kernel).
  double tol = 0.0;
  /// true: modified Huang, p_i = H_i (H_i a_i) (re-projection); false: plain Huang,
  /// p_i = H_i a_i (kept for the accuracy comparison in the README).
  bool reproject = true;
};

struct HuangResult {
  /// 0: solved. > 0: row info (1-based) is inconsistent with the rows before it; x is then
  /// not a solution. < 0: argument -info was invalid.
  int info = 0;
  Eigen::VectorXd x;                ///< the solution nearest to x1 (minimum norm when x1 = 0)
  Eigen::MatrixXd H;                ///< n x n orthogonal projector onto null(A)
  int rank = 0;                     ///< numerical rank of A
  std::vector<bool> row_dependent;  ///< row i depends linearly on rows 0..i-1 (size m)
};

/// Solves A x = b, starting from x1 (the result is the solution nearest to x1).
HuangResult huang_solve(const Eigen::MatrixXd& A, const Eigen::VectorXd& b,
                        const Eigen::VectorXd& x1, const HuangOptions& options = {});

/// Solves A x = b from x1 = 0: the minimum-norm solution.
HuangResult huang_solve(const Eigen::MatrixXd& A, const Eigen::VectorXd& b,
                        const HuangOptions& options = {});

/// A basis D (n x (n - rank), full column rank) of null(A), extracted deterministically from the
/// projector H returned by huang_solve (rule documented in the Fortran header). info as above.
struct NullBasisResult {
  int info = 0;
  Eigen::MatrixXd D;
};
NullBasisResult huang_null_basis(const Eigen::MatrixXd& H, int rank,
                                 const HuangOptions& options = {});

/// Reusable scratch storage for repeated calls on systems of the same size (the engine solves
/// a small system per right-hand-side evaluation): with the overloads below, nothing is
/// allocated after the first call of a given size.
struct HuangWorkspace {
  Eigen::VectorXd work;
  std::vector<int> idep;
};

/// As huang_solve(A, b, x1, options), but writes into `result` (reusing its storage) and uses
/// `workspace` for scratch. Returns result.info. Size mismatches are argument errors numbered as
/// in the kernel: b.size() != A.rows() gives info = -6, x1.size() != A.cols() gives -7; a tol
/// that is NaN or >= 1 gives -8.
int huang_solve(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, const Eigen::VectorXd& x1,
                const HuangOptions& options, HuangWorkspace& workspace, HuangResult& result);

/// As huang_null_basis(H, rank, options), reusing `result` and `workspace`. Returns result.info.
/// A non-square H gives info = -3; rank outside [0, H.cols()] gives -2.
int huang_null_basis(const Eigen::MatrixXd& H, int rank, const HuangOptions& options,
                     HuangWorkspace& workspace, NullBasisResult& result);

}  // namespace pcsim
