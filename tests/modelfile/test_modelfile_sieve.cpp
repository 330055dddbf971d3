// models/sieve_1995.toml, the paper's (3.4) and (3.4a)-(3.4f) with the errata applied (erratum
// 7 included: rolling is s + r phi = s(0) + r phi(0)), is the C++ closed form of
// tests/sieve/support/model.hpp: the same M, h, Q, constraint rows and reactions at random states, with
// contact and rolling active and with lock_theta too; its printed-sign variant equals the C++
// rolling_as_printed form; fstar, the period and the slow coordinate are declared as the issue
// asks.
#define BOOST_TEST_MODULE modelfile_sieve
#include <boost/test/unit_test.hpp>

#include <cmath>

#include "mech/simulation.hpp"
#include "modelfile/model_file.hpp"
#include "modelfile_test_util.hpp"
#include "sieve/support/model.hpp"

using namespace pcsim;
using namespace pcsim::modelfile;
using namespace pcsim::modelfile::testing;

namespace {

// Parameters with every geometric offset non-zero (the defaults have several zeros, which would
// hide sign errors in the terms they multiply), and a non-zero initial roller angle (so the
// rolling constant s(0) + r phi(0) is not s(0)).
sieve::SieveSettings general_settings() {
  sieve::SieveSettings set;
  set.p.xc = 0.03;
  set.p.yc = -0.07;
  set.p.xb = 0.05;
  set.p.yb = 0.11;
  set.p.e = 0.013;
  set.p.omega = 263.0;
  set.q0 = {0, 0, 0, 0.4, 0.15, 0.2};
  return set;
}

std::map<std::string, double> parameters_of(const sieve::SieveParameters& p) {
  return {{"m0", p.m0}, {"m1", p.m1}, {"m2", p.m2},   {"J0", p.J0},         {"J1", p.J1},
          {"J2", p.J2}, {"r", p.r},   {"e", p.e},     {"cx", p.cx},         {"cy", p.cy},
          {"ctheta", p.ctheta}, {"bx", p.bx}, {"by", p.by}, {"btheta", p.btheta},
          {"omega", p.omega},   {"g", p.g},   {"x0", p.x0}, {"y0", p.y0},   {"xc", p.xc},
          {"yc", p.yc}, {"xb", p.xb}, {"yb", p.yb}, {"a", p.a}, {"b", p.b}, {"u0", p.u0},
          {"f", p.f}};
}

Eigen::VectorXd q0_of(const sieve::SieveSettings& set) {
  Eigen::VectorXd q0(6);
  for (int i = 0; i < 6; ++i) q0[i] = set.q0[i];
  return q0;
}

struct State {
  double t;
  Eigen::VectorXd q, qd;
};

// States well away from the design point in every coordinate: theta up to ±0.6 rad, s and u
// of order 0.1..1 m, velocities of order 1, t anywhere in a period.
State random_state(std::mt19937& rng) {
  State s;
  s.t = 0.05 * (1 + uniform(rng));
  s.q.resize(6);
  s.qd.resize(6);
  s.q << 0.01 * uniform(rng), 0.01 * uniform(rng), 0.6 * uniform(rng), 0.4 + 0.5 * uniform(rng),
      0.15 + 0.1 * uniform(rng), 3 * uniform(rng);
  for (int i = 0; i < 6; ++i) s.qd(i) = uniform(rng);
  return s;
}

// A random state on contact (u = u0) and rolling (s + r phi = s0 + r phi0), positions and
// velocities, with theta locked if asked.
State random_state_on_constraints(std::mt19937& rng, const sieve::SieveSettings& set,
                                  bool lock_theta) {
  State s = random_state(rng);
  s.q(4) = set.p.u0;
  s.q(3) = set.q0[3] - set.p.r * (s.q(5) - set.q0[5]);
  s.qd(4) = 0;
  s.qd(3) = -set.p.r * s.qd(5);
  if (lock_theta) s.q(2) = s.qd(2) = 0.0;
  return s;
}

}  // namespace

