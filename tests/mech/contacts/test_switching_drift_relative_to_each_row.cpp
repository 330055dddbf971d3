// Issue 19, "tolerances relative to the quantities they compare": the drift a closed constraint
// may accumulate between projections (row_within_projection_tol, cpp/mech/projection.hpp) is
// relative to that row's own terms, never to the largest coordinate. Before, a state was left
// unprojected while every position residual was below projection_tol (1 + |q|∞), so a ball
// 1e5 m along a floor could sit 1e-8 m inside it, and a pendulum's rod was kept to a
// tolerance set by whatever coordinate was largest.
//  * A Cartesian pendulum hung at a pivot (px, py) far from the origin keeps its rod to the
//    same multiple of the rod's rounding scale (Σ_j |∂Φ/∂q_j| |q_j|) as at the origin, and moves
//    the same relative to its pivot (to the integrator's tolerance at the coordinates' size).
//  * A ball resting on a floor y ≥ X, at x = 0 or 1e5 along it: the penetration is set by X
//    (the gap's terms), not by x.
#define BOOST_TEST_MODULE switching_drift_relative_to_each_row
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <limits>
#include <random>
#include <string>

#include "mech/projection.hpp"
#include "switching_util.hpp"

using namespace switching_test;

namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();

std::shared_ptr<const Model> test_model(const std::string& stem, const std::map<std::string, double>& p) {
  const auto d = modelfile::load_model_file(std::string(PCSIM_SOURCE_DIR) + "/tests/mech/contacts/models/" + stem + ".toml");
  return d->instantiate(p, Eigen::VectorXd(), 0.0);
}

struct PendulumRun {
  /// max over accepted steps of |Φ| / (1 + Σ_j |∂Φ/∂q_j| |q_j|): the drift rule's own measure
  double res_over_scale_max = 0.0;
  double theta_end = NAN, omega_end = NAN;
  SimulationResult r;
};

PendulumRun pendulum(double px, double py) {
  const double L = 1.0, theta0 = 1.0;
  auto m = test_model("pendulum_offset_pivot", {{"px", px}, {"py", py}, {"L", L}});
  Eigen::VectorXd q0(2), qd0 = Eigen::VectorXd::Zero(2);
  q0 << px + L * std::sin(theta0), py - L * std::cos(theta0);
  SimulationOptions o;
  o.rtol = o.atol = 1e-10;
  o.t_end = 3.0;
  o.active_constraints = {"rod"};
  PendulumRun out;
  out.r = simulate(*m, q0, qd0, o, [&](const StepView& v) {
    const Sample& s = v.sample(v.t);
    const double dx = s.q(0) - px, dy = s.q(1) - py;
    const double phi = m->position_residual(0, v.t, s.q);
    const double scale = std::abs(2 * dx) * std::abs(s.q(0)) + std::abs(2 * dy) * std::abs(s.q(1));
    out.res_over_scale_max = std::max(out.res_over_scale_max, std::abs(phi) / (1.0 + scale));
    return true;
  });
  const double dx = out.r.q_end(0) - px, dy = out.r.q_end(1) - py;
  out.theta_end = std::atan2(dx, -dy);
  out.omega_end = (dx * out.r.qd_end(1) - dy * out.r.qd_end(0)) / (dx * dx + dy * dy);
  return out;
}

}  // namespace

BOOST_AUTO_TEST_CASE(pendulum_keeps_its_rod_to_its_own_rounding_wherever_it_hangs) {
  const PendulumRun ref = pendulum(0.0, 0.0);
  BOOST_REQUIRE_MESSAGE(ref.r.status == SimulationStatus::success, ref.r.message);
  const double tol = SimulationOptions{}.projection_tol;
  for (auto [px, py] : {std::pair{0.0, 0.0}, {1e3, 0.0}, {1e5, 0.0}, {1e5, -1e3}, {-1e5, 1e5}}) {
    const PendulumRun p = pendulum(px, py);
    BOOST_TEST_CONTEXT("pivot (" << px << ", " << py << ")") {
      BOOST_REQUIRE_MESSAGE(p.r.status == SimulationStatus::success, p.r.message);
      BOOST_TEST_MESSAGE("pivot (" << px << ", " << py << "): max |Phi|/scale " << p.res_over_scale_max
                         << ", theta_end - ref " << p.theta_end - ref.theta_end
                         << ", omega_end - ref " << p.omega_end - ref.omega_end
                         << ", steps " << p.r.stats.steps);
      // Every accepted state satisfies the rod to projection_tol of its own terms (a state left
      // alone passed that test; a projected one is within Newton's rounding of it). At the
      // origin the scale is 1 + 2 L² = 3, at 1e5 it is ~2e5: the same rule, no looser.
      BOOST_TEST(p.res_over_scale_max <= tol);
      // The motion relative to the pivot: the integrator controls the error of x, y to
      // rtol |q| + atol, i.e. 1e-10 (1 + |pivot|) m, so the angle may differ by that much
      // (a few times, over 3 s); the drift rule adds nothing beyond it.
      const double allowed = 20 * 1e-10 * (1 + std::max(std::abs(px), std::abs(py)));
      BOOST_TEST(std::abs(p.theta_end - ref.theta_end) <= allowed);
      BOOST_TEST(std::abs(p.omega_end - ref.omega_end) <= 10 * allowed);
    }
  }
}

