// Public C++ API of the explicit Runge-Kutta integrator for y' = f(t, y): the Dormand-Prince
// 8(5,3) pair (order 8, error estimators of orders 5 and 3, dense output of order 7), with a
// stiffness test (h|lambda| from stage differences) and event location. For non-stiff problems
// it needs far fewer f-evaluations than Radau IIA. Two implementations behind one interface:
// the Fortran-77 kernel ERKDP8 through the ISO_C_BINDING bridge (Kernel::fortran) and its C++
// port (Kernel::cpp); they take the same steps and round identically.
//
//   pcsim::OdeProblem p;  p.n = 2;
//   p.rhs = [](double t, const double* y, double* f) { f[0] = y[1]; f[1] = -y[0]; return true; };
//   pcsim::ExplicitRkOptions o;  o.rtol = o.atol = 1e-10;
//   pcsim::ExplicitRkResult r = pcsim::explicit_rk_integrate(p, 0.0, Eigen::Vector2d(1, 0), 10.0, o);
//   if (r.status != pcsim::OdeStatus::success) { ... r.message ... }
#pragma once

#include <string>
#include <vector>

#include "common/eigen_instances.hpp"

#include "common/kernel.hpp"
#include "ode/events.hpp"
#include "ode/radau.hpp"  // OdeProblem, StepInfo, StepAction, StepCallback
#include "ode/status.hpp"

namespace pcsim {

/// What the stiffness test does (see docs/explicit.md).
enum class StiffnessAction {
  off,     ///< no test
  report,  ///< test every accepted step and report in the result (default)
  stop,    ///< also end the integration with status stiffness_detected when it fires
};

struct ExplicitRkOptions {
  Kernel kernel = Kernel::fortran;
  double rtol = 1e-6;           ///< scalar relative tolerance (>= 10 eps), if rtol_vec is empty
  double atol = 1e-6;           ///< scalar absolute tolerance (> 0), if atol_vec is empty
  Eigen::VectorXd rtol_vec;     ///< per-component relative tolerances (size n) or empty
  Eigen::VectorXd atol_vec;     ///< per-component absolute tolerances (size n) or empty
  double h0 = 0.0;              ///< initial step; 0 = automatic (one extra f-evaluation)
  double hmax = 0.0;            ///< largest step; 0 = |t_end - t0|
  long max_steps = 100000;      ///< give up after this many steps (status too_many_steps)
  double fixed_step = 0.0;      ///< > 0: take exactly this step, no error control (order tests)
  double safety = 0.0;          ///< step-size safety factor; 0 = 0.9
  double fac_min = 0.0;         ///< smallest step ratio h_new/h; 0 = 0.333
  double fac_max = 0.0;         ///< largest step ratio h_new/h; 0 = 6
  StiffnessAction stiffness = StiffnessAction::report;
  int stiff_persistence = 15;   ///< stiff steps (without 6 non-stiff in a row) before it fires
  int max_failed_evaluations = 20;  ///< consecutive failed/non-finite f before giving up
  EventFunctions events;        ///< optional event functions (status root_found)
};

/// Counters, exact and deterministic for a fixed problem, options and kernel.
struct ExplicitRkStats {
  long f_evals = 0;      ///< all evaluations of f (stages, dense output, first-step guess)
  long g_evals = 0;      ///< evaluations of the event functions
  long steps = 0;        ///< steps attempted = accepted + rejected + failed
  long accepted = 0;
  long rejected = 0;     ///< rejected by the error test
  long failed = 0;       ///< abandoned because f failed or was not finite (retried with h/2)
  long stiff_steps = 0;  ///< accepted steps with h|lambda| above the stability boundary
};

struct ExplicitRkResult {
  OdeStatus status = OdeStatus::bad_input;
  double t = 0.0;              ///< time reached (t_end on success; the root; the failure time)
  Eigen::VectorXd y;           ///< solution at t
  double h_last = 0.0;         ///< the step size proposed next (pass as h0 to continue)
  ExplicitRkStats stats;
  std::string message;         ///< human-readable reason unless success, naming the time
  std::vector<int> roots;      ///< on root_found: per event function +1 rising, -1 falling, 0
  bool stiffness_detected = false;
  double stiffness_time = 0.0; ///< when the stiffness test fired (if stiffness_detected)
  double h_lambda = 0.0;       ///< the last estimate of h|lambda|
};

/// Integrates y' = f(t, y) from (t0, y0) to t_end. The problem must be an ODE (no mass
/// matrix, no index counts). on_step is called after every accepted step with its dense
/// output (a step that ends at an event ends at the root). Never throws: failures come back
/// in status/message. Re-entrant: concurrent calls share no state.
ExplicitRkResult explicit_rk_integrate(const OdeProblem& problem, double t0,
                                       const Eigen::VectorXd& y0, double t_end,
                                       const ExplicitRkOptions& options,
                                       const StepCallback& on_step = {});

/// The real stability boundary the stiffness test compares h|lambda| with (6.1; the method's
/// stability interval on the negative real axis is [-6.39, 0]).
double explicit_rk_stiffness_bound();

}  // namespace pcsim
