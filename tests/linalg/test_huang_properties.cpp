// What the Huang solver computes, checked against oracles that are not itself: LAPACK's dgelsd
// (minimum-norm solution), Eigen's SVD (row space, null space), hand-computed bases, and the
// structure the test systems were built with (dependent rows, inconsistent rows).
#define BOOST_TEST_MODULE huang_properties
#include <boost/test/unit_test.hpp>
#include "common/eigen_instances.hpp"

#include "huang_test_util.hpp"
#include "linalg/huang.hpp"

using namespace pcsim;
using namespace pcsim::test;

namespace {

const Kernel kKernels[] = {Kernel::fortran, Kernel::cpp};

HuangOptions options_for(Kernel k) {
  HuangOptions o;
  o.kernel = k;
  return o;
}

// The random well-scaled systems used by several properties: every shape, full rank and
// rank-deficient. Their condition numbers (on the row space) are modest, < 1e4.
std::vector<TestSystem> well_scaled_systems(unsigned seed) {
  std::mt19937 rng(seed);
  std::vector<TestSystem> out;
  for (int n : {1, 2, 4, 6, 10, 16}) {
    for (int m : {std::max(1, n / 2), n, 2 * n}) {
      const int full = std::min(m, n);
      for (int r : {full, full / 2}) {
        for (int rep = 0; rep < 3; ++rep) {
          out.push_back(make_system(rng, n, random_pattern(rng, m, r), 0.0, 0.0));
        }
      }
    }
  }
  return out;
}

// Condition number on the row space, from the nonzero singular values (dgelsd's).
double kappa(const GelsdResult& g) {
  return g.rank > 0 ? g.s(0) / g.s(g.rank - 1) : 1.0;
}

}  // namespace

BOOST_AUTO_TEST_CASE(min_norm_solution_matches_dgelsd) {
  // Both solvers are backward stable, so their solutions of a consistent system differ by a
  // forward error of order eps * kappa(A) (first-order perturbation of the pseudo-inverse
  // solution, with the rank kept). Threshold: 10 * max(m, n) * eps * kappa.
  for (Kernel k : kKernels) {
    for (const TestSystem& s : well_scaled_systems(11)) {
      const int m = static_cast<int>(s.A.rows()), n = static_cast<int>(s.A.cols());
      const HuangResult h = huang_solve(s.A, s.b, options_for(k));
      // rcond 1e-10: the zero singular values of the rank-deficient products are O(eps).
      const GelsdResult g = gelsd(s.A, s.b, 1e-10);
      BOOST_TEST_REQUIRE(h.info == 0);
      BOOST_TEST_REQUIRE(g.info == 0);
      BOOST_TEST(h.rank == s.rank);
      BOOST_TEST(g.rank == s.rank);
      const double bound = 10.0 * std::max(m, n) * kEps * kappa(g);
      BOOST_TEST(rel_diff(h.x, g.x) <= bound, "m " << m << " n " << n << " rank " << s.rank);
    }
  }
}

BOOST_AUTO_TEST_CASE(min_norm_solution_lies_in_row_space) {
  // LAPACK's dqrt14 idea: x lies in the row space of A iff appending x' to A does not raise
  // the rank. We take the (rank+1)-th singular value of [A / ||A||; x' / ||x||] (Eigen's SVD,
  // an independent oracle) and require it below 30 * max(m, n) * eps (LAPACK's test threshold
  // 30 on the ratio to max(m, n) * eps).
  for (Kernel k : kKernels) {
    for (const TestSystem& s : well_scaled_systems(12)) {
      const int m = static_cast<int>(s.A.rows()), n = static_cast<int>(s.A.cols());
      const HuangResult h = huang_solve(s.A, s.b, options_for(k));
      BOOST_TEST_REQUIRE(h.info == 0);
      if (s.rank == n || h.x.norm() == 0.0) continue;  // row space is everything
      Eigen::MatrixXd aug(m + 1, n);
      aug.topRows(m) = s.A / s.A.norm();
      aug.row(m) = h.x.transpose() / h.x.norm();
      const Eigen::VectorXd sv = Eigen::JacobiSVD<Eigen::MatrixXd>(aug).singularValues();
      BOOST_TEST(sv(s.rank) <= 30.0 * std::max(m, n) * kEps);
    }
  }
}

