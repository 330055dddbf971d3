// Coulomb friction in a plane: a 2-D cone (two friction rows at one contact; docs/switching.md
// "2-D Coulomb cone") against exact solutions. models/contact/particle_plane.toml is a puck on a
// plane 250 m up, launched 1000 m from the origin; tests/mech/contacts/models/dumbbell_plane.toml
// two of them on a rod, 120 m down. Between events the straight-line motions are polynomial in t
// (constant or linear accelerations), which the integrators reproduce to rounding: tolerances
// 1e-10 relative. The motion on the incline is not polynomial: its invariant v (1 + cos phi) is
// held to the integration's accuracy (rtol 1e-10, checked to 1e-8). On spatial joints (bodies):
// a spinning puck (point_on_plane), a coin (wheel) and a billiard ball with sidespin (ball) set
// down sliding, each against its closed form.
#define BOOST_TEST_MODULE switching_plane_friction
#include <boost/test/unit_test.hpp>

#include <cmath>

#include "switching_util.hpp"

using namespace switching_test;

namespace {
constexpr double kG = 9.81, kM = 0.5, kZ0 = 250.0;
Eigen::VectorXd v3(double a, double b, double c) { return Eigen::Vector3d(a, b, c); }

std::shared_ptr<const Model> dumbbell(const std::map<std::string, double>& p) {
  const auto d = modelfile::load_model_file(std::string(PCSIM_SOURCE_DIR) +
                                            "/tests/mech/contacts/models/dumbbell_plane.toml");
  return d->instantiate(p, Eigen::VectorXd(), 0.0);
}
}  // namespace

BOOST_AUTO_TEST_CASE(a_puck_on_a_level_plane_slides_on_a_straight_line_and_stops_at_the_closed_form_instant) {
  const double mu_k = 0.3, vx = 1.2, vy = -1.6, v0 = std::hypot(vx, vy);
  for (OdeMethod method : {OdeMethod::radau, OdeMethod::explicit_rk}) {
    auto m = contact_model("particle_plane", {{"mu_s", 0.4}, {"mu_k", mu_k}});
    SimulationOptions o;
    o.method = method;
    o.rtol = o.atol = 1e-10;
    Trace tr;
    const auto r = run(*m, v3(1000.0, -500.0, kZ0), v3(vx, vy, 0.0), 1.0, o, {}, &tr);
    BOOST_REQUIRE_MESSAGE(r.status == SimulationStatus::success, r.message);
    const double ts = v0 / (mu_k * kG), d = v0 * v0 / (2 * mu_k * kG);
    BOOST_REQUIRE_EQUAL(r.events.size(), 1u);
    BOOST_TEST(r.events[0].kind == ContactEventKind::stick);
    BOOST_TEST(std::abs(r.events[0].t - ts) < 1e-12);
    BOOST_TEST(std::abs(r.q_end[0] - (1000.0 + d * vx / v0)) < 1e-10 * d);
    BOOST_TEST(std::abs(r.q_end[1] - (-500.0 + d * vy / v0)) < 1e-10 * d);
    BOOST_TEST(r.qd_end.norm() < 1e-12);
    BOOST_TEST(std::abs(r.contacts[0].run.slip_distance - d) < 1e-9 * d);
    // All the kinetic energy went into friction.
    BOOST_TEST(std::abs(r.contacts[0].run.energy_friction - 0.5 * kM * v0 * v0) < 1e-9 * kM * v0 * v0);
    // In slip the friction force is mu_k m g against the velocity: R_x/R_y = v_x/v_y.
    for (std::size_t i = 0; i < tr.t.size(); ++i) {
      if (tr.modes[i][0] != ContactMode::slip || tr.t[i] > 0.9 * ts) continue;
      const double s = tr.qd[i].head<2>().norm();
      BOOST_TEST(std::abs(tr.R[i][0] + mu_k * kM * kG * tr.qd[i][0] / s) < 1e-9 * kM * kG);
      BOOST_TEST(std::abs(tr.R[i][1] + mu_k * kM * kG * tr.qd[i][1] / s) < 1e-9 * kM * kG);
      BOOST_TEST(std::abs(tr.R[i][2] - kM * kG) < 1e-9 * kM * kG);
    }
  }
}

