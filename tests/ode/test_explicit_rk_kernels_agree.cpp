// The Fortran kernel ERKDP8 (through the bridge) and its C++ port take the same steps: on
// every problem and option set below both record the same accepted times and states, bitwise,
// and the same counters. Bitwise because the port performs the same floating-point operations
// in the same order (no BLAS, no reductions reordered); a tolerance would hide a port error
// that changes one decision late in a run.
#define BOOST_TEST_MODULE explicit_rk_kernels_agree
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <sstream>

#include "explicit_problems.hpp"

using namespace pcsim;
using namespace pcsim::explicit_problems;

namespace {

struct Run {
  ExplicitRkResult r;
  Trace trace;
};

Run run(const OdeProblem& p, double t0, const Eigen::VectorXd& y0, double t1,
        ExplicitRkOptions o, Kernel k, const StepCallback& extra = {}) {
  Run out;
  o.kernel = k;
  StepCallback rec = recorder(out.trace);
  out.r = explicit_rk_integrate(p, t0, y0, t1, o, [&](StepInfo& s) {
    StepAction a = extra ? extra(s) : StepAction::proceed;
    rec(s);
    return a;
  });
  return out;
}

void expect_identical(const Run& a, const Run& b, const std::string& what) {
  BOOST_TEST_CONTEXT(what) {
    BOOST_TEST(int(a.r.status) == int(b.r.status));
    BOOST_TEST(a.r.t == b.r.t);
    BOOST_TEST(a.r.h_last == b.r.h_last);
    BOOST_TEST(a.r.stats.f_evals == b.r.stats.f_evals);
    BOOST_TEST(a.r.stats.g_evals == b.r.stats.g_evals);
    BOOST_TEST(a.r.stats.steps == b.r.stats.steps);
    BOOST_TEST(a.r.stats.accepted == b.r.stats.accepted);
    BOOST_TEST(a.r.stats.rejected == b.r.stats.rejected);
    BOOST_TEST(a.r.stats.failed == b.r.stats.failed);
    BOOST_TEST(a.r.stats.stiff_steps == b.r.stats.stiff_steps);
    BOOST_TEST(a.r.h_lambda == b.r.h_lambda);
    BOOST_TEST(a.r.roots == b.r.roots, boost::test_tools::per_element());
    BOOST_TEST(a.r.y == b.r.y);
    BOOST_REQUIRE_EQUAL(a.trace.t.size(), b.trace.t.size());
    std::size_t differ = 0;
    for (std::size_t i = 0; i < a.trace.t.size(); ++i)
      differ += (a.trace.t[i] != b.trace.t[i]) || (a.trace.y[i] != b.trace.y[i]);
    BOOST_TEST(differ == 0u, differ << " of " << a.trace.t.size() << " steps differ");
    BOOST_TEST_MESSAGE(what << ": " << a.trace.t.size() << " steps, " << a.r.stats.f_evals
                            << " f-evaluations, identical");
  }
}

std::string sci(double x) {
  std::ostringstream s;
  s << x;
  return s.str();
}

void both(const std::string& what, const OdeProblem& p, double t0, const Eigen::VectorXd& y0,
          double t1, const ExplicitRkOptions& o, const StepCallback& extra = {}) {
  expect_identical(run(p, t0, y0, t1, o, Kernel::fortran, extra),
                   run(p, t0, y0, t1, o, Kernel::cpp, extra), what);
}

}  // namespace

BOOST_AUTO_TEST_CASE(kernels_take_identical_steps_on_reference_problems) {
  ExplicitRkOptions o;
  for (double tol : {1e-4, 1e-8, 1e-12}) {
    o.rtol = o.atol = tol;
    both("arenstorf tol " + sci(tol), arenstorf_problem(), 0.0, arenstorf_y0(),
         kArenstorfPeriod, o);
    both("hnw tol " + sci(tol), hnw_exact_problem(), 0.0, hnw_exact_solution(0.0),
         5.0, o);
  }
  o.rtol = o.atol = 1e-7;
  both("oscillators", oscillators_problem(), 0.0, Eigen::VectorXd::Zero(8), 0.5, o);
  both("backwards", hnw_exact_problem(), 2.0, hnw_exact_solution(2.0), 0.0, o);
}

BOOST_AUTO_TEST_CASE(kernels_take_identical_steps_with_options) {
  ExplicitRkOptions o;
  o.rtol_vec = Eigen::Vector4d(1e-6, 1e-9, 1e-7, 1e-8);
  o.atol_vec = Eigen::Vector4d(1e-8, 1e-6, 1e-9, 1e-7);
  both("vector tolerances", arenstorf_problem(), 0.0, arenstorf_y0(), kArenstorfPeriod, o);
  o = ExplicitRkOptions{};
  o.h0 = 1e-3;
  o.hmax = 0.05;
  o.safety = 0.8;
  o.fac_min = 0.2;
  o.fac_max = 4.0;
  both("h0, hmax, safety, step ratios", arenstorf_problem(), 0.0, arenstorf_y0(),
       kArenstorfPeriod, o);
  o = ExplicitRkOptions{};
  o.fixed_step = 0.01;
  both("fixed step", hnw_exact_problem(), 0.0, hnw_exact_solution(0.0), 1.0, o);
}

BOOST_AUTO_TEST_CASE(kernels_agree_when_the_callback_modifies_the_state) {
  // A projection after each step, as the mechanics engine does: the harmonic oscillator's
  // state is scaled back onto the circle |y| = 1 of its exact solution.
  OdeProblem p;
  p.n = 2;
  p.rhs = [](double, const double* y, double* f) {
    f[0] = y[1];
    f[1] = -y[0];
    return true;
  };
  ExplicitRkOptions o;
  o.rtol = o.atol = 1e-5;
  both("projection", p, 0.0, Eigen::Vector2d(1.0, 0.0), 20.0, o, [](StepInfo& s) {
    const double r = std::hypot(s.y[0], s.y[1]);
    s.y[0] /= r;
    s.y[1] /= r;
    return StepAction::state_modified;
  });
}

BOOST_AUTO_TEST_CASE(kernels_agree_on_events_stiffness_and_failures) {
  ExplicitRkOptions o;
  o.rtol = o.atol = 1e-8;
  o.events.count = 2;
  o.events.g = [](double t, const double* y, double* g) {
    g[0] = y[0];         // the satellite crosses x = 0
    g[1] = t - 3.0;      // a time event
    return true;
  };
  both("events", arenstorf_problem(), 0.0, arenstorf_y0(), kArenstorfPeriod, o);

  ExplicitRkOptions s;
  s.rtol = s.atol = 1e-6;
  s.stiffness = StiffnessAction::stop;
  OdeProblem vdp;
  vdp.n = 2;
  vdp.rhs = [](double, const double* y, double* f) {
    f[0] = y[1];
    f[1] = ((1 - y[0] * y[0]) * y[1] - y[0]) / 1e-6;
    return true;
  };
  both("stiffness stop", vdp, 0.0, Eigen::Vector2d(2.0, 0.0), 2.0, s);

  OdeProblem nan_after;
  nan_after.n = 1;
  nan_after.rhs = [](double t, const double* y, double* f) {
    f[0] = t > 1.0 ? std::nan("") : -y[0];
    return true;
  };
  both("persistent NaN", nan_after, 0.0, Eigen::VectorXd::Ones(1), 2.0, ExplicitRkOptions{});
}
