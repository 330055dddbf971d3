/* C interface to the explicit Runge-Kutta kernel, Dormand-Prince 8(5,3) with dense output of
 * order 7 (fortran/explicit_rk.f through bridge/explicit_rk_bridge.f90). Arguments are those of
 * ERKDP8 / ERKDEN / ERKCOE in the same order, so IDID = -i names the same argument i on both
 * sides; the Fortran headers document every argument, option slot, statistics slot and IDID
 * value (the codes of bridge/pcsim_ode_status.h). Arrays are column-major; nothing is
 * transposed. Scalars in by value; outputs through pointers. The C++ port
 * (cpp/ode/explicit_rk_port.hpp) takes the same callbacks and option/statistics slots. */
#ifndef PCSIM_EXPLICIT_RK_H
#define PCSIM_EXPLICIT_RK_H

#ifdef __cplusplus
extern "C" {
#endif

/* Callbacks. The kernel passes every argument by reference; ctx points to the opaque context
 * pointer given to pcsim_erk_integrate. Callbacks must not throw or longjmp.
 *   fcn:    f[0..n) = f(*t, y). *ierr = 0 ok, 1 cannot evaluate here (step retried with h/2),
 *           anything else fatal (IDID = callback_error). A non-finite f is retried like 1.
 *   gfcn:   g[0..ng) = g(*t, y), the event functions. *ierr != 0 or a non-finite g: fatal.
 *   solout: after each accepted step [*told, *t] (t = the root if an event ends it); the
 *           dense output of the step is pcsim_erk_dense(n, s, *told, *hd, cont, *ldc, ...),
 *           cont[ldc x 8]; y[n] may be modified. *irtrn = 0 proceed, 1 y modified, 2 stop
 *           (IDID = stopped_by_callback), anything else fatal. */
typedef void (*pcsim_erk_fcn)(const int* n, const double* t, const double* y, double* f,
                              void* const* ctx, int* ierr);
typedef void (*pcsim_erk_gfcn)(const int* n, const double* t, const double* y, const int* ng,
                               double* g, void* const* ctx, int* ierr);
typedef void (*pcsim_erk_solout)(const int* n, const double* told, const double* t,
                                 const double* hd, double* y, const double* cont,
                                 const int* ldc, void* const* ctx, int* irtrn);

/* Integrates y' = f(t, y) from *t to tend (ERKDP8).
 *   fcn, gfcn, solout  must all be non-null (gfcn is called only if ng > 0, solout only if
 *                      iout = 1; pass a stub otherwise)
 *   itol 0 scalar / 1 vector tolerances;  iout 0 no solout / 1 solout after each step
 *   n >= 1 unknowns;  ng >= 0 event functions
 *   t     in: t0, out: time reached            y [n]   in: y(t0), out: y(t)
 *   h     in: initial step (0: automatic), out: the step proposed next
 *   rtol, atol [1] or [n]: rtol >= 10 eps, atol > 0 (else IDID = tolerance_too_small)
 *   work  [lwork]   lwork  >= 20 + 27 n + 3 ng; work[0..5] options (0 = default):
 *                   hmax, hfix, safe, facmin, facmax, root tolerance;
 *                   work[10] (out) last h|lambda| estimate, work[11] (out) time of detection
 *   iwork [liwork]  liwork >= 20 + 3 ng; iwork[0..3] options (0 = default): nmax,
 *                   stiffness (0 count, 1 return stiffness_detected, -1 off), persistence,
 *                   consecutive failed f before giving up;
 *                   iwork[10..17] statistics: f evaluations, steps, accepted, rejected,
 *                   failed (f failed or non-finite), g evaluations, stiff steps, stiffness
 *                   detected (0/1);
 *                   iwork[20..20+ng) (out) roots: +1 rising, -1 falling, 0;
 *                   iwork[20+ng..20+2ng) (in) direction filter: 0 any, +1 rising, -1 falling
 *   idid  a code of pcsim_ode_status.h: success, stopped_by_callback, root_found, -i argument
 *         i illegal, too_many_steps, step_too_small, non_finite, rhs_failed, callback_error,
 *         tolerance_too_small, stiffness_detected */
void pcsim_erk_integrate(pcsim_erk_fcn fcn, pcsim_erk_gfcn gfcn, pcsim_erk_solout solout,
                         void* ctx, int itol, int iout, int n, int ng, double* t, double tend,
                         double* y, double* h, const double* rtol, const double* atol,
                         double* work, int lwork, int* iwork, int liwork, int* idid);

/* Dense output (ERKDEN) of the step starting at told with step hd, at t, from cont [ldc x 8]
 * into yout [n]. info 0 ok, -i argument i illegal. */
void pcsim_erk_dense(int n, double t, double told, double hd, const double* cont, int ldc,
                     double* yout, int* info);

/* The method coefficients (ERKCOE): a [16 x 16] (column-major, strictly lower triangular),
 * b [16], c [16], bh [16] (3rd-order weights), er [16] (5th-order error weights), d [4 x 16]
 * (dense-output weights). */
void pcsim_erk_coefficients(double* a, double* b, double* c, double* bh, double* er, double* d);

#ifdef __cplusplus
}
#endif

#endif /* PCSIM_EXPLICIT_RK_H */
