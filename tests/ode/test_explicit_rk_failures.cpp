// How the explicit Runge-Kutta integrator fails, through both kernels: a non-finite f or state
// is retried with smaller steps and reported as non_finite (with the time) if it persists; a
// right-hand side that cannot evaluate likewise as rhs_failed; exceptions from any callback
// end the run with callback_error and their message; tolerances below 10 eps, too many steps,
// a step-size underflow and bad input each have their own status. Both kernels end with the
// same status, time and counters.
#define BOOST_TEST_MODULE explicit_rk_failures
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "explicit_problems.hpp"

using namespace pcsim;
using namespace pcsim::explicit_problems;

namespace {

OdeProblem decay() {
  OdeProblem p;
  p.n = 1;
  p.rhs = [](double, const double* y, double* f) {
    f[0] = -y[0];
    return true;
  };
  return p;
}

// Runs both kernels, checks they agree on status, time and counters, returns the Fortran one.
ExplicitRkResult both(const OdeProblem& p, double t0, const Eigen::VectorXd& y0, double t1,
                      ExplicitRkOptions o, const StepCallback& cb = {}) {
  o.kernel = Kernel::fortran;
  const ExplicitRkResult f = explicit_rk_integrate(p, t0, y0, t1, o, cb);
  o.kernel = Kernel::cpp;
  const ExplicitRkResult c = explicit_rk_integrate(p, t0, y0, t1, o, cb);
  BOOST_TEST(int(f.status) == int(c.status));
  BOOST_TEST(f.t == c.t);
  BOOST_TEST(f.stats.f_evals == c.stats.f_evals);
  BOOST_TEST(f.stats.steps == c.stats.steps);
  BOOST_TEST(f.stats.failed == c.stats.failed);
  BOOST_TEST_MESSAGE(to_string(f.status) << ": " << f.message);
  return f;
}

}  // namespace

BOOST_AUTO_TEST_CASE(non_finite_stages_are_retried_smaller_and_the_run_succeeds) {
  // y' = -y from 1 with a first step of 50: the stage values overshoot below zero, where this
  // f returns NaN (as a model outside its domain might); halving h recovers.
  OdeProblem p;
  p.n = 1;
  p.rhs = [](double, const double* y, double* f) {
    f[0] = y[0] < 0.0 ? std::numeric_limits<double>::quiet_NaN() : -y[0];
    return true;
  };
  ExplicitRkOptions o;
  o.h0 = 50.0;
  o.rtol = o.atol = 1e-8;
  const ExplicitRkResult r = both(p, 0.0, Eigen::VectorXd::Ones(1), 10.0, o);
  BOOST_TEST(int(r.status) == int(OdeStatus::success));
  BOOST_TEST(r.stats.failed > 0);
  BOOST_TEST(std::abs(r.y[0] - std::exp(-10.0)) < 1e-9);
}

BOOST_AUTO_TEST_CASE(persistent_non_finite_f_fails_with_non_finite_and_the_time) {
  for (double bad : {std::numeric_limits<double>::quiet_NaN(),
                     std::numeric_limits<double>::infinity()}) {
    OdeProblem p;
    p.n = 1;
    p.rhs = [bad](double t, const double* y, double* f) {
      f[0] = t > 1.0 ? bad : -y[0];
      return true;
    };
    const ExplicitRkResult r = both(p, 0.0, Eigen::VectorXd::Ones(1), 2.0, ExplicitRkOptions{});
    BOOST_TEST(int(r.status) == int(OdeStatus::non_finite));
    BOOST_TEST((r.t > 0.9 && r.t <= 1.0), "t = " << r.t);  // the last accepted state
    BOOST_TEST(std::isfinite(r.y[0]));
    BOOST_TEST(r.message.find("t = ") != std::string::npos);
    BOOST_TEST(r.stats.failed >= 20);  // max_failed_evaluations consecutive failures
  }
}