BOOST_AUTO_TEST_CASE(ball_on_lifted_floor_penetrates_by_the_gaps_rounding_not_by_x) {
  const double tol = SimulationOptions{}.projection_tol;
  for (double X : {0.0, 1.0, 50.0}) {
    for (double x : {0.0, 1e3, 1e5}) {
      auto m = test_model("ball_far_along_lifted_floor", {{"X", X}, {"e_n", 0.8}});
      Eigen::VectorXd q0(2);
      q0 << x, X + 1.0;
      SimulationOptions o;
      o.rtol = o.atol = 1e-10;
      SwitchingOptions sw;
      sw.zeno_time = 1e-9;
      const SwitchingResult r = run(*m, q0, Eigen::VectorXd::Zero(2), 8.0, o, sw);
      BOOST_TEST_CONTEXT("X = " << X << ", x = " << x) {
        BOOST_REQUIRE_MESSAGE(r.status == SimulationStatus::success, r.message);
        const double pen = r.contacts.at(0).run.penetration_max;
        BOOST_TEST_MESSAGE("X = " << X << ", x = " << x << ": penetration_max " << pen
                           << " (" << pen / (kEps * (1.0 + X)) << " eps (1 + X)), residual_pos_max "
                           << r.residual_pos_max << ", gap_end " << r.contacts.at(0).gap_end);
        // The closed floor's drift is allowed projection_tol (1 + |y|) of its own terms: at the
        // floor y ≈ X that is 1e-13 (1 + X) (about 450 eps X for X >> 1); x does not enter.
        // The factor 1.5 covers the states at events (the event offset is of rounding size,
        // the contact class's 100 eps of the gap's terms).
        BOOST_TEST(pen <= 1.5 * tol * (1.0 + X));
        BOOST_TEST(r.residual_pos_max <= 1.5 * tol * (1.0 + X));
      }
    }
  }
}

// The rule itself, on generated rows: a coordinate that does not enter a row (g_ij = 0) never
// changes its verdict, however large; a residual of a few hundred roundings of the row's terms
// is accepted, one far beyond them refused. The old rule (projection_tol (1 + |q|∞)) accepted a
// floor y ≥ 0 drifted 1e-9 m inside as soon as some other coordinate was 1e5.
BOOST_AUTO_TEST_CASE(drift_rule_ignores_coordinates_outside_the_row) {
  const double tol = SimulationOptions{}.projection_tol;
  {
    Eigen::RowVectorXd g(2);
    g << 0.0, 1.0;  // the floor y >= 0
    Eigen::VectorXd q(2), qd = Eigen::VectorXd::Zero(2);
    q << 1e5, -1e-9;
    BOOST_TEST(!row_within_projection_tol(g, 0.0, true, q(1), 0.0, q, qd, tol));
    q(1) = -5e-14;
    BOOST_TEST(row_within_projection_tol(g, 0.0, true, q(1), 0.0, q, qd, tol));
    qd << 1e5, 1e-9;  // the gap rate 1e-9 m/s, whatever the speed along the floor
    BOOST_TEST(!row_within_projection_tol(g, 0.0, false, 0.0, 0.0, q, qd, tol));
  }
  std::mt19937_64 rng(19);
  std::uniform_real_distribution<double> u(-1.0, 1.0), e(-3.0, 5.0);
  int accepted = 0, refused = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const int n = 2 + trial % 5;
    Eigen::RowVectorXd g(n);
    Eigen::VectorXd q(n), qd(n);
    for (int j = 0; j < n; ++j) {
      g(j) = (j == 0) ? 0.0 : u(rng) * std::pow(10.0, e(rng));  // q_0 does not enter the row
      q(j) = u(rng) * std::pow(10.0, e(rng));
      qd(j) = u(rng) * std::pow(10.0, e(rng));
    }
    const double g0 = u(rng), t = 10 * std::abs(u(rng));
    const double scale = g.cwiseAbs().dot(q.cwiseAbs()) + std::abs(g0) * t;
    // A velocity on the row (adjust q̇ along the largest |g_j|; exact up to rounding).
    int jmax;
    g.cwiseAbs().maxCoeff(&jmax);
    qd(jmax) -= (g.dot(qd) + g0) / g(jmax);
    const double vscale = g.cwiseAbs().dot(qd.cwiseAbs()) + std::abs(g0);
    const double frac = std::pow(10.0, 2 * u(rng));  // residual / tolerance in [0.01, 100]
    const double phi = frac * tol * (1.0 + scale);
    const bool expected = frac <= 0.5 && std::abs(g.dot(qd) + g0) <= tol * (1.0 + vscale);
    if (frac > 0.5 && frac < 2.0) continue;  // too near the threshold for rounding of the scale
    const bool verdict = row_within_projection_tol(g, g0, true, phi, t, q, qd, tol);
    BOOST_TEST_CONTEXT("trial " << trial) {
      BOOST_TEST(verdict == expected);
      for (double big : {0.0, 1e5, -1e12}) {
        Eigen::VectorXd q2 = q, qd2 = qd;
        q2(0) = big;
        qd2(0) = -big;
        BOOST_TEST(row_within_projection_tol(g, g0, true, phi, t, q2, qd2, tol) == verdict);
      }
    }
    (verdict ? accepted : refused) += 1;
  }
  BOOST_TEST(accepted > 200);
  BOOST_TEST(refused > 200);
}