BOOST_AUTO_TEST_CASE(solution_from_start_vector_is_the_nearest_solution) {
  // From x1, the result must be x1 + pinv(A) (b - A x1): the solution nearest to x1. Oracle:
  // dgelsd on the shifted right-hand side; threshold as for the minimum-norm solution, relative
  // to max(||x||, ||x1||) because x1 itself is carried along.
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (Kernel k : kKernels) {
    for (const TestSystem& s : well_scaled_systems(14)) {
      const int m = static_cast<int>(s.A.rows()), n = static_cast<int>(s.A.cols());
      Eigen::VectorXd x1(n);
      for (int j = 0; j < n; ++j) x1(j) = 10.0 * u(rng);
      const HuangResult h = huang_solve(s.A, s.b, x1, options_for(k));
      const GelsdResult g = gelsd(s.A, s.b - s.A * x1, 1e-10);
      BOOST_TEST_REQUIRE(h.info == 0);
      const Eigen::VectorXd expected = x1 + g.x;
      const double bound = 10.0 * std::max(m, n) * kEps * kappa(g);
      BOOST_TEST((h.x - expected).norm() / std::max(expected.norm(), x1.norm()) <= bound);
    }
  }
}

BOOST_AUTO_TEST_CASE(projector_is_symmetric_idempotent_and_annihilates_rows) {
  // H is built symmetric exactly (same product subtracted on both sides). Idempotency and
  // ||A H|| / ||A|| are rounding-level for the modified algorithm: 10 * max(m, n) * eps.
  // trace(H) = n - rank (a projector's trace is its rank), and H equals I - V_r V_r' from
  // Eigen's SVD to eps * kappa (a subspace perturbation bound).
  for (Kernel k : kKernels) {
    for (const TestSystem& s : well_scaled_systems(15)) {
      const int m = static_cast<int>(s.A.rows()), n = static_cast<int>(s.A.cols());
      const HuangResult h = huang_solve(s.A, s.b, options_for(k));
      BOOST_TEST_REQUIRE(h.info == 0);
      const double tol = 10.0 * std::max(m, n) * kEps;
      BOOST_TEST((h.H - h.H.transpose()).norm() == 0.0);
      BOOST_TEST((h.H * h.H - h.H).norm() <= tol * std::sqrt(double(n)));
      BOOST_TEST((s.A * h.H).norm() <= tol * s.A.norm());
      BOOST_TEST(std::abs(h.H.trace() - (n - s.rank)) <= tol * n);
      Eigen::JacobiSVD<Eigen::MatrixXd> svd(s.A, Eigen::ComputeFullV);
      const Eigen::MatrixXd Vr = svd.matrixV().leftCols(s.rank);
      const Eigen::MatrixXd P = Eigen::MatrixXd::Identity(n, n) - Vr * Vr.transpose();
      const Eigen::VectorXd sv = svd.singularValues();
      const double kap = s.rank > 0 ? sv(0) / sv(s.rank - 1) : 1.0;
      BOOST_TEST((h.H - P).norm() <= tol * kap * std::sqrt(double(n)));
    }
  }
}

BOOST_AUTO_TEST_CASE(null_basis_is_orthonormal_full_rank_and_annihilated_by_A) {
  // A D = 0 to rounding (10 * max(m, n) * eps * ||A||), D' D = I to rounding (so D has full
  // column rank n - rank), and D D' = H (D spans exactly the range of the projector).
  for (Kernel k : kKernels) {
    for (const TestSystem& s : well_scaled_systems(16)) {
      const int m = static_cast<int>(s.A.rows()), n = static_cast<int>(s.A.cols());
      const HuangResult h = huang_solve(s.A, s.b, options_for(k));
      BOOST_TEST_REQUIRE(h.info == 0);
      const NullBasisResult nb = huang_null_basis(h.H, h.rank, options_for(k));
      BOOST_TEST_REQUIRE(nb.info == 0);
      const double tol = 10.0 * std::max(m, n) * kEps;
      BOOST_TEST(nb.D.rows() == n);
      BOOST_TEST(nb.D.cols() == n - s.rank);
      BOOST_TEST((s.A * nb.D).norm() <= tol * s.A.norm() * std::sqrt(double(n)));
      const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(nb.D.cols(), nb.D.cols());
      BOOST_TEST((nb.D.transpose() * nb.D - I).norm() <= tol * n);
      BOOST_TEST((nb.D * nb.D.transpose() - h.H).norm() <= tol * n);
    }
  }
}

