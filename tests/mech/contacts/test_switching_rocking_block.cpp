// A rigid block rocking on a rigid floor (models/contact/rocking_block.toml; Housner 1963):
// released tilted by theta0 on its left corner, it rotates about that corner (the corner
// sticks), hits the floor with the right corner at theta = 0, and with e_n = 0 continues about
// the right corner with the angular velocity multiplied by Housner's 1 - (3/2) sin^2(alpha),
// alpha = atan(b/h) (angular momentum about the impacting corner is conserved; the left corner
// lifts off). The impact involves both corners, so the mode decision is an LCP solved by
// Siconos (Lemke, and the enumerative solver). Oracles: the rotation time from theta0 to 0 by
// quadrature of dt = dtheta / omega(theta) (energy about the corner), the speed at impact from
// the energy, Housner's factor, and the second impact after the swing to the other side.
#define BOOST_TEST_MODULE switching_rocking_block
#include <boost/test/unit_test.hpp>

#include <cmath>

#include "switching_util.hpp"

using namespace switching_test;

namespace {
constexpr double kG = 9.81, kB = 0.1, kH = 0.3, kM = 10.0;
const double kR2 = kB * kB + kH * kH;
const double kJO = 4.0 / 3.0 * kM * kR2;  // about a corner

// Time to rotate about a corner from rest at |theta| = th0 to theta = 0: t = int dtheta / w,
// w(theta)^2 = 2 m g (y(th0) - y(theta)) / J_O, y(theta) = b sin(theta) + h cos(theta), with
// theta = th0 - s^2 (smooth integrand 2 s / w) and composite Gauss-Legendre (5 points, 400 panels).
double fall_time(double th0) {
  auto y = [](double th) { return kB * std::sin(th) + kH * std::cos(th); };
  const double smax = std::sqrt(th0);
  auto f = [&](double s) {
    if (s == 0.0) {  // w ~ s sqrt(2 m g y'(th0) / J_O)
      const double dy = kB * std::cos(th0) - kH * std::sin(th0);
      return 2.0 / std::sqrt(2 * kM * kG * dy / kJO);
    }
    const double th = th0 - s * s;
    return 2.0 * s / std::sqrt(2 * kM * kG * (y(th0) - y(th)) / kJO);
  };
  const double x[5] = {0.0, -0.5384693101056831, 0.5384693101056831, -0.9061798459386640, 0.9061798459386640};
  const double w[5] = {0.5688888888888889, 0.4786286704993665, 0.4786286704993665, 0.2369268850561891, 0.2369268850561891};
  const int P = 400;
  double sum = 0.0;
  for (int p = 0; p < P; ++p) {
    const double a = smax * p / P, b = smax * (p + 1) / P;
    for (int k = 0; k < 5; ++k) sum += 0.5 * (b - a) * w[k] * f(0.5 * (a + b) + 0.5 * (b - a) * x[k]);
  }
  return sum;
}
}  // namespace

