// Shared helpers for the Huang tests: the LAPACK oracle (dgelsd), random test systems with
// known structure (fixed seeds), and the classic ill-conditioned matrices.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "common/eigen_instances.hpp"

extern "C" void dgelsd_(const int* m, const int* n, const int* nrhs, double* a, const int* lda,
                        double* b, const int* ldb, double* s, const double* rcond, int* rank,
                        double* work, const int* lwork, int* iwork, int* info);

namespace pcsim::test {

constexpr double kEps = std::numeric_limits<double>::epsilon();

/// LAPACK's minimum-norm solution of A x = b (SVD, divide and conquer); singular values
/// below rcond * s_max are treated as zero. Also returns the singular values and the rank.
struct GelsdResult {
  int info = 0;
  int rank = 0;
  Eigen::VectorXd x;
  Eigen::VectorXd s;
};
inline GelsdResult gelsd(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, double rcond) {
  const int m = static_cast<int>(A.rows()), n = static_cast<int>(A.cols());
  const int nrhs = 1, lda = std::max(1, m), ldb = std::max({1, m, n});
  Eigen::MatrixXd a = A;
  Eigen::VectorXd bb = Eigen::VectorXd::Zero(ldb);
  bb.head(m) = b;
  GelsdResult r;
  r.s.resize(std::max(1, std::min(m, n)));
  double wq = 0.0;
  int iwq = 0, lwork = -1;
  dgelsd_(&m, &n, &nrhs, a.data(), &lda, bb.data(), &ldb, r.s.data(), &rcond, &r.rank, &wq,
          &lwork, &iwq, &r.info);
  lwork = static_cast<int>(wq) + 1;
  std::vector<double> work(static_cast<std::size_t>(lwork));
  std::vector<int> iwork(static_cast<std::size_t>(std::max(1, iwq)));
  dgelsd_(&m, &n, &nrhs, a.data(), &lda, bb.data(), &ldb, r.s.data(), &rcond, &r.rank,
          work.data(), &lwork, iwork.data(), &r.info);
  r.x = bb.head(n);
  r.s.conservativeResize(std::min(m, n));
  return r;
}

/// A random system with a prescribed pattern of dependent rows. Rows with dependent[i] = false
/// are random (so independent of the earlier ones with probability 1, as long as there are
/// fewer than n of them); rows with dependent[i] = true are random combinations of the
/// independent rows before them. Rows and columns are then scaled by 10^U(-row_decades,
/// row_decades) and 10^U(-col_decades, col_decades). b = A x_true, so the system is consistent.
struct TestSystem {
  Eigen::MatrixXd A;
  Eigen::VectorXd b;
  Eigen::VectorXd x_true;
  std::vector<bool> dependent;
  int rank = 0;
};
inline TestSystem make_system(std::mt19937& rng, int n, const std::vector<bool>& dependent,
                              double row_decades, double col_decades) {
  const int m = static_cast<int>(dependent.size());
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  TestSystem s;
  s.A.resize(m, n);
  s.dependent = dependent;
  std::vector<int> independent;
  for (int i = 0; i < m; ++i) {
    if (!dependent[static_cast<std::size_t>(i)]) {
      for (int j = 0; j < n; ++j) s.A(i, j) = u(rng);
      independent.push_back(i);
    } else {
      s.A.row(i).setZero();
      for (int k : independent) s.A.row(i) += u(rng) * s.A.row(k);
    }
  }
  s.rank = static_cast<int>(independent.size());
  for (int i = 0; i < m; ++i) s.A.row(i) *= std::pow(10.0, row_decades * u(rng));
  for (int j = 0; j < n; ++j) s.A.col(j) *= std::pow(10.0, col_decades * u(rng));
  s.x_true.resize(n);
  for (int j = 0; j < n; ++j) s.x_true(j) = u(rng);
  s.b = s.A * s.x_true;
  return s;
}

/// A dependence pattern for an m x n system with rank r (r <= min(m, n)): r independent rows
/// and m - r dependent ones at random positions, the first row always independent (a dependent
/// row needs earlier independent rows). r = 0 gives all-dependent zero rows.
inline std::vector<bool> random_pattern(std::mt19937& rng, int m, int r) {
  std::vector<bool> dep(static_cast<std::size_t>(m), true);
  if (r == 0) return dep;
  std::vector<int> pos(static_cast<std::size_t>(std::max(0, m - 1)));
  for (int i = 0; i < m - 1; ++i) pos[static_cast<std::size_t>(i)] = i + 1;
  std::shuffle(pos.begin(), pos.end(), rng);
  dep[0] = false;
  for (int k = 0; k < r - 1; ++k) dep[static_cast<std::size_t>(pos[static_cast<std::size_t>(k)])] = false;
  return dep;
}

/// The n x n Hilbert matrix, H(i, j) = 1 / (i + j + 1) (0-based).
inline Eigen::MatrixXd hilbert(int n) {
  Eigen::MatrixXd A(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) A(i, j) = 1.0 / (i + j + 1);
  return A;
}

/// The m x n Vandermonde matrix of the equispaced points t_i = i / (m - 1) in [0, 1],
/// V(i, j) = t_i^j.
inline Eigen::MatrixXd vandermonde(int m, int n) {
  Eigen::MatrixXd V(m, n);
  for (int i = 0; i < m; ++i) {
    const double t = m > 1 ? static_cast<double>(i) / (m - 1) : 0.0;
    double p = 1.0;
    for (int j = 0; j < n; ++j) {
      V(i, j) = p;
      p *= t;
    }
  }
  return V;
}

/// Relative normwise difference ||a - b|| / ||b|| (absolute if b = 0).
inline double rel_diff(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  const double nb = b.norm();
  return nb > 0.0 ? (a - b).norm() / nb : (a - b).norm();
}

}  // namespace pcsim::test
