// Issue 19, "contacts far from the origin": a contact's event and accumulation tolerances are
// relative to its own gap and gap rate, never to the size of the coordinates. A ball bouncing
// (e = 0.8) 50 m along the floor used to bounce 429,062 times and end 4.8e-6 m inside the floor
// (every bounce started a rounding deeper, and the landing threshold grew with x); on an incline
// the impact speed stopped shrinking at ~1e-5 m/s, more the farther down the slope. The models
// are in tests/mech/contacts/models/. Exact solution (H = 1 m dropped from rest, normal gravity
// g_n): t1 = sqrt(2 H / g_n), rebound speeds e^k g_n t1, and the flights 2 e^k t1 sum to the
// time of rest t_rest = t1 + 2 e t1 / (1 − e) = t1 (1 + e) / (1 − e).
#define BOOST_TEST_MODULE switching_contacts_far_from_origin
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <string>

#include "switching_util.hpp"

using namespace switching_test;

namespace {

constexpr double kG = 9.81, kE = 0.8;

std::shared_ptr<const Model> test_model(const std::string& stem, const std::map<std::string, double>& p) {
  const auto d = modelfile::load_model_file(std::string(PCSIM_SOURCE_DIR) + "/tests/mech/contacts/models/" + stem + ".toml");
  return d->instantiate(p, Eigen::VectorXd(), 0.0);
}

struct Rest {
  double t = NAN;          ///< the accumulation event (the contact closes for good)
  long impacts = 0;        ///< impact events before it (the accumulation counts as one)
  double last_speed = 0.0; ///< approach speed of the accumulation impact
  SwitchingResult r;
};

Rest rest_of(const Model& m, const Eigen::VectorXd& q0, double zeno_time, OdeMethod method = OdeMethod::automatic) {
  SimulationOptions o;
  o.rtol = o.atol = 1e-10;
  o.method = method;
  SwitchingOptions sw;
  sw.zeno_time = zeno_time;
  Rest out;
  out.r = run(m, q0, Eigen::VectorXd::Zero(q0.size()), 6.0, o, sw);
  for (const auto& e : out.r.events) {
    if (e.kind == ContactEventKind::impact || e.kind == ContactEventKind::accumulation) ++out.impacts;
    if (e.kind == ContactEventKind::accumulation) {
      out.t = e.t;
      out.last_speed = -e.vn_before;
      break;
    }
  }
  return out;
}

double exact_rest(double g_n) {
  const double t1 = std::sqrt(2.0 / g_n);
  return t1 * (1 + kE) / (1 - kE);
}

}  // namespace

// x does not enter the gap y >= 0: the run is the one at x = 0, event for event.
BOOST_AUTO_TEST_CASE(ball_along_the_floor_rests_at_the_same_time_whatever_x) {
  auto m = test_model("ball_far_along_floor", {{"e_n", kE}});
  const double zeno = 1e-9;
  Rest ref;
  for (double X : {0.0, 50.0, 1e3, 1e5}) {
    Eigen::VectorXd q0(2);
    q0 << X, 1.0;
    const Rest r = rest_of(*m, q0, zeno);
    BOOST_TEST_CONTEXT("x = " << X) {
      BOOST_REQUIRE_MESSAGE(r.r.status == SimulationStatus::success, r.r.message);
      BOOST_REQUIRE(std::isfinite(r.t));
      // The accumulation rule closes the contact early by at most zeno_time / (1 − e).
      BOOST_TEST(r.t <= exact_rest(kG) + 1e-12);
      BOOST_TEST(r.t >= exact_rest(kG) - zeno / (1 - kE) - 1e-12, "rest at " << r.t);
      BOOST_TEST(r.last_speed < 1e-7);  // down to kG zeno_time / (2 e)-ish, not a rounding floor
      if (X == 0.0) {
        ref = r;
      } else {
        BOOST_TEST(r.impacts == ref.impacts);
        BOOST_TEST(std::abs(r.t - ref.t) < 1e-12);
      }
      // It rests on the floor, not inside it, and says how deep any root's far side went.
      const ContactStats& st = r.r.contacts.at(0);
      BOOST_TEST(std::abs(r.r.q_end[1]) < 1e-15);
      BOOST_TEST(st.gap_end >= -st.gap_tol_end);
      BOOST_TEST(st.run.penetration_max < 1e-12);
      BOOST_TEST(r.r.residual_pos_max >= st.run.penetration_max);
      // The flights recorded and the time with the contact open agree.
      BOOST_TEST(std::abs(st.run.flight_time + st.run.closed_time - r.r.t) < 1e-9);
      BOOST_TEST(std::abs(st.run.flight_time - ref.t) < 1e-9);
    }
  }
  BOOST_TEST_MESSAGE("ball along the floor: rest at " << ref.t << " s after " << ref.impacts
                                                      << " impacts; exact " << exact_rest(kG));
}

