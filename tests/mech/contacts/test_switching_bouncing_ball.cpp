// A ball dropped on a fixed floor (models/contact/bouncing_ball.toml) against the exact
// solution: landing at t1 = sqrt(2H/g) with v1 = g t1, rebounds e^k v1, flights 2 e^k v1 / g,
// apexes e^(2k) H, and for e < 1 rest at the accumulation time t1 + 2 e v1 / (g (1 - e)),
// after which the contact holds. The free flight is a parabola, which every Runge-Kutta
// method integrates exactly, so the only errors are the event location (100 eps |t|) and
// rounding: the tolerances below are 1e-10 relative over a dozen bounces.
#define BOOST_TEST_MODULE switching_bouncing_ball
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <fstream>
#include <string>

#include "switching_util.hpp"

using namespace switching_test;

namespace {
constexpr double kG = 9.81, kH = 1.0;
}

BOOST_AUTO_TEST_CASE(impact_times_speeds_and_apexes_follow_the_geometric_series) {
  for (Kernel k : {Kernel::fortran, Kernel::cpp}) {
    for (OdeMethod method : {OdeMethod::radau, OdeMethod::explicit_rk}) {
      for (double e : {0.5, 0.8}) {
        auto m = contact_model("bouncing_ball", {{"e_n", e}});
        SimulationOptions o;
        o.kernel = k;
        o.method = method;
        o.rtol = o.atol = 1e-10;
        SwitchingOptions sw;
        sw.zeno_time = 1e-9;
        const auto r = run(*m, Eigen::VectorXd::Constant(1, kH), Eigen::VectorXd::Zero(1), 5.0, o, sw);
        BOOST_TEST_CONTEXT(to_string(k) << " " << to_string(method) << " e = " << e) {
          BOOST_REQUIRE_MESSAGE(r.status == SimulationStatus::success, r.message);
          const double t1 = std::sqrt(2 * kH / kG), v1 = kG * t1;
          const auto impacts = events_of(r, ContactEventKind::impact);
          BOOST_REQUIRE(impacts.size() >= 10u);
          double t_exact = t1, v = v1;
          for (std::size_t i = 0; i < 10; ++i) {
            BOOST_TEST(std::abs(impacts[i].t - t_exact) < 1e-10 * t_exact, "impact " << i << " at " << impacts[i].t << " exact " << t_exact);
            BOOST_TEST(std::abs(-impacts[i].vn_before - v) < 1e-9 * v1);
            BOOST_TEST(std::abs(impacts[i].vn_after - e * v) < 1e-9 * v1);
            BOOST_TEST(std::abs(impacts[i].normal - (1 + e) * v) < 1e-9 * v1);  // impulse m (1 + e) v, m = 1
            BOOST_TEST(std::abs(impacts[i].energy_lost - 0.5 * (1 - e * e) * v * v) < 1e-9 * v1 * v1);
            t_exact += 2 * e * v / kG;
            v *= e;
          }
          // Apexes of the flights after each impact: e^(2k) H.
          const auto& fl = r.contacts.at(0).flights;
          BOOST_REQUIRE(fl.size() >= 10u);
          double apex = kH;
          for (std::size_t i = 1; i < 10; ++i) {
            apex *= e * e;
            BOOST_TEST(std::abs(fl[i].max_gap - apex) < 1e-9 * kH, "flight " << i << " apex " << fl[i].max_gap << " exact " << apex);
          }
        }
      }
    }
  }
}