BOOST_AUTO_TEST_CASE(null_basis_follows_the_documented_pivoting_rule) {
  // Hand-computed: A = [1 1 0] gives H = [.5 -.5 0; -.5 .5 0; 0 0 1]. Column norms .707, .707,
  // 1: the first within a factor 2 of the largest is column 1, so d1 = (1, -1, 0)/sqrt(2);
  // projecting it out zeroes column 2 and leaves e3, so d2 = e3.
  Eigen::MatrixXd A(1, 3);
  A << 1.0, 1.0, 0.0;
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(1);
  Eigen::MatrixXd expected(3, 2);
  const double r = 1.0 / std::sqrt(2.0);
  expected << r, 0.0, -r, 0.0, 0.0, 1.0;
  // A = [0 0 1; 0 1 0] leaves only e1: D = e1 (sign fixed: the pivot column has H(j,j) > 0).
  Eigen::MatrixXd A2(2, 3);
  A2 << 0.0, 0.0, 1.0, 0.0, 1.0, 0.0;
  for (Kernel k : kKernels) {
    const HuangResult h = huang_solve(A, b, options_for(k));
    const NullBasisResult nb = huang_null_basis(h.H, h.rank, options_for(k));
    BOOST_TEST_REQUIRE(nb.info == 0);
    BOOST_TEST((nb.D - expected).norm() <= 4 * kEps);  // a few roundings of O(1) entries
    const HuangResult h2 = huang_solve(A2, Eigen::VectorXd::Ones(2), options_for(k));
    const NullBasisResult nb2 = huang_null_basis(h2.H, h2.rank, options_for(k));
    BOOST_TEST_REQUIRE(nb2.info == 0);
    BOOST_TEST((nb2.D - Eigen::Vector3d(1.0, 0.0, 0.0)).norm() == 0.0);  // exact arithmetic
  }
}

BOOST_AUTO_TEST_CASE(null_basis_rejects_a_matrix_that_is_not_a_projector_of_that_rank) {
  // H = 0 has no range: asking for a 1-column basis must fail at column 1; H = e1 e1' has a
  // 1-dimensional range: asking for 2 columns fails at column 2.
  for (Kernel k : kKernels) {
    BOOST_TEST(huang_null_basis(Eigen::MatrixXd::Zero(3, 3), 2, options_for(k)).info == 1);
    Eigen::MatrixXd H = Eigen::MatrixXd::Zero(3, 3);
    H(0, 0) = 1.0;
    BOOST_TEST(huang_null_basis(H, 1, options_for(k)).info == 2);
    BOOST_TEST(huang_null_basis(H, 2, options_for(k)).info == 0);
  }
}

BOOST_AUTO_TEST_CASE(dependent_rows_are_flagged_exactly_where_constructed) {
  // Random patterns, every shape, rows scaled over 16 decades and columns over 4: the
  // dependence test is relative to ||a_i||, so row scaling must not matter.
  std::mt19937 rng(17);
  int flagged = 0;
  for (Kernel k : kKernels) {
    for (int n : {2, 3, 6, 12}) {
      for (int m : {n / 2 + 1, n, 2 * n + 3}) {
        for (int r = 1; r <= std::min(m, n); ++r) {
          for (double row_dec : {0.0, 8.0}) {
            for (double col_dec : {0.0, 2.0}) {
              const TestSystem s =
                  make_system(rng, n, random_pattern(rng, m, r), row_dec, col_dec);
              const HuangResult h = huang_solve(s.A, s.b, options_for(k));
              BOOST_TEST_REQUIRE(h.info == 0);
              BOOST_TEST(h.row_dependent == s.dependent);
              BOOST_TEST(h.rank == r);
              for (bool d : s.dependent) flagged += d ? 1 : 0;
            }
          }
        }
      }
    }
  }
  BOOST_TEST_MESSAGE("dependent rows constructed and checked: " << flagged);
  BOOST_TEST(flagged > 500);  // the sweep exercises the dependent branch a lot
}

