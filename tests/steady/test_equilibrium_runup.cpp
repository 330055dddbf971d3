// The physical start: the static equilibrium (mech/equilibrium) against closed forms (a mass
// on a spring held on an inclined line: position and the normal force; a forced oscillator's
// averaged load; the sieve's holding force m2 g sin(theta) on its tilted deck), and the
// exciter run-up (models/sieve_1995_runup.toml): after the run-up it is the sieve of
// models/sieve_1995.toml at the time t − t_runup/2, and with it the whole-run contact verdict
// of e = 0.04 m, which the start at full speed violates at t = 0, holds.
#define BOOST_TEST_MODULE steady_equilibrium_runup
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <random>

#include "mech/equilibrium.hpp"
#include "modelfile/model_file.hpp"
#if PCSIM_WITH_SIEVE
#include "sieve/source.hpp"
#endif
#include "sim/case.hpp"
#include "sim/file_source.hpp"
#include "sim/run.hpp"

using namespace pcsim;

BOOST_AUTO_TEST_CASE(equilibrium_of_a_spring_mass_on_an_inclined_line_equals_the_closed_form) {
  // A mass m at (x, y), gravity −g along y, a spring k from the origin, held on the line
  // y = x tan(a): along the line ξ, V = ½ k ξ² + m g ξ sin(a), so ξ = −m g sin(a)/k, and the
  // line pushes with the normal force m g cos(a).
  const auto d = modelfile::load_model_text(R"toml([model]
name = "incline"
coordinates = ["x", "y"]
[model.parameters]
m = 2.0
k = 50.0
g = 9.81
a = 0.3
[model.energy]
kinetic = "0.5*m*(x_d^2 + y_d^2)"
potential = "0.5*k*(x^2 + y^2) + m*g*y"
[[model.constraint]]
name = "line"
holonomic = "y*cos(a) - x*sin(a)"
)toml", "incline.toml");
  const auto model = d->instantiate({});
  const double m = 2, k = 50, g = 9.81, a = 0.3;
  const mech::EquilibriumResult e = mech::static_equilibrium(*model, {0}, Eigen::Vector2d(0.3, -0.2));
  BOOST_REQUIRE_MESSAGE(e.issue == mech::ModelIssue::none, e.message);
  const double xi = -m * g * std::sin(a) / k;
  BOOST_TEST(std::abs(e.q[0] - xi * std::cos(a)) < 1e-13);
  BOOST_TEST(std::abs(e.q[1] - xi * std::sin(a)) < 1e-13);
  // R = gᵀ λ with g = (−sin a, cos a): the normal force's magnitude is |λ|.
  BOOST_TEST(std::abs(std::abs(e.lambda[0]) - m * g * std::cos(a)) < 1e-12);
}

BOOST_AUTO_TEST_CASE(equilibrium_of_an_excited_system_balances_the_period_mean_of_the_forces) {
  // x'' + k x = F0 + F1 cos(ωt) + F2 sin(2ωt): the mean load is F0, the equilibrium F0/k.
  const auto d = modelfile::load_model_text(R"toml([model]
name = "excited"
coordinates = ["x"]
period = "2*pi/omega"
[model.parameters]
k = 4.0
F0 = 1.5
F1 = 30.0
omega = 7.0
[model.energy]
kinetic = "0.5*x_d^2"
potential = "0.5*k*x^2"
[model.forces]
x = "F0 + F1*cos(omega*t) + F1*sin(2*omega*t)"
)toml", "excited.toml");
  mech::EquilibriumOptions o;
  o.period = 2 * 3.14159265358979323846 / 7.0;
  const mech::EquilibriumResult e = mech::static_equilibrium(*d->instantiate({}), {}, Eigen::VectorXd::Zero(1), o);
  BOOST_REQUIRE(e.issue == mech::ModelIssue::none);
  BOOST_TEST(std::abs(e.q[0] - 1.5 / 4.0) < 1e-14);
  // At t0 alone (no period) the load would be F0 + F1: the averaging matters.
  const mech::EquilibriumResult e0 = mech::static_equilibrium(*d->instantiate({}), {}, Eigen::VectorXd::Zero(1));
  BOOST_TEST(std::abs(e0.q[0] - 31.5 / 4.0) < 1e-13);
}

#if PCSIM_WITH_SIEVE  // the sieve's (its built-in model and verdicts)
BOOST_AUTO_TEST_CASE(sieve_equilibrium_holds_the_roller_with_its_weight_along_the_tilted_deck) {
  // At rest on the deck tilted by theta, the roller's weight pulls it along the deck with
  // m2 g sin(theta); rolling exerts no static force (Q_phi = 0), so the holding force on s is
  // exactly m2 g sin(theta_eq), and every other coordinate is balanced.
  sieve::register_sieve();
  const sim::Case c = sim::load_case(std::string(PCSIM_SOURCE_DIR) + "/cases/sieve_1995.toml",
                                     {{"initial.from", "equilibrium"}});
  const sim::Setup& s = c.setup;
  const auto model = c.model->instantiate(s.parameters, s.q0, 0.0, c.table, "");
  const mech::EquilibriumResult e = sim::case_equilibrium(c, s, *model);
  BOOST_TEST(e.q[3] == 0.4);   // s held
  BOOST_TEST(e.q[4] == 0.15);  // u = u0
  const double m2 = 0.5, g = 9.81;
  BOOST_TEST(std::abs(e.holding_force[0] - m2 * g * std::sin(e.q[2])) < 1e-15);
  BOOST_TEST(e.residual < 1e-9);
  BOOST_TEST_MESSAGE("sieve at rest: theta = " << e.q[2] << " rad, x = " << e.q[0] << " m, y = " << e.q[1]
                                               << " m, holding force " << e.holding_force[0] << " N");
}
#endif