BOOST_AUTO_TEST_CASE(with_restitution_below_one_it_rests_at_the_accumulation_time) {
  const double e = 0.5;
  auto m = contact_model("bouncing_ball", {{"e_n", e}});
  SimulationOptions o;
  o.rtol = o.atol = 1e-10;
  SwitchingOptions sw;
  sw.zeno_time = 1e-8;
  Trace tr;
  const auto r = run(*m, Eigen::VectorXd::Constant(1, kH), Eigen::VectorXd::Zero(1), 4.0, o, sw, &tr);
  BOOST_REQUIRE_MESSAGE(r.status == SimulationStatus::success, r.message);
  const double t1 = std::sqrt(2 * kH / kG), v1 = kG * t1;
  const double t_inf = t1 + 2 * e * v1 / (kG * (1 - e));
  const auto acc = events_of(r, ContactEventKind::accumulation);
  BOOST_REQUIRE_EQUAL(acc.size(), 1u);
  // The rule closes the contact at the last impact whose rebound would fly less than zeno_time;
  // the bounces it skips would have lasted at most zeno_time / (1 - e).
  BOOST_TEST_MESSAGE("accumulation closed at t = " << acc[0].t << ", exact t_inf = " << t_inf << ", after "
                                                   << events_of(r, ContactEventKind::impact).size() << " impacts");
  BOOST_TEST(acc[0].t <= t_inf + 1e-10);
  BOOST_TEST(t_inf - acc[0].t <= sw.zeno_time / (1 - e) + 1e-10);
  BOOST_TEST(acc[0].vn_after == 0.0);
  BOOST_TEST(acc[0].mode_after == ContactMode::contact);
  BOOST_TEST(r.events.back().t == acc[0].t);  // nothing happens afterwards
  // The contact holds to the end: at rest on the floor, carrying the weight m g.
  BOOST_TEST(std::abs(r.q_end[0]) < 1e-12);
  BOOST_TEST(std::abs(r.qd_end[0]) < 1e-12);
  for (std::size_t i = 0; i < tr.t.size(); ++i) {
    if (tr.t[i] <= acc[0].t) continue;
    BOOST_TEST(tr.modes[i][0] == ContactMode::contact);
    BOOST_TEST(std::abs(tr.R[i][0] - kG) < 1e-9);
  }
  // Closed from the accumulation to the end.
  BOOST_TEST(std::abs(r.contacts[0].run.closed_time - (4.0 - acc[0].t)) < 1e-9);
}

BOOST_AUTO_TEST_CASE(an_elastic_ball_bounces_with_period_2_t1_forever) {
  auto m = contact_model("bouncing_ball", {{"e_n", 1.0}});
  SimulationOptions o;
  o.rtol = o.atol = 1e-10;
  const auto r = run(*m, Eigen::VectorXd::Constant(1, kH), Eigen::VectorXd::Zero(1), 10.0, o);
  BOOST_REQUIRE_MESSAGE(r.status == SimulationStatus::success, r.message);
  const double t1 = std::sqrt(2 * kH / kG);
  const auto impacts = events_of(r, ContactEventKind::impact);
  BOOST_REQUIRE_EQUAL(impacts.size(), static_cast<std::size_t>(std::floor((10.0 - t1) / (2 * t1)) + 1));
  for (std::size_t i = 0; i < impacts.size(); ++i) {
    BOOST_TEST(std::abs(impacts[i].t - (2 * i + 1) * t1) < 1e-10 * 10.0);
    BOOST_TEST(std::abs(impacts[i].energy_lost) < 1e-9);
  }
  BOOST_TEST(events_of(r, ContactEventKind::accumulation).empty());
  BOOST_TEST(r.contacts[0].run.max_flight_height <= kH * (1 + 1e-10));
  BOOST_TEST(r.contacts[0].run.max_flight_height >= kH * (1 - 1e-10));
}

// A single contact's complementarity problem is solved in closed form: none of the runs above
// loads the LCP plugin, hence neither Siconos nor the OpenBLAS it links.
BOOST_AUTO_TEST_CASE(single_contact_runs_never_load_siconos_or_openblas) {
  BOOST_TEST(!lcp::lcp_library_loaded());
  std::ifstream maps("/proc/self/maps");
  std::string line;
  bool siconos = false, openblas = false;
  while (std::getline(maps, line)) {
    siconos = siconos || line.find("siconos") != std::string::npos;
    openblas = openblas || line.find("openblas") != std::string::npos;
  }
  BOOST_TEST(!siconos);
  BOOST_TEST(!openblas);
}