BOOST_AUTO_TEST_CASE(inconsistent_system_reports_first_inconsistent_row) {
  // Perturbing b at a dependent row breaks consistency at that row and no earlier one (the
  // dependent rows are combinations of independent rows only). With two perturbed rows, INFO
  // names the first. The returned x still solves the rows before INFO.
  std::mt19937 rng(19);
  int cases = 0;
  for (Kernel k : kKernels) {
    for (int rep = 0; rep < 40; ++rep) {
      const int n = 3 + rep % 5, m = n + 2 + rep % 3;
      const TestSystem s = make_system(rng, n, random_pattern(rng, m, n - 1), 4.0, 0.0);
      std::vector<int> dep;
      for (int i = 0; i < m; ++i)
        if (s.dependent[static_cast<std::size_t>(i)]) dep.push_back(i);
      BOOST_TEST_REQUIRE(dep.size() >= 2u);
      const int first = dep[static_cast<std::size_t>(rep) % (dep.size() - 1)];
      const int second = dep.back();
      Eigen::VectorXd b = s.b;
      // A relative change of 1e-6 in b_i is far above the default tolerance (~1e-13).
      b(first) += 1e-6 * (std::abs(b(first)) + s.A.row(first).norm());
      b(second) *= -2.0;
      b(second) += s.A.row(second).norm();
      const HuangResult h = huang_solve(s.A, b, options_for(k));
      BOOST_TEST(h.info == first + 1);
      const Eigen::VectorXd res = (s.A * h.x - b).head(first);
      BOOST_TEST(res.norm() <= 1e-12 * b.head(first).norm());
      ++cases;
    }
    // A zero row with b_i != 0 is inconsistent; with b_i = 0 it is dependent and harmless.
    Eigen::MatrixXd Z(2, 3);
    Z << 1.0, 2.0, 3.0, 0.0, 0.0, 0.0;
    BOOST_TEST(huang_solve(Z, Eigen::Vector2d(1.0, 1e-300), options_for(k)).info == 2);
    const HuangResult ok = huang_solve(Z, Eigen::Vector2d(1.0, 0.0), options_for(k));
    BOOST_TEST(ok.info == 0);
    BOOST_TEST(ok.row_dependent == std::vector<bool>({false, true}));
  }
  BOOST_TEST(cases == 80);
}

BOOST_AUTO_TEST_CASE(degenerate_shapes_behave_as_documented) {
  // m = 0: nothing to solve, x = x1, H = I. n = 0: every row is 0 = b_i.
  for (Kernel k : kKernels) {
    const Eigen::VectorXd x1 = Eigen::Vector3d(1.0, -2.0, 3.0);
    const HuangResult e = huang_solve(Eigen::MatrixXd(0, 3), Eigen::VectorXd(0), x1, options_for(k));
    BOOST_TEST(e.info == 0);
    BOOST_TEST(e.rank == 0);
    BOOST_TEST((e.x - x1).norm() == 0.0);
    BOOST_TEST((e.H - Eigen::MatrixXd::Identity(3, 3)).norm() == 0.0);
    BOOST_TEST(huang_solve(Eigen::MatrixXd(2, 0), Eigen::Vector2d(0.0, 0.0), options_for(k)).info == 0);
    BOOST_TEST(huang_solve(Eigen::MatrixXd(2, 0), Eigen::Vector2d(0.0, 1.0), options_for(k)).info == 2);
    // Full rank square: H = 0 exactly and the null basis is empty.
    Eigen::MatrixXd A(2, 2);
    A << 2.0, 1.0, 1.0, 3.0;
    const HuangResult f = huang_solve(A, Eigen::Vector2d(1.0, 2.0), options_for(k));
    BOOST_TEST(f.rank == 2);
    BOOST_TEST(f.H.norm() == 0.0);
    const NullBasisResult nb = huang_null_basis(f.H, f.rank, options_for(k));
    BOOST_TEST(nb.info == 0);
    BOOST_TEST(nb.D.cols() == 0);
  }
}