BOOST_AUTO_TEST_CASE(on_a_slope_with_mu_equal_to_tan_alpha_a_puck_launched_across_it_keeps_v_times_one_plus_cos_phi) {
  const double alpha = 0.4, mu = std::tan(alpha), v0 = 2.0;
  auto m = contact_model("particle_plane", {{"alpha", alpha}, {"mu_s", mu}, {"mu_k", mu}});
  SimulationOptions o;
  o.rtol = o.atol = 1e-10;
  Trace tr;
  const double T = 6.0;
  const auto r = run(*m, v3(-300.0, 700.0, kZ0), v3(v0, 0.0, 0.0), T, o, {}, &tr);
  BOOST_REQUIRE_MESSAGE(r.status == SimulationStatus::success, r.message);
  // The direction turns from across the slope (phi = 90 deg) towards down it: each time it has
  // turned 90 deg from its reference the reference is renewed (no event is recorded).
  BOOST_TEST(r.events.empty());
  double worst = 0.0;
  for (std::size_t i = 0; i < tr.t.size(); ++i) {
    BOOST_TEST(tr.modes[i][0] == ContactMode::slip);
    const double vx = tr.qd[i][0], vy = tr.qd[i][1], v = std::hypot(vx, vy);
    worst = std::max(worst, std::abs(v * (1.0 + vy / v) - v0) / v0);
  }
  BOOST_TEST_MESSAGE("v (1 + cos phi) = v0 within " << worst << " relative over " << T << " s");
  BOOST_TEST(worst < 1e-8);
  // The speed tends to v0 / 2 (4 % from it after 6 s) and the energy balance closes with the
  // friction work: T0 + V0 = T + V + W_friction.
  const double v_end = r.qd_end.head<2>().norm();
  BOOST_TEST(std::abs(v_end - 0.5 * v0) < 0.05 * v0);
  const double dV = -kM * kG * std::sin(alpha) * (r.q_end[1] - 700.0);
  const double dT = 0.5 * kM * (r.qd_end.squaredNorm() - v0 * v0);
  const double W = r.contacts[0].run.energy_friction;
  BOOST_TEST_MESSAGE("energy balance " << dT + dV + W << " J of friction work " << W << " J");
  BOOST_TEST(std::abs(dT + dV + W) < 1e-8 * W);
}

BOOST_AUTO_TEST_CASE(a_growing_force_breaks_static_friction_at_the_closed_form_instant_and_drags_the_puck_along_it) {
  const double mu_s = 0.4, mu_k = 0.3, k = 2.0, beta = 2.2, T = 2.0;
  auto m = contact_model("particle_plane", {{"mu_s", mu_s}, {"mu_k", mu_k}, {"k_F", k}, {"beta", beta}});
  SimulationOptions o;
  o.rtol = o.atol = 1e-10;
  const auto r = run(*m, v3(1000.0, -500.0, kZ0), v3(0.0, 0.0, 0.0), T, o);
  BOOST_REQUIRE_MESSAGE(r.status == SimulationStatus::success, r.message);
  const double t1 = mu_s * kM * kG / k;
  BOOST_REQUIRE_EQUAL(r.events.size(), 1u);
  BOOST_TEST(r.events[0].kind == ContactEventKind::slip);
  BOOST_TEST(std::abs(r.events[0].t - t1) < 1e-10);
  BOOST_TEST(std::abs(r.events[0].tangential - mu_s * kM * kG) < 1e-8);
  // Along beta: s'' = k t / m - mu_k g from t1 at rest.
  const double tau = T - t1;
  const double v = k / (2 * kM) * (T * T - t1 * t1) - mu_k * kG * tau;
  const double s = k / (6 * kM) * (T * T * T - t1 * t1 * t1) - k * t1 * t1 / (2 * kM) * tau - 0.5 * mu_k * kG * tau * tau;
  BOOST_TEST(std::abs(r.q_end[0] - (1000.0 + s * std::cos(beta))) < 1e-10 * s);
  BOOST_TEST(std::abs(r.q_end[1] - (-500.0 + s * std::sin(beta))) < 1e-10 * s);
  BOOST_TEST(std::abs(r.qd_end[0] - v * std::cos(beta)) < 1e-10 * v);
  BOOST_TEST(std::abs(r.qd_end[1] - v * std::sin(beta)) < 1e-10 * v);
}

