// Event location of the explicit pair (issue 12): sign changes of g(t, y) are located on the
// dense output to the stated time tolerance, the run returns root_found at the earliest root
// with which functions fired and their direction, a restart from the root does not fire it
// again, and the direction filter works. Known event times: a falling body (t* = sqrt(2H/g)),
// exponential decay (t* = ln 2), several roots in one step, a root in the first step. Both
// kernels, which must agree bitwise.
#define BOOST_TEST_MODULE explicit_rk_events
#include <boost/test/unit_test.hpp>

#include <cmath>

#include "explicit_problems.hpp"

using namespace pcsim;
using namespace pcsim::explicit_problems;

namespace {

ExplicitRkResult both(const OdeProblem& p, double t0, const Eigen::VectorXd& y0, double t1,
                      ExplicitRkOptions o) {
  o.kernel = Kernel::fortran;
  const ExplicitRkResult f = explicit_rk_integrate(p, t0, y0, t1, o);
  o.kernel = Kernel::cpp;
  const ExplicitRkResult c = explicit_rk_integrate(p, t0, y0, t1, o);
  BOOST_TEST(int(f.status) == int(c.status));
  BOOST_TEST(f.t == c.t);
  BOOST_TEST(f.y == c.y);
  BOOST_TEST(f.roots == c.roots, boost::test_tools::per_element());
  BOOST_TEST(f.stats.g_evals == c.stats.g_evals);
  return f;
}

OdeProblem decay() {
  OdeProblem p;
  p.n = 1;
  p.rhs = [](double, const double* y, double* f) {
    f[0] = -y[0];
    return true;
  };
  return p;
}

}  // namespace

BOOST_AUTO_TEST_CASE(falling_body_reaches_the_ground_at_sqrt_2h_over_g) {
  const double H = 10.0, g = 9.81, t_star = std::sqrt(2.0 * H / g);
  ExplicitRkOptions o;
  o.rtol = o.atol = 1e-8;
  o.events.count = 1;
  o.events.g = [](double, const double* y, double* gv) {
    gv[0] = y[0];
    return true;
  };
  const ExplicitRkResult r = both(falling_body(g), 0.0, Eigen::Vector2d(H, 0.0), 10.0, o);
  BOOST_REQUIRE(r.status == OdeStatus::root_found);
  BOOST_TEST(r.roots == std::vector<int>{-1}, boost::test_tools::per_element());
  // The default tolerance is 100 eps (|t| + |h|) ~ 1e-13 here; the solution is a quadratic,
  // which the method and its dense output reproduce to rounding, so 1e-13 bounds the error.
  BOOST_TEST(std::abs(r.t - t_star) < 1e-13, "t - t* = " << r.t - t_star);
  BOOST_TEST(r.t >= t_star - 1e-15);  // returned on the far side of the root
  BOOST_TEST(std::abs(r.y[0]) < 1e-12);
  BOOST_TEST(std::abs(r.y[1] + g * t_star) < 1e-12);
  BOOST_TEST_MESSAGE("falling body: t - t* = " << r.t - t_star << " after " << r.stats.g_evals
                                               << " g-evaluations, " << r.stats.accepted << " steps");
  // Regula falsi on a smooth g converges superlinearly: few evaluations per root.
  BOOST_TEST(r.stats.g_evals <= r.stats.accepted + 1 + 12);

  // A stated, looser tolerance is honoured too.
  o.events.time_tolerance = 1e-6;
  const ExplicitRkResult loose = both(falling_body(g), 0.0, Eigen::Vector2d(H, 0.0), 10.0, o);
  BOOST_TEST(std::abs(loose.t - t_star) <= 1e-6);
}

BOOST_AUTO_TEST_CASE(root_of_a_nonlinear_solution_to_the_integration_accuracy) {
  // y' = -y, y(0) = 1, g = y - 1/2: t* = ln 2. The root's error is the dense output's error
  // divided by |y'| = 1/2: of the order of the tolerance.
  ExplicitRkOptions o;
  o.rtol = o.atol = 1e-10;
  o.events.count = 1;
  o.events.g = [](double, const double* y, double* g) {
    g[0] = y[0] - 0.5;
    return true;
  };
  const ExplicitRkResult r = both(decay(), 0.0, Eigen::VectorXd::Ones(1), 5.0, o);
  BOOST_REQUIRE(r.status == OdeStatus::root_found);
  BOOST_TEST(std::abs(r.t - std::log(2.0)) < 1e-9, "t - ln 2 = " << r.t - std::log(2.0));
}