// On a frictionless incline the ball slides down x (17 m/s, 52 m by t = 6 s) while it bounces in
// y with g cos(alpha): the impact speeds keep shrinking to the accumulation, at any distance.
BOOST_AUTO_TEST_CASE(ball_on_an_incline_keeps_its_series_at_any_distance) {
  const double alpha = 0.3;
  auto m = test_model("ball_incline", {{"e_n", kE}, {"alpha", alpha}});
  const double zeno = 1e-9, g_n = kG * std::cos(alpha);
  Rest ref;
  for (double X : {0.0, -50.0, 50.0, 1e3, -1e5, 1e5}) {
    Eigen::VectorXd q0(2);
    q0 << X, 1.0;
    const Rest r = rest_of(*m, q0, zeno);
    BOOST_TEST_CONTEXT("x0 = " << X) {
      BOOST_REQUIRE_MESSAGE(r.r.status == SimulationStatus::success, r.r.message);
      BOOST_REQUIRE(std::isfinite(r.t));
      BOOST_TEST(r.t <= exact_rest(g_n) + 1e-12);
      BOOST_TEST(r.t >= exact_rest(g_n) - zeno / (1 - kE) - 1e-12, "rest at " << r.t);
      BOOST_TEST(r.last_speed < 1e-7, "the impact speed stopped shrinking at " << r.last_speed);
      if (X == 0.0) {
        ref = r;
      } else {
        BOOST_TEST(r.impacts == ref.impacts);
        BOOST_TEST(std::abs(r.t - ref.t) < 1e-12);
      }
      BOOST_TEST(std::abs(r.r.q_end[1]) < 1e-15);
      BOOST_TEST(r.r.contacts.at(0).run.penetration_max < 1e-12);
      // It slides on: x = X + g sin(alpha) t² / 2 at the end.
      BOOST_TEST(std::abs(r.r.q_end[0] - (X + 0.5 * kG * std::sin(alpha) * 36.0)) < 1e-9 * (1 + std::abs(X)));
    }
  }
}

// The floor y − X >= 0 with y near X: the gap is known to X eps only (y's own rounding), and a
// rebound whose apex is below the gap's resolution (kResolve kRound eps |y| = 1600 eps X) cannot
// be resolved, so the accumulation rule takes it. The time of rest is then early by at most
// the flight of that apex over (1 − e): tau_res / (1 − e), tau_res = 2 sqrt(2 a_res / g).
// With a zeno_time above every tau_res, all floors give the same series.
BOOST_AUTO_TEST_CASE(ball_on_a_lifted_floor_rests_within_the_resolution_bound) {
  constexpr double kEps = 2.220446049250313e-16;
  Rest ref, ref_coarse;
  for (double X : {0.0, 50.0, 1e3, 1e5}) {
    auto m = test_model("ball_lifted_floor", {{"e_n", kE}, {"X", X}});
    const Eigen::VectorXd q0 = Eigen::VectorXd::Constant(1, X + 1.0);
    const double zeno = 1e-9;
    const double a_res = 16.0 * 100.0 * kEps * X;
    const double tau = std::max(zeno, 2.0 * std::sqrt(2.0 * a_res / kG));
    const Rest r = rest_of(*m, q0, zeno);
    const Rest c = rest_of(*m, q0, 1e-3);
    BOOST_TEST_CONTEXT("floor at X = " << X) {
      BOOST_REQUIRE_MESSAGE(r.r.status == SimulationStatus::success, r.r.message);
      BOOST_REQUIRE_MESSAGE(c.r.status == SimulationStatus::success, c.r.message);
      BOOST_REQUIRE(std::isfinite(r.t));
      // The first impact time is computed from y − X: X eps of rounding in the gap, 1e-12 s.
      BOOST_TEST(r.t <= exact_rest(kG) + 1e-12);
      BOOST_TEST(r.t >= exact_rest(kG) - 1.2 * tau / (1 - kE), "rest at " << r.t << ", bound " << tau / (1 - kE));
      BOOST_TEST(r.r.q_end[0] == X);  // resting on the floor, not 4.8e-6 m inside it
      // Its landings are located a gap rounding (the event offset, kRound eps |y| = 100 eps X)
      // below the surface, on the root's far side, and reported as such.
      BOOST_TEST(r.r.contacts.at(0).run.penetration_max <= 1e-12 + 2 * 100 * kEps * X);
      // The impacts skipped: those whose flights lie between zeno_time and tau_res.
      if (X == 0.0) {
        ref = r;
        ref_coarse = c;
      } else {
        const long skipped = static_cast<long>(std::ceil(std::log(tau / zeno) / std::log(1 / kE))) + 1;
        BOOST_TEST(r.impacts <= ref.impacts);
        BOOST_TEST(r.impacts >= ref.impacts - skipped);
        // zeno_time = 1e-3 s exceeds tau_res of every floor here (1.7e-4 s at X = 1e5).
        BOOST_TEST(std::abs(c.impacts - ref_coarse.impacts) <= 1);
        BOOST_TEST(std::abs(c.t - ref_coarse.t) < 1e-9 * (1 + X));
      }
      BOOST_TEST_MESSAGE("floor at " << X << ": " << r.impacts << " impacts, rest at " << r.t
                                     << " (exact " << exact_rest(kG) << ", bound " << tau / (1 - kE)
                                     << "); with zeno_time 1e-3: " << c.impacts << " impacts, rest at " << c.t);
    }
  }
}

