// The two sieve models (the paper's closed form and the geometric form) agree: M, Q and h at
// random states; their kinetic energies differ exactly by the exciter's m0 e² ω (ω/2 + θ̇),
// which changes no equation of motion; reactions obey the ideality criterion and the statics.
#define BOOST_TEST_MODULE sieve_model
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <random>

#include "mech/simulation.hpp"
#include "sieve/support/analytic_model.hpp"
#include "sieve/support/model.hpp"

using namespace pcsim;
using namespace pcsim::sieve;
using namespace pcsim::sim;

namespace {

struct RandomState {
  double t;
  Eigen::VectorXd q, qd;
};

// States well away from the design point in every coordinate, so that no term is hidden by a
// zero: θ up to ±0.6 rad, s, u of order 0.1..1 m, velocities of order 1, t anywhere in a period.
RandomState random_state(std::mt19937& rng) {
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  RandomState s;
  s.t = 0.05 * (1 + U(rng));
  s.q.resize(6);
  s.qd.resize(6);
  s.q << 0.01 * U(rng), 0.01 * U(rng), 0.6 * U(rng), 0.4 + 0.5 * U(rng), 0.15 + 0.1 * U(rng),
      3 * U(rng);
  for (int i = 0; i < 6; ++i) s.qd(i) = U(rng);
  return s;
}

// Parameters with every geometric offset non-zero (the defaults have several zeros, which would
// hide sign errors in the terms they multiply).
SieveSettings general_settings() {
  SieveSettings set;
  set.p.xc = 0.03;
  set.p.yc = -0.07;
  set.p.xb = 0.05;
  set.p.yb = 0.11;
  set.q0 = {0, 0, 0, 0.4, 0.15, 0.2};
  return set;
}

// A random state moved onto the contact (u = u0) and rolling (s + r phi = s0 + r phi0)
// constraints, positions and velocities, so reactions can be evaluated there.
RandomState random_state_on_constraints(std::mt19937& rng, const SieveSettings& set) {
  RandomState s = random_state(rng);
  s.q(4) = set.p.u0;
  s.q(3) = set.q0[3] - set.p.r * (s.q(5) - set.q0[5]);
  s.qd(4) = 0;
  s.qd(3) = -set.p.r * s.qd(5);
  return s;
}


double rel_diff(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).cwiseAbs().maxCoeff() / std::max(a.cwiseAbs().maxCoeff(), 1e-300);
}

// The closed form with the exciter term the repaired (3.4) lacks, added back: a third model
// whose h must equal the closed form's, which proves that the term contributes nothing to h.
struct ClosedFormPlusExciterTerm : SieveClosedForm {
  template <class S> S kinetic_energy(const VecX<S>& q, const VecX<S>& qd, const S& t) const {
    return SieveClosedForm::kinetic_energy(q, qd, t) +
           p.m0 * p.e * p.e * p.omega * (0.5 * p.omega + qd(2));
  }
};

// The closed form with (3.4b)'s damper sign as printed.
struct Printed34b : SieveClosedForm {
  template <class S>
  VecX<S> applied_forces(const VecX<S>& q, const VecX<S>& qd, const S& t) const {
    VecX<S> Q = SieveClosedForm::applied_forces(q, qd, t);
    const S ly = p.xb * std::cos(q(2)) + p.a * std::sin(q(2));
    Q(1) -= 2.0 * p.by * ly * qd(2);  // −b_y[ẏ + ly θ̇] instead of −b_y[ẏ − ly θ̇]
    return Q;
  }
};

}  // namespace