BOOST_AUTO_TEST_CASE(non_finite_f_at_the_initial_state_fails_at_once) {
  OdeProblem p;
  p.n = 1;
  p.rhs = [](double, const double*, double* f) {
    f[0] = std::numeric_limits<double>::quiet_NaN();
    return true;
  };
  const ExplicitRkResult r = both(p, 0.5, Eigen::VectorXd::Ones(1), 2.0, ExplicitRkOptions{});
  BOOST_TEST(int(r.status) == int(OdeStatus::non_finite));
  BOOST_TEST(r.t == 0.5);
  BOOST_TEST(r.stats.f_evals == 1);
}

BOOST_AUTO_TEST_CASE(overflowing_solution_is_not_accepted) {
  // y' = y^2, y(0) = 1: y = 1/(1 - t) blows up at t = 1. The run must end before t = 1 with
  // a failure (step_too_small or non_finite), never return an infinite state as a success.
  OdeProblem p;
  p.n = 1;
  p.rhs = [](double, const double* y, double* f) {
    f[0] = y[0] * y[0];
    return true;
  };
  const ExplicitRkResult r = both(p, 0.0, Eigen::VectorXd::Ones(1), 2.0, ExplicitRkOptions{});
  BOOST_TEST((r.status == OdeStatus::step_too_small || r.status == OdeStatus::non_finite));
  // The numerical blow-up time is within about the tolerance (1e-6) of 1 (observed 1 + 1.1e-7).
  BOOST_TEST((r.t > 0.99 && r.t < 1.0 + 1e-5), "t = " << r.t);
  BOOST_TEST(std::isfinite(r.y[0]));
}

BOOST_AUTO_TEST_CASE(rhs_that_cannot_evaluate_is_retried_then_rhs_failed) {
  // Recoverable: f refuses y < 0 (first step too large).
  OdeProblem p;
  p.n = 1;
  p.rhs = [](double, const double* y, double* f) {
    if (y[0] < 0.0) return false;
    f[0] = -y[0];
    return true;
  };
  ExplicitRkOptions o;
  o.h0 = 50.0;
  ExplicitRkResult r = both(p, 0.0, Eigen::VectorXd::Ones(1), 10.0, o);
  BOOST_TEST(int(r.status) == int(OdeStatus::success));
  BOOST_TEST(r.stats.failed > 0);
  // Persistent: f refuses t > 1.
  OdeProblem q;
  q.n = 1;
  q.rhs = [](double t, const double* y, double* f) {
    f[0] = -y[0];
    return t <= 1.0;
  };
  r = both(q, 0.0, Eigen::VectorXd::Ones(1), 2.0, ExplicitRkOptions{});
  BOOST_TEST(int(r.status) == int(OdeStatus::rhs_failed));
  BOOST_TEST((r.t > 0.9 && r.t <= 1.0), "t = " << r.t);
}

BOOST_AUTO_TEST_CASE(exceptions_from_callbacks_end_with_callback_error) {
  OdeProblem p;
  p.n = 1;
  p.rhs = [](double t, const double* y, double* f) {
    if (t > 0.5) throw std::runtime_error("model exploded");
    f[0] = -y[0];
    return true;
  };
  ExplicitRkResult r = both(p, 0.0, Eigen::VectorXd::Ones(1), 1.0, ExplicitRkOptions{});
  BOOST_TEST(int(r.status) == int(OdeStatus::callback_error));
  BOOST_TEST(r.message.find("model exploded") != std::string::npos);
  BOOST_TEST(r.message.find("right-hand side") != std::string::npos);

  r = both(decay(), 0.0, Eigen::VectorXd::Ones(1), 1.0, ExplicitRkOptions{},
           [](StepInfo& s) -> StepAction {
             if (s.t > 0.3) throw std::logic_error("output disk full");
             return StepAction::proceed;
           });
  BOOST_TEST(int(r.status) == int(OdeStatus::callback_error));
  BOOST_TEST(r.message.find("output disk full") != std::string::npos);
  BOOST_TEST(r.t > 0.3);  // the step was accepted before the callback saw it

  ExplicitRkOptions o;
  o.events.count = 1;
  o.events.g = [](double t, const double*, double* g) {
    if (t > 0.2) throw std::runtime_error("bad event");
    g[0] = 1.0;
    return true;
  };
  r = both(decay(), 0.0, Eigen::VectorXd::Ones(1), 1.0, o);
  BOOST_TEST(int(r.status) == int(OdeStatus::callback_error));
  BOOST_TEST(r.message.find("bad event") != std::string::npos);

  o.events.g = [](double, const double*, double* g) {
    g[0] = std::nan("");
    return true;
  };
  r = both(decay(), 0.0, Eigen::VectorXd::Ones(1), 1.0, o);
  BOOST_TEST(int(r.status) == int(OdeStatus::callback_error));
  BOOST_TEST(r.message.find("not finite") != std::string::npos);
}

