// Every invalid argument of the Huang kernels is reported as INFO = -i (i = its position),
// identically by the Fortran kernel through the C bridge and by the C++ port, and by the
// public API for the arguments it derives from Eigen sizes.
#define BOOST_TEST_MODULE huang_arguments
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <limits>
#include <vector>

#include "linalg/huang.hpp"
#include "linalg/huang_port.hpp"
#include "pcsim_huang.h"

using namespace pcsim;

namespace {

// The arguments of PCHUAN for a valid 3 x 4 problem; each case spoils one (or two) of them.
struct SolveArgs {
  int meth = 0, m = 3, n = 4, lda = 3, ldh = 4, lwork = 8;
  double tol = 0.0;
  std::vector<double> a = std::vector<double>(64, 1.0), b = std::vector<double>(16, 1.0),
                      x = std::vector<double>(16, 0.5), h = std::vector<double>(64, 0.0),
                      work = std::vector<double>(64, 0.0);
  std::vector<int> idep = std::vector<int>(16, 0);
  int rank = -7;
};

int via_bridge(SolveArgs s) {
  int info = 99;
  pcsim_huang_solve(s.meth, s.m, s.n, s.a.data(), s.lda, s.b.data(), s.x.data(), s.tol,
                    s.h.data(), s.ldh, &s.rank, s.idep.data(), s.work.data(), s.lwork, &info);
  return info;
}

int via_port(SolveArgs s) {
  return huang_port::solve(s.meth, s.m, s.n, s.a.data(), s.lda, s.b.data(), s.x.data(), s.tol,
                           s.h.data(), s.ldh, &s.rank, s.idep.data(), s.work.data(), s.lwork);
}

struct NullArgs {
  int n = 4, rank = 2, ldh = 4, ldd = 4, lwork = 20;
  std::vector<double> h = std::vector<double>(64, 0.0), d = std::vector<double>(64, 0.0),
                      work = std::vector<double>(64, 0.0);
};

int via_bridge(NullArgs s) {
  int info = 99;
  pcsim_huang_null_basis(s.n, s.rank, s.h.data(), s.ldh, s.d.data(), s.ldd, s.work.data(),
                         s.lwork, &info);
  return info;
}

int via_port(NullArgs s) {
  return huang_port::null_basis(s.n, s.rank, s.h.data(), s.ldh, s.d.data(), s.ldd,
                                s.work.data(), s.lwork);
}

template <class Args, class Spoil>
void expect_info(Spoil spoil, int expected) {
  Args args;
  spoil(args);
  BOOST_TEST(via_bridge(args) == expected);
  BOOST_TEST(via_port(args) == expected);
}

}  // namespace

BOOST_AUTO_TEST_CASE(valid_arguments_give_info_zero) {
  // The baseline the spoiled cases start from must itself be valid (else the checks below
  // could pass for the wrong reason).
  BOOST_TEST(via_bridge(SolveArgs{}) == 0);
  BOOST_TEST(via_port(SolveArgs{}) == 0);
  NullArgs nb;
  for (int i = 0; i < 4; ++i) nb.h[static_cast<std::size_t>(i * 4 + i)] = i < 2 ? 1.0 : 0.0;
  BOOST_TEST(via_bridge(nb) == 0);
  BOOST_TEST(via_port(nb) == 0);
}

BOOST_AUTO_TEST_CASE(every_bad_solve_argument_gets_its_info) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  expect_info<SolveArgs>([](SolveArgs& s) { s.meth = -1; }, -1);
  expect_info<SolveArgs>([](SolveArgs& s) { s.meth = 3; }, -1);
  expect_info<SolveArgs>([](SolveArgs& s) { s.m = -1; }, -2);
  expect_info<SolveArgs>([](SolveArgs& s) { s.n = -1; }, -3);
  expect_info<SolveArgs>([](SolveArgs& s) { s.lda = 2; }, -5);
  expect_info<SolveArgs>([](SolveArgs& s) { s.m = 0; s.lda = 0; }, -5);
  expect_info<SolveArgs>([nan](SolveArgs& s) { s.tol = nan; }, -8);
  expect_info<SolveArgs>([](SolveArgs& s) { s.tol = 1.0; }, -8);
  expect_info<SolveArgs>([](SolveArgs& s) { s.ldh = 3; }, -10);
  expect_info<SolveArgs>([](SolveArgs& s) { s.n = 0; s.ldh = 0; }, -10);
  expect_info<SolveArgs>([](SolveArgs& s) { s.lwork = 7; }, -14);
  expect_info<SolveArgs>([](SolveArgs& s) { s.lwork = 0; }, -14);
  // The first bad argument wins.
  expect_info<SolveArgs>([](SolveArgs& s) { s.meth = 5; s.m = -1; }, -1);
  expect_info<SolveArgs>([](SolveArgs& s) { s.lda = 1; s.lwork = 1; }, -5);
  // Boundary values that are valid.
  expect_info<SolveArgs>([](SolveArgs& s) { s.meth = 2; }, 0);
  expect_info<SolveArgs>([](SolveArgs& s) { s.tol = 0.5; }, 0);
  expect_info<SolveArgs>([](SolveArgs& s) { s.tol = -1.0; }, 0);
}