// A run that starts with the ball inside the floor (moving out of it: the start is not projected)
// says so: the penetration (1 cm at t = 0) is in the contact's statistics and in the run's
// position residual; a good run reports only its roots' far side (rounding).
BOOST_AUTO_TEST_CASE(penetration_is_reported_where_it_happens_and_not_otherwise) {
  auto m = test_model("ball_far_along_floor", {{"e_n", kE}});
  SimulationOptions o;
  o.rtol = o.atol = 1e-10;
  SwitchingOptions sw;
  sw.zeno_time = 1e-9;
  Eigen::VectorXd q0(2), qd0(2);
  q0 << 3.0, -0.01;
  qd0 << 0.0, 1.0;
  const auto bad = run(*m, q0, qd0, 1.0, o, sw);
  BOOST_REQUIRE_MESSAGE(bad.status == SimulationStatus::success, bad.message);
  const ContactStats& sb = bad.contacts.at(0);
  BOOST_TEST(sb.run.penetration_max == 0.01);
  BOOST_TEST(sb.run.penetration_time == 0.0);
  BOOST_TEST(bad.residual_pos_max >= 0.01);
  BOOST_TEST(sb.gap_end >= 0.0);  // it came out and bounces on the floor
  BOOST_TEST(events_of(bad, ContactEventKind::impact).size() >= 1u);
  q0 << 3.0, 1.0;
  qd0.setZero();
  const auto good = run(*m, q0, qd0, 6.0, o, sw);
  BOOST_REQUIRE_MESSAGE(good.status == SimulationStatus::success, good.message);
  BOOST_TEST(good.contacts.at(0).run.penetration_max < 1e-12);
  BOOST_TEST(good.residual_pos_max < 1e-12);
}

// Two corners, every impact an LCP: the block rocking 1e5 m along the floor (x enters neither
// corner's gap nor its normal velocity) rocks as at x = 0: the same events, the accumulation at
// the same time (the integrator's steps differ with x's tolerance: 1e-8 s).
BOOST_AUTO_TEST_CASE(rocking_block_far_along_the_floor_rocks_as_at_the_origin) {
  const double b = 0.1, h = 0.3, theta = 0.1;
  auto m = contact_model("rocking_block", {{"e_n", 0.0}, {"mu", 1.0}});
  SimulationOptions o;
  o.rtol = o.atol = 1e-10;
  o.method = OdeMethod::automatic;
  std::vector<SwitchingResult> rs;
  for (double X : {0.0, 1e5, -1e5}) {
    Eigen::VectorXd q0(3);
    q0 << X, b * std::sin(theta) + h * std::cos(theta), theta;
    rs.push_back(run(*m, q0, Eigen::VectorXd::Zero(3), 3.0, o));
    BOOST_REQUIRE_MESSAGE(rs.back().status == SimulationStatus::success, rs.back().message);
  }
  for (std::size_t i = 1; i < rs.size(); ++i) {
    BOOST_REQUIRE_EQUAL(rs[i].events.size(), rs[0].events.size());
    for (std::size_t k = 0; k < rs[0].events.size(); ++k) {
      BOOST_TEST(rs[i].events[k].constraint == rs[0].events[k].constraint);
      BOOST_TEST(rs[i].events[k].kind == rs[0].events[k].kind);
      BOOST_TEST(std::abs(rs[i].events[k].t - rs[0].events[k].t) < 1e-8);
    }
    for (std::size_t c = 0; c < 2; ++c)
      BOOST_TEST(rs[i].contacts[c].run.penetration_max < 1e-11);
  }
}

