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
//   if (r.status != pcsim::OdeStatus::success) { ... r.message ... }
#pragma once

#include <functional>
#include <string>
#include <utility>
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
  /// Return false if it cannot be computed (status jacobian_failed). With second_order_count =
  /// m1 > 0 rows 0..m1-1 are unused.
  std::function<bool(double t, const double* y, double* dfdy)> jacobian;

  /// Constant mass matrix K (n x n). Empty (0 x 0): the identity (an ODE).
  Eigen::MatrixXd mass;

  int index2_count = 0;  ///< number of index-2 variables (after the index-1 ones)
  int index3_count = 0;  ///< number of index-3 variables (last)

  /// Second-order structure as in RADAU5 (M1, M2): y'_i = y_{i+m2} for i < m1, i.e. f_i must
  /// return y[i + m2] exactly, the first m1 rows and columns of K are those of the identity,
  /// and m1 is a multiple of m2 with m1 + m2 <= n. The linear systems then have order n - m1.
  /// 0: none. second_order_stride 0 means m2 = m1.
  int second_order_count = 0;
  int second_order_stride = 0;

  /// Event functions (like SUNDIALS' IDARootInit): g[0..event_count) = g(t, y). After each
  /// accepted step the integrator looks for sign changes and returns at the earliest root with
  /// status root_found (see docs/radau.md "Events"). Exceptions end the run (callback_error).
  int event_count = 0;
  std::function<void(double t, const double* y, double* g)> events;
  /// Per event function: 0 any sign change, +1 only increasing (- to +), -1 only decreasing.
  /// Empty: all 0.
  std::vector<int> event_direction;
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

  // RADAU5's tuning knobs (0 = the default in parentheses; docs/radau.md "Options").
  double unit_roundoff = 0.0;   ///< (2.2e-16) step-size floor, FD increments, rtol floor
  double safety = 0.0;          ///< (0.9) safety factor of the step control, in (0.001, 1)
  double jacobian_reuse = 0.0;  ///< (0.001) recompute J after a step only if theta > this
  double newton_tol = 0.0;      ///< (max(10 uround/rtol', min(0.03, sqrt(rtol')))) stop Newton
  double keep_step_low = 0.0;   ///< (1.0) keep h and the LU if h_new/h in [low, high]
  double keep_step_high = 0.0;  ///< (1.2)
  double max_step_growth = 0.0; ///< (5) largest factor h_new/h
  double max_step_shrink = 0.0; ///< (0.125) smallest factor h_new/h
  /// Linear algebra: automatic (own LU up to order 64, LAPACK above), own_lu, or lapack
  /// (DGETRF/ZGETRF/DGETRS/ZGETRS + DGEMV, the path before the own LU).
  enum class LinearAlgebra { automatic, own_lu, lapack } linear_algebra = LinearAlgebra::automatic;
  /// Pass a diagonal mass matrix to the kernels as a diagonal (true) or as a full matrix.
  bool diagonal_mass = true;
};

/// Counters, exact and deterministic for a fixed problem, options and kernel.
struct RadauStats {
  long f_evals = 0;             ///< evaluations of f, without those for FD Jacobians (RADAU5's)
  long f_evals_jacobian = 0;    ///< evaluations of f for finite-difference Jacobians
  long jacobians = 0;           ///< Jacobian evaluations
  long lu_decompositions = 0;   ///< LU decompositions (each real+complex pair counts once)
  long linear_solves = 0;       ///< forward-backward substitutions (real+complex pair once)
  long steps = 0;               ///< steps attempted
  long accepted = 0;
  long rejected = 0;             ///< = error_test + newton + evaluation rejections
  long error_test_rejections = 0;
  long newton_rejections = 0;    ///< divergence, too many iterations, predicted slow convergence
  long evaluation_rejections = 0;  ///< f could not be evaluated, or a value was not finite
  long singular_matrices = 0;
  long event_evals = 0;          ///< evaluations of the event functions
};

/// A step's dense output kept beyond the step callback (StepInfo::copy_dense): the polynomial's
/// coefficients copied out of the integrator's work array, evaluated by the same routine as
/// StepInfo::dense, so that its values are the same bit for bit, on any thread.
class DenseCopy {
 public:
  /// The polynomial at s into out[0..n).
  void dense(double s, double* out) const { eval_(*this, s, out); }
  int n() const { return n_; }
  bool empty() const { return eval_ == nullptr; }

  // Internal: filled by the integrator that made the step.
  std::vector<double> cont_;
  int n_ = 0, ldc_ = 0;
  double a_ = 0.0, b_ = 0.0;  ///< the integrator's two scalars of the step (its start; h or end)
  int kernel_ = 0;            ///< the Kernel that made it (its own dense routine evaluates it)
  void (*eval_)(const DenseCopy& self, double s, double* out) = nullptr;
};

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
  /// A copy of this step's dense output that outlives the call (its storage is reused).
  void copy_dense(DenseCopy& out) const { impl_copy_(impl_, out); }

  // Internal: the kernel sets these so dense() can evaluate the polynomial.
  const void* impl_ = nullptr;
  void (*impl_dense_)(const void* impl, double s, double* out) = nullptr;
  double (*impl_dense1_)(const void* impl, int i, double s) = nullptr;
  void (*impl_copy_)(const void* impl, DenseCopy& out) = nullptr;
};

enum class StepAction {
  proceed,         ///< go on
  state_modified,  ///< the callback changed *y (e.g. a projection); go on from the new y
  stop,            ///< end the integration now (status stopped_by_callback)
};
using StepCallback = std::function<StepAction(StepInfo& step)>;

struct RadauResult {
  OdeStatus status = OdeStatus::bad_input;
  double t = 0.0;              ///< time reached (t_end on success; time of failure otherwise)
  Eigen::VectorXd y;           ///< solution at t
  double h_last = 0.0;         ///< the last (predicted) step size
  RadauStats stats;
  std::string message;         ///< human-readable reason on failure, naming the time
  /// On root_found: per event function +1 (increased through 0 at t), -1 (decreased), 0.
  std::vector<int> root_directions;
};

/// Integrates K y' = f(t, y) from (t0, y0) to t_end. Never throws: failures come back in
/// status/message. Re-entrant: concurrent calls share no state.
RadauResult radau_integrate(const OdeProblem& problem, double t0, const Eigen::VectorXd& y0,
                            double t_end, const RadauOptions& options,
                            const StepCallback& on_step = {});

}  // namespace pcsim