// Tolerance 1e-12 relative to each block's largest entry (h and Q: or 1 N): the tape and the
// C++ AD evaluate the same formulas in a different order; the largest cancellation in Q is
// cx (dx − σ0) against the preload, about 1e3, so the difference is ~1e-13.
BOOST_AUTO_TEST_CASE(sieve_file_equals_the_cpp_closed_form_at_random_states) {
  const sieve::SieveSettings set = general_settings();
  const auto cpp = sieve::make_sieve_model(set, sieve::ModelForm::closed_form);
  const auto desc = load_model_file(model_path("sieve_1995.toml"));
  const auto file = desc->instantiate(parameters_of(set.p), q0_of(set), 0.0);
  BOOST_TEST(file->coordinates() == cpp->coordinates());
  const std::vector<std::string> names = {"contact", "rolling", "rolling_velocity", "lock_theta"};
  const std::vector<int> af = indices(*file, names), ac = indices(*cpp, names);
  std::mt19937 rng(1995);
  for (int trial = 0; trial < 20; ++trial) {
    const State s = random_state(rng);
    const Evaluation a = evaluate(*file, af, s.t, s.q, s.qd);
    const Evaluation b = evaluate(*cpp, ac, s.t, s.q, s.qd);
    BOOST_TEST(rel_diff(a.M, b.M) < 1e-12);
    BOOST_TEST(rel_diff(a.h, b.h, 1.0) < 1e-12);
    BOOST_TEST(rel_diff(a.Q, b.Q, 1.0) < 1e-12);
    BOOST_TEST(rel_diff(a.g, b.g) < 1e-12);
    BOOST_TEST(rel_diff(a.g0, b.g0, 1.0) < 1e-12);
    BOOST_TEST(rel_diff(a.gamma, b.gamma, 1.0) < 1e-12);
    for (std::size_t k = 0; k < names.size(); ++k) {
      const double pa = file->position_residual(af[k], s.t, s.q);
      const double pb = cpp->position_residual(ac[k], s.t, s.q);
      if (std::isnan(pb)) {
        BOOST_TEST(std::isnan(pa));  // rolling_velocity has no position
      } else {
        BOOST_TEST(std::abs(pa - pb) < 1e-14);
      }
    }
  }
}

// Reactions through the compatibility equations, contact and rolling active, and with the desk
// locked: 1e-12 relative to the largest reaction (the solve is well conditioned: cond < 1e3).
BOOST_AUTO_TEST_CASE(sieve_file_reactions_equal_the_cpp_closed_form) {
  const sieve::SieveSettings set = general_settings();
  const auto cpp = sieve::make_sieve_model(set, sieve::ModelForm::closed_form);
  const auto file = load_model_file(model_path("sieve_1995.toml"))
                        ->instantiate(parameters_of(set.p), q0_of(set), 0.0);
  std::mt19937 rng(3);
  for (bool lock : {false, true}) {
    std::vector<std::string> active = {"contact", "rolling"};
    if (lock) active.push_back("lock_theta");
    for (int trial = 0; trial < 10; ++trial) {
      const State s = random_state_on_constraints(rng, set, lock);
      const mech::ReactionResult ra = mech::reactions(*file, active, s.t, s.q, s.qd);
      const mech::ReactionResult rb = mech::reactions(*cpp, active, s.t, s.q, s.qd);
      BOOST_REQUIRE(ra.issue == mech::ModelIssue::none);
      BOOST_REQUIRE(rb.issue == mech::ModelIssue::none);
      BOOST_TEST_CONTEXT("lock_theta " << lock << " trial " << trial) {
        BOOST_TEST(rel_diff(ra.R, rb.R) < 1e-12);
        BOOST_TEST(rel_diff(ra.qdd, rb.qdd) < 1e-12);
        // Erratum 7's ideality: R_phi = r R_s.
        BOOST_TEST(std::abs(ra.R[5] - set.p.r * ra.R[3]) < 1e-12 * ra.R.cwiseAbs().maxCoeff());
        // fstar = |R_s|/R_u where R_u > 0 (the C++ reports +inf otherwise; the file's
        // abs(R_s)/R_u is negative there, which the verdict reads the same way).
        Eigen::VectorXd fa, fb;
        file->derived(s.t, s.q, s.qd, ra.qdd, ra.R, fa);
        cpp->derived(s.t, s.q, s.qd, rb.qdd, rb.R, fb);
        BOOST_REQUIRE(fa.size() == 1);
        if (rb.R[4] > 0) {
          BOOST_TEST(std::abs(fa[0] - fb[0]) < 1e-11 * std::max(1.0, fb[0]));
        } else {
          BOOST_TEST(fa[0] <= 0.0);
        }
      }
    }
  }
}