// ---- The ball written with bodies and joints (issue 22): a particle on a `point_on_line` joint
// to the floor, unilateral with restitution (models/contact/bouncing_ball_bodies.toml). The
// closed form above holds event for event, and the energy-form ball gives the same events.
BOOST_AUTO_TEST_CASE(ball_as_a_body_on_a_point_on_line_joint_bounces_as_the_geometric_series) {
  const double e = 0.5;
  SimulationOptions o;
  o.rtol = o.atol = 1e-10;
  SwitchingOptions sw;
  sw.zeno_time = 1e-9;
  auto mb = contact_model("bouncing_ball_bodies", {{"e_n", e}});
  const auto b = run(*mb, Eigen::Vector2d(0.3, kH), Eigen::Vector2d(0.2, 0.0), 2.0, o, sw);
  auto me = contact_model("bouncing_ball", {{"e_n", e}});
  const auto r = run(*me, Eigen::VectorXd::Constant(1, kH), Eigen::VectorXd::Zero(1), 2.0, o, sw);
  BOOST_REQUIRE_MESSAGE(b.status == SimulationStatus::success, b.message);
  BOOST_REQUIRE_MESSAGE(r.status == SimulationStatus::success, r.message);
  const double t1 = std::sqrt(2 * kH / kG), v1 = kG * t1;
  const auto impacts = events_of(b, ContactEventKind::impact);
  BOOST_REQUIRE(impacts.size() >= 10u);
  double t_exact = t1, v = v1;
  for (std::size_t i = 0; i < 10; ++i) {
    BOOST_TEST(std::abs(impacts[i].t - t_exact) < 1e-10 * t_exact, "impact " << i << " at " << impacts[i].t << " exact " << t_exact);
    BOOST_TEST(std::abs(impacts[i].vn_after - e * v) < 1e-9 * v1);
    t_exact += 2 * e * v / kG;
    v *= e;
  }
  const auto& fl = b.contacts.at(0).flights;
  BOOST_REQUIRE(fl.size() >= 10u);
  double apex = kH;
  for (std::size_t i = 1; i < 10; ++i) {
    apex *= e * e;
    BOOST_TEST(std::abs(fl[i].max_gap - apex) < 1e-9 * kH, "flight " << i << " apex " << fl[i].max_gap << " exact " << apex);
  }
  // Event for event the energy-form ball's; the horizontal motion is untouched (no friction).
  BOOST_REQUIRE_EQUAL(b.events.size(), r.events.size());
  for (std::size_t i = 0; i < b.events.size(); ++i) {
    BOOST_TEST(b.events[i].kind == r.events[i].kind);
    BOOST_TEST(std::abs(b.events[i].t - r.events[i].t) < 1e-12);
  }
  BOOST_TEST(std::abs(b.q_end[1] - r.q_end[0]) < 1e-12);
  BOOST_TEST(std::abs(b.q_end[0] - (0.3 + 0.2 * 2.0)) < 1e-12);
}

