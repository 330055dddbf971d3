// Simulation of a mechanical system by the principle of compatibility: reaction forces,
// consistent initial values, the ODE and DAE forms on the Radau IIA integrator, drift control.
#pragma once

#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "common/eigen_instances.hpp"

#include "common/kernel.hpp"
#include "mech/model.hpp"
#include "mech/status.hpp"
#include "ode/integrate.hpp"
#include "ode/radau.hpp"

namespace pcsim::mech {

struct SimulationOptions {
  Kernel kernel = Kernel::fortran;  ///< Huang and Radau kernel path
  Form form = Form::ode;
  double t0 = 0.0, t_end = 1.0;
  OdeMethod method = OdeMethod::radau;  ///< radau, explicit_rk, or automatic (explicit, then
                                        ///< Radau where the stiffness test fires)
  RadauOptions::LinearAlgebra linear_algebra = RadauOptions::LinearAlgebra::automatic;
  /// How the ODE form and the samples solve for R: the structured solve of the compatibility
  /// system (default) or the paper's dense one. The DAE form always carries [G; Dᵀ] with
  /// Huang's D.
  ReactionMethod reaction_method = ReactionMethod::compatibility_structured;
  /// The drift projection after every accepted step (the path before issue 14), instead of only
  /// where a constraint is violated beyond its tolerance (default).
  bool project_every_step = false;
  double rtol = 1e-8, atol = 1e-8;
  double h0 = 0.0;                  ///< 0: integrator default
  double hmax = 0.0;                ///< 0: integrator default
  long max_steps = 1000000;
  std::vector<std::string> active_constraints;  ///< by name, in this order (rows of g)
  Stabilization stabilization = Stabilization::projection;
  double baumgarte_alpha = 10.0;    ///< 1/s
  double baumgarte_beta = 10.0;     ///< 1/s
  double projection_tol = 1e-13;    ///< Newton tolerance of the position projection (relative)
};

/// The integrator's options from the engine's (tolerances, steps, kernel, Newton linear
/// algebra): the one place they are filled, for smooth runs, switching segments and the
/// steady state's variational equations.
OdeOptions ode_options(const SimulationOptions& options);

/// One integration of a run to options.t_end: a smooth run, or one segment of a switching run.
struct Span {
  double h0 = 0.0;       ///< the first step (0: the integrator's default)
  double hmax = 0.0;     ///< the largest step (0: the integrator's default)
  long max_steps = 0;    ///< steps left to the run
  EventFunctions events;
  /// Rows of y that are q' = v (RADAU5's M1; stride n): Radau's linear systems shrink to the
  /// others. Not taken with linear_algebra = lapack (LAPACK's LU on the full system).
  int second_order = 0;
  int second_order_stride = 0;
};

/// The state of the system at one time, with reactions and derived quantities consistent with it.
struct Sample {
  double t = 0.0;
  Eigen::VectorXd q, qd, qdd, R, derived;
  Eigen::VectorXd lambda;     ///< R = gᵀ λ: one multiplier per active constraint, in row order
  double residual_pos = 0.0;  ///< max |Φ_i(q, t)| over the active holonomic constraints
  double residual_vel = 0.0;  ///< max |g q̇ + g0| over all active constraints
};

namespace detail {
struct SampleSpec;
class SampleSite;
}  // namespace detail

/// Issue 23: one step of simulate() kept beyond the observer call (StepView::record), to be
/// observed later on another thread (StepReplayer): the state at its end, the dense output's
/// polynomial, and what its samples are computed with. Its storage is reused by record().
struct StepRecord {
  double t_prev = 0.0, t = 0.0;
  Eigen::VectorXd q, qd;  ///< the state at t (the accepted, possibly projected, one)
  DenseCopy dense;        ///< empty at the initial state (t_prev == t)
  std::shared_ptr<const detail::SampleSpec> spec;
};

/// One accepted step [t_prev, t] as seen by a StepObserver. Valid only during the call.
class StepView {
 public:
  double t_prev = 0.0;
  double t = 0.0;
  /// The state at s in [t_prev, t]: the integrator's dense output for q and q̇ (at s == t the
  /// accepted — and, with projection, projected — state), with q̈, R and derived computed from it.
  Sample at(double s) const { return sample(s); }
  /// The same as at(s), without a copy: the reference stays valid until the next call of
  /// sample() or at() on any view of this run (read it at once; do not keep it).
  const Sample& sample(double s) const;
  /// Whether state() and derived() are cheaper than sample() (they always work).
  bool has_state() const { return impl_state_ != nullptr && impl_derived_ != nullptr; }
  /// q and q̇ at s in [t_prev, t] from the dense output alone, without the dynamics: the same
  /// values as sample(s).q and .qd (at s == t the accepted state).
  void state(double s, Eigen::VectorXd& q, Eigen::VectorXd& qd) const;
  /// The model's derived quantities at (s, q, q̇) for given q̈, R and multipliers (in the run's
  /// row order): what sample() computes from its own, here from values the caller supplies
  /// (for example interpolated between samples).
  void derived(double s, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
               const Eigen::VectorXd& qdd, const Eigen::VectorXd& R, const Eigen::VectorXd& lambda,
               Eigen::VectorXd& out) const;