BOOST_AUTO_TEST_CASE(several_roots_in_one_step_report_the_earliest_then_the_next) {
  // Fixed step 1 on [0, 1]: g0 = t - 0.7, g1 = 0.3 - t (falling), g2 = t - 0.5, g3 = 2 (t - 0.5):
  // all change sign in the one step; the earliest (0.3) is reported first, then on restarts
  // 0.5 (g2 and g3 together), then 0.7, then the run reaches t_end.
  ExplicitRkOptions o;
  o.fixed_step = 1.0;
  o.events.count = 4;
  o.events.g = [](double t, const double*, double* g) {
    g[0] = t - 0.7;
    g[1] = 0.3 - t;
    g[2] = t - 0.5;
    g[3] = 2.0 * (t - 0.5);
    return true;
  };
  const std::vector<std::pair<double, std::vector<int>>> expected = {
      {0.3, {0, -1, 0, 0}}, {0.5, {0, 0, 1, 1}}, {0.7, {1, 0, 0, 0}}};
  double t = 0.0;
  Eigen::VectorXd y = Eigen::VectorXd::Ones(1);
  for (const auto& [t_root, roots] : expected) {
    o.fixed_step = 1.0 - t;  // one step to the end each time
    const ExplicitRkResult r = both(decay(), t, y, 1.0, o);
    BOOST_REQUIRE(r.status == OdeStatus::root_found);
    BOOST_TEST(std::abs(r.t - t_root) < 1e-13, "root " << r.t << " expected " << t_root);
    BOOST_TEST(r.roots == roots, boost::test_tools::per_element());
    BOOST_TEST(std::abs(r.y[0] - std::exp(-r.t)) < 1e-6);  // dense output at the root
    t = r.t;
    y = r.y;
  }
  o.fixed_step = 1.0 - t;
  BOOST_TEST(int(both(decay(), t, y, 1.0, o).status) == int(OdeStatus::success));
}

BOOST_AUTO_TEST_CASE(root_in_the_first_step) {
  // y' = -y from 1, g = y - 0.999: t* = ln(1/0.999) = 1.0005e-3, inside the first step.
  ExplicitRkOptions o;
  o.rtol = o.atol = 1e-10;
  o.h0 = 0.01;
  o.events.count = 1;
  o.events.g = [](double, const double* y, double* g) {
    g[0] = y[0] - 0.999;
    return true;
  };
  const ExplicitRkResult r = both(decay(), 0.0, Eigen::VectorXd::Ones(1), 1.0, o);
  BOOST_REQUIRE(r.status == OdeStatus::root_found);
  BOOST_TEST(r.stats.accepted == 1);
  BOOST_TEST(std::abs(r.t - std::log(1.0 / 0.999)) < 1e-12);
}

BOOST_AUTO_TEST_CASE(restart_at_a_root_does_not_fire_it_again) {
  // Harmonic oscillator y = (sin t, cos t), g = y0: roots at pi (falling), 2 pi (rising).
  OdeProblem p;
  p.n = 2;
  p.rhs = [](double, const double* y, double* f) {
    f[0] = y[1];
    f[1] = -y[0];
    return true;
  };
  ExplicitRkOptions o;
  o.rtol = o.atol = 1e-11;
  o.events.count = 1;
  o.events.g = [](double, const double* y, double* g) {
    g[0] = y[0];
    return true;
  };
  ExplicitRkResult r = both(p, 0.0, Eigen::Vector2d(0.0, 1.0), 7.0, o);  // g(0) = 0 exactly
  BOOST_REQUIRE(r.status == OdeStatus::root_found);  // not at t = 0
  BOOST_TEST(std::abs(r.t - M_PI) < 1e-9);
  BOOST_TEST(r.roots == std::vector<int>{-1}, boost::test_tools::per_element());
  r = both(p, r.t, r.y, 7.0, o);  // restart at the root
  BOOST_REQUIRE(r.status == OdeStatus::root_found);
  BOOST_TEST(std::abs(r.t - 2.0 * M_PI) < 1e-9, "next root " << r.t);
  BOOST_TEST(r.roots == std::vector<int>{1}, boost::test_tools::per_element());
  r = both(p, r.t, r.y, 7.0, o);
  BOOST_TEST(int(r.status) == int(OdeStatus::success));

  // The direction filter: only rising roots are events, so the first is at 2 pi.
  o.events.direction = {1};
  r = both(p, 0.0, Eigen::Vector2d(0.0, 1.0), 7.0, o);
  BOOST_REQUIRE(r.status == OdeStatus::root_found);
  BOOST_TEST(std::abs(r.t - 2.0 * M_PI) < 1e-9);
}

BOOST_AUTO_TEST_CASE(step_callback_sees_the_step_ending_at_the_root) {
  ExplicitRkOptions o;
  o.rtol = o.atol = 1e-8;
  o.events.count = 1;
  o.events.g = [](double, const double* y, double* g) {
    g[0] = y[0] - 0.5;
    return true;
  };
  for (Kernel k : {Kernel::fortran, Kernel::cpp}) {
    o.kernel = k;
    double last_t = -1.0, last_y = 0.0, dense_at_end = 0.0;
    const ExplicitRkResult r = explicit_rk_integrate(
        decay(), 0.0, Eigen::VectorXd::Ones(1), 5.0, o, [&](StepInfo& s) {
          last_t = s.t;
          last_y = s.y[0];
          dense_at_end = s.dense(0, s.t);
          return StepAction::proceed;
        });
    BOOST_REQUIRE(r.status == OdeStatus::root_found);
    BOOST_TEST(last_t == r.t);
    BOOST_TEST(last_y == r.y[0]);
    BOOST_TEST(dense_at_end == r.y[0]);
  }
}