// Tolerance 1e-12 relative (the issue's): both forms evaluate the same polynomial-trigonometric
// expressions in a different order, so they differ by a few hundred ulps of the largest term.
BOOST_AUTO_TEST_CASE(closed_and_geometric_forms_have_equal_mass_matrix_h_and_Q) {
  const SieveSettings set = general_settings();
  const auto closed = make_sieve_model(set, ModelForm::closed_form);
  const auto geo = make_sieve_model(set, ModelForm::geometric);
  std::mt19937 rng(20240605);
  for (int trial = 0; trial < 50; ++trial) {
    const RandomState s = random_state(rng);
    Eigen::MatrixXd M1(6, 6), M2(6, 6);
    Eigen::VectorXd h1(6), h2(6), Q1(6), Q2(6);
    closed->kinetic_terms(s.t, s.q, s.qd, M1, h1);
    geo->kinetic_terms(s.t, s.q, s.qd, M2, h2);
    closed->forces(s.t, s.q, s.qd, Q1);
    geo->forces(s.t, s.q, s.qd, Q2);
    BOOST_TEST(rel_diff(M1, M2) < 1e-12);
    BOOST_TEST(rel_diff(h1, h2) < 1e-12);
    BOOST_TEST(rel_diff(Q1, Q2) < 1e-12);
    BOOST_TEST((M1 - M1.transpose()).cwiseAbs().maxCoeff() == 0.0);
  }
}

// T_geometric − T_(3.4) = m0 e² ω (ω/2 + θ̇) at every state: the difference is exactly the
// documented term (1e-12 relative to T), and adding it to the closed form leaves M and h
// unchanged (its θ̇-coefficient m0 e² ω is constant in q and t, so d/dt ∂/∂θ̇ and ∂/∂q vanish).
BOOST_AUTO_TEST_CASE(kinetic_energies_differ_by_the_exciter_term_which_changes_no_equation) {
  const SieveSettings set = general_settings();
  SieveClosedForm closed;
  SieveGeometric geo;
  closed.p = geo.p = set.p;
  ClosedFormPlusExciterTerm plus;
  plus.p = set.p;
  const auto m_closed = mech::make_model(closed);
  const auto m_plus = mech::make_model(plus);
  std::mt19937 rng(7);
  for (int trial = 0; trial < 50; ++trial) {
    const RandomState s = random_state(rng);
    const double Tg = geo.kinetic_energy<double>(s.q, s.qd, s.t);
    const double Tc = closed.kinetic_energy<double>(s.q, s.qd, s.t);
    const double term = set.p.m0 * set.p.e * set.p.e * set.p.omega * (0.5 * set.p.omega + s.qd(2));
    BOOST_TEST(std::abs((Tg - Tc) - term) <= 1e-12 * std::abs(Tg));
    BOOST_TEST(term != 0.0);  // the term is really there (the test could fail)
    Eigen::MatrixXd M1(6, 6), M2(6, 6);
    Eigen::VectorXd h1(6), h2(6);
    m_closed->kinetic_terms(s.t, s.q, s.qd, M1, h1);
    m_plus->kinetic_terms(s.t, s.q, s.qd, M2, h2);
    BOOST_TEST(rel_diff(M1, M2) < 1e-14);
    BOOST_TEST(rel_diff(h1, h2) < 1e-14);
  }
}

// Each erratum matters: undoing one in the closed form breaks the agreement with the geometric
// form (so the agreement test above can fail, and the errata are not cosmetic). Checked for the
// (3.4b) damper sign, via a model whose Q_y uses the printed "+".
BOOST_AUTO_TEST_CASE(printed_damper_sign_of_3_4b_disagrees_with_the_geometry) {
  Printed34b printed;
  printed.p = general_settings().p;
  const auto bad = mech::make_model(printed);
  const auto geo = make_sieve_model(general_settings(), ModelForm::geometric);
  std::mt19937 rng(3);
  const RandomState s = random_state(rng);
  Eigen::VectorXd Q1(6), Q2(6);
  bad->forces(s.t, s.q, s.qd, Q1);
  geo->forces(s.t, s.q, s.qd, Q2);
  BOOST_TEST(rel_diff(Q1, Q2) > 1e-3);
}