  /// Issue 23: copies this step into `out` for a StepReplayer (on any thread); false where the
  /// view cannot be recorded (the switching driver's views), and its observer must run here.
  bool record(StepRecord& out) const { return impl_record_ != nullptr && impl_record_(impl_, out); }

  // Internal: set by simulate().
  const void* impl_ = nullptr;
  bool (*impl_record_)(const void* impl, StepRecord& out) = nullptr;
  const Sample& (*impl_at_)(const void* impl, double s) = nullptr;
  void (*impl_state_)(const void* impl, double s, Eigen::VectorXd& q, Eigen::VectorXd& qd) = nullptr;
  void (*impl_derived_)(const void* impl, double s, const Eigen::VectorXd& q,
                        const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd,
                        const Eigen::VectorXd& R, const Eigen::VectorXd& lambda,
                        Eigen::VectorXd& out) = nullptr;
};

/// Called once at t0 (t_prev == t == t0, the consistent initial state) and after every accepted
/// step. Return false to stop (status stopped_by_callback).
using StepObserver = std::function<bool(const StepView&)>;

/// Issue 23: replays StepRecords as StepViews on the thread that calls replay(), with a
/// workspace of its own: the observer sees the same samples, bit for bit, as it would have seen
/// in the step's own observer call. One replayer serves the records of one thread.
class StepReplayer {
 public:
  StepReplayer();
  ~StepReplayer();
  StepReplayer(const StepReplayer&) = delete;
  StepReplayer& operator=(const StepReplayer&) = delete;
  /// The observer's answer for the recorded step.
  bool replay(const StepRecord& record, const StepObserver& observer);