BOOST_AUTO_TEST_CASE(runup_model_equals_the_sieve_shifted_by_half_the_runup_after_it) {
  const auto plain = sim::embedded_description("sieve_1995");
  const auto runup = sim::embedded_description("sieve_1995_runup");
  const double tr = 0.7;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 20; ++trial) {
    Eigen::VectorXd q(6), qd(6);
    q << 1e-3 * u(rng), 1e-3 * u(rng), 0.01 * u(rng), 0.3 * u(rng), 0.15, 2 * u(rng);
    for (int i = 0; i < 6; ++i) qd[i] = u(rng);
    const double t = tr + 0.5 * (1 + u(rng));
    const auto a = runup->instantiate({{"t_runup", tr}}, q, 0.0);
    const auto b = plain->instantiate({}, q, 0.0);
    Eigen::MatrixXd Ma(6, 6), Mb(6, 6);
    Eigen::VectorXd ha(6), hb(6), Qa(6), Qb(6);
    a->kinetic_terms(t, q, qd, Ma, ha);
    b->kinetic_terms(t - tr / 2, q, qd, Mb, hb);
    a->forces(t, q, qd, Qa);
    b->forces(t - tr / 2, q, qd, Qb);
    BOOST_TEST((Ma - Mb).cwiseAbs().maxCoeff() <= 1e-12 * Mb.cwiseAbs().maxCoeff());
    BOOST_TEST((ha - hb).cwiseAbs().maxCoeff() <= 1e-10 * (1 + hb.cwiseAbs().maxCoeff()));
    BOOST_TEST((Qa - Qb).cwiseAbs().maxCoeff() <= 1e-10 * (1 + Qb.cwiseAbs().maxCoeff()));
  }
  // At t = 0 the exciter stands still: no centrifugal load m0 e omega^2 in h, only the force
  // of its angular acceleration omega/t_runup, m0 e omega/t_runup (and J0 omega/t_runup on theta).
  Eigen::VectorXd q(6), qd = Eigen::VectorXd::Zero(6);
  q << 0, 0, 0, 0.4, 0.15, 0;
  const auto a = runup->instantiate({{"t_runup", tr}}, q, 0.0);
  Eigen::MatrixXd M(6, 6);
  Eigen::VectorXd h(6);
  a->kinetic_terms(0.0, q, qd, M, h);
  const double m0 = 1.27, e = 0.01, omega = 280;
  BOOST_TEST(std::abs(h[0]) + std::abs(h[1]) <= 1.01 * std::sqrt(2.0) * m0 * e * omega / tr);
  BOOST_TEST(std::abs(h[0]) + std::abs(h[1]) < 0.01 * m0 * e * omega * omega);
}

#if PCSIM_WITH_SIEVE  // the sieve's (its built-in model and verdicts)
BOOST_AUTO_TEST_CASE(runup_keeps_the_contact_that_the_start_at_full_speed_loses_at_t0) {
  // e = 0.04 m: switched on at full speed at t = 0, the exciter's centrifugal force
  // m0 e omega^2 = 3983 N pulls the desk (at rest, its dampers idle) down at ~g, and R_u <= 0 at
  // once; the static equilibrium start does not change that. Run up over 2 s, the contact holds
  // over the whole run. 4 s runs keep the test quick (the window's summary is not compared).
  sieve::register_sieve();
  auto run = [](std::vector<sim::Override> o) {
    o.push_back({"parameters.e", "0.04"});
    o.push_back({"solver.t_end", "4"});
    return sim::to_json(sim::run_case(sim::load_case(std::string(PCSIM_SOURCE_DIR) + "/cases/sieve_1995.toml", o)));
  };
  const nlohmann::json full = run({});
  BOOST_TEST(!full["contact_kept"].get<bool>());
  BOOST_TEST(full["first_violation"]["contact"].get<double>() == 0.0);
  const nlohmann::json eq = run({{"initial.from", "equilibrium"}});
  BOOST_TEST(!eq["contact_kept"].get<bool>());
  const nlohmann::json ramp = run({{"initial.from", "equilibrium"}, {"parameters.t_runup", "2"}});
  BOOST_TEST(ramp["contact_kept"].get<bool>());
  BOOST_TEST(ramp["rolling_kept"].get<bool>());
  BOOST_TEST_MESSAGE("e = 0.04: full speed at t = 0 loses contact at t = 0; run-up over 2 s: min R_u over the window "
                     << ramp["R_u_min"].get<double>() << " N");
}
#endif
