// A block on an incline with Coulomb friction (models/contact/block_incline.toml) against the
// exact solutions: it sticks when tan(alpha) <= mu_s; otherwise it slides with
// x_dd = g (sin(alpha) - mu_k cos(alpha)); pushed up the slope it stops at
// t_s = v0 / (g (sin(alpha) + mu_k cos(alpha))) and then sticks (tan(alpha) <= mu_s) or slides
// back (reversal). Between events the motion is polynomial (constant accelerations), which the
// integrators reproduce to rounding, so the tolerances are 1e-10 relative.
// The reactions in slip come from compatibility with the friction law in place of one
// ideality row; the paper's dense [G; D^T; friction] system and the structured solve agree.
#define BOOST_TEST_MODULE switching_block_incline
#include <boost/test/unit_test.hpp>

#include <cmath>

#include "switching_util.hpp"

using namespace switching_test;

namespace {
constexpr double kG = 9.81, kM = 2.0;
Eigen::VectorXd v2(double a, double b) { return Eigen::Vector2d(a, b); }
}  // namespace

BOOST_AUTO_TEST_CASE(it_sticks_when_tan_alpha_is_below_mu_s) {
  const double alpha = 0.3, mu_s = 0.4;  // tan(alpha) = 0.309
  auto m = contact_model("block_incline", {{"alpha", alpha}, {"mu_s", mu_s}, {"mu_k", 0.3}});
  Trace tr;
  SimulationOptions o;
  o.rtol = o.atol = 1e-10;
  const auto r = run(*m, v2(0.5, 0.0), v2(0.0, 0.0), 2.0, o, {}, &tr);
  BOOST_REQUIRE_MESSAGE(r.status == SimulationStatus::success, r.message);
  BOOST_TEST(r.events.empty());
  BOOST_TEST(std::abs(r.q_end[0] - 0.5) < 1e-12);
  for (std::size_t i = 0; i < tr.t.size(); ++i) {
    BOOST_TEST(tr.modes[i][0] == ContactMode::stick);
    BOOST_TEST(std::abs(tr.R[i][0] + kM * kG * std::sin(alpha)) < 1e-9);  // friction holds it
    BOOST_TEST(std::abs(tr.R[i][1] - kM * kG * std::cos(alpha)) < 1e-9);  // normal force
  }
}

BOOST_AUTO_TEST_CASE(it_slides_with_the_exact_acceleration_when_tan_alpha_exceeds_mu_s) {
  const double alpha = 0.5, mu_k = 0.3;  // tan(alpha) = 0.546 > mu_s = 0.4
  for (OdeMethod method : {OdeMethod::radau, OdeMethod::explicit_rk}) {
    auto m = contact_model("block_incline", {{"alpha", alpha}, {"mu_s", 0.4}, {"mu_k", mu_k}});
    SimulationOptions o;
    o.method = method;
    o.rtol = o.atol = 1e-10;
    Trace tr;
    const auto r = run(*m, v2(0.0, 0.0), v2(0.0, 0.0), 1.5, o, {}, &tr);
    BOOST_REQUIRE_MESSAGE(r.status == SimulationStatus::success, r.message);
    const double a = kG * (std::sin(alpha) - mu_k * std::cos(alpha));
    BOOST_TEST(std::abs(r.q_end[0] - 0.5 * a * 1.5 * 1.5) < 1e-10 * 0.5 * a * 1.5 * 1.5);
    BOOST_TEST(std::abs(r.qd_end[0] - a * 1.5) < 1e-10 * a * 1.5);
    BOOST_TEST(r.events.empty());  // it slides from the start (the initial mode), never stops
    BOOST_TEST(tr.modes.back()[0] == ContactMode::slip);
    BOOST_TEST(std::abs(tr.R.back()[0] + mu_k * kM * kG * std::cos(alpha)) < 1e-9);
    // Slip distance and friction work: the block slid 0.5 a T^2 against mu_k m g cos(alpha).
    const double d = 0.5 * a * 1.5 * 1.5;
    BOOST_TEST(std::abs(r.contacts[0].run.slip_distance - d) < 1e-9 * d);
    BOOST_TEST(std::abs(r.contacts[0].run.energy_friction - mu_k * kM * kG * std::cos(alpha) * d) < 1e-8 * d);
  }
}

