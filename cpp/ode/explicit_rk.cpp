// The public explicit Runge-Kutta API: validates the problem and options, lays out the work
// arrays, runs the Fortran kernel ERKDP8 (through the bridge) or its C++ port with the same
// callbacks, and maps IDID to OdeStatus with a message naming the time. Exceptions never reach
// the kernels: the trampolines below catch everything and report an error code.
#include "ode/explicit_rk.hpp"
#include "common/format.hpp"

#include <climits>
#include <cmath>
#include <exception>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "ode/explicit_rk_port.hpp"
#include "pcsim_kernels.h"

namespace pcsim {

double explicit_rk_stiffness_bound() { return explicit_rk_port::kStiffnessBound; }

namespace {

// What one integration shares with the trampolines (reached through the context pointer).
struct CallContext {
  const OdeProblem* problem = nullptr;
  const StepCallback* on_step = nullptr;
  const EventFunctions* events = nullptr;
  Kernel kernel = Kernel::fortran;
  std::string error;  // why a callback failed, for the message
};

// The step being reported, for StepInfo::dense.
struct DenseImpl {
  Kernel kernel;
  int n;
  const double* cont;
  int ldc;
  double told, hd;
};

void dense_all(const void* impl, double s, double* out) {
  const auto* d = static_cast<const DenseImpl*>(impl);
  if (d->kernel == Kernel::fortran) {
    int info = 0;
    pcsim_erk_dense(d->n, s, d->told, d->hd, d->cont, d->ldc, out, &info);
  } else {
    explicit_rk_port::dense(d->n, s, d->told, d->hd, d->cont, d->ldc, out);
  }
}

double dense_one(const void* impl, int i, double s) {
  const auto* d = static_cast<const DenseImpl*>(impl);
  double out = 0.0;
  if (i < 0 || i >= d->n) return std::nan("");
  if (d->kernel == Kernel::fortran) {
    int info = 0;
    pcsim_erk_dense(1, s, d->told, d->hd, d->cont + i, d->ldc, &out, &info);
  } else {
    explicit_rk_port::dense(1, s, d->told, d->hd, d->cont + i, d->ldc, &out);
  }
  return out;
}

std::string at_time(double t) { return format_number(t); }

// The step's polynomial copied out (8 columns of ldc), evaluated by dense_all itself.
void copy_eval(const DenseCopy& c, double s, double* out) {
  const DenseImpl d{static_cast<Kernel>(c.kernel_), c.n_, c.cont_.data(), c.ldc_, c.a_, c.b_};
  dense_all(&d, s, out);
}

void copy_all(const void* impl, DenseCopy& out) {
  const auto* d = static_cast<const DenseImpl*>(impl);
  out.cont_.assign(d->cont, d->cont + static_cast<std::ptrdiff_t>(8) * d->ldc);
  out.n_ = d->n;
  out.ldc_ = d->ldc;
  out.a_ = d->told;
  out.b_ = d->hd;
  out.kernel_ = static_cast<int>(d->kernel);
  out.eval_ = &copy_eval;
}

// Records why a callback failed; called inside a catch handler, it must not throw itself.
void record_error(CallContext* c, const char* who, double t) noexcept {
  try {
    std::string what = "unknown exception";
    try {
      throw;
    } catch (const std::exception& ex) {
      what = ex.what();
    } catch (...) {
    }
    c->error = std::string(who) + " threw at t = " + at_time(t) + ": " + what;
  } catch (...) {
    c->error.clear();  // out of memory: the generic message will do
  }
}

extern "C" void erk_fcn_trampoline(const int* /*n*/, const double* t, const double* y, double* f,
                                   void* const* ctx, int* ierr) {
  auto* c = static_cast<CallContext*>(*ctx);
  try {
    *ierr = c->problem->rhs(*t, y, f) ? 0 : 1;
  } catch (...) {
    record_error(c, "the right-hand side", *t);
    *ierr = 2;
  }
}

extern "C" void erk_gfcn_trampoline(const int* /*n*/, const double* t, const double* y,
                                    const int* ng, double* g, void* const* ctx, int* ierr) {
  auto* c = static_cast<CallContext*>(*ctx);
  try {
    if (!c->events->g(*t, y, g)) {
      c->error = "the event functions could not be evaluated at t = " + at_time(*t);
      *ierr = 1;
      return;
    }
    for (int i = 0; i < *ng; ++i) {
      if (!std::isfinite(g[i])) {
        c->error = "event function " + std::to_string(i) + " is not finite at t = " + at_time(*t);
        *ierr = 1;
        return;
      }
    }
    *ierr = 0;
  } catch (...) {
    record_error(c, "the event functions", *t);
    *ierr = 2;
  }
}

extern "C" void erk_solout_trampoline(const int* n, const double* told, const double* t,
                                      const double* hd, double* y, const double* cont,
                                      const int* ldc, void* const* ctx, int* irtrn) {
  auto* c = static_cast<CallContext*>(*ctx);
  DenseImpl impl{c->kernel, *n, cont, *ldc, *told, *hd};
  StepInfo info;
  info.t_prev = *told;
  info.t = *t;
  info.h = *t - *told;
  info.n = *n;
  info.y = y;
  info.impl_ = &impl;
  info.impl_dense_ = &dense_all;
  info.impl_dense1_ = &dense_one;
  info.impl_copy_ = &copy_all;
  try {
    switch ((*c->on_step)(info)) {
      case StepAction::proceed: *irtrn = 0; break;
      case StepAction::state_modified: *irtrn = 1; break;
      case StepAction::stop: *irtrn = 2; break;
      default: *irtrn = 3; break;
    }
  } catch (...) {
    record_error(c, "the step callback", *t);
    *irtrn = 3;
  }
}

// Stubs for callbacks the kernel never calls (ng = 0, iout = 0): the bridge needs valid
// procedure pointers.
extern "C" void erk_gfcn_unused(const int*, const double*, const double*, const int*, double*,
                                void* const*, int* ierr) {
  *ierr = 1;
}
extern "C" void erk_solout_unused(const int*, const double*, const double*, const double*,
                                  double*, const double*, const int*, void* const*, int* irtrn) {
  *irtrn = 0;
}

ExplicitRkResult bad(const std::string& why) {
  ExplicitRkResult r;
  r.status = OdeStatus::bad_input;
  r.message = "explicit_rk: bad input: " + why;
  return r;
}

}  // namespace

ExplicitRkResult explicit_rk_integrate(const OdeProblem& problem, double t0,
                                       const Eigen::VectorXd& y0, double t_end,
                                       const ExplicitRkOptions& options,
                                       const StepCallback& on_step) {
  const int n = problem.n;
  // ---- Validate (the kernels check again; this names the problem in words).
  if (n <= 0) return bad("n = " + std::to_string(n) + ", expected n > 0");
  if (!problem.rhs) return bad("no right-hand side (problem.rhs is empty)");
  if (y0.size() != n)
    return bad("y0 has " + std::to_string(y0.size()) + " entries, expected n = " +
               std::to_string(n));
  if (!y0.allFinite()) return bad("y0 is not finite");
  if (problem.mass.size() != 0)
    return bad("a mass matrix was given; the explicit method integrates ODEs y' = f only "
               "(use Radau for K y' = f)");
  if (problem.index2_count != 0 || problem.index3_count != 0)
    return bad("index2_count/index3_count must be 0 for the explicit method (DAEs: use Radau)");
  if (!std::isfinite(t0) || !std::isfinite(t_end)) return bad("t0 and t_end must be finite");
  const bool vec_tol = options.rtol_vec.size() != 0 || options.atol_vec.size() != 0;
  Eigen::VectorXd rtol, atol;
  if (vec_tol) {
    rtol = options.rtol_vec.size() != 0 ? options.rtol_vec
                                        : Eigen::VectorXd::Constant(n, options.rtol);
    atol = options.atol_vec.size() != 0 ? options.atol_vec
                                        : Eigen::VectorXd::Constant(n, options.atol);
    if (rtol.size() != n || atol.size() != n)
      return bad("rtol_vec/atol_vec must have n = " + std::to_string(n) + " entries");
  } else {
    rtol = Eigen::VectorXd::Constant(1, options.rtol);
    atol = Eigen::VectorXd::Constant(1, options.atol);
  }
  if (!(options.h0 >= 0.0) || !std::isfinite(options.h0)) return bad("h0 must be >= 0");
  if (!(options.hmax >= 0.0) || !std::isfinite(options.hmax)) return bad("hmax must be >= 0");
  if (!(options.fixed_step >= 0.0) || !std::isfinite(options.fixed_step))
    return bad("fixed_step must be >= 0");
  if (options.max_steps <= 0) return bad("max_steps must be > 0");
  if (options.stiff_persistence <= 0) return bad("stiff_persistence must be > 0");
  if (options.max_failed_evaluations <= 0) return bad("max_failed_evaluations must be > 0");
  const EventFunctions& ev = options.events;
  if (ev.count < 0) return bad("events.count must be >= 0");
  if (ev.count > 0 && !ev.g) return bad("events.count > 0 but events.g is empty");
  if (!ev.direction.empty() && int(ev.direction.size()) != ev.count)
    return bad("events.direction must be empty or have events.count entries");
  for (int d : ev.direction)
    if (d < -1 || d > 1) return bad("events.direction entries must be -1, 0 or +1");
  if (!(ev.time_tolerance >= 0.0) || !std::isfinite(ev.time_tolerance))
    return bad("events.time_tolerance must be >= 0");
  // Safety and step ratios: the kernel checks the ranges (IDID = -15); say which in words.
  if (options.safety != 0.0 && !(options.safety > 1e-4 && options.safety < 1.0))
    return bad("safety must be in (1e-4, 1) or 0 for the default");
  if (options.fac_min != 0.0 && !(options.fac_min > 0.0 && options.fac_min <= 1.0))
    return bad("fac_min must be in (0, 1] or 0 for the default");
  if (options.fac_max != 0.0 && !(options.fac_max >= 1.0))
    return bad("fac_max must be >= 1 or 0 for the default");

  // ---- Work arrays (layout: fortran/explicit_rk.f, ERKDP8).
  const int ng = ev.count;
  const int lwork = 20 + 27 * n + 3 * ng;
  const int liwork = 20 + 3 * ng;
  std::vector<double> work(std::size_t(lwork), 0.0);
  std::vector<int> iwork(std::size_t(liwork), 0);
  work[0] = options.hmax;
  work[1] = options.fixed_step;
  work[2] = options.safety;
  work[3] = options.fac_min;
  work[4] = options.fac_max;
  work[5] = ev.time_tolerance;
  iwork[0] = options.max_steps > INT_MAX ? INT_MAX : int(options.max_steps);
  iwork[1] = options.stiffness == StiffnessAction::off    ? -1
             : options.stiffness == StiffnessAction::stop ? 1
                                                          : 0;
  iwork[2] = options.stiff_persistence;
  iwork[3] = options.max_failed_evaluations;
  for (int i = 0; i < ng && !ev.direction.empty(); ++i) iwork[std::size_t(20 + ng + i)] = ev.direction[std::size_t(i)];

  const int itol = vec_tol ? 1 : 0;
  const int iout = on_step ? 1 : 0;
  CallContext ctx;
  ctx.problem = &problem;
  ctx.on_step = &on_step;
  ctx.events = &ev;
  ctx.kernel = options.kernel;
  pcsim_erk_gfcn gf = ng > 0 ? &erk_gfcn_trampoline : &erk_gfcn_unused;
  pcsim_erk_solout sol = iout ? &erk_solout_trampoline : &erk_solout_unused;

  ExplicitRkResult r;
  r.y = y0;
  double t = t0;
  double h = options.h0;
  int idid = 0;
  if (options.kernel == Kernel::fortran) {
    pcsim_erk_integrate(&erk_fcn_trampoline, gf, sol, &ctx, itol, iout, n, ng, &t, t_end,
                        r.y.data(), &h, rtol.data(), atol.data(), work.data(), lwork,
                        iwork.data(), liwork, &idid);
  } else {
    idid = explicit_rk_port::integrate(&erk_fcn_trampoline, gf, sol, &ctx, itol, iout, n, ng,
                                       &t, t_end, r.y.data(), &h, rtol.data(), atol.data(),
                                       work.data(), lwork, iwork.data(), liwork);
  }

  r.t = t;
  r.h_last = h;
  r.stats.f_evals = iwork[10];
  r.stats.steps = iwork[11];
  r.stats.accepted = iwork[12];
  r.stats.rejected = iwork[13];
  r.stats.failed = iwork[14];
  r.stats.g_evals = iwork[15];
  r.stats.stiff_steps = iwork[16];
  r.stiffness_detected = iwork[17] == 1;
  r.stiffness_time = work[11];
  r.h_lambda = work[10];
  r.status = ode_status_from_idid(idid);
  if (r.status == OdeStatus::root_found)
    r.roots.assign(iwork.begin() + 20, iwork.begin() + 20 + ng);

  const std::string where = std::string("explicit_rk (") + to_string(options.kernel) + ")";
  switch (r.status) {
    case OdeStatus::success: break;
    case OdeStatus::stopped_by_callback:
      r.message = where + ": stopped by the step callback at t = " + at_time(t);
      break;
    case OdeStatus::root_found: {
      std::string which;
      for (int i = 0; i < ng; ++i)
        if (r.roots[std::size_t(i)] != 0)
          which += (which.empty() ? "" : ", ") + std::string("g") + std::to_string(i) +
                   (r.roots[std::size_t(i)] > 0 ? " rising" : " falling");
      r.message = where + ": event (" + which + ") at t = " + at_time(t);
      break;
    }
    case OdeStatus::too_many_steps:
      r.message = where + ": the step budget of " + counted(iwork[0], "step") +
                  " (solver.max_steps) is used up at t = " +
                  at_time(t);
      break;
    case OdeStatus::step_too_small:
      r.message = where + ": step size too small at t = " + at_time(t) + " (h = " +
                  at_time(h) + ")";
      break;
    case OdeStatus::non_finite:
      r.message = where + ": the right-hand side or the new state is not finite (NaN or Inf) "
                  "after t = " + at_time(t) + ", also with smaller steps";
      break;
    case OdeStatus::rhs_failed:
      r.message = where + ": the right-hand side cannot be evaluated after t = " + at_time(t) +
                  ", also with smaller steps";
      break;
    case OdeStatus::callback_error:
      r.message = where + ": " +
                  (ctx.error.empty() ? "a callback returned an invalid code at t = " + at_time(t)
                                     : ctx.error);
      break;
    case OdeStatus::tolerance_too_small:
      r.message = where + ": tolerances must be rtol >= 10 eps = " +
                  at_time(10.0 * std::numeric_limits<double>::epsilon()) + " and atol > 0";
      break;
    case OdeStatus::stiffness_detected:
      r.message = where + ": the problem is stiff from t = " + at_time(r.stiffness_time) +
                  " on (h|lambda| = " + at_time(r.h_lambda) + "); returned at t = " + at_time(t);
      break;
    default:
      r.message = where + ": argument " + std::to_string(-idid) + " of the kernel is invalid";
      break;
  }
  return r;
}

}  // namespace pcsim