// Ideality (sieve-model.md section 4): with contact and rolling, Dᵀ R = 0 gives
// R_x = R_y = R_θ = 0 and R_φ = r R_s (erratum 7: the rolling row is [0,0,0,1,0,r]). Tolerance 1e-9 relative to |R|: R comes from a
// 6x6 solve with condition ~1e6 (m1/J2-scale spread of M).
BOOST_AUTO_TEST_CASE(reactions_obey_the_ideality_criterion) {
  const SieveSettings set = general_settings();
  const auto geo = make_sieve_model(set, ModelForm::geometric);
  std::mt19937 rng(11);
  for (int trial = 0; trial < 10; ++trial) {
    const RandomState s = random_state_on_constraints(rng, set);
    const auto r = mech::reactions(*geo, {"contact", "rolling"}, s.t, s.q, s.qd);
    BOOST_TEST_REQUIRE(static_cast<int>(r.issue) == static_cast<int>(mech::ModelIssue::none));
    const double scale = r.R.cwiseAbs().maxCoeff();
    BOOST_TEST(scale > 0.0);
    BOOST_TEST(std::abs(r.R(0)) <= 1e-9 * scale);
    BOOST_TEST(std::abs(r.R(1)) <= 1e-9 * scale);
    BOOST_TEST(std::abs(r.R(2)) <= 1e-9 * scale);
    BOOST_TEST(std::abs(r.R(5) - set.p.r * r.R(3)) <= 1e-9 * scale);
  }
}

// Statics, an analytic oracle: without the exciter (e = 0), with the desk held level
// (lock_theta) and at rest at x = y = 0 (the spring preload carries the weight), nothing
// accelerates; the roller rests on the deck, R_u = m2 g, R_s = 0, f* = 0, and the lock holds
// the gravity moment of the exciter mass and the roller, R_θ = g (m0 y0 + m2 s). Tolerance
// 1e-10: one well-conditioned solve of forces of order 1..4000 N.
BOOST_AUTO_TEST_CASE(roller_at_rest_on_level_deck_carries_its_weight) {
  SieveSettings set;
  set.p.e = 0.0;
  set.q0 = {0, 0, 0, 0.4, set.p.u0, 0};
  const auto geo = make_sieve_model(set, ModelForm::geometric);
  Eigen::VectorXd q(6), qd = Eigen::VectorXd::Zero(6);
  for (int i = 0; i < 6; ++i) q(i) = set.q0[i];
  const auto r = mech::reactions(*geo, {"contact", "rolling", "lock_theta"}, 0.0, q, qd);
  BOOST_TEST_REQUIRE(static_cast<int>(r.issue) == static_cast<int>(mech::ModelIssue::none));
  const double W = set.p.m2 * set.p.g;
  const double moment = set.p.g * (set.p.m0 * set.p.y0 + set.p.m2 * q(3));
  BOOST_TEST(std::abs(r.R(2) - moment) <= 1e-10 * moment);
  BOOST_TEST(std::abs(r.R(4) - W) <= 1e-10 * W);
  BOOST_TEST(std::abs(r.R(3)) <= 1e-10 * W);
  BOOST_TEST(r.qdd.cwiseAbs().maxCoeff() <= 1e-10);  // equilibrium: nothing accelerates
  Eigen::VectorXd out;
  geo->derived(0.0, q, qd, r.qdd, r.R, out);
  BOOST_TEST(out(0) <= 1e-10);
}

// The roller's own spin equation, an exact relation the engine does not use directly:
// J2 (θ̈ + φ̈) = Q_φ + R_φ = r R_s (no applied moment about the roller centre). Tolerance 1e-8
// relative: θ̈ + φ̈ is the small difference of accelerations of order R/J2.
BOOST_AUTO_TEST_CASE(rolling_reaction_balances_the_roller_spin) {
  SieveSettings set = general_settings();
  const auto geo = make_sieve_model(set, ModelForm::geometric);
  std::mt19937 rng(5);
  for (int trial = 0; trial < 10; ++trial) {
    const RandomState s = random_state_on_constraints(rng, set);
    const auto r = mech::reactions(*geo, {"contact", "rolling"}, s.t, s.q, s.qd);
    BOOST_TEST_REQUIRE(static_cast<int>(r.issue) == static_cast<int>(mech::ModelIssue::none));
    // Roller spin: J2 (θ̈ + φ̈) = R_φ = r R_s (no other moment about the roller centre).
    const double spin = set.p.J2 * (r.qdd(2) + r.qdd(5));
    BOOST_TEST(std::abs(spin - set.p.r * r.R(3)) <= 1e-8 * (std::abs(spin) + 1e-12));
  }
}

