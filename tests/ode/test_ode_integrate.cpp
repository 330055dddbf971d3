// ode_integrate, the method selection the engine calls for solver.method: radau and explicit
// run one method; auto runs the explicit pair and, where its stiffness test fires, continues
// with Radau to t_end, reporting both and the switch time. On van der Pol (eps = 1e-6) auto
// switches early and reaches Radau's accuracy against the published reference; on the
// Arenstorf orbit it never switches and equals the explicit run bitwise.
#define BOOST_TEST_MODULE ode_integrate
#include <boost/test/unit_test.hpp>

#include <cmath>

#include "problems.hpp"
#include "explicit_problems.hpp"
#include "ode/integrate.hpp"

using namespace pcsim;

BOOST_AUTO_TEST_CASE(method_names_parse_and_print) {
  BOOST_TEST((parse_ode_method("radau") == OdeMethod::radau));
  BOOST_TEST((parse_ode_method("explicit") == OdeMethod::explicit_rk));
  BOOST_TEST((parse_ode_method("auto") == OdeMethod::automatic));
  BOOST_TEST(!parse_ode_method("rk45").has_value());
  for (OdeMethod m : {OdeMethod::radau, OdeMethod::explicit_rk, OdeMethod::automatic})
    BOOST_TEST((parse_ode_method(to_string(m)) == m));
}

BOOST_AUTO_TEST_CASE(auto_switches_to_radau_on_van_der_pol_with_radau_accuracy) {
  auto vdp = testproblems::van_der_pol_published();
  for (Kernel k : {Kernel::fortran, Kernel::cpp}) {
    OdeOptions o;
    o.kernel = k;
    o.rtol = o.atol = 1e-6;
    long calls = 0;
    double t_prev = vdp.t0;
    bool monotone = true;
    const OdeResult a = ode_integrate(vdp.problem, vdp.t0, vdp.y0, vdp.t_end, o,
                                      OdeMethod::automatic, [&](StepInfo& s) {
                                        ++calls;
                                        monotone = monotone && s.t > t_prev;
                                        t_prev = s.t;
                                        return StepAction::proceed;
                                      });
    const OdeResult r = ode_integrate(vdp.problem, vdp.t0, vdp.y0, vdp.t_end, o, OdeMethod::radau);
    BOOST_REQUIRE(a.status == OdeStatus::success);
    BOOST_REQUIRE(r.status == OdeStatus::success);
    BOOST_TEST(a.used_explicit);
    BOOST_TEST(a.used_radau);
    BOOST_TEST((a.switch_time > 0.0 && a.switch_time < 1e-3), "switch at " << a.switch_time);
    BOOST_TEST(a.t == vdp.t_end);
    BOOST_TEST(calls == a.accepted);  // every accepted step of both phases reported, in order
    BOOST_TEST(monotone);
    BOOST_TEST(a.f_evals == a.explicit_stats.f_evals + a.radau_stats.f_evals);
    const double ea = testproblems::max_relative_error(a.y, vdp.y_ref);
    const double er = testproblems::max_relative_error(r.y, vdp.y_ref);
    BOOST_TEST_MESSAGE(to_string(k) << ": auto switched at t = " << a.switch_time << ", error "
                                    << ea << " (" << a.f_evals << " f-evaluations); radau error "
                                    << er << " (" << r.f_evals << ")");
    // Radau's accuracy: within 3x of Radau alone (observed 1.9e-7 vs 4.2e-7), at a cost
    // within 1.5x of Radau alone.
    BOOST_TEST(ea < 3.0 * er);
    BOOST_TEST(double(a.f_evals) < 1.5 * double(r.f_evals));
    BOOST_TEST(!r.used_explicit);
    BOOST_TEST(std::isnan(r.switch_time));
  }
}

BOOST_AUTO_TEST_CASE(auto_stays_explicit_on_a_non_stiff_problem) {
  using namespace explicit_problems;
  OdeOptions o;
  o.rtol = o.atol = 1e-9;
  const OdeResult a = ode_integrate(arenstorf_problem(), 0.0, arenstorf_y0(), kArenstorfPeriod,
                                    o, OdeMethod::automatic);
  const OdeResult e = ode_integrate(arenstorf_problem(), 0.0, arenstorf_y0(), kArenstorfPeriod,
                                    o, OdeMethod::explicit_rk);
  BOOST_REQUIRE(a.status == OdeStatus::success);
  BOOST_TEST(a.used_explicit);
  BOOST_TEST(!a.used_radau);
  BOOST_TEST(std::isnan(a.switch_time));
  BOOST_TEST(a.y == e.y);
  BOOST_TEST(a.f_evals == e.f_evals);
  // And it is the cheaper method here: Radau needs more f-evaluations for less accuracy.
  const OdeResult r = ode_integrate(arenstorf_problem(), 0.0, arenstorf_y0(), kArenstorfPeriod,
                                    o, OdeMethod::radau);
  BOOST_REQUIRE(r.status == OdeStatus::success);
  BOOST_TEST_MESSAGE("arenstorf 1e-9: explicit " << e.f_evals << " f-evaluations, error "
                     << (e.y - arenstorf_y0()).lpNorm<Eigen::Infinity>() << "; radau "
                     << r.f_evals << ", error " << (r.y - arenstorf_y0()).lpNorm<Eigen::Infinity>());
  BOOST_TEST(e.f_evals < r.f_evals);
}

