// Public C++ API of the 3-stage Radau IIA integrator (order 5) for K y' = f(t, y), with K
// constant and possibly singular (ODEs and DAEs of index 1; index-2/3 variables by error
// scaling). Two implementations behind one interface: the Fortran-77 kernel through the
// ISO_C_BINDING bridge (Kernel::fortran) and its C++ port on Eigen (Kernel::cpp). Both follow
// the same algorithm step for step, so they take the same steps.
//
// Minimal use (see README "Integrating your own system"):
//
//   pcsim::OdeProblem p;
//   p.n = 2;
//   p.rhs = [](double t, const double* y, double* f) { f[0] = y[1]; f[1] = -y[0]; return true; };
//   pcsim::RadauOptions o;  o.rtol = o.atol = 1e-8;
//   pcsim::RadauResult r = pcsim::radau_integrate(p, 0.0, Eigen::Vector2d(1, 0), 10.0, o);
//   if (r.status != pcsim::RadauStatus::success) { ... r.message ... }
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "common/kernel.hpp"
#include "ode/status.hpp"

namespace pcsim {

/// The system K y' = f(t, y). Variables are ordered: index-1 (and ODE) variables first, then
/// index-2, then index-3 (as in RADAU5's NIND1/NIND2/NIND3).
struct OdeProblem {
  int n = 0;  ///< number of unknowns, > 0

  /// f(t, y) into f[0..n). Return false if f cannot be evaluated at this (t, y) (e.g. NaN or
  /// outside the model's domain): the integrator then rejects the step and retries smaller.
  /// Exceptions thrown here are caught and end the integration with status callback_error.
  std::function<bool(double t, const double* y, double* f)> rhs;

  /// Optional analytic Jacobian df/dy, column-major n x n into dfdy. Empty: finite differences.
  std::function<void(double t, const double* y, double* dfdy)> jacobian;

  /// Constant mass matrix K (n x n). Empty (0 x 0): the identity (an ODE).
  Eigen::MatrixXd mass;

  int index2_count = 0;  ///< number of index-2 variables (after the index-1 ones)
  int index3_count = 0;  ///< number of index-3 variables (last)
};

struct RadauOptions {
  Kernel kernel = Kernel::fortran;
  double rtol = 1e-6;           ///< scalar relative tolerance (> 0), used if rtol_vec is empty
  double atol = 1e-6;           ///< scalar absolute tolerance (> 0), used if atol_vec is empty
  Eigen::VectorXd rtol_vec;     ///< per-component relative tolerances (size n) or empty
  Eigen::VectorXd atol_vec;     ///< per-component absolute tolerances (size n) or empty
  double h0 = 0.0;              ///< initial step; 0 = default
  double hmax = 0.0;            ///< largest step; 0 = |t_end - t0|
  long max_steps = 100000;      ///< give up after this many steps (status too_many_steps)
  int max_newton = 7;           ///< Newton iterations per step before the step is retried
  bool gustafsson = true;       ///< predictive (true) or classical step-size control
  double fixed_step = 0.0;      ///< > 0: take exactly this step, no error control (order tests)
};

/// Counters, exact and deterministic for a fixed problem, options and kernel.
struct RadauStats {
  long f_evals = 0;             ///< evaluations of f (including those for FD Jacobians)
  long jacobians = 0;           ///< Jacobian evaluations
  long lu_decompositions = 0;   ///< LU decompositions (each real+complex pair counts once)
  long linear_solves = 0;       ///< forward-backward substitutions (real+complex pair once)
  long steps = 0;               ///< steps attempted
  long accepted = 0;
  long rejected = 0;
};

/// The Radau kernel's statuses are the shared ODE status table (ode/status.hpp); the old name
/// stays as an alias so code written against RadauStatus compiles unchanged.
using RadauStatus = OdeStatus;

/// What the step callback sees after every accepted step [t_prev, t].
class StepInfo {
 public:
  double t_prev = 0.0;  ///< start of the accepted step
  double t = 0.0;       ///< end of the accepted step
  double h = 0.0;       ///< the step taken, t - t_prev
  int n = 0;
  double* y = nullptr;  ///< the solution at t; the callback may modify it (return state_modified)

  /// Dense output: the collocation polynomial of this step at s in [t_prev, t], into out[0..n).
  void dense(double s, double* out) const;
  /// One component of the dense output at s.
  double dense(int i, double s) const;

  // Internal: the kernel sets these so dense() can evaluate the polynomial.
  const void* impl_ = nullptr;
  void (*impl_dense_)(const void* impl, double s, double* out) = nullptr;
  double (*impl_dense1_)(const void* impl, int i, double s) = nullptr;
};

enum class StepAction {
  proceed,         ///< go on
  state_modified,  ///< the callback changed *y (e.g. a projection); go on from the new y
  stop,            ///< end the integration now (status stopped_by_callback)
};
using StepCallback = std::function<StepAction(StepInfo& step)>;

struct RadauResult {
  RadauStatus status = RadauStatus::bad_input;
  double t = 0.0;              ///< time reached (t_end on success; time of failure otherwise)
  Eigen::VectorXd y;           ///< solution at t
  double h_last = 0.0;         ///< the last (predicted) step size
  RadauStats stats;
  std::string message;         ///< human-readable reason on failure, naming the time
};

/// Integrates K y' = f(t, y) from (t0, y0) to t_end. Never throws: failures come back in
/// status/message. Re-entrant: concurrent calls share no state.
RadauResult radau_integrate(const OdeProblem& problem, double t0, const Eigen::VectorXd& y0,
                            double t_end, const RadauOptions& options,
                            const StepCallback& on_step = {});

}  // namespace pcsim