BOOST_AUTO_TEST_CASE(pushed_up_it_stops_at_the_exact_time_and_sticks) {
  const double alpha = 0.3, mu_k = 0.3, v0 = 2.0;
  auto m = contact_model("block_incline", {{"alpha", alpha}, {"mu_s", 0.4}, {"mu_k", mu_k}});
  SimulationOptions o;
  o.rtol = o.atol = 1e-10;
  const auto r = run(*m, v2(0.0, 0.0), v2(-v0, 0.0), 2.0, o);
  BOOST_REQUIRE_MESSAGE(r.status == SimulationStatus::success, r.message);
  const double a = kG * (std::sin(alpha) + mu_k * std::cos(alpha));
  const double ts = v0 / a;
  BOOST_REQUIRE_EQUAL(r.events.size(), 1u);
  BOOST_TEST(r.events[0].kind == ContactEventKind::stick);
  BOOST_TEST(std::abs(r.events[0].t - ts) < 1e-12);
  BOOST_TEST(std::abs(r.q_end[0] + v0 * v0 / (2 * a)) < 1e-10);
  BOOST_TEST(std::abs(r.qd_end[0]) < 1e-12);
}

BOOST_AUTO_TEST_CASE(pushed_up_a_steeper_slope_it_stops_and_slides_back) {
  const double alpha = 0.5, mu_k = 0.3, v0 = 2.0, T = 1.5;
  auto m = contact_model("block_incline", {{"alpha", alpha}, {"mu_s", 0.4}, {"mu_k", mu_k}});
  SimulationOptions o;
  o.rtol = o.atol = 1e-10;
  const auto r = run(*m, v2(0.0, 0.0), v2(-v0, 0.0), T, o);
  BOOST_REQUIRE_MESSAGE(r.status == SimulationStatus::success, r.message);
  const double up = kG * (std::sin(alpha) + mu_k * std::cos(alpha));
  const double down = kG * (std::sin(alpha) - mu_k * std::cos(alpha));
  const double ts = v0 / up, xs = -v0 * v0 / (2 * up);
  BOOST_REQUIRE_EQUAL(r.events.size(), 1u);
  BOOST_TEST(r.events[0].kind == ContactEventKind::reversal);
  BOOST_TEST(std::abs(r.events[0].t - ts) < 1e-12);
  BOOST_TEST(std::abs(r.q_end[0] - (xs + 0.5 * down * (T - ts) * (T - ts))) < 1e-10);
  BOOST_TEST(std::abs(r.qd_end[0] - down * (T - ts)) < 1e-10);
}

