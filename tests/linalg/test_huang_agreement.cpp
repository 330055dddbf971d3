// The Fortran kernel (through the bridge) and the C++ port give the same results on the same
// inputs: a few hundred random systems of every shape, rank and scaling (fixed seeds).
#define BOOST_TEST_MODULE huang_agreement
#include <boost/test/unit_test.hpp>

#include "huang_test_util.hpp"
#include "linalg/huang.hpp"

using namespace pcsim;
using namespace pcsim::test;

namespace {

// Both paths perform the same floating-point operations in the same order (the port mirrors
// the Fortran loops), so in practice they agree bitwise; 1e-13 relative is the issue's
// contract and leaves room for a compiler that contracts a*b+c into an FMA on one side only.
constexpr double kAgree = 1e-13;

struct Counts {
  int systems = 0, rank_deficient = 0, inconsistent = 0;
  double max_diff = 0.0;  // largest relative difference seen (x, H or D), for the log
};

void compare_paths(const TestSystem& s, const Eigen::VectorXd& x1, const Eigen::VectorXd& b,
                   bool reproject, Counts& counts) {
  HuangOptions of, oc;
  of.kernel = Kernel::fortran;
  oc.kernel = Kernel::cpp;
  of.reproject = oc.reproject = reproject;
  const HuangResult f = huang_solve(s.A, b, x1, of);
  const HuangResult c = huang_solve(s.A, b, x1, oc);
  BOOST_TEST_REQUIRE(f.info == c.info);
  BOOST_TEST_REQUIRE(f.info >= 0);
  BOOST_TEST(f.rank == c.rank);
  BOOST_TEST(f.row_dependent == c.row_dependent);
  BOOST_TEST(rel_diff(c.x, f.x) <= kAgree);
  BOOST_TEST(rel_diff(c.H, f.H) <= kAgree);
  counts.max_diff = std::max({counts.max_diff, rel_diff(c.x, f.x), rel_diff(c.H, f.H)});
  ++counts.systems;
  if (f.rank < std::min(s.A.rows(), s.A.cols())) ++counts.rank_deficient;
  if (f.info > 0) {
    ++counts.inconsistent;
    return;
  }
  const NullBasisResult df = huang_null_basis(f.H, f.rank, of);
  const NullBasisResult dc = huang_null_basis(f.H, f.rank, oc);
  BOOST_TEST_REQUIRE(df.info == 0, "n " << s.A.cols() << " m " << s.A.rows() << " rank " << f.rank << " H " << f.H.rows() << "x" << f.H.cols());
  BOOST_TEST_REQUIRE(dc.info == 0);
  BOOST_TEST(rel_diff(dc.D, df.D) <= kAgree);
  counts.max_diff = std::max(counts.max_diff, rel_diff(dc.D, df.D));
}

}  // namespace

BOOST_AUTO_TEST_CASE(fortran_and_cpp_paths_agree_on_random_systems) {
  std::mt19937 rng(20260101);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Counts counts;
  // shape: 0 square, 1 underdetermined, 2 overdetermined (consistent by construction)
  for (int shape = 0; shape < 3; ++shape) {
    for (int n : {1, 2, 3, 6, 9, 17}) {
      const int m = shape == 0 ? n : shape == 1 ? std::max(1, n / 2) : 2 * n + 1;
      for (bool deficient : {false, true}) {
        const int full = std::min(m, n);
        const int r = deficient ? full / 2 : full;
        for (double row_dec : {0.0, 6.0}) {
          for (double col_dec : {0.0, 3.0}) {
            for (int rep = 0; rep < 2; ++rep) {
              const TestSystem s = make_system(rng, n, random_pattern(rng, m, r), row_dec, col_dec);
              const Eigen::VectorXd zero = Eigen::VectorXd::Zero(n);
              Eigen::VectorXd x1(n);
              for (int j = 0; j < n; ++j) x1(j) = u(rng);
              compare_paths(s, zero, s.b, true, counts);
              compare_paths(s, x1, s.b, true, counts);
              compare_paths(s, zero, s.b, false, counts);
              // An inconsistent right-hand side (when a dependent row exists): same INFO.
              Eigen::VectorXd bad = s.b;
              for (int i = 0; i < m; ++i) {
                if (s.dependent[static_cast<std::size_t>(i)]) {
                  bad(i) += 1.0 + std::abs(bad(i));
                  break;
                }
              }
              compare_paths(s, zero, bad, true, counts);
            }
          }
        }
      }
    }
  }
  BOOST_TEST_MESSAGE("systems compared: " << counts.systems << ", rank-deficient: "
                                          << counts.rank_deficient
                                          << ", inconsistent: " << counts.inconsistent
                                          << ", max relative difference: " << counts.max_diff);
  // The sweep must really cover the classes the contract names.
  BOOST_TEST(counts.systems >= 500);
  BOOST_TEST(counts.rank_deficient >= 100);
  BOOST_TEST(counts.inconsistent >= 50);
}

BOOST_AUTO_TEST_CASE(workspace_overloads_agree_with_value_api_and_reuse_storage) {
  // The engine reuses one workspace and one result; the answers must not depend on that.
  std::mt19937 rng(7);
  HuangWorkspace ws;
  HuangResult res;
  NullBasisResult nb;
  for (Kernel k : {Kernel::fortran, Kernel::cpp}) {
    HuangOptions o;
    o.kernel = k;
    for (int rep = 0; rep < 20; ++rep) {
      const int n = 6, m = rep % 2 == 0 ? 3 : 4;
      const TestSystem s = make_system(rng, n, random_pattern(rng, m, 3), 0.0, 0.0);
      const Eigen::VectorXd zero = Eigen::VectorXd::Zero(n);
      BOOST_TEST_REQUIRE(huang_solve(s.A, s.b, zero, o, ws, res) == 0);
      const HuangResult ref = huang_solve(s.A, s.b, o);
      BOOST_TEST((res.x - ref.x).norm() == 0.0);
      BOOST_TEST((res.H - ref.H).norm() == 0.0);
      BOOST_TEST(res.row_dependent == ref.row_dependent);
      BOOST_TEST_REQUIRE(huang_null_basis(res.H, res.rank, o, ws, nb) == 0);
      BOOST_TEST((nb.D - huang_null_basis(ref.H, ref.rank, o).D).norm() == 0.0);
    }
  }
}