// In slip the friction law -mu_k lambda_n v/|v| replaces two ideality rows: the paper's dense
// [G; D^T; friction] system and the structured solve give the closed form.
BOOST_AUTO_TEST_CASE(the_2d_friction_law_replaces_two_ideality_rows_in_both_formulations) {
  const double mu_k = 0.3;
  auto m = contact_model("particle_plane", {{"mu_s", 0.4}, {"mu_k", mu_k}});
  const double N = kM * kG;
  for (Kernel kern : {Kernel::fortran, Kernel::cpp}) {
    ReactionResult res[2];
    int i = 0;
    for (ReactionMethod meth : {ReactionMethod::compatibility, ReactionMethod::compatibility_structured}) {
      res[i] = switching_reactions(*m, {"contact", "slide_x", "slide_y"}, {ContactMode::slip}, {1}, 0.0,
                                   v3(1000.0, -500.0, kZ0), v3(0.6, -0.8, 0.0), meth, kern);
      BOOST_REQUIRE_MESSAGE(res[i].issue == ModelIssue::none, res[i].message);
      BOOST_TEST(std::abs(res[i].R[0] + 0.6 * mu_k * N) < 1e-12 * N);
      BOOST_TEST(std::abs(res[i].R[1] - 0.8 * mu_k * N) < 1e-12 * N);
      BOOST_TEST(std::abs(res[i].R[2] - N) < 1e-12 * N);
      ++i;
    }
    BOOST_TEST((res[0].qdd - res[1].qdd).cwiseAbs().maxCoeff() < 1e-12 * kG);
  }
}

BOOST_AUTO_TEST_CASE(a_dumbbell_pushed_across_its_rod_stops_with_both_cones_at_once) {
  const double mu_k = 0.3, L = 0.4, v0 = 1.5, z0 = -120.0;
  auto m = dumbbell({{"mu_k", mu_k}});
  Eigen::VectorXd q(6), qd(6);
  q << 400 - L, 900, z0, 400 + L, 900, z0;
  qd << 0, v0, 0, 0, v0, 0;
  SimulationOptions o;
  o.rtol = o.atol = 1e-10;
  const auto r = run(*m, q, qd, 1.0, o);
  BOOST_REQUIRE_MESSAGE(r.status == SimulationStatus::success, r.message);
  const double ts = v0 / (mu_k * kG), d = v0 * v0 / (2 * mu_k * kG);
  BOOST_REQUIRE_EQUAL(r.events.size(), 2u);
  for (const auto& e : r.events) {
    BOOST_TEST(e.kind == ContactEventKind::stick);
    BOOST_TEST(std::abs(e.t - ts) < 1e-12);
  }
  BOOST_TEST(std::abs(r.q_end[1] - (900 + d)) < 1e-10 * d);
  BOOST_TEST(std::abs(r.q_end[4] - (900 + d)) < 1e-10 * d);
  BOOST_TEST(r.qd_end.norm() < 1e-12);
}

