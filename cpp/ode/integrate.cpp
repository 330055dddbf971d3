// ode_integrate: runs Radau, the explicit pair, or the explicit pair followed by Radau when the
// stiffness test fires (auto), and merges their results and counters.
#include "ode/integrate.hpp"
#include "common/format.hpp"

#include <sstream>

namespace pcsim {

std::optional<OdeMethod> parse_ode_method(std::string_view name) {
  if (name == "radau") return OdeMethod::radau;
  if (name == "explicit") return OdeMethod::explicit_rk;
  if (name == "auto") return OdeMethod::automatic;
  return std::nullopt;
}

const char* to_string(OdeMethod method) {
  switch (method) {
    case OdeMethod::radau: return "radau";
    case OdeMethod::explicit_rk: return "explicit";
    case OdeMethod::automatic: return "auto";
  }
  return "unknown";
}

namespace {

RadauOptions radau_options(const OdeOptions& o) {
  RadauOptions r = o.radau;
  r.kernel = o.kernel;
  r.rtol = o.rtol;
  r.atol = o.atol;
  r.rtol_vec = o.rtol_vec;
  r.atol_vec = o.atol_vec;
  r.h0 = o.h0;
  r.hmax = o.hmax;
  r.max_steps = o.max_steps;
  return r;
}

ExplicitRkOptions explicit_options(const OdeOptions& o) {
  ExplicitRkOptions e = o.explicit_rk;
  e.kernel = o.kernel;
  e.rtol = o.rtol;
  e.atol = o.atol;
  e.rtol_vec = o.rtol_vec;
  e.atol_vec = o.atol_vec;
  e.h0 = o.h0;
  e.hmax = o.hmax;
  e.max_steps = o.max_steps;
  e.events = o.events;
  return e;
}

void add_explicit(OdeResult& out, const ExplicitRkResult& r) {
  out.used_explicit = out.used_explicit || r.stats.accepted > 0;
  out.explicit_stats = r.stats;
  out.f_evals += r.stats.f_evals;
  out.steps += r.stats.steps;
  out.accepted += r.stats.accepted;
  out.rejected += r.stats.rejected + r.stats.failed;
}

void add_radau(OdeResult& out, const RadauResult& r) {
  out.used_radau = out.used_radau || r.stats.accepted > 0;
  out.radau_stats = r.stats;
  out.f_evals += r.stats.f_evals;
  out.steps += r.stats.steps;
  out.accepted += r.stats.accepted;
  out.rejected += r.stats.rejected;
}

std::string at_time(double t) { return format_number(t); }

}  // namespace

OdeResult ode_integrate(const OdeProblem& problem, double t0, const Eigen::VectorXd& y0,
                        double t_end, const OdeOptions& options, OdeMethod method,
                        const StepCallback& on_step) {
  OdeResult out;
  out.method = method;
  const bool has_events = options.events.count > 0;
  const bool dae = problem.mass.size() != 0 || problem.index2_count != 0 ||
                   problem.index3_count != 0;
  if (method == OdeMethod::automatic && dae) method = OdeMethod::radau;

  if (method == OdeMethod::radau) {
    if (has_events) {
      out.status = OdeStatus::bad_input;
      out.message = "ode_integrate: event functions are not supported by the Radau kernel yet "
                    "(use method explicit or auto)";
      return out;
    }
    const RadauResult r = radau_integrate(problem, t0, y0, t_end, radau_options(options), on_step);
    add_radau(out, r);
    out.status = r.status;
    out.t = r.t;
    out.y = r.y;
    out.h_last = r.h_last;
    out.message = r.message;
    return out;
  }

  ExplicitRkOptions eo = explicit_options(options);
  if (method == OdeMethod::automatic) eo.stiffness = StiffnessAction::stop;
  const ExplicitRkResult e = explicit_rk_integrate(problem, t0, y0, t_end, eo, on_step);
  add_explicit(out, e);
  out.status = e.status;
  out.t = e.t;
  out.y = e.y;
  out.h_last = e.h_last;
  out.message = e.message;
  out.roots = e.roots;
  if (method != OdeMethod::automatic || e.status != OdeStatus::stiffness_detected) return out;

  // auto: continue with Radau from the state where the stiffness test fired.
  if (has_events) {
    out.message += "; auto cannot switch to Radau because Radau has no event functions yet";
    return out;
  }
  out.switch_time = e.t;
  RadauOptions ro = radau_options(options);
  ro.h0 = std::abs(e.h_last);
  const RadauResult r = radau_integrate(problem, e.t, e.y, t_end, ro, on_step);
  add_radau(out, r);
  out.status = r.status;
  out.t = r.t;
  out.y = r.y;
  out.h_last = r.h_last;
  out.message = r.message;
  if (r.status != OdeStatus::success)
    out.message = "auto (switched to Radau at t = " + at_time(e.t) + "): " + r.message;
  return out;
}

}  // namespace pcsim