// The holonomic and the velocity form of (3.2) are the same constraint row (g = [0,0,0,1,0,−r],
// g0 = 0), so they give the same reactions (1e-12 relative: same linear system).
BOOST_AUTO_TEST_CASE(holonomic_and_velocity_forms_of_rolling_give_equal_reactions) {
  const SieveSettings set = general_settings();
  const auto geo = make_sieve_model(set, ModelForm::geometric);
  std::mt19937 rng(9);
  const RandomState s = random_state(rng);
  const auto a = mech::reactions(*geo, active_constraints(set.constraints, false), s.t, s.q, s.qd);
  const auto b = mech::reactions(*geo, active_constraints(set.constraints, true), s.t, s.q, s.qd);
  BOOST_TEST_REQUIRE(static_cast<int>(a.issue) == 0);
  BOOST_TEST_REQUIRE(static_cast<int>(b.issue) == 0);
  BOOST_TEST(rel_diff(a.R, b.R) < 1e-12);
}

// fstar = |R_s|/R_u, and +inf once the contact force is not positive.
BOOST_AUTO_TEST_CASE(fstar_is_friction_ratio_and_infinite_without_contact) {
  SieveCommon m;
  Eigen::VectorXd R(6), out, z = Eigen::VectorXd::Zero(6);
  R << 0, 0, 0, -1.5, 3.0, 0.15;
  m.derived(0, z, z, R, out);
  BOOST_TEST(out(0) == 0.5);
  R(4) = 0.0;
  m.derived(0, z, z, R, out);
  BOOST_TEST(std::isinf(out(0)));
}

// The hand-derived model (the one `pcsim run` integrates) equals the AD-derived geometric form:
// M, h and Q to 1e-12 relative (same reason as above), constraint rows exactly, and the
// holonomic residuals to rounding.
BOOST_AUTO_TEST_CASE(hand_derived_model_equals_the_ad_derived_forms) {
  const SieveSettings set = general_settings();
  const auto an = make_sieve_model(set, ModelForm::analytic);
  const auto geo = make_sieve_model(set, ModelForm::geometric);
  std::mt19937 rng(424242);
  const std::vector<int> all = {0, 1, 2, 3};
  for (int trial = 0; trial < 50; ++trial) {
    const RandomState s = random_state(rng);
    Eigen::MatrixXd M1(6, 6), M2(6, 6), g1(4, 6), g2(4, 6);
    Eigen::VectorXd h1(6), h2(6), Q1(6), Q2(6), a1(4), a2(4), c1(4), c2(4);
    an->kinetic_terms(s.t, s.q, s.qd, M1, h1);
    geo->kinetic_terms(s.t, s.q, s.qd, M2, h2);
    an->forces(s.t, s.q, s.qd, Q1);
    geo->forces(s.t, s.q, s.qd, Q2);
    an->constraint_rows(all, s.t, s.q, s.qd, g1, a1, c1);
    geo->constraint_rows(all, s.t, s.q, s.qd, g2, a2, c2);
    BOOST_TEST(rel_diff(M1, M2) < 1e-12);
    BOOST_TEST(rel_diff(h1, h2) < 1e-12);
    BOOST_TEST(rel_diff(Q1, Q2) < 1e-12);
    BOOST_TEST((g1 - g2).cwiseAbs().maxCoeff() == 0.0);
    BOOST_TEST(a1.cwiseAbs().maxCoeff() + a2.cwiseAbs().maxCoeff() == 0.0);
    BOOST_TEST(c1.cwiseAbs().maxCoeff() + c2.cwiseAbs().maxCoeff() < 1e-15);
    for (int i : {0, 1, 3})
      BOOST_TEST(std::abs(an->position_residual(i, s.t, s.q) -
                          geo->position_residual(i, s.t, s.q)) < 1e-15);
  }
  BOOST_TEST(an->constraints().size() == geo->constraints().size());
  BOOST_TEST(an->derived_names() == geo->derived_names(), boost::test_tools::per_element());
}
