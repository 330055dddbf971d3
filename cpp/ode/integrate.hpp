// Method selection for y' = f(t, y) (issue 14, solver.method): Radau IIA, the explicit
// Dormand-Prince 8(5,3) pair, or "auto", which starts explicit and continues with Radau from
// the state where the explicit method's stiffness test fired. One call for the engine.
#pragma once

#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "common/eigen_instances.hpp"

#include "common/kernel.hpp"
#include "ode/events.hpp"
#include "ode/explicit_rk.hpp"
#include "ode/radau.hpp"
#include "ode/status.hpp"

namespace pcsim {

enum class OdeMethod {
  radau,        ///< Radau IIA (stiff problems, DAEs)
  explicit_rk,  ///< Dormand-Prince 8(5,3) (non-stiff ODEs)
  automatic,    ///< explicit until the stiffness test fires, then Radau to t_end
};

/// "radau", "explicit", "auto" -> the method; anything else -> nullopt.
std::optional<OdeMethod> parse_ode_method(std::string_view name);
/// The inverse of parse_ode_method.
const char* to_string(OdeMethod method);

/// Settings for ode_integrate. The common fields below override the same fields of the
/// method-specific structs, which carry only what is particular to one method.
struct OdeOptions {
  Kernel kernel = Kernel::fortran;
  double rtol = 1e-6;           ///< relative tolerance (Radau rescales it, see docs/radau.md)
  double atol = 1e-6;
  Eigen::VectorXd rtol_vec;     ///< per-component, or empty
  Eigen::VectorXd atol_vec;
  double h0 = 0.0;              ///< initial step; 0 = each method's default
  double hmax = 0.0;            ///< 0 = |t_end - t0|
  long max_steps = 100000;      ///< per method
  /// Event functions for every method (status root_found, OdeResult::roots). Radau receives
  /// them as its own (OdeProblem::event_count; it locates roots to 100 uround (|t| + |h|) and
  /// ignores time_tolerance). Alternatively the problem may carry Radau-style events
  /// (OdeProblem::event_count), which the explicit pair then receives; not both.
  EventFunctions events;
  RadauOptions radau;           ///< Radau-only settings: max_newton, gustafsson
  ExplicitRkOptions explicit_rk;  ///< explicit-only settings: safety, step ratios, stiffness
};

struct OdeResult {
  OdeStatus status = OdeStatus::bad_input;
  double t = 0.0;               ///< time reached
  Eigen::VectorXd y;            ///< solution at t
  double h_last = 0.0;          ///< the step proposed next by the method that ran last
  std::string message;          ///< reason unless success, naming the method and the time
  std::vector<int> roots;       ///< on root_found: per event function +1, -1 or 0

  OdeMethod method = OdeMethod::radau;  ///< the method asked for
  bool used_explicit = false;   ///< the explicit pair took steps
  bool used_radau = false;      ///< Radau took steps
  double switch_time = std::numeric_limits<double>::quiet_NaN();  ///< auto: where Radau took over

  ExplicitRkStats explicit_stats;  ///< counters of the explicit part (zero if unused)
  RadauStats radau_stats;          ///< counters of the Radau part (zero if unused)
  long f_evals = 0;             ///< totals over both methods
  long steps = 0;
  long accepted = 0;
  long rejected = 0;            ///< error-test rejections plus the explicit pair's failed steps
};

/// Integrates y' = f(t, y) (or K y' = f with method radau) from (t0, y0) to t_end with the
/// given method; on_step sees every accepted step of whichever method runs, with its dense
/// output. auto: the explicit pair with StiffnessAction::stop; when the stiffness test fires at
/// t_s, Radau continues from (t_s, y(t_s)) with h0 = the explicit pair's last step; result
/// fields say which methods ran and switch_time = t_s. A problem with a mass matrix or index
/// counts goes to Radau directly under auto. Events work with every method, and under auto
/// on both sides of the switch (a root exactly at the switch time is masked there, as at any
/// restart). Never throws.
OdeResult ode_integrate(const OdeProblem& problem, double t0, const Eigen::VectorXd& y0,
                        double t_end, const OdeOptions& options, OdeMethod method,
                        const StepCallback& on_step = {});

}  // namespace pcsim