// ---- Contacts on body joints far from the origin (issue 22): the floor of
// models/contact/bouncing_ball_bodies.toml and the slope of disk_incline_bodies.toml moved to
// (1000 m, 1000 m). The ball's gap is ball_y - Y0 with both near 1000, so it is known to
// 1000 eps only, and the bounds are those of the lifted floor above (same tau_res): it rests
// within tau_res / (1 - e) of the closed-form accumulation time, on the floor (to the gap's
// rounding), and with a zeno_time above tau_res exactly as at the origin. The disk spun
// backwards sticks at the closed-form instant, as at the origin.
BOOST_AUTO_TEST_CASE(body_joint_contacts_1000_m_from_the_origin_switch_as_at_the_origin) {
  constexpr double kEps = 2.220446049250313e-16;
  const double zeno = 1e-9;
  Rest ref_coarse;
  for (double X : {0.0, 1e3}) {
    BOOST_TEST_CONTEXT("floor at (" << X << ", " << X << ")") {
      auto mb = switching_test::contact_model("bouncing_ball_bodies", {{"e_n", kE}, {"X0", X}, {"Y0", X}});
      const Eigen::Vector2d q0(X + 0.5, X + 1.0);
      const Rest r = rest_of(*mb, q0, zeno);
      const Rest c = rest_of(*mb, q0, 1e-3);
      BOOST_REQUIRE_MESSAGE(r.r.status == SimulationStatus::success, r.r.message);
      BOOST_REQUIRE_MESSAGE(c.r.status == SimulationStatus::success, c.r.message);
      BOOST_REQUIRE(std::isfinite(r.t));
      const double tau = std::max(zeno, 2.0 * std::sqrt(2.0 * 16.0 * 100.0 * kEps * X / kG));
      BOOST_TEST(r.t <= exact_rest(kG) + 1e-12);
      BOOST_TEST(r.t >= exact_rest(kG) - 1.2 * tau / (1 - kE), "rest at " << r.t << ", bound " << tau / (1 - kE));
      BOOST_TEST(std::abs(r.r.q_end[1] - X) <= 1e-12 + 2 * 100 * kEps * X);  // on the floor
      BOOST_TEST(r.r.contacts.at(0).run.penetration_max <= 1e-12 + 2 * 100 * kEps * X);
      BOOST_TEST(std::abs(r.r.q_end[0] - q0[0]) < 1e-12 * (1 + X));     // no friction: x untouched
      if (X == 0.0) ref_coarse = c;
      else BOOST_TEST(std::abs(c.t - ref_coarse.t) < 1e-9 * (1 + X));
    }
  }
  // The disk on the slope through (X0, Y0), spun backwards: stick at
  // t* = r |w0| / (g sin(alpha) + mu g cos(alpha) (1 + m r^2 / J)).
  const double alpha = 0.5, r = 0.2, mu = 0.2, w0 = -10.0, ts = r * -w0 / (kG * std::sin(alpha) + mu * kG * std::cos(alpha) * 3.0);
  for (double X : {0.0, 1e3}) {
    BOOST_TEST_CONTEXT("slope through (" << X << ", " << X << ")") {
      const Eigen::Vector3d q0(X + r * std::sin(alpha), X + r * std::cos(alpha), 0.0);
      auto m = switching_test::contact_model("disk_incline_bodies", {{"alpha", alpha}, {"X0", X}, {"Y0", X}}, q0);
      SimulationOptions o;
      o.rtol = o.atol = 1e-10;
      const auto d = run(*m, q0, Eigen::Vector3d(0.0, 0.0, w0), 0.4, o);
      BOOST_REQUIRE_MESSAGE(d.status == SimulationStatus::success, d.message);
      BOOST_REQUIRE_EQUAL(d.events.size(), 1u);
      BOOST_TEST(d.events[0].kind == ContactEventKind::stick);
      BOOST_TEST(std::abs(d.events[0].t - ts) < 1e-9, "stick at " << d.events[0].t << ", exact " << ts);
    }
  }
}