BOOST_AUTO_TEST_CASE(a_spinning_dumbbell_turns_through_the_closed_form_angle_with_its_slip_directions_renewed) {
  const double mu_k = 0.3, L = 0.4, w0 = 9.0, z0 = -120.0;
  auto m = dumbbell({{"mu_k", mu_k}, {"L", L}});
  Eigen::VectorXd q(6), qd(6);
  q << 400 - L, 900, z0, 400 + L, 900, z0;
  qd << 0, -w0 * L, 0, 0, w0 * L, 0;
  SimulationOptions o;
  o.rtol = o.atol = 1e-10;
  Trace tr;
  const double ts = w0 * L / (mu_k * kG), theta = w0 * w0 * L / (2 * mu_k * kG);
  const auto r = run(*m, q, qd, ts + 0.5, o, {}, &tr);
  BOOST_REQUIRE_MESSAGE(r.status == SimulationStatus::success, r.message);
  const auto sticks = events_of(r, ContactEventKind::stick);
  BOOST_REQUIRE_EQUAL(sticks.size(), 2u);
  // Circular motion is not polynomial in t: the stop is as accurate as the integration
  // (rtol 1e-10 over 1.2 s), not to rounding.
  for (const auto& e : sticks) {
    BOOST_TEST_MESSAGE("stop at " << e.t << " s, closed form " << ts << " s");
    BOOST_TEST(std::abs(e.t - ts) < 3e-9);
  }
  BOOST_TEST(sticks.size() == r.events.size());  // the renewals of the direction are no events
  // The centre stays, the rod turned through theta (mod 2 pi).
  BOOST_TEST(std::abs(0.5 * (r.q_end[0] + r.q_end[3]) - 400.0) < 1e-9);
  BOOST_TEST(std::abs(0.5 * (r.q_end[1] + r.q_end[4]) - 900.0) < 1e-9);
  const double ang = std::atan2(r.q_end[4] - r.q_end[1], r.q_end[3] - r.q_end[0]);
  const double two_pi = 8 * std::atan(1.0);
  const double want = std::remainder(theta, two_pi);
  BOOST_TEST_MESSAGE("turned " << theta << " rad; end angle " << ang << ", closed form " << want);
  BOOST_TEST(std::abs(std::remainder(ang - want, two_pi)) < 3e-9);
  BOOST_TEST(r.qd_end.norm() < 1e-12);
}

// At impulse level the 2-D cone's law is the same: the tangential impulse stops the sliding if it
// can within mu_k Lambda_n, else it is mu_k Lambda_n against the sliding velocity after (for a
// particle, against v_t before). Newton's law gives Lambda_n = (1 + e) m sqrt(2 g h).
BOOST_AUTO_TEST_CASE(a_puck_landing_with_a_sliding_velocity_gets_the_coulomb_bounded_impulse_of_the_2d_cone) {
  const double mu_k = 0.3, e = 0.5, h = 0.2, vn = std::sqrt(2 * kG * h);
  for (double vt : {2.0, 0.1}) {  // slides on after the impact / stopped by it
    const double dir_x = 0.8, dir_y = -0.6;
    auto m = contact_model("particle_plane", {{"mu_s", 0.4}, {"mu_k", mu_k}, {"e_n", e}});
    SimulationOptions o;
    o.rtol = o.atol = 1e-10;
    const double tl = std::sqrt(2 * h / kG);
    const auto r = run(*m, v3(1000.0, -500.0, kZ0 + h), v3(vt * dir_x, vt * dir_y, 0.0), tl + 1e-3, o);
    BOOST_REQUIRE_MESSAGE(r.status == SimulationStatus::success, r.message);
    const auto imp = events_of(r, ContactEventKind::impact);
    BOOST_REQUIRE(!imp.empty());
    const auto& ev = imp[0];
    const double Ln = (1 + e) * kM * vn;
    // The gap z - 250 is known to its rounding, 100 eps 250 m = 5.6e-12 m: over vn = 2 m/s, 3e-12 s.
    BOOST_TEST(std::abs(ev.t - tl) < 1e-11);
    BOOST_TEST(std::abs(ev.normal - Ln) < 1e-10 * Ln);
    BOOST_TEST(std::abs(ev.vn_after - e * vn) < 1e-10 * vn);
    const double vt_after = std::max(vt - mu_k * Ln / kM, 0.0);
    BOOST_TEST_MESSAGE("v_t " << vt << " -> " << ev.vt_after << " (closed form " << vt_after << ")");
    BOOST_TEST(std::abs(ev.vt_after - vt_after) < 1e-10 * vt);
    BOOST_TEST(std::abs(ev.tangential - std::min(mu_k * Ln, kM * vt)) < 1e-10 * Ln);
    // The sliding velocity keeps its direction (or is gone); the energy lost is the drop of T.
    const double T_before = 0.5 * kM * (vt * vt + vn * vn), T_after = 0.5 * kM * (vt_after * vt_after + e * e * vn * vn);
    BOOST_TEST(std::abs(ev.energy_lost - (T_before - T_after)) < 1e-10 * T_before);
  }
}