BOOST_AUTO_TEST_CASE(impact_on_the_other_corner_follows_housner) {
  const double th0 = 0.1;
  for (lcp::LcpSolver solver : {lcp::LcpSolver::lemke, lcp::LcpSolver::enumerative}) {
    auto m = contact_model("rocking_block", {{"b", kB}, {"h", kH}, {"m", kM}, {"e_n", 0.0}, {"mu", 1.0}});
    const Eigen::Vector3d q0(0.0, kB * std::sin(th0) + kH * std::cos(th0), th0);
    SimulationOptions o;
    o.rtol = o.atol = 1e-11;
    SwitchingOptions sw;
    sw.lcp_solver = solver;
    const auto r = run(*m, q0, Eigen::Vector3d::Zero(), 1.2, o, sw);
    BOOST_TEST_CONTEXT("solver " << int(solver)) {
      BOOST_REQUIRE_MESSAGE(r.status == SimulationStatus::success, r.message);
      BOOST_TEST(r.lcp_solves > 0);
      const auto impacts = events_of(r, ContactEventKind::impact);
      const auto lifts = events_of(r, ContactEventKind::lift_off);
      BOOST_REQUIRE(impacts.size() >= 2u);
      BOOST_REQUIRE(lifts.size() >= 2u);
      const double t1 = fall_time(th0);
      BOOST_TEST(impacts[0].constraint == "right");
      BOOST_TEST(lifts[0].constraint == "left");
      BOOST_TEST(std::abs(impacts[0].t - t1) < 1e-8, "first impact " << impacts[0].t << ", quadrature " << t1);
      BOOST_TEST(lifts[0].t == impacts[0].t);
      // Speed at impact from the energy, and Housner's factor after it. At theta = 0 a corner
      // rotating about the other one moves normal to the floor at 2 b omega.
      const double w_before = std::sqrt(2 * kM * kG * (kB * std::sin(th0) + kH * std::cos(th0) - kH) / kJO);
      const double factor = 1.0 - 1.5 * kB * kB / kR2;
      BOOST_TEST(std::abs(-impacts[0].vn_before - 2 * kB * w_before) < 1e-8);
      BOOST_TEST(std::abs(lifts[0].vn_after - 2 * kB * w_before * factor) < 1e-8,
                 "left corner lifts at " << lifts[0].vn_after << ", Housner " << 2 * kB * w_before * factor);
      BOOST_TEST(std::abs(impacts[0].vn_after) < 1e-12);
      BOOST_TEST(std::abs(impacts[0].vt_after) < 1e-12);  // the new corner sticks
      // The swing about the right corner: up to |theta_max| where the energy is spent, back to 0:
      // the second impact (left corner) after twice the fall time from |theta_max|.
      const double E = 0.5 * kJO * std::pow(w_before * factor, 2) / (kM * kG);  // height gained
      double lo = 0.0, hi = 0.3;  // b sin(th) + h cos(th) - h = E
      for (int it = 0; it < 200; ++it) {
        const double mid = 0.5 * (lo + hi);
        (kB * std::sin(mid) + kH * std::cos(mid) - kH < E ? lo : hi) = mid;
      }
      const double t2 = t1 + 2 * fall_time(0.5 * (lo + hi));
      BOOST_TEST(impacts[1].constraint == "left");
      BOOST_TEST(std::abs(impacts[1].t - t2) < 1e-7, "second impact " << impacts[1].t << ", quadrature " << t2);
      BOOST_TEST_MESSAGE("Siconos solver " << int(solver) << ": impacts at " << impacts[0].t << " and " << impacts[1].t
                                           << " s (quadrature " << t1 << ", " << t2 << "); " << r.lcp_solves << " LCPs");
    }
  }
}

// Each impact takes energy (Housner's factor squared per impact at small amplitude) and the
// intervals between impacts shrink geometrically: the impacts accumulate in finite time. The
// accumulation rule closes both corners there (SwitchingOptions::zeno_time) and the block
// rests on both, carrying its weight, with no event afterwards (no stall: a few dozen LCPs).
BOOST_AUTO_TEST_CASE(rocking_accumulates_and_the_block_rests_on_both_corners) {
  const double th0 = 0.1;
  auto m = contact_model("rocking_block", {{"b", kB}, {"h", kH}, {"m", kM}, {"e_n", 0.0}, {"mu", 1.0}});
  const Eigen::Vector3d q0(0.0, kB * std::sin(th0) + kH * std::cos(th0), th0);
  SimulationOptions o;
  o.rtol = o.atol = 1e-10;
  Trace tr;
  const auto r = run(*m, q0, Eigen::Vector3d::Zero(), 3.0, o, {}, &tr);
  BOOST_REQUIRE_MESSAGE(r.status == SimulationStatus::success, r.message);
  const auto acc = events_of(r, ContactEventKind::accumulation);
  BOOST_REQUIRE(!acc.empty());
  const double t_rest = acc.back().t;
  BOOST_TEST_MESSAGE("rest from t = " << t_rest << " s after " << events_of(r, ContactEventKind::impact).size()
                                      << " impacts; " << r.lcp_solves << " LCPs, " << r.events.size() << " events");
  BOOST_TEST(t_rest < 2.1);
  BOOST_TEST(r.events.back().t <= t_rest + 1e-3);
  BOOST_TEST(r.lcp_solves < 200);
  BOOST_TEST(tr.modes.back()[0] == ContactMode::stick);
  BOOST_TEST(tr.modes.back()[1] == ContactMode::stick);
  BOOST_TEST(std::abs(tr.R.back()[1] - kM * kG) < 1e-9 * kM * kG);   // the weight
  BOOST_TEST(std::abs(tr.q.back()[2]) < 1e-12);                         // flat
  BOOST_TEST(r.qd_end.cwiseAbs().maxCoeff() < 1e-12);                   // at rest
}
