// pcsim modes on linear and linearizable systems against oracles that are not pcsim's
// first-order form: 2-DOF spring-mass chains (undamped, damped, free-free) against the roots of
// det(lambda^2 M + lambda C + K) = 0 (companion matrix of the quartic), and a pendulum written in
// Cartesian coordinates with a rod constraint, its pivot far from the origin, against sqrt(g/L).
#define BOOST_TEST_MODULE modes_linear
#include <boost/test/unit_test.hpp>

#include <cmath>

#include "../support/cli_util.hpp"
#include "common/error.hpp"
#include "modes/modes_case.hpp"
#include "modes_test_util.hpp"
#include "sim/case.hpp"

using namespace pcsim;
using namespace pcsim::modes;
using namespace pcsim::modes::testing;

namespace {

std::vector<std::complex<double>> eigenvalues(const nlohmann::json& j) {
  std::vector<std::complex<double>> out;
  for (const auto& e : j["eigenvalues"]) out.emplace_back(e["re"].get<double>(), e["im"].get<double>());
  return out;
}

nlohmann::json chain_modes(const Chain& c, Linearization* L = nullptr) {
  const sim::Case k = sim::load_case_text(chain_case(c), "chain.toml");
  return case_modes(k, {}, L);
}

double largest(const std::vector<std::complex<double>>& v) {
  double m = 0;
  for (const auto& x : v) m = std::max(m, std::abs(x));
  return m;
}

}  // namespace

// Tolerance 1e-11 of the largest |lambda|: both sides are eigenvalue computations of
// well-conditioned 4x4 matrices (rounding ~1e-15 relative); a wrong K, C or M entry moves the
// roots by far more.
BOOST_AUTO_TEST_CASE(undamped_chain_matches_its_characteristic_polynomial) {
  Chain c;
  c.k3 = 30;
  Linearization L;
  const nlohmann::json j = chain_modes(c, &L);
  const auto want = chain_roots(c);
  BOOST_TEST(set_distance(eigenvalues(j), want) <= 1e-11 * largest(want));
  BOOST_TEST(j["tangent_space"]["dimension"].get<int>() == 4);
  BOOST_TEST(j["modes"].size() == 2u);
  for (const auto& m : j["modes"]) {
    BOOST_TEST(m["kind"].get<std::string>() == "oscillatory");
    BOOST_TEST(std::abs(m["damping_ratio"].get<double>()) <= 1e-12);
  }
  // Undamped: the undamped frequencies are the eigenvalues' imaginary parts.
  const auto& u = j["undamped"]["frequencies"];
  BOOST_TEST(std::abs(u[0]["omega_rad_s"].get<double>() - j["modes"][0]["im"].get<double>()) <= 1e-11 * largest(want));
  BOOST_TEST(std::abs(u[1]["omega_rad_s"].get<double>() - j["modes"][1]["im"].get<double>()) <= 1e-11 * largest(want));
  BOOST_TEST(j["stable"].get<bool>());
}

BOOST_AUTO_TEST_CASE(damped_chain_matches_its_characteristic_polynomial) {
  Chain c;
  c.k3 = 30;
  c.c1 = 0.5;
  c.c2 = 0.3;
  c.c3 = 0.1;
  const nlohmann::json j = chain_modes(c);
  const auto want = chain_roots(c);
  BOOST_TEST(set_distance(eigenvalues(j), want) <= 1e-11 * largest(want));
  // zeta = -Re/|lambda| of each root, and the undamped frequencies from K and M alone:
  // det(K - w^2 M) = 0, w^2 = ((k11 m2 + k22 m1) -+ sqrt(...)) / (2 m1 m2).
  for (const auto& m : j["modes"]) {
    const std::complex<double> l(m["re"].get<double>(), m["im"].get<double>());
    BOOST_TEST(std::abs(m["damping_ratio"].get<double>() + l.real() / std::abs(l)) <= 1e-14);
    BOOST_TEST(m["damping_ratio"].get<double>() > 0);
  }
  const double k11 = c.k1 + c.k2, k22 = c.k2 + c.k3, k12 = -c.k2;
  const double b = k11 * c.m2 + k22 * c.m1, d = std::sqrt(b * b - 4 * c.m1 * c.m2 * (k11 * k22 - k12 * k12));
  const auto& u = j["undamped"]["frequencies"];
  BOOST_TEST(std::abs(u[0]["omega2"].get<double>() - (b - d) / (2 * c.m1 * c.m2)) <= 1e-11 * (b + d) / (2 * c.m1 * c.m2));
  BOOST_TEST(std::abs(u[1]["omega2"].get<double>() - (b + d) / (2 * c.m1 * c.m2)) <= 1e-11 * (b + d) / (2 * c.m1 * c.m2));
}