// Two friction rows that are one sliding velocity written twice (a model's variants of one
// friction row, both activated) are refused before the run, naming both.
BOOST_AUTO_TEST_CASE(two_parallel_friction_rows_at_one_contact_are_refused) {
  const auto d = modelfile::load_model_file(std::string(PCSIM_SOURCE_DIR) +
                                            "/tests/mech/contacts/models/particle_line_twice.toml");
  auto m = d->instantiate({}, Eigen::Vector2d(3.0, 0.0), 0.0);
  const auto r = run(*m, Eigen::Vector2d(3.0, 0.0), Eigen::Vector2d(1.0, 0.0), 1.0);
  BOOST_TEST((r.status == SimulationStatus::invalid_model));
  BOOST_TEST_MESSAGE(r.message);
  BOOST_TEST(r.message.find("'slide' and 'slide_again'") != std::string::npos);
  BOOST_TEST(r.message.find("parallel") != std::string::npos);
  // One of them activated: the block slides and stops.
  SimulationOptions o;
  o.active_constraints = {"contact", "slide"};
  const auto r1 = run(*m, Eigen::Vector2d(3.0, 0.0), Eigen::Vector2d(1.0, 0.0), 1.0, o);
  BOOST_REQUIRE_MESSAGE(r1.status == SimulationStatus::success, r1.message);
  BOOST_TEST(events_of(r1, ContactEventKind::stick).size() == 1u);
}

// ---- The 2-D cone on spatial joints (bodies and joints, issue 22) ------------------------------

namespace {
std::shared_ptr<const modelfile::ModelDescription> body_model(const std::string& stem) {
  return modelfile::load_model_file(std::string(PCSIM_SOURCE_DIR) + "/models/contact/" + stem + ".toml");
}
Eigen::Index index_of(const modelfile::ModelDescription& d, const std::string& n) {
  const auto& names = d.coordinates();
  return static_cast<Eigen::Index>(std::find(names.begin(), names.end(), n) - names.begin());
}
// ė = ½ Eᵀ ω (E = [−e1 e0 −e3 e2; −e2 e3 e0 −e1; −e3 −e2 e1 e0]) and back, ω = 2 E ė.
Eigen::Matrix<double, 3, 4> E_of(const Eigen::Vector4d& e) {
  Eigen::Matrix<double, 3, 4> E;
  E << -e[1], e[0], -e[3], e[2], -e[2], e[3], e[0], -e[1], -e[3], -e[2], e[1], e[0];
  return E;
}
}  // namespace

// models/contact/puck_plane_bodies.toml: a spinning puck launched along ground x on a plane whose
// rows run 0.5 rad from it, 300 m out and 50 m up: the round cone brakes it along its velocity
// (a straight path; a square pyramid of the two rows would turn it), it stops at v0/(mu_k g)
// (one stick event, 1e-12 s) after v0²/(2 mu_k g) (1e-10 relative), and its spin is untouched
// (no drilling friction: the angle turned is wz T to 1e-7 rad; the Euler parameters turn as
// cos and sin of wz t/2, integrated at rtol 1e-10: observed 2.9e-8 rad over 1 s).
BOOST_AUTO_TEST_CASE(a_spinning_puck_body_slides_straight_across_the_rows_and_stops_at_the_closed_form_instant) {
  const auto d = body_model("puck_plane_bodies");
  const double mu_k = 0.3, v0 = 1.5, wz = 7.0, X0 = 300, Y0 = -200, Z0 = 50, T = 1.0;
  auto m = d->instantiate({{"mu_k", mu_k}});
  Eigen::VectorXd q = Eigen::VectorXd::Zero(m->n()), qd = q;
  q[index_of(*d, "puck_x")] = X0;
  q[index_of(*d, "puck_y")] = Y0;
  q[index_of(*d, "puck_z")] = Z0;
  q[index_of(*d, "puck_e0")] = 1.0;
  qd[index_of(*d, "puck_x")] = v0;
  const Eigen::Vector4d e0(1, 0, 0, 0);
  const Eigen::Vector4d ed0 = 0.5 * E_of(e0).transpose() * Eigen::Vector3d(0, 0, wz);
  for (int k = 0; k < 4; ++k) qd[index_of(*d, "puck_e" + std::to_string(k))] = ed0[k];
  SimulationOptions o;
  o.rtol = o.atol = 1e-10;
  const auto r = run(*m, q, qd, T, o);
  BOOST_REQUIRE_MESSAGE(r.status == SimulationStatus::success, r.message);
  const double ts = v0 / (mu_k * kG), dist = v0 * v0 / (2 * mu_k * kG);
  BOOST_REQUIRE_EQUAL(r.events.size(), 1u);
  BOOST_TEST(r.events[0].kind == ContactEventKind::stick);
  BOOST_TEST(std::abs(r.events[0].t - ts) < 1e-12);
  BOOST_TEST(std::abs(r.q_end[index_of(*d, "puck_x")] - (X0 + dist)) < 1e-10 * dist);
  BOOST_TEST(std::abs(r.q_end[index_of(*d, "puck_y")] - Y0) < 1e-10 * dist);
  BOOST_TEST(std::abs(r.q_end[index_of(*d, "puck_z")] - Z0) < 1e-10);
  Eigen::Vector4d e;
  for (int k = 0; k < 4; ++k) e[k] = r.q_end[index_of(*d, "puck_e" + std::to_string(k))];
  const double turned = 2 * std::atan2(e[3], e[0]);
  BOOST_TEST_MESSAGE("puck: stop " << r.events[0].t - ts << " s from the closed form, spin turned " << turned
                     << " rad, wz T = " << std::remainder(wz * T, 8 * std::atan(1.0)));
  BOOST_TEST(std::abs(std::remainder(turned - wz * T, 8 * std::atan(1.0))) < 1e-7);
}