// The paper's printed sign (constraints.rolling_as_printed in a case) is the constraint
// rolling_printed in both the file and the C++ forms: the same rows, residuals and reactions.
BOOST_AUTO_TEST_CASE(rolling_printed_equals_the_cpp_rolling_as_printed) {
  sieve::SieveSettings set = general_settings();
  set.constraints.rolling_as_printed = true;
  const auto cpp = sieve::make_sieve_model(set, sieve::ModelForm::closed_form);
  const auto file = load_model_file(model_path("sieve_1995.toml"))
                        ->instantiate(parameters_of(set.p), q0_of(set), 0.0);
  std::mt19937 rng(4);
  for (int trial = 0; trial < 10; ++trial) {
    State s = random_state(rng);
    s.q(4) = set.p.u0;
    s.q(3) = set.q0[3] + set.p.r * (s.q(5) - set.q0[5]);  // s − r phi = s0 − r phi0
    s.qd(4) = 0;
    s.qd(3) = set.p.r * s.qd(5);
    const int ic = cpp->constraint_index("rolling_printed"), ifl = file->constraint_index("rolling_printed");
    BOOST_TEST(std::abs(file->position_residual(ifl, s.t, s.q) - cpp->position_residual(ic, s.t, s.q)) < 1e-14);
    const mech::ReactionResult ra = mech::reactions(*file, {"contact", "rolling_printed"}, s.t, s.q, s.qd);
    const mech::ReactionResult rb = mech::reactions(*cpp, {"contact", "rolling_printed"}, s.t, s.q, s.qd);
    BOOST_REQUIRE(ra.issue == mech::ModelIssue::none);
    BOOST_TEST(rel_diff(ra.R, rb.R) < 1e-12);
  }
}

BOOST_AUTO_TEST_CASE(sieve_file_declares_its_constraints_period_and_slow_coordinate) {
  const auto desc = load_model_file(model_path("sieve_1995.toml"));
  BOOST_TEST(desc->name() == "sieve_1995");
  BOOST_TEST(desc->default_active_constraints() == (std::vector<std::string>{"contact", "rolling"}));
  const auto& c = desc->constraints();
  BOOST_REQUIRE(c.size() == 5u);
  BOOST_TEST(c[1].from_initial);
  BOOST_TEST(c[4].name == "rolling_printed");
  BOOST_TEST(c[4].from_initial);
  BOOST_TEST(!c[4].active_by_default);
  BOOST_TEST(static_cast<int>(c[2].kind) == static_cast<int>(mech::ConstraintKind::velocity));
  BOOST_TEST(desc->slow_coordinates() == std::vector<std::string>{"s"});
  BOOST_REQUIRE(desc->period_expression().has_value());
  BOOST_TEST(std::abs(desc->period() - 2 * M_PI / 280.0) < 1e-15);
  BOOST_TEST(std::abs(desc->period({{"omega", 300.0}}) - 2 * M_PI / 300.0) < 1e-15);
  // Parameters carry the case file's units and ranges.
  const ParameterSpec* m2 = desc->parameter("m2");
  BOOST_REQUIRE(m2);
  BOOST_TEST(m2->unit == "kg");
  BOOST_TEST(!m2->admits(0.0));
  BOOST_TEST(m2->admits(1e-3));
  BOOST_TEST(desc->parameter("m0")->admits(0.0));
  BOOST_TEST(!desc->parameter("m0")->admits(-1e-3));
  BOOST_TEST(desc->parameter("b")->admits(-5.0));
  // Every constant row is recognized as such (the engine then computes D once per run).
  const auto model = desc->instantiate({}, Eigen::VectorXd::Zero(6), 0.0);
  for (const auto& info : model->constraints()) BOOST_TEST(info.constant_row);
}