BOOST_AUTO_TEST_CASE(bad_argument_leaves_the_start_vector_untouched) {
  SolveArgs s;
  s.lwork = 1;
  int info = 0;
  pcsim_huang_solve(s.meth, s.m, s.n, s.a.data(), s.lda, s.b.data(), s.x.data(), s.tol,
                    s.h.data(), s.ldh, &s.rank, s.idep.data(), s.work.data(), s.lwork, &info);
  BOOST_TEST(info == -14);
  BOOST_TEST(s.x == std::vector<double>(16, 0.5));
  BOOST_TEST(huang_port::solve(s.meth, s.m, s.n, s.a.data(), s.lda, s.b.data(), s.x.data(),
                               s.tol, s.h.data(), s.ldh, &s.rank, s.idep.data(), s.work.data(),
                               s.lwork) == -14);
  BOOST_TEST(s.x == std::vector<double>(16, 0.5));
}

BOOST_AUTO_TEST_CASE(every_bad_null_basis_argument_gets_its_info) {
  expect_info<NullArgs>([](NullArgs& s) { s.n = -1; }, -1);
  expect_info<NullArgs>([](NullArgs& s) { s.rank = -1; }, -2);
  expect_info<NullArgs>([](NullArgs& s) { s.rank = 5; }, -2);
  expect_info<NullArgs>([](NullArgs& s) { s.ldh = 3; }, -4);
  expect_info<NullArgs>([](NullArgs& s) { s.ldd = 3; }, -6);
  expect_info<NullArgs>([](NullArgs& s) { s.lwork = 19; }, -8);
  expect_info<NullArgs>([](NullArgs& s) { s.n = 0; s.rank = 0; s.ldh = 0; }, -4);
  expect_info<NullArgs>([](NullArgs& s) { s.rank = 9; s.ldd = 1; }, -2);
}

BOOST_AUTO_TEST_CASE(workspace_query_returns_the_minimal_lwork) {
  for (int n : {0, 1, 4}) {
    SolveArgs s;
    s.n = n;
    s.ldh = std::max(1, n);
    s.lwork = -1;
    BOOST_TEST(via_bridge(s) == 0);
    int info = 99;
    pcsim_huang_solve(s.meth, s.m, s.n, s.a.data(), s.lda, s.b.data(), s.x.data(), s.tol,
                      s.h.data(), s.ldh, &s.rank, s.idep.data(), s.work.data(), s.lwork, &info);
    BOOST_TEST(s.work[0] == std::max(1, 2 * n));
    s.work[0] = 0.0;
    BOOST_TEST(huang_port::solve(s.meth, s.m, s.n, s.a.data(), s.lda, s.b.data(), s.x.data(),
                                 s.tol, s.h.data(), s.ldh, &s.rank, s.idep.data(),
                                 s.work.data(), s.lwork) == 0);
    BOOST_TEST(s.work[0] == std::max(1, 2 * n));
    NullArgs q;
    q.n = n;
    q.rank = 0;
    q.ldh = q.ldd = std::max(1, n);
    q.lwork = -1;
    pcsim_huang_null_basis(q.n, q.rank, q.h.data(), q.ldh, q.d.data(), q.ldd, q.work.data(),
                           q.lwork, &info);
    BOOST_TEST(info == 0);
    BOOST_TEST(q.work[0] == std::max(1, n * n + n));
    q.work[0] = 0.0;
    BOOST_TEST(huang_port::null_basis(q.n, q.rank, q.h.data(), q.ldh, q.d.data(), q.ldd,
                                      q.work.data(), q.lwork) == 0);
    BOOST_TEST(q.work[0] == std::max(1, n * n + n));
  }
}

BOOST_AUTO_TEST_CASE(public_api_reports_size_mismatches_with_kernel_numbering) {
  const Eigen::MatrixXd A = Eigen::MatrixXd::Ones(3, 4);
  for (Kernel k : {Kernel::fortran, Kernel::cpp}) {
    HuangOptions o;
    o.kernel = k;
    BOOST_TEST(huang_solve(A, Eigen::VectorXd::Ones(2), o).info == -6);
    BOOST_TEST(huang_solve(A, Eigen::VectorXd::Ones(3), Eigen::VectorXd::Zero(3), o).info == -7);
    o.tol = std::numeric_limits<double>::quiet_NaN();
    BOOST_TEST(huang_solve(A, Eigen::VectorXd::Ones(3), o).info == -8);
    o.tol = 2.0;
    BOOST_TEST(huang_solve(A, Eigen::VectorXd::Ones(3), o).info == -8);
    o.tol = 0.0;
    BOOST_TEST(huang_null_basis(Eigen::MatrixXd::Identity(3, 4), 0, o).info == -3);
    BOOST_TEST(huang_null_basis(Eigen::MatrixXd::Identity(3, 3), 4, o).info == -2);
    BOOST_TEST(huang_null_basis(Eigen::MatrixXd::Identity(3, 3), -1, o).info == -2);
  }
}