BOOST_AUTO_TEST_CASE(daes_go_to_radau) {
  auto dae = testproblems::index1_dae();
  OdeOptions o;
  o.rtol = o.atol = 1e-6;
  const OdeResult a = ode_integrate(dae.problem, dae.t0, dae.y0, dae.t_end, o, OdeMethod::automatic);
  BOOST_TEST(int(a.status) == int(OdeStatus::success));
  BOOST_TEST(a.used_radau);
  BOOST_TEST(!a.used_explicit);
  const OdeResult e = ode_integrate(dae.problem, dae.t0, dae.y0, dae.t_end, o, OdeMethod::explicit_rk);
  BOOST_TEST(int(e.status) == int(OdeStatus::bad_input));
}

// A body falling from H = 2 m under g: y(t) = H - g t^2 / 2 lands at sqrt(2 H / g). Events
// given in OdeOptions reach every method and both kernels (Radau through its own event
// functions), and the root agrees with the closed form to 1e-12 (the location tolerances are
// 100 eps (|t| + |h|) ~ 1e-13; the dense output is exact on a parabola).
BOOST_AUTO_TEST_CASE(events_reach_every_method_and_kernel) {
  const double H = 2.0, grav = 9.81;
  OdeProblem p;
  p.n = 2;
  p.rhs = [grav](double, const double* y, double* f) {
    f[0] = y[1];
    f[1] = -grav;
    return true;
  };
  OdeOptions o;
  o.rtol = o.atol = 1e-10;
  o.events.count = 2;
  o.events.g = [](double, const double* y, double* g) {
    g[0] = y[0];         // the height: falling root at the landing
    g[1] = y[1] + 100.0;  // never zero
    return true;
  };
  o.events.direction = {-1, 0};
  const double exact = std::sqrt(2 * H / grav);
  for (Kernel k : {Kernel::fortran, Kernel::cpp}) {
    for (OdeMethod m : {OdeMethod::radau, OdeMethod::explicit_rk, OdeMethod::automatic}) {
      o.kernel = k;
      const OdeResult r = ode_integrate(p, 0.0, Eigen::Vector2d(H, 0.0), 10.0, o, m);
      BOOST_TEST_CONTEXT(to_string(k) << " " << to_string(m)) {
        BOOST_REQUIRE(int(r.status) == int(OdeStatus::root_found));
        BOOST_TEST(std::abs(r.t - exact) < 1e-12);
        BOOST_REQUIRE(r.roots.size() == 2u);
        BOOST_TEST(r.roots[0] == -1);
        BOOST_TEST(r.roots[1] == 0);
        BOOST_TEST(r.y[0] <= 0.0);  // on the far side of the root
      }
    }
  }
  // The same functions given the Radau way (OdeProblem::event_count) reach the explicit pair.
  OdeProblem q = p;
  q.event_count = 1;
  q.events = [](double, const double* y, double* g) { g[0] = y[0]; };
  OdeOptions plain;
  plain.rtol = plain.atol = 1e-10;
  const OdeResult e = ode_integrate(q, 0.0, Eigen::Vector2d(H, 0.0), 10.0, plain, OdeMethod::explicit_rk);
  BOOST_REQUIRE(int(e.status) == int(OdeStatus::root_found));
  BOOST_TEST(std::abs(e.t - exact) < 1e-12);
  // Both at once is refused.
  const OdeResult both = ode_integrate(q, 0.0, Eigen::Vector2d(H, 0.0), 10.0, o, OdeMethod::radau);
  BOOST_TEST(int(both.status) == int(OdeStatus::bad_input));
  BOOST_TEST(both.message.find("twice") != std::string::npos);
  // A g that cannot be evaluated ends a Radau run with callback_error naming the time.
  OdeOptions bad = plain;
  bad.events.count = 1;
  bad.events.g = [](double t, const double*, double* g) {
    g[0] = 1.0;
    return t < 0.1;
  };
  const OdeResult b = ode_integrate(p, 0.0, Eigen::Vector2d(H, 0.0), 10.0, bad, OdeMethod::radau);
  BOOST_TEST(int(b.status) == int(OdeStatus::callback_error));
  BOOST_TEST(b.message.find("event") != std::string::npos);
}

// auto with events: on van der Pol (eps = 1e-6) the explicit pair hands over to Radau at
// t ~ 4e-5; a root of y1 - 1.8 (y1 falls from 2 to 1.71 at t = 2) lies after the switch and is
// found by Radau, at the time Radau alone finds it (both to their location tolerance and
// within the integration error, 1e-6 relative).
BOOST_AUTO_TEST_CASE(auto_finds_roots_after_switching_to_radau) {
  auto vdp = testproblems::van_der_pol_published();
  OdeOptions o;
  o.rtol = o.atol = 1e-8;
  o.events.count = 1;
  o.events.g = [](double, const double* y, double* g) {
    g[0] = y[0] - 1.8;
    return true;
  };
  o.events.direction = {-1};
  const OdeResult a = ode_integrate(vdp.problem, vdp.t0, vdp.y0, vdp.t_end, o, OdeMethod::automatic);
  const OdeResult r = ode_integrate(vdp.problem, vdp.t0, vdp.y0, vdp.t_end, o, OdeMethod::radau);
  BOOST_REQUIRE(int(a.status) == int(OdeStatus::root_found));
  BOOST_REQUIRE(int(r.status) == int(OdeStatus::root_found));
  BOOST_TEST(a.used_explicit);
  BOOST_TEST(a.used_radau);
  BOOST_TEST(a.switch_time < a.t);
  BOOST_TEST(std::abs(a.t - r.t) < 1e-6 * r.t, "auto root " << a.t << ", radau root " << r.t);
  BOOST_TEST(std::abs(a.y[0] - 1.8) < 1e-9);
}