// The free-free chain (no wall springs): a rigid-body mode at lambda = 0 and one oscillation at
// sqrt(k2 (1/m1 + 1/m2)), with the two masses moving against each other (shape -m1/m2).
BOOST_AUTO_TEST_CASE(free_free_chain_has_a_rigid_body_mode_labelled) {
  Chain c;
  c.k1 = 0;
  c.k3 = 0;
  const nlohmann::json j = chain_modes(c);
  int rigid = 0, osc = 0;
  for (const auto& m : j["modes"]) {
    if (m["kind"] == "rigid-body") ++rigid;
    if (m["kind"] == "oscillatory") {
      ++osc;
      BOOST_TEST(std::abs(m["im"].get<double>() - std::sqrt(c.k2 * (1 / c.m1 + 1 / c.m2))) <= 1e-12 * 10);
      BOOST_TEST(std::abs(m["shape"]["x2"]["re"].get<double>() * m["shape"]["x1"]["re"].get<double>() < 0));
      BOOST_TEST(m["dominant"][0].get<std::string>() == "x1");  // m1 < m2 moves more
    }
  }
  BOOST_TEST(rigid >= 1);
  BOOST_TEST(osc == 1);
  BOOST_TEST(j["zero_modes"].get<int>() >= 1);
}

// The Cartesian pendulum with its pivot at (1e3, -5e2): two coordinates, one rod constraint;
// the tangent space has dimension 2 and its oscillation is sqrt(g/L) to 1e-12 (the issue's).
BOOST_AUTO_TEST_CASE(cartesian_pendulum_far_from_the_origin_gives_sqrt_g_over_l) {
  const sim::Case c = sim::load_case("tests/modes/pendulum_far_case.toml");
  Linearization L;
  const nlohmann::json j = case_modes(c, {}, &L);
  const double want = std::sqrt(9.81 / 1.5);
  BOOST_TEST(j["tangent_space"]["dimension"].get<int>() == 2);
  BOOST_TEST(j["tangent_space"]["rank"].get<int>() == 2);
  BOOST_TEST(L.invariance <= 1e-14);
  BOOST_REQUIRE(j["modes"].size() == 1u);
  const auto& m = j["modes"][0];
  BOOST_TEST(std::abs(m["im"].get<double>() - want) <= 1e-12 * want);
  BOOST_TEST(std::abs(m["re"].get<double>()) <= 1e-12 * want);
  BOOST_TEST(std::abs(m["natural_frequency_hz"].get<double>() - want / (2 * M_PI)) <= 1e-12 * want);
  BOOST_TEST(std::abs(j["undamped"]["frequencies"][0]["omega_rad_s"].get<double>() - want) <= 1e-12 * want);
  // The mode swings the mass sideways (x), not along the rod (y).
  BOOST_TEST(m["dominant"].size() == 1u);
  BOOST_TEST(m["dominant"][0].get<std::string>() == "x");
}

// An initial state that is not at rest: off the hanging position (on the circle, so the rod
// holds, but gravity has a tangential part): refused with the residual and the moving coordinates.
BOOST_AUTO_TEST_CASE(a_state_that_is_not_at_rest_is_refused_with_residual_and_coordinates) {
  const double a = 0.1, L = 1.5;
  sim::Case c = sim::load_case("tests/modes/pendulum_far_case.toml",
                               {{"initial.x", format_number(1000.0 + L * std::sin(a))},
                                {"initial.y", format_number(-500.0 - L * std::cos(a))}});
  try {
    case_modes(c, {});
    BOOST_FAIL("expected InputError");
  } catch (const InputError& e) {
    const std::string w = e.what();
    BOOST_TEST_MESSAGE(w);
    BOOST_TEST(pcsim_test::has(w, "not a rest state"));
    BOOST_TEST(pcsim_test::has(w, "residual"));
    BOOST_TEST(pcsim_test::has(w, "accelerating: x"));
  }
  // A velocity is not rest either.
  c = sim::load_case("tests/modes/pendulum_far_case.toml", {{"initial.x_d", "0.2"}});
  BOOST_CHECK_EXCEPTION(case_modes(c, {}), InputError,
                        [](const InputError& e) { return pcsim_test::has(e.what(), "q_d = 0, but x"); });
}

// A coordinate without inertia that the constraints leave free: the mass matrix is singular
// on the tangent space: exit 3 (NumericalError) with the reason.
BOOST_AUTO_TEST_CASE(a_singular_mass_matrix_is_a_numerical_error) {
  const std::string text =
      "[model]\nname = \"massless\"\ncoordinates = [\"x\", \"z\"]\n[model.parameters]\nk = 1.0\n"
      "[model.energy]\nkinetic = \"0.5*x_d^2\"\npotential = \"0.5*k*x^2 + 0.5*k*z^2\"\n";
  const sim::Case c = sim::load_case_text(text, "massless.toml");
  BOOST_CHECK_THROW(case_modes(c, {}), NumericalError);
}