// models/contact/coin_friction_bodies.toml: an upright coin (a thin disk, J = m r²/2) set down
// 1000 m out moving at vx0 and turning at wy0, its contact point sliding at vs = vx0 − r wy0: the
// cone's friction mu_k m g brakes the sliding at 3 mu_k g, so the coin rolls from
// t* = vs/(3 mu_k g) (one stick event) at (2 vx0 + r wy0)/3, the perfectly rough coin's velocity;
// the friction work is the drop of T (1e-9). The centre's motion is polynomial, but the Euler
// parameters turn as cos and sin of the rolling angle, integrated at rtol 1e-11: the instant to
// 1e-9 relative and the rolling velocity to 5e-10 (observed 4.6e-10 and 2.0e-10).
BOOST_AUTO_TEST_CASE(a_coin_body_sliding_on_its_rim_rolls_from_the_closed_form_instant) {
  const auto d = body_model("coin_friction_bodies");
  const double r = 0.012, mm = 0.01, mu_k = 0.2, vx0 = 0.4, wy0 = 10.0, off = 1000.0, T = 0.2;
  auto model = d->instantiate({{"mu_k", mu_k}, {"A", 0.0}, {"X0", off}, {"Y0", off}, {"Z0", -off}});
  Eigen::VectorXd q = Eigen::VectorXd::Zero(model->n()), qd = q;
  const double c45 = std::sqrt(0.5);
  const Eigen::Vector4d e0(c45, c45, 0, 0);  // axis along ground -y
  q[index_of(*d, "coin_x")] = off;
  q[index_of(*d, "coin_y")] = off;
  q[index_of(*d, "coin_z")] = -off + r;
  qd[index_of(*d, "coin_x")] = vx0;
  const Eigen::Vector4d ed0 = 0.5 * E_of(e0).transpose() * Eigen::Vector3d(0, wy0, 0);
  for (int k = 0; k < 4; ++k) {
    q[index_of(*d, "coin_e" + std::to_string(k))] = e0[k];
    qd[index_of(*d, "coin_e" + std::to_string(k))] = ed0[k];
  }
  SimulationOptions o;
  o.rtol = o.atol = 1e-11;
  const auto b = run(*model, q, qd, T, o);
  BOOST_REQUIRE_MESSAGE(b.status == SimulationStatus::success, b.message);
  const double vs = vx0 - r * wy0, ts = vs / (3 * mu_k * kG), v1 = (2 * vx0 + r * wy0) / 3;
  BOOST_REQUIRE_EQUAL(b.events.size(), 1u);
  BOOST_TEST(b.events[0].kind == ContactEventKind::stick);
  BOOST_TEST(std::abs(b.events[0].t - ts) < 1e-9 * ts, "rolls from " << b.events[0].t << ", closed form " << ts);
  BOOST_TEST(std::abs(b.qd_end[index_of(*d, "coin_x")] - v1) < 5e-10 * v1);
  Eigen::Vector4d e, ed;
  for (int k = 0; k < 4; ++k) {
    e[k] = b.q_end[index_of(*d, "coin_e" + std::to_string(k))];
    ed[k] = b.qd_end[index_of(*d, "coin_e" + std::to_string(k))];
  }
  const Eigen::Vector3d w = 2 * E_of(e) * ed;
  BOOST_TEST(std::abs(w[1] * r - v1) < 5e-10 * v1);
  const double J = mm * r * r / 2;
  const double T0 = 0.5 * mm * vx0 * vx0 + 0.5 * J * wy0 * wy0, T1 = 0.5 * mm * v1 * v1 + 0.5 * J * (v1 / r) * (v1 / r);
  const double W = b.contacts[0].run.energy_friction;
  BOOST_TEST_MESSAGE("coin: rolls from " << b.events[0].t - ts << " s off the closed form at " << b.qd_end[index_of(*d, "coin_x")] - v1
                     << " m/s off; friction work " << W << " J, drop of T " << T0 - T1 << " J");
  BOOST_TEST(std::abs(W - (T0 - T1)) < 1e-9 * (T0 - T1));
}