// In slip the friction law -mu_k lambda_n sign(v_t) replaces one ideality row D^T R = 0: the
// paper's dense system and the structured solve (R = (g^T + F) lambda) give the same R and the
// closed form R = (-sigma mu_k m g cos(alpha), m g cos(alpha)), to rounding.
BOOST_AUTO_TEST_CASE(friction_law_replaces_an_ideality_row_in_both_formulations) {
  const double alpha = 0.5, mu_k = 0.3;
  auto m = contact_model("block_incline", {{"alpha", alpha}, {"mu_s", 0.4}, {"mu_k", mu_k}});
  for (int sigma : {+1, -1}) {
    for (Kernel k : {Kernel::fortran, Kernel::cpp}) {
      const auto dense = switching_reactions(*m, {"contact", "friction"}, {ContactMode::slip}, {sigma}, 0.0,
                                             v2(0.1, 0.0), v2(sigma * 0.7, 0.0), ReactionMethod::compatibility, k);
      const auto structured = switching_reactions(*m, {"contact", "friction"}, {ContactMode::slip}, {sigma}, 0.0,
                                                  v2(0.1, 0.0), v2(sigma * 0.7, 0.0),
                                                  ReactionMethod::compatibility_structured, k);
      BOOST_REQUIRE_MESSAGE(dense.issue == ModelIssue::none, dense.message);
      BOOST_REQUIRE_MESSAGE(structured.issue == ModelIssue::none, structured.message);
      const double N = kM * kG * std::cos(alpha);
      BOOST_TEST(std::abs(dense.R[0] + sigma * mu_k * N) < 1e-12 * N);
      BOOST_TEST(std::abs(dense.R[1] - N) < 1e-12 * N);
      BOOST_TEST((dense.R - structured.R).cwiseAbs().maxCoeff() < 1e-12 * N);
      BOOST_TEST((dense.qdd - structured.qdd).cwiseAbs().maxCoeff() < 1e-12 * kG);
    }
  }
}

// ---- The same block written with bodies and joints (issue 22): a particle on a `point_on_line`
// joint with the contact attributes, whose mu_static adds the sliding row `rest_slide`
// (models/contact/block_incline_bodies.toml). Pushed up the slope (v0 along -x of the slope's
// frame) it stops at the closed-form instant and then sticks (alpha = 0.3, tan < mu_s) or slides
// back (alpha = 0.5): the same event at the same time as the energy-form block, the same state.
BOOST_AUTO_TEST_CASE(block_as_a_body_on_a_point_on_line_joint_stops_and_sticks_or_reverses_as_the_energy_form) {
  const double mu_k = 0.3, v0 = 2.0, T = 1.5;
  for (double alpha : {0.3, 0.5}) {
    BOOST_TEST_CONTEXT("alpha = " << alpha) {
      const std::map<std::string, double> p{{"alpha", alpha}, {"mu_s", 0.4}, {"mu_k", mu_k}};
      SimulationOptions o;
      o.rtol = o.atol = 1e-10;
      auto mb = contact_model("block_incline_bodies", p, v2(0.0, 0.0));
      const Eigen::Vector2d t(std::cos(alpha), -std::sin(alpha));  // down the slope, ground axes
      const auto b = run(*mb, v2(0.0, 0.0), -v0 * t, T, o);
      auto me = contact_model("block_incline", p);
      const auto e = run(*me, v2(0.0, 0.0), v2(-v0, 0.0), T, o);
      BOOST_REQUIRE_MESSAGE(b.status == SimulationStatus::success, b.message);
      BOOST_REQUIRE_MESSAGE(e.status == SimulationStatus::success, e.message);
      const double up = kG * (std::sin(alpha) + mu_k * std::cos(alpha));
      const double ts = v0 / up;
      BOOST_REQUIRE_EQUAL(b.events.size(), 1u);
      BOOST_TEST(b.events[0].kind == (alpha < 0.4 ? ContactEventKind::stick : ContactEventKind::reversal));
      BOOST_TEST(std::abs(b.events[0].t - ts) < 1e-12);
      BOOST_REQUIRE_EQUAL(e.events.size(), 1u);
      BOOST_TEST(e.events[0].kind == b.events[0].kind);
      BOOST_TEST(std::abs(e.events[0].t - b.events[0].t) < 1e-12);
      BOOST_TEST(std::abs(e.events[0].normal - b.events[0].normal) < 1e-10);
      // Position and speed along the slope; the block stays on it.
      const double s = b.q_end.dot(t), v = b.qd_end.dot(t);
      BOOST_TEST(std::abs(s - e.q_end[0]) < 1e-10);
      BOOST_TEST(std::abs(v - e.qd_end[0]) < 1e-10);
      BOOST_TEST(std::abs(b.q_end[0] * std::sin(alpha) + b.q_end[1] * std::cos(alpha)) < 1e-12);
    }
  }
}