// A spatial ball (Euler parameters) dropped, sliding sideways and spinning, on a plane through a
// spatial `point_on_plane` joint (unilateral, restitution; frictionless): its centre's height over
// the plane follows the same series (impacts at the closed-form times, apexes e^(2k) H), the
// horizontal velocity is untouched by the frictionless impacts.
BOOST_AUTO_TEST_CASE(spatial_ball_on_a_point_on_plane_joint_bounces_as_the_geometric_series) {
  const double e = 0.7, r0 = 0.1;
  const auto d = modelfile::load_model_text(R"([model]
name = "ball3d"
[model.parameters]
m = 2.0
g = 9.81
r = 0.1
e_n = 0.7
[model.body.ground]
markers = { floor = [0, 0, "r"] }
[model.body.ball]
kind = "spatial"
mass = "m"
inertia = ["2/5*m*r^2", "2/5*m*r^2", "2/5*m*r^2"]
[model.joint.floor]
type = "point_on_plane"
marker1 = "floor"
body2 = "ball"
unilateral = true
restitution = "e_n"
[model.force.gravity]
type = "gravity"
g = [0, 0, "-g"]
)", "ball3d.toml");
  const auto& names = d->coordinates();
  Eigen::VectorXd q0 = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(names.size())), qd0 = q0;
  auto at = [&](const std::string& n) {
    for (std::size_t i = 0; i < names.size(); ++i)
      if (names[i] == n) return static_cast<Eigen::Index>(i);
    BOOST_FAIL("no coordinate " + n);
    return Eigen::Index(0);
  };
  q0[at("ball_z")] = r0 + kH;
  q0[at("ball_e0")] = 1.0;
  qd0[at("ball_x")] = 0.4;
  qd0[at("ball_e3")] = 1.5;  // spinning about z at 3 rad/s (e_dot = omega / 2 at e = (1, 0, 0, 0))
  auto m = d->instantiate({}, q0, 0.0);
  SimulationOptions o;
  o.rtol = o.atol = 1e-10;
  SwitchingOptions sw;
  sw.zeno_time = 1e-9;
  const auto b = run(*m, q0, qd0, 3.0, o, sw);
  BOOST_REQUIRE_MESSAGE(b.status == SimulationStatus::success, b.message);
  const double t1 = std::sqrt(2 * kH / kG), v1 = kG * t1;
  const auto impacts = events_of(b, ContactEventKind::impact);
  BOOST_REQUIRE(impacts.size() >= 8u);
  double t_exact = t1, v = v1;
  for (std::size_t i = 0; i < 8; ++i) {
    BOOST_TEST(std::abs(impacts[i].t - t_exact) < 1e-9 * t_exact, "impact " << i << " at " << impacts[i].t << " exact " << t_exact);
    BOOST_TEST(std::abs(impacts[i].vn_after - e * v) < 1e-8 * v1);
    BOOST_TEST(std::abs(impacts[i].normal - 2.0 * (1 + e) * v) < 1e-8 * v1);  // impulse m (1 + e) v
    t_exact += 2 * e * v / kG;
    v *= e;
  }
  const auto& fl = b.contacts.at(0).flights;
  BOOST_REQUIRE(fl.size() >= 8u);
  double apex = kH;
  for (std::size_t i = 1; i < 8; ++i) {
    apex *= e * e;
    BOOST_TEST(std::abs(fl[i].max_gap - apex) < 1e-8 * kH, "flight " << i << " apex " << fl[i].max_gap << " exact " << apex);
  }
  BOOST_TEST(std::abs(b.qd_end[at("ball_x")] - 0.4) < 1e-10);
  BOOST_TEST(std::abs(b.q_end[at("ball_x")] - 1.2) < 1e-9);
  // It rests on the plane after the accumulation time t1 (1 + e) / (1 - e), still spinning.
  BOOST_TEST(std::abs(b.q_end[at("ball_z")] - r0) < 1e-12);
  BOOST_TEST(!events_of(b, ContactEventKind::accumulation).empty());
}