// models/contact/billiard_ball_bodies.toml (a `ball` joint with unilateral, mu_static, mu_kinetic:
// its no-slip rows are the cone's two friction rows): a homogeneous ball (J = 2/5 m R²) set down on
// the cloth 500 m from the origin with centre velocity v0 = (1.2, −0.5) m/s and spin
// w0 = (10, 20, 15) rad/s (15 rad/s of sidespin about the normal). Its contact point slides at
// u = v + w × (−R z). In slip the friction force is −mu_k m g û (û = u/|u|), so
//   dv/dt = −mu_k g û,   dw/dt = (−R z) × (−mu_k m g û) / J = (5 mu_k g / 2R) z × û,
//   du/dt = dv/dt + R z × dw/dt = −mu_k g û − (5/2) mu_k g û = −(7/2) mu_k g û:
// u keeps its direction and shrinks at (7/2) mu_k g, so the ball rolls from t* = 2|u0|/(7 mu_k g)
// (one stick event) at v_f = v0 − mu_k g t* û = v0 − (2/7) u0, with w_h = z × v_f / R and the
// sidespin w_z unchanged (the friction's moment about the centre is horizontal: no drilling
// friction); then it rolls on uniformly (no force on a rolling ball on a level plane). The friction
// work mu_k m g ∫|u| dt = m |u0|²/7 is the drop of T. The centre's motion is polynomial in t (1e-10
// relative, as the puck's); the Euler parameters turn as cos and sin of angles growing with t,
// integrated at rtol 1e-11, so the stick instant (located on them) and the spin are held to the
// integration's accuracy, bounded at 1e-9 relative (measured, Release: t* 1.2e-11, the spin
// 2.2e-11, the centre 7.5e-12 in position and 2.1e-11 in velocity, the direction of u 1.2e-12).
BOOST_AUTO_TEST_CASE(a_billiard_ball_set_down_skidding_rolls_from_the_closed_form_instant_keeping_its_sidespin) {
  const auto d = body_model("billiard_ball_bodies");
  const double m = 0.17, R = 0.0286, mu_k = 0.2, T = 0.3, J = 0.4 * m * R * R;
  const Eigen::Vector3d X0(400.0, -300.0, 120.0), v0(1.2, -0.5, 0.0), w0(10.0, 20.0, 15.0), z(0, 0, 1);
  auto model = d->instantiate({{"mu_k", mu_k}});
  Eigen::VectorXd q = Eigen::VectorXd::Zero(model->n()), qd = q;
  const Eigen::Index ib = index_of(*d, "ball_x");
  const Eigen::Vector4d e0(1, 0, 0, 0);
  q.segment<3>(ib) = X0 + R * z;
  q.segment<4>(ib + 3) = e0;
  qd.segment<3>(ib) = v0;
  qd.segment<4>(ib + 3) = 0.5 * E_of(e0).transpose() * w0;
  SimulationOptions o;
  o.rtol = o.atol = 1e-11;
  Trace tr;
  const auto b = run(*model, q, qd, T, o, {}, &tr);
  BOOST_REQUIRE_MESSAGE(b.status == SimulationStatus::success, b.message);
  const Eigen::Vector3d u0 = v0 + w0.cross(-R * z), uh = u0.normalized();
  const double ts = 2 * u0.norm() / (7 * mu_k * kG);
  const Eigen::Vector3d vf = v0 - 2.0 / 7.0 * u0, wf = z.cross(vf) / R + w0[2] * z;
  const Eigen::Vector3d xf = X0 + R * z + v0 * ts - 0.5 * mu_k * kG * ts * ts * uh + vf * (T - ts);
  BOOST_REQUIRE_EQUAL(b.events.size(), 1u);
  BOOST_TEST(b.events[0].kind == ContactEventKind::stick);
  const double err_ts = std::abs(b.events[0].t - ts) / ts;
  const double err_x = (b.q_end.segment<3>(ib) - xf).norm() / (xf - X0).norm();
  const double err_v = (b.qd_end.segment<3>(ib) - vf).norm() / vf.norm();
  const Eigen::Vector4d e = b.q_end.segment<4>(ib + 3), ed = b.qd_end.segment<4>(ib + 3);
  const Eigen::Vector3d w = 2 * E_of(e) * ed;
  const double err_w = (w - wf).norm() / wf.norm();
  // In slip: u along û0, |u| = |u0| - (7/2) mu_k g t, and the friction force -mu_k m g û on the
  // centre (the generalized reactions of ball_x, ball_y).
  double err_dir = 0, err_u = 0, err_R = 0;
  int slipping = 0;
  for (std::size_t i = 0; i < tr.t.size(); ++i) {
    if (tr.modes[i][0] != ContactMode::slip || tr.t[i] > 0.9 * ts) continue;
    ++slipping;
    const Eigen::Vector3d wi = 2 * E_of(tr.q[i].segment<4>(ib + 3)) * tr.qd[i].segment<4>(ib + 3);
    const Eigen::Vector3d ui = tr.qd[i].segment<3>(ib) + wi.cross(-R * z);
    err_dir = std::max(err_dir, ui.cross(uh).norm() / u0.norm());
    err_u = std::max(err_u, std::abs(ui.norm() - (u0.norm() - 3.5 * mu_k * kG * tr.t[i])) / u0.norm());
    for (int k = 0; k < 2; ++k)
      err_R = std::max(err_R, std::abs(tr.R[i][ib + k] + mu_k * m * kG * uh[k]) / (mu_k * m * kG));
  }
  const double T0 = 0.5 * m * v0.squaredNorm() + 0.5 * J * w0.squaredNorm();
  const double T1 = 0.5 * m * b.qd_end.segment<3>(ib).squaredNorm() + 0.5 * J * w.squaredNorm();
  const double W = b.contacts[0].run.energy_friction, W_closed = m * u0.squaredNorm() / 7;
  BOOST_TEST_MESSAGE("billiard ball: rolls from t* " << err_ts << " rel. off; centre at T " << err_x << ", velocity "
                     << err_v << ", spin " << err_w << " rel.; in slip (" << slipping << " steps) u off its direction "
                     << err_dir << ", |u| " << err_u << ", friction force " << err_R << " rel.; friction work " << W
                     << " J: closed form m|u0|^2/7 " << (W - W_closed) / W_closed << " rel., drop of T "
                     << (W - (T0 - T1)) / W_closed << " rel.");
  BOOST_TEST(slipping > 3);
  BOOST_TEST(err_ts < 1e-9);
  BOOST_TEST(err_x < 1e-10);
  BOOST_TEST(err_v < 1e-10);
  BOOST_TEST(std::abs(b.q_end[ib + 2] - (X0[2] + R)) < 1e-12);
  BOOST_TEST(err_w < 1e-9);
  BOOST_TEST(err_dir < 1e-10);
  BOOST_TEST(err_u < 1e-10);
  BOOST_TEST(err_R < 1e-10);
  BOOST_TEST(std::abs(W - W_closed) < 1e-9 * W_closed);
  BOOST_TEST(std::abs(W - (T0 - T1)) < 1e-9 * W_closed);
}
