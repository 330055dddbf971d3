// Issue 21: redundant but consistent constraints. R (and q̈) are unique whatever the rank of g:
// from g q̈ = −γ and M q̈ = f + gᵀ λ, (g M⁻¹ gᵀ) λ = −G0, and two solutions λ, λ' differ by δ with
// |L⁻¹ gᵀ δ|² = δᵀ g M⁻¹ gᵀ δ = 0, so gᵀ δ = 0 and R = gᵀ λ is the same. These tests check it
// numerically against the full-rank formulations of the same model without the redundant row
// (the existing, independently tested solves), at random states, in several row orders; and
// that the simulation of a redundant set is that of the independent set.
#define BOOST_TEST_MODULE mech_redundant
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cmath>
#include <random>

#include "mech/models/registry.hpp"
#include "mech/simulation.hpp"

using namespace pcsim;
using namespace pcsim::mech;

namespace {

double rel(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return (a - b).norm() / std::max(1e-300, std::max(a.norm(), b.norm()));
}

Eigen::VectorXd slider_crank_q() {
  const ModelParameters p = default_parameters("slider_crank");
  const double l1 = p.at("l1"), l2 = p.at("l2");
  Eigen::VectorXd q(5);
  q << 0.0, l1 + 0.5 * l2, 0.0, 0.0, l1 + l2;
  return q;
}

}  // namespace

// The slider-crank with B_y_copy = 2 B_y (rows and γ twice B_y's: consistent at every state at
// the acceleration level, so random states are consistent for the reaction solve). Tolerance
// 1e-10 relative, as the issue asks: both are backward-stable solves of a problem whose
// independent part is well conditioned (the full-rank test in test_reactions agrees to 1e-10).
BOOST_AUTO_TEST_CASE(r_of_the_redundant_set_equals_r_without_the_redundant_row_at_random_states) {
  const auto model = create_model("slider_crank");
  const std::vector<std::string> base = {"A_x", "A_y", "B_x", "B_y"};
  const std::vector<std::vector<std::string>> redundant = {
      {"A_x", "A_y", "B_x", "B_y", "B_y_copy"},
      {"B_y_copy", "A_x", "A_y", "B_x", "B_y"},
      {"A_y", "B_y", "B_y_copy", "B_x", "A_x"},
  };
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (Kernel kernel : {Kernel::fortran, Kernel::cpp}) {
    for (int trial = 0; trial < 20; ++trial) {
      Eigen::VectorXd q(5), qd(5);
      for (int i = 0; i < 5; ++i) {
        q[i] = 1.5 * u(rng);
        qd[i] = 2.0 * u(rng);
      }
      const double t = u(rng);
      const ReactionResult ref =
          reactions(*model, base, t, q, qd, ReactionMethod::compatibility_structured, kernel);
      BOOST_REQUIRE((ref.issue == ModelIssue::none));
      for (const auto& set : redundant) {
        for (ReactionMethod m : {ReactionMethod::compatibility_structured, ReactionMethod::compatibility}) {
          const ReactionResult r = reactions(*model, set, t, q, qd, m, kernel);
          BOOST_TEST_CONTEXT("trial " << trial << " first row " << set[0] << " method "
                                      << static_cast<int>(m)) {
            BOOST_REQUIRE_MESSAGE((r.issue == ModelIssue::none), r.message);
            BOOST_TEST(rel(r.R, ref.R) < 1e-10);
            BOOST_TEST(rel(r.qdd, ref.qdd) < 1e-10);
            // λ is a split of R (R = gᵀ λ): the minimum-norm one over the rows scaled to unit
            // length (so a row's units do not decide its share). B_y and B_y_copy (row 2 B_y)
            // are the same unit row, which carries B_y's multiplier μ in equal shares:
            // λ_By + 2 λ_copy = μ and λ_By = 2 λ_copy.
            const auto idx = [&](const std::string& n) {
              return static_cast<int>(std::find(set.begin(), set.end(), n) - set.begin());
            };
            const double lb = r.lambda[idx("B_y")], lc = r.lambda[idx("B_y_copy")];
            const double mu = ref.lambda[3];
            BOOST_TEST(std::abs(lb + 2 * lc - mu) <= 1e-9 * (1.0 + std::abs(mu)));
            BOOST_TEST(std::abs(lb - 2 * lc) <= 1e-9 * (1.0 + std::abs(mu)));
            BOOST_TEST(std::abs(r.lambda[idx("A_x")] - ref.lambda[0]) <= 1e-9 * (1.0 + ref.lambda.norm()));
          }
        }
      }
    }
  }
}

// A set with a redundant row is no longer refused: it runs, and its motion is that of the
// independent set (the same q̈ at every state, so the same trajectory to the integration's
// accuracy: 1e-7 here at rtol 1e-10).
BOOST_AUTO_TEST_CASE(a_redundant_set_runs_and_moves_as_the_independent_set) {
  const auto model = create_model("slider_crank");
  SimulationOptions o;
  o.t_end = 0.5;
  o.rtol = o.atol = 1e-10;
  o.active_constraints = {"A_x", "A_y", "B_x", "B_y"};
  const SimulationResult a = simulate(*model, slider_crank_q(), Eigen::VectorXd::Zero(5), o);
  o.active_constraints = {"A_x", "A_y", "B_x", "B_y", "B_y_copy"};
  const SimulationResult b = simulate(*model, slider_crank_q(), Eigen::VectorXd::Zero(5), o);
  BOOST_REQUIRE((a.status == SimulationStatus::success));
  BOOST_REQUIRE_MESSAGE((b.status == SimulationStatus::success), b.message);
  BOOST_TEST(std::abs(a.q_end[0]) > 0.01);  // the crank moved
  BOOST_TEST((a.q_end - b.q_end).lpNorm<Eigen::Infinity>() < 1e-7);
  BOOST_TEST((a.qd_end - b.qd_end).lpNorm<Eigen::Infinity>() < 1e-7);
  // check_model says which row is redundant, without refusing it.
  const CheckResult c = check_model(*model, o.active_constraints, 0.0, slider_crank_q(),
                                    Eigen::VectorXd::Zero(5));
  BOOST_TEST((c.issue == ModelIssue::none));
  BOOST_TEST(c.rank == 4);
  BOOST_TEST((c.redundant == std::vector<int>{4}));
  BOOST_TEST(c.message.find("'B_y_copy' is redundant") != std::string::npos, c.message);
}

// Contradictory rows are still refused by name: B_y_shifted = B_y − 0.1.
BOOST_AUTO_TEST_CASE(contradictory_rows_are_still_refused_by_name) {
  const auto model = create_model("slider_crank");
  SimulationOptions o;
  o.active_constraints = {"A_x", "A_y", "B_x", "B_y", "B_y_shifted"};
  const SimulationResult r = simulate(*model, slider_crank_q(), Eigen::VectorXd::Zero(5), o);
  BOOST_TEST((r.status == SimulationStatus::invalid_model));
  BOOST_TEST((r.issue == ModelIssue::inconsistent_constraints));
  BOOST_TEST(r.message.find("'B_y_shifted'") != std::string::npos, r.message);
}