// Issue 22 (WHL): an upright coin (models/contact/coin_bodies.toml, a frictionless spatial
// `wheel`, no_slip = false, unilateral with e_n) dropped from H while sliding sideways and
// spinning about its axis. Upright, the contact point is straight below the centre, so the
// normal impulses have no moment about it and the gap's gradient has no Euler-parameter part
// (sigma = |w1 x a| is at its maximum 1): the centre's height follows the ball's geometric
// series (impacts at the closed-form times, rebounds e^k v1, impulses m (1 + e) e^(k-1) v1,
// apexes e^(2k) H), the horizontal velocity and the spin are untouched, and the Euler
// parameters at the end are the closed form e0 (x) (cos(s t/2), 0, 0, sin(s t/2)). The same at
// the plane's origin and 1000 m away from it on every axis (the gap's rounding there,
// 100 eps 1000 = 2e-11 m, moves an event by < 1e-11 s).
BOOST_AUTO_TEST_CASE(upright_coin_on_a_frictionless_wheel_joint_bounces_as_the_geometric_series) {
  const double e = 0.7, m = 0.01, r = 0.012, vx = 0.3, spin = 20.0, T = 2.4;
  const double c45 = std::sqrt(0.5);
  for (double off : {0.0, 1000.0}) {
    BOOST_TEST_CONTEXT("plane at (" << off << ", " << -off << ", " << off << ")") {
      const auto d = modelfile::load_model_file(std::string(PCSIM_SOURCE_DIR) + "/models/contact/coin_bodies.toml");
      const auto& names = d->coordinates();
      auto at = [&](const std::string& n) {
        for (std::size_t i = 0; i < names.size(); ++i)
          if (names[i] == n) return static_cast<Eigen::Index>(i);
        BOOST_FAIL("no coordinate " + n);
        return Eigen::Index(0);
      };
      Eigen::VectorXd q0 = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(names.size())), qd0 = q0;
      q0[at("coin_x")] = off + 0.5;
      q0[at("coin_y")] = -off;
      q0[at("coin_z")] = off + r + kH;
      q0[at("coin_e0")] = c45;
      q0[at("coin_e1")] = c45;  // upright: the axis along ground -y
      qd0[at("coin_x")] = vx;
      qd0[at("coin_e2")] = -0.5 * c45 * spin;  // e_dot = e (x) (0, 0, 0, spin) / 2
      qd0[at("coin_e3")] = 0.5 * c45 * spin;
      const std::map<std::string, double> p{{"e_n", e}, {"m", m}, {"r", r}, {"X0", off}, {"Y0", -off}, {"Z0", off}};
      auto model = d->instantiate(p, q0, 0.0);
      SimulationOptions o;
      o.rtol = o.atol = 1e-10;
      SwitchingOptions sw;
      sw.zeno_time = 1e-9;
      const auto b = run(*model, q0, qd0, T, o, sw);
      BOOST_REQUIRE_MESSAGE(b.status == SimulationStatus::success, b.message);
      const double t1 = std::sqrt(2 * kH / kG), v1 = kG * t1;
      const auto impacts = events_of(b, ContactEventKind::impact);
      BOOST_REQUIRE(impacts.size() >= 8u);
      double t_exact = t1, v = v1;
      for (std::size_t i = 0; i < 8; ++i) {
        BOOST_TEST(std::abs(impacts[i].t - t_exact) < 1e-9 * t_exact, "impact " << i << " at " << impacts[i].t << " exact " << t_exact);
        BOOST_TEST(std::abs(impacts[i].vn_after - e * v) < 1e-8 * v1);
        BOOST_TEST(std::abs(impacts[i].normal - m * (1 + e) * v) < 1e-8 * m * v1);
        t_exact += 2 * e * v / kG;
        v *= e;
      }
      BOOST_TEST(events_of(b, ContactEventKind::lift_off).empty());  // rebounds only
      const auto& fl = b.contacts.at(0).flights;
      BOOST_REQUIRE(fl.size() >= 8u);
      double apex = kH;
      for (std::size_t i = 1; i < 8; ++i) {
        apex *= e * e;
        BOOST_TEST(std::abs(fl[i].max_gap - apex) < 1e-8 * kH, "flight " << i << " apex " << fl[i].max_gap << " exact " << apex);
      }
      BOOST_TEST(std::abs(b.qd_end[at("coin_x")] - vx) < 1e-10);
      BOOST_TEST(std::abs(b.q_end[at("coin_x")] - (off + 0.5 + vx * T)) < 1e-9 * (1 + off));
      BOOST_TEST(std::abs(b.q_end[at("coin_y")] + off) < 1e-9 * (1 + off));
      // Energy: the impacts' losses (events.csv's energy_lost) are the drop of m g z + m z_d^2 / 2
      // (the horizontal motion and the spin keep their kinetic energy).
      double lost = 0.0;
      for (const auto& ev : b.events) lost += ev.energy_lost;
      const double dE = m * kG * (b.q_end[at("coin_z")] - q0[at("coin_z")]) + 0.5 * m * std::pow(b.qd_end[at("coin_z")], 2);
      BOOST_TEST(std::abs(lost + dE) < 1e-9 * m * kG * kH, "lost " << lost << " J, energy change " << dE << " J");
      const double C = std::cos(spin * T / 2), S = std::sin(spin * T / 2);
      const double ex[4] = {c45 * C, c45 * C, -c45 * S, c45 * S};
      const char* en[4] = {"coin_e0", "coin_e1", "coin_e2", "coin_e3"};
      for (int k = 0; k < 4; ++k)
        BOOST_TEST(std::abs(b.q_end[at(en[k])] - ex[k]) < 1e-8, en[k] << " " << b.q_end[at(en[k])] << " exact " << ex[k]);
    }
  }
}