BOOST_AUTO_TEST_CASE(stop_from_the_callback_ends_at_the_step) {
  int calls = 0;
  const ExplicitRkResult r = both(decay(), 0.0, Eigen::VectorXd::Ones(1), 10.0,
                                  ExplicitRkOptions{}, [&calls](StepInfo& s) {
                                    ++calls;
                                    return s.t > 2.0 ? StepAction::stop : StepAction::proceed;
                                  });
  BOOST_TEST(int(r.status) == int(OdeStatus::stopped_by_callback));
  BOOST_TEST((r.t > 2.0 && r.t < 10.0));
  BOOST_TEST(std::abs(r.y[0] - std::exp(-r.t)) < 1e-6);
}

BOOST_AUTO_TEST_CASE(tolerances_limits_and_bad_input_have_their_own_status) {
  ExplicitRkOptions o;
  o.rtol = 1e-17;  // below 10 eps = 2.2e-15
  BOOST_TEST(int(both(decay(), 0.0, Eigen::VectorXd::Ones(1), 1.0, o).status) ==
             int(OdeStatus::tolerance_too_small));
  o.rtol = 1e-6;
  o.atol = 0.0;
  BOOST_TEST(int(both(decay(), 0.0, Eigen::VectorXd::Ones(1), 1.0, o).status) ==
             int(OdeStatus::tolerance_too_small));
  o = ExplicitRkOptions{};
  o.max_steps = 5;
  ExplicitRkResult r = both(arenstorf_problem(), 0.0, arenstorf_y0(), kArenstorfPeriod, o);
  BOOST_TEST(int(r.status) == int(OdeStatus::too_many_steps));
  BOOST_TEST(r.stats.steps == 5);

  OdeProblem dae = decay();
  dae.mass = Eigen::MatrixXd::Identity(1, 1);
  r = explicit_rk_integrate(dae, 0.0, Eigen::VectorXd::Ones(1), 1.0, ExplicitRkOptions{});
  BOOST_TEST(int(r.status) == int(OdeStatus::bad_input));
  BOOST_TEST(r.message.find("mass matrix") != std::string::npos);
  r = explicit_rk_integrate(decay(), 0.0, Eigen::VectorXd::Ones(2), 1.0, ExplicitRkOptions{});
  BOOST_TEST(int(r.status) == int(OdeStatus::bad_input));
  o = ExplicitRkOptions{};
  o.events.count = 1;  // but no g
  r = explicit_rk_integrate(decay(), 0.0, Eigen::VectorXd::Ones(1), 1.0, o);
  BOOST_TEST(int(r.status) == int(OdeStatus::bad_input));
  o = ExplicitRkOptions{};
  o.safety = 2.0;
  r = explicit_rk_integrate(decay(), 0.0, Eigen::VectorXd::Ones(1), 1.0, o);
  BOOST_TEST(int(r.status) == int(OdeStatus::bad_input));
  BOOST_TEST(r.message.find("safety") != std::string::npos);

  // t_end = t0: nothing to do, success without evaluations.
  r = both(decay(), 1.0, Eigen::VectorXd::Ones(1), 1.0, ExplicitRkOptions{});
  BOOST_TEST(int(r.status) == int(OdeStatus::success));
  BOOST_TEST(r.stats.f_evals == 0);
}
