// The Siconos LCP plugin against an oracle of its own: brute-force enumeration of the 2^n
// complementary bases with Eigen's LU (independent of Siconos and of its BLAS). Both Siconos
// solvers (lexicographic Lemke, enumeration) must return the unique solution of P-matrix LCPs,
// a complementary feasible point of a Stewart-Trinkle friction LCP, and report an infeasible
// LCP instead of inventing a solution. The plugin is loaded only by the first solve.
#define BOOST_TEST_MODULE lcp_siconos
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <random>

#include "lcp/lcp.hpp"

using namespace pcsim::lcp;

namespace {

// All solutions by enumeration: for each subset S (z_i > 0 allowed for i in S, w_i = 0 there),
// solve M_SS z_S = -q_S and keep it if z_S >= 0 and w = M z + q >= 0.
std::vector<Eigen::VectorXd> brute_force(const Eigen::MatrixXd& M, const Eigen::VectorXd& q) {
  const int n = static_cast<int>(q.size());
  std::vector<Eigen::VectorXd> out;
  for (int mask = 0; mask < (1 << n); ++mask) {
    std::vector<int> S;
    for (int i = 0; i < n; ++i)
      if (mask & (1 << i)) S.push_back(i);
    Eigen::VectorXd z = Eigen::VectorXd::Zero(n);
    if (!S.empty()) {
      const int k = static_cast<int>(S.size());
      Eigen::MatrixXd A(k, k);
      Eigen::VectorXd b(k);
      for (int a = 0; a < k; ++a) {
        b[a] = -q[S[a]];
        for (int c = 0; c < k; ++c) A(a, c) = M(S[a], S[c]);
      }
      const Eigen::FullPivLU<Eigen::MatrixXd> lu(A);
      if (!lu.isInvertible()) continue;
      const Eigen::VectorXd x = lu.solve(b);
      for (int a = 0; a < k; ++a) z[S[a]] = x[a];
    }
    const Eigen::VectorXd w = M * z + q;
    const double scale = 1.0 + q.cwiseAbs().maxCoeff();
    if (z.minCoeff() >= -1e-12 * scale && w.minCoeff() >= -1e-12 * scale) out.push_back(z);
  }
  return out;
}

double complementarity(const Eigen::VectorXd& z, const Eigen::VectorXd& w) {
  return std::max({-z.minCoeff(), -w.minCoeff(), z.cwiseProduct(w).cwiseAbs().maxCoeff(), 0.0});
}

}  // namespace

BOOST_AUTO_TEST_CASE(plugin_is_loaded_only_by_the_first_solve) {
  BOOST_TEST(!lcp_library_loaded());
  const LcpResult r = solve_lcp(Eigen::MatrixXd::Identity(1, 1), Eigen::VectorXd::Constant(1, -2.0));
  BOOST_TEST_MESSAGE("first solve: " << to_string(r.status) << " " << r.message);
  BOOST_REQUIRE(r.status == LcpStatus::solved);
  BOOST_TEST(lcp_library_loaded());
  BOOST_TEST(r.z[0] == 2.0);
  BOOST_TEST(r.w[0] == 0.0);
}

// P-matrices (symmetric positive definite, and positive definite plus a skew part) have a
// unique solution for every q. Tolerance: 1e-10 of the solution's scale; the problems are
// well conditioned (smallest eigenvalue of the symmetric part >= 0.1) and pivoting loses a few
// digits at most.
BOOST_AUTO_TEST_CASE(both_solvers_find_the_unique_solution_of_p_matrix_lcps) {
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int cases = 0;
  for (int n = 1; n <= 6; ++n) {
    for (int rep = 0; rep < 8; ++rep) {
      Eigen::MatrixXd B(n, n), K(n, n);
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) B(i, j) = u(rng), K(i, j) = u(rng);
      Eigen::MatrixXd M = B * B.transpose() + 0.1 * Eigen::MatrixXd::Identity(n, n);
      if (rep % 2) M += K - K.transpose();  // non-symmetric, still positive definite
      Eigen::VectorXd q(n);
      for (int i = 0; i < n; ++i) q[i] = 2.0 * u(rng);
      const auto all = brute_force(M, q);
      BOOST_REQUIRE_EQUAL(all.size(), 1u);  // the oracle itself: P-matrix, one solution
      for (LcpSolver s : {LcpSolver::lemke, LcpSolver::enumerative}) {
        LcpOptions o;
        o.solver = s;
        const LcpResult r = solve_lcp(M, q, o);
        BOOST_TEST_CONTEXT("n = " << n << " rep " << rep << " solver " << int(s)) {
          BOOST_REQUIRE(r.status == LcpStatus::solved);
          const double scale = 1.0 + all[0].cwiseAbs().maxCoeff();
          BOOST_TEST((r.z - all[0]).cwiseAbs().maxCoeff() < 1e-10 * scale);
          BOOST_TEST((r.w - (M * r.z + q)).cwiseAbs().maxCoeff() < 1e-10 * scale);
          BOOST_TEST(complementarity(r.z, r.w) < 1e-10 * scale);
        }
        ++cases;
      }
    }
  }
  BOOST_TEST_MESSAGE(cases << " LCPs agree with brute force");
}

