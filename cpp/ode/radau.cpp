// The public Radau IIA API: validates the problem and options, lays out the work arrays, runs
// the Fortran kernel (through the bridge) or its C++ port with the same callbacks, and maps
// IDID to OdeStatus with a message naming the time. Exceptions never reach the kernels: the
// trampolines below catch everything and report an error code.
#include "ode/radau.hpp"
#include "common/format.hpp"

#include <climits>
#include <cmath>
#include <complex>
#include <exception>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "ode/radau_port.hpp"
#include "pcsim_kernels.h"

namespace pcsim {

void StepInfo::dense(double s, double* out) const { impl_dense_(impl_, s, out); }
double StepInfo::dense(int i, double s) const { return impl_dense1_(impl_, i, s); }

namespace {

// What one integration shares with the trampolines (reached through the context pointer).
struct CallContext {
  const OdeProblem* problem = nullptr;
  const StepCallback* on_step = nullptr;
  Kernel kernel = Kernel::fortran;
  std::string error;  // why a callback failed, for the message
};

// The step being reported, for StepInfo::dense.
struct DenseImpl {
  Kernel kernel;
  int n;
  const double* cont;
  int ldc;
  double told, tnew;
};

void dense_all(const void* impl, double s, double* out) {
  const auto* d = static_cast<const DenseImpl*>(impl);
  if (d->kernel == Kernel::fortran) {
    int info = 0;
    pcsim_radau_dense(d->n, s, d->told, d->tnew, d->cont, d->ldc, out, &info);
  } else {
    radau_port::dense(d->n, s, d->told, d->tnew, d->cont, d->ldc, out);
  }
}

double dense_one(const void* impl, int i, double s) {
  const auto* d = static_cast<const DenseImpl*>(impl);
  double out = 0.0;
  if (i < 0 || i >= d->n) return std::nan("");
  if (d->kernel == Kernel::fortran) {
    int info = 0;
    pcsim_radau_dense(1, s, d->told, d->tnew, d->cont + i, d->ldc, &out, &info);
  } else {
    radau_port::dense(1, s, d->told, d->tnew, d->cont + i, d->ldc, &out);
  }
  return out;
}

// The step's polynomial copied out (4 columns of ldc), evaluated by dense_all itself.
void copy_eval(const DenseCopy& c, double s, double* out) {
  const DenseImpl d{static_cast<Kernel>(c.kernel_), c.n_, c.cont_.data(), c.ldc_, c.a_, c.b_};
  dense_all(&d, s, out);
}

void copy_all(const void* impl, DenseCopy& out) {
  const auto* d = static_cast<const DenseImpl*>(impl);
  out.cont_.assign(d->cont, d->cont + static_cast<std::ptrdiff_t>(4) * d->ldc);
  out.n_ = d->n;
  out.ldc_ = d->ldc;
  out.a_ = d->told;
  out.b_ = d->tnew;
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
    c->error = std::string(who) + " threw at t = " + std::to_string(t) + ": " + what;
  } catch (...) {
    c->error.clear();  // out of memory: the generic message will do
  }
}

extern "C" void radau_fcn_trampoline(const int* /*n*/, const double* t, const double* y,
                                     double* f, void* const* ctx, int* ierr) {
  auto* c = static_cast<CallContext*>(*ctx);
  try {
    *ierr = c->problem->rhs(*t, y, f) ? 0 : 1;
  } catch (...) {
    record_error(c, "the right-hand side", *t);
    *ierr = 2;
  }
}

extern "C" void radau_jac_trampoline(const int* n, const double* t, const double* y, double* dfdy,
                                     const int* ldj, void* const* ctx, int* ierr) {
  auto* c = static_cast<CallContext*>(*ctx);
  try {
    bool ok = true;
    if (*ldj == *n) {
      ok = c->problem->jacobian(*t, y, dfdy);
    } else {  // never with the kernels (ldj = n); kept correct for any leading dimension
      std::vector<double> tmp(std::size_t(*n) * std::size_t(*n));
      ok = c->problem->jacobian(*t, y, tmp.data());
      for (int j = 0; j < *n; ++j)
        for (int i = 0; i < *n; ++i) dfdy[i + std::size_t(*ldj) * j] = tmp[i + std::size_t(*n) * j];
    }
    *ierr = ok ? 0 : 1;
  } catch (...) {
    record_error(c, "the Jacobian", *t);
    *ierr = 2;
  }
}

extern "C" void radau_solout_trampoline(const int* n, const double* told, const double* t,
                                        double* y, const double* cont, const int* ldc,
                                        void* const* ctx, int* irtrn) {
  auto* c = static_cast<CallContext*>(*ctx);
  DenseImpl impl{c->kernel, *n, cont, *ldc, *told, *t};
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

extern "C" void radau_gfcn_trampoline(const int* /*n*/, const double* t, const double* y,
                                      const int* /*ng*/, double* g, void* const* ctx, int* ierr) {
  auto* c = static_cast<CallContext*>(*ctx);
  try {
    c->problem->events(*t, y, g);
    *ierr = 0;
  } catch (...) {
    record_error(c, "the event functions", *t);
    *ierr = 2;
  }
}

// Stubs for callbacks the kernel never calls (jac with ijac = 0, solout with iout = 0): the
// bridge needs valid procedure pointers.
extern "C" void radau_jac_unused(const int*, const double*, const double*, double*, const int*,
                                 void* const*, int* ierr) {
  *ierr = 3;
}
extern "C" void radau_gfcn_unused(const int*, const double*, const double*, const int*,
                                   double*, void* const*, int* ierr) {
  *ierr = 3;
}
extern "C" void radau_solout_unused(const int*, const double*, const double*, double*,
                                    const double*, const int*, void* const*, int* irtrn) {
  *irtrn = 0;
}

std::string at_time(double t) { return format_number(t); }

RadauResult bad(const std::string& why, OdeStatus status = OdeStatus::bad_input) {
  RadauResult r;
  r.status = status;
  r.message = std::string("radau: ") +
              (status == OdeStatus::bad_input ? "bad input: " : "tolerance too small: ") + why;
  return r;
}

}  // namespace

RadauResult radau_integrate(const OdeProblem& problem, double t0, const Eigen::VectorXd& y0,
                            double t_end, const RadauOptions& options,
                            const StepCallback& on_step) {
  const int n = problem.n;
  // ---- Validate (the kernels check again; this names the problem in words).
  if (n <= 0) return bad("n = " + std::to_string(n) + ", expected n > 0");
  if (!problem.rhs) return bad("no right-hand side (problem.rhs is empty)");
  if (y0.size() != n)
    return bad("y0 has " + std::to_string(y0.size()) + " entries, expected n = " +
               std::to_string(n));
  if (!y0.allFinite()) return bad("y0 is not finite");
  if (problem.mass.size() != 0 && (problem.mass.rows() != n || problem.mass.cols() != n))
    return bad("mass matrix is " + std::to_string(problem.mass.rows()) + " x " +
               std::to_string(problem.mass.cols()) + ", expected " + std::to_string(n) + " x " +
               std::to_string(n) + " or empty");
  if (problem.mass.size() != 0 && !problem.mass.allFinite()) return bad("mass matrix not finite");
  if (problem.index2_count < 0 || problem.index3_count < 0 ||
      problem.index2_count + problem.index3_count > n)
    return bad("index2_count/index3_count must be >= 0 with sum <= n");
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
  const double uround =
      options.unit_roundoff > 0.0 ? options.unit_roundoff : std::numeric_limits<double>::epsilon();
  for (Eigen::Index i = 0; i < rtol.size(); ++i)
    if (!(rtol[i] >= 10.0 * uround) || !std::isfinite(rtol[i]))
      return bad("relative tolerances must be finite and >= 10 unit roundoffs (" +
                     at_time(10.0 * uround) + "), got " + at_time(rtol[i]),
                 OdeStatus::tolerance_too_small);
  for (Eigen::Index i = 0; i < atol.size(); ++i)
    if (!(atol[i] > 0.0) || !std::isfinite(atol[i]))
      return bad("absolute tolerances must be finite and > 0, got " + at_time(atol[i]),
                 OdeStatus::tolerance_too_small);
  if (!(options.h0 >= 0.0) || !std::isfinite(options.h0)) return bad("h0 must be >= 0");
  if (!(options.hmax >= 0.0) || !std::isfinite(options.hmax)) return bad("hmax must be >= 0");
  if (!(options.fixed_step >= 0.0) || !std::isfinite(options.fixed_step))
    return bad("fixed_step must be >= 0");
  if (options.max_steps <= 0) return bad("max_steps must be > 0");
  if (options.max_newton <= 0) return bad("max_newton must be > 0");

  const int m1 = problem.second_order_count;
  const int m2 = problem.second_order_stride != 0 ? problem.second_order_stride : m1;
  if (m1 < 0 || m2 < 0 || (m1 > 0 && (m1 % m2 != 0 || m1 + m2 > n)))
    return bad("second_order_count m1 = " + std::to_string(m1) + ", stride m2 = " +
               std::to_string(m2) + ": expected m1 a multiple of m2 and m1 + m2 <= n");
  const int ng = problem.event_count;
  if (ng < 0) return bad("event_count must be >= 0");
  if (ng > 0 && !problem.events) return bad("event_count > 0 but no event functions given");
  if (!problem.event_direction.empty() &&
      static_cast<int>(problem.event_direction.size()) != ng)
    return bad("event_direction must be empty or have event_count entries");
  for (int d : problem.event_direction)
    if (d < -1 || d > 1) return bad("event_direction entries must be -1, 0 or +1");

  // ---- The mass matrix as the kernels take it: identity, diagonal or full, below the m1
  // second-order rows (whose block must be the identity, decoupled from the rest).
  int imas = 0;
  Eigen::MatrixXd am_full;
  Eigen::VectorXd am_diag;
  if (problem.mass.size() != 0) {
    const Eigen::MatrixXd& K = problem.mass;
    if (m1 > 0) {
      if (!K.topLeftCorner(m1, m1).isIdentity(0.0) || !K.topRightCorner(m1, n - m1).isZero(0.0) ||
          !K.bottomLeftCorner(n - m1, m1).isZero(0.0))
        return bad("with second_order_count m1 > 0 the first m1 rows and columns of the mass "
                   "matrix must be those of the identity");
    }
    const Eigen::MatrixXd low = K.bottomRightCorner(n - m1, n - m1);
    Eigen::MatrixXd off = low;
    off.diagonal().setZero();
    if (options.diagonal_mass && off.isZero(0.0)) {
      imas = 2;
      am_diag = low.diagonal();
    } else {
      imas = 1;
      am_full = low;
    }
  }

  // ---- Work arrays (layout: fortran/radau.f, RADIIA).
  const int lwork = 20 + 23 * n + 4 * n * n + 4 * ng;
  const int lzwork = n * n + n;
  const int liwork = 30 + 3 * n + 2 * ng;
  std::vector<double> work(std::size_t(lwork), 0.0);
  std::vector<std::complex<double>> zwork(static_cast<std::size_t>(lzwork));
  std::vector<int> iwork(std::size_t(liwork), 0);
  work[0] = options.hmax;
  work[1] = options.fixed_step;
  work[2] = options.safety;
  work[3] = options.jacobian_reuse;
  work[4] = options.newton_tol;
  work[5] = options.keep_step_low;
  work[6] = options.keep_step_high;
  work[7] = options.max_step_growth > 0.0 ? options.max_step_growth : 0.0;
  work[8] = options.max_step_shrink;
  work[9] = options.unit_roundoff;
  iwork[0] = options.max_steps > INT_MAX ? INT_MAX : int(options.max_steps);
  iwork[1] = options.max_newton;
  iwork[2] = problem.index2_count;
  iwork[3] = problem.index3_count;
  iwork[4] = options.gustafsson ? 0 : 1;
  iwork[6] = m1;
  iwork[7] = m2;
  iwork[8] = options.linear_algebra == RadauOptions::LinearAlgebra::automatic ? 0
             : options.linear_algebra == RadauOptions::LinearAlgebra::own_lu  ? 1
                                                                              : 2;
  for (int i = 0; i < ng && !problem.event_direction.empty(); ++i)
    iwork[30 + i] = problem.event_direction[i];

  const int ijac = problem.jacobian ? 1 : 0;
  const int itol = vec_tol ? 1 : 0;
  const int iout = on_step ? 1 : 0;
  const double one = 1.0;
  const double* am = imas == 1 ? am_full.data() : imas == 2 ? am_diag.data() : &one;
  const int ldm = imas == 1 ? n - m1 : 1;

  CallContext ctx;
  ctx.problem = &problem;
  ctx.on_step = &on_step;
  ctx.kernel = options.kernel;
  pcsim_radau_jac jac = ijac ? &radau_jac_trampoline : &radau_jac_unused;
  pcsim_radau_solout sol = iout ? &radau_solout_trampoline : &radau_solout_unused;
  pcsim_radau_gfcn gf = ng > 0 ? &radau_gfcn_trampoline : &radau_gfcn_unused;

  RadauResult r;
  r.y = y0;
  double t = t0;
  double h = options.h0;
  int idid = 0;
  if (options.kernel == Kernel::fortran) {
    pcsim_radau_integrate(&radau_fcn_trampoline, jac, sol, gf, &ctx, ijac, imas, itol, iout, ng,
                          n, &t, t_end, r.y.data(), &h, rtol.data(), atol.data(), am, ldm,
                          work.data(), lwork, reinterpret_cast<double*>(zwork.data()), lzwork,
                          iwork.data(), liwork, &idid);
  } else {
    idid = radau_port::integrate(&radau_fcn_trampoline, jac, sol, gf, &ctx, ijac, imas, itol,
                                 iout, ng, n, &t, t_end, r.y.data(), &h, rtol.data(), atol.data(),
                                 am, ldm, work.data(), lwork,
                                 reinterpret_cast<double*>(zwork.data()), lzwork, iwork.data(),
                                 liwork);
  }

  r.t = t;
  r.h_last = h;
  r.stats.f_evals = iwork[10];
  r.stats.jacobians = iwork[11];
  r.stats.lu_decompositions = iwork[12];
  r.stats.linear_solves = iwork[13];
  r.stats.steps = iwork[14];
  r.stats.accepted = iwork[15];
  r.stats.rejected = iwork[16];
  r.stats.singular_matrices = iwork[17];
  r.stats.f_evals_jacobian = iwork[18];
  r.stats.error_test_rejections = iwork[19];
  r.stats.newton_rejections = iwork[20];
  r.stats.evaluation_rejections = iwork[21];
  r.stats.event_evals = iwork[22];

  const std::string where = std::string("radau (") + to_string(options.kernel) + ")";
  const std::string at = " at t = " + at_time(t);
  r.status = ode_status_from_idid(idid);
  switch (r.status) {
    case OdeStatus::success: break;
    case OdeStatus::stopped_by_callback:
      r.message = where + ": stopped by the step callback" + at;
      break;
    case OdeStatus::root_found: {
      r.root_directions.assign(iwork.begin() + 30 + ng, iwork.begin() + 30 + 2 * ng);
      std::string which;
      for (int i = 0; i < ng; ++i)
        if (r.root_directions[i] != 0)
          which += (which.empty() ? "" : ", ") + std::string("g") + std::to_string(i) +
                   (r.root_directions[i] > 0 ? " (increasing)" : " (decreasing)");
      r.message = where + ": event function root" + at + ": " + which;
      break;
    }
    case OdeStatus::too_many_steps:
      r.message = where + ": the step budget of " + counted(iwork[0], "step") +
                  " (solver.max_steps) is used up" + at;
      break;
    case OdeStatus::step_too_small:
      r.message = where + ": step size too small (error test)" + at + " (h = " + at_time(h) + ")";
      break;
    case OdeStatus::newton_failure:
      r.message = where + (options.fixed_step > 0.0
                               ? ": Newton iteration did not converge with the fixed step"
                               : ": Newton iteration failed repeatedly as h shrank") +
                  at + " (h = " + at_time(h) + ")";
      break;
    case OdeStatus::singular_matrix:
      r.message = where + ": iteration matrix repeatedly singular" + at;
      break;
    case OdeStatus::non_finite: {
      const int what = iwork[23];
      r.message = where + ": " +
                  (what == 1   ? std::string("the right-hand side")
                   : what == 2 ? std::string("the Jacobian")
                               : std::string("the Newton increment or the error estimate")) +
                  " was not finite (NaN or Inf)" + at +
                  (what == 2 ? "" : ", also after reducing the step size");
      break;
    }
    case OdeStatus::rhs_failed:
      r.message = where + ": the right-hand side could not be evaluated" + at +
                  " (at the accepted state, or repeatedly as h shrank)";
      break;
    case OdeStatus::jacobian_failed:
      r.message = where + ": the Jacobian callback reported failure" + at;
      break;
    case OdeStatus::callback_error:
      r.message = where + ": " + (ctx.error.empty() ? "a callback failed" + at : ctx.error);
      break;
    case OdeStatus::tolerance_too_small:
      r.message = where + ": tolerance too small or not > 0";
      break;
    case OdeStatus::inconsistent_start:
      r.message = where + ": inconsistent initial values" + at +
                  ": the algebraic equations do not hold within the tolerance (correct the "
                  "algebraic variables of y0)";
      break;
    case OdeStatus::missing_index_counts:
      r.message = where + ": the first step failed" + at +
                  " with a singular mass matrix and no index-2/3 counts: the index counts "
                  "(index2_count, index3_count) may be missing";
      break;
    case OdeStatus::bad_input:
      r.message = where + ": argument " + std::to_string(-idid) + " of the kernel is invalid" +
                  (idid == -24 && m1 > 0 ? " (or f does not return f_i = y_{i+m2} for i < m1)"
                                         : "");
      break;
    default:
      r.message = where + ": " + meaning(r.status) + at;
      break;
  }
  return r;
}

}  // namespace pcsim