 private:
  std::unique_ptr<detail::SampleSite> site_;
};

/// Issue 21: where the rank of the active constraint rows changed during a run. The rank is
/// counted at the filter's threshold: row-scaled singular values σ_i > kRankReport σ_max (the
/// rank-revealing solve enforces a direction fully only above it). The watched quantity is
/// σ_r0/σ_max, r0 the rank at the start; a change is located on the integrator's dense output
/// (bisection for the threshold crossings, golden section for the instant of the smallest value)
/// to 1e-12 s relative to max(1, |t|), or the step's resolution when the run ends inside it.
struct RankChange {
  double t = 0.0;       ///< the instant: where σ_r0/σ_max is smallest between t_from and t_to
  double t_from = 0.0;  ///< where σ_r0/σ_max fell below kRankReport
  double t_to = std::numeric_limits<double>::quiet_NaN();  ///< where it rose above (NaN: never)
  int rank_before = 0;  ///< the rank before (r0)
  int rank = 0;         ///< the rank at t
  double sigma = 0.0;   ///< σ_r0/σ_max at t
  std::vector<int> rows;  ///< the rows (indices into the active set) that became dependent
};
inline constexpr double kRankReport = 1e-6;

struct SimulationResult {
  SimulationStatus status = SimulationStatus::invalid_model;
  OdeStatus integrator_status = OdeStatus::bad_input;  ///< the integrator's own status
  ModelIssue issue = ModelIssue::none;  ///< the cause when the model or constraints are bad
  std::string message;                  ///< human-readable reason on failure (names things)
  double t = 0.0;                       ///< time reached
  RadauStats stats;                     ///< totals over the methods used
  bool used_explicit = false, used_radau = false;  ///< which methods took steps
  double switch_time = std::numeric_limits<double>::quiet_NaN();  ///< automatic: where Radau took over
  double initial_correction_pos = 0.0;  ///< |Δq|₂ of the consistent-initial-value projection
  double initial_correction_vel = 0.0;  ///< |Δq̇|₂
  double residual_pos_max = 0.0;        ///< over the accepted steps (after projection if on)
  double residual_vel_max = 0.0;
  Eigen::VectorXd q_end, qd_end;
  /// Issue 21: the rank of the active rows at the start (kRankReport; the number of rows when
  /// none), the rows (indices into the active set) dependent there, and the changes during the
  /// run (simulate(); not tracked by simulate_switching). rank_start < the number of rows: the
  /// split λ of R is indeterminate from the start, with a null space of that difference.
  int rank_start = 0;
  std::vector<int> dependent_start;
  std::vector<RankChange> rank_changes;
};

/// The one driver of simulate() and simulate_switching(): integrates `problem` over the span
/// from (t0, y0) with ode_options(options) and the span's settings, and adds the integration's
/// counts and methods to `result` (integrator_status set).
OdeResult integrate_span(OdeProblem& problem, double t0, const Eigen::VectorXd& y0,
                         const SimulationOptions& options, const Span& span,
                         const StepCallback& on_step, SimulationResult& result);

/// Integrates from (q0, qd0) at options.t0 to options.t_end. Never throws (exceptions thrown by
/// the observer are reported as callback_error). Before integrating it checks the model at the
/// initial state (mass matrix, finiteness, rank of the active constraints by name) and projects
/// (q0, qd0) onto the active constraints (minimum-norm Huang correction).
SimulationResult simulate(const Model& model, const Eigen::VectorXd& q0,
                          const Eigen::VectorXd& qd0, const SimulationOptions& options,
                          const StepObserver& observer = {});

/// Checks an active constraint set at a state: names resolve, M is SPD, everything is finite,
/// rows are independent (Huang rank and row flags), constant_row promises hold.
struct CheckResult {
  ModelIssue issue = ModelIssue::none;
  std::string message;  ///< names the constraints / coordinates involved
  std::vector<int> active;  ///< the resolved indices into model.constraints()
  /// Issue 21: the rank of the active rows at the state (Huang), and the rows (indices into
  /// `active`) that depend on earlier ones. Dependent rows whose right-hand sides agree are
  /// accepted (issue stays none, message says which); contradictory ones are refused.
  int rank = 0;
  std::vector<int> redundant;
};
CheckResult check_model(const Model& model, const std::vector<std::string>& active, double t,
                        const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                        Kernel kernel = Kernel::fortran);

struct ReactionResult {
  ModelIssue issue = ModelIssue::none;
  std::string message;
  Eigen::VectorXd R;    ///< generalized reaction forces (n)
  Eigen::VectorXd qdd;  ///< accelerations M⁻¹(Q − h + R)
  Eigen::VectorXd lambda;  ///< R = gᵀ λ, one multiplier per active constraint (row order)
};
/// Reactions and accelerations at one state, by one of the three formulations.
ReactionResult reactions(const Model& model, const std::vector<std::string>& active, double t,
                         const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                         ReactionMethod method = ReactionMethod::compatibility,
                         Kernel kernel = Kernel::fortran);

/// Consistent initial values: the minimum-norm corrections of q (Newton on the holonomic Φ) and
/// of q̇ (g q̇ + g0 = 0) onto the active constraints, by the Huang kernel.
struct ProjectionResult {
  ModelIssue issue = ModelIssue::none;
  std::string message;
  Eigen::VectorXd q, qd;
  double correction_pos = 0.0, correction_vel = 0.0;  ///< |Δq|₂, |Δq̇|₂
};
ProjectionResult project_consistent(const Model& model, const std::vector<std::string>& active,
                                    double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                    Kernel kernel = Kernel::fortran);

}  // namespace pcsim::mech