// The planar Coulomb LCP of one frictional contact (Stewart-Trinkle form, as the switching
// simulation builds it): z = (lambda_n, beta+, beta-, zeta), with a Delassus matrix W of a block
// corner. Its matrix is not a P-matrix (zeros on the diagonal); Lemke's method still ends in a
// complementary feasible point, which brute force confirms is a solution.
BOOST_AUTO_TEST_CASE(lemke_solves_a_planar_coulomb_friction_lcp) {
  const double mu = 0.5;
  Eigen::Matrix2d W;
  W << 2.5, -1.2, -1.2, 1.9;
  for (double bn : {-3.0, -1.0, 0.5}) {
    for (double bt : {-4.0, 0.3, 2.0}) {
      Eigen::MatrixXd M = Eigen::MatrixXd::Zero(4, 4);
      Eigen::VectorXd q(4);
      // w_n = W_nn l + W_nt (b+ - b-) + bn;  w_b+ = zeta + v_t;  w_b- = zeta - v_t;
      // w_zeta = mu l - b+ - b-, with v_t = W_tn l + W_tt (b+ - b-) + bt.
      M(0, 0) = W(0, 0); M(0, 1) = W(0, 1); M(0, 2) = -W(0, 1);
      M(1, 0) = W(1, 0); M(1, 1) = W(1, 1); M(1, 2) = -W(1, 1); M(1, 3) = 1.0;
      M(2, 0) = -W(1, 0); M(2, 1) = -W(1, 1); M(2, 2) = W(1, 1); M(2, 3) = 1.0;
      M(3, 0) = mu; M(3, 1) = -1.0; M(3, 2) = -1.0;
      q << bn, bt, -bt, 0.0;
      const LcpResult r = solve_lcp(M, q);
      BOOST_TEST_CONTEXT("bn = " << bn << ", bt = " << bt) {
        BOOST_REQUIRE(r.status == LcpStatus::solved);
        BOOST_TEST(complementarity(r.z, M * r.z + q) < 1e-10);
        BOOST_TEST(!brute_force(M, q).empty());
      }
    }
  }
}

BOOST_AUTO_TEST_CASE(an_infeasible_lcp_is_reported_not_solved) {
  // w = -z - 1 >= 0 has no z >= 0.
  const LcpResult r = solve_lcp(Eigen::MatrixXd::Constant(1, 1, -1.0), Eigen::VectorXd::Constant(1, -1.0));
  BOOST_TEST(brute_force(Eigen::MatrixXd::Constant(1, 1, -1.0), Eigen::VectorXd::Constant(1, -1.0)).empty());
  BOOST_TEST((r.status == LcpStatus::no_solution), to_string(r.status) << ": " << r.message);
  BOOST_TEST(!r.message.empty());
}

BOOST_AUTO_TEST_CASE(bad_input_is_refused_with_a_reason) {
  BOOST_TEST((solve_lcp(Eigen::MatrixXd(2, 3), Eigen::VectorXd(2)).status == LcpStatus::bad_input));
  BOOST_TEST((solve_lcp(Eigen::MatrixXd(0, 0), Eigen::VectorXd(0)).status == LcpStatus::bad_input));
  Eigen::MatrixXd M = Eigen::MatrixXd::Identity(2, 2);
  M(0, 1) = std::nan("");
  const LcpResult r = solve_lcp(M, Eigen::VectorXd::Zero(2));
  BOOST_TEST((r.status == LcpStatus::bad_input));
  BOOST_TEST(r.message.find("finite") != std::string::npos);
}
