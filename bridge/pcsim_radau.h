/* C interface to the Radau IIA kernel (fortran/radau.f through bridge/radau_bridge.f90).
 * Arguments are those of RADIIA / RADDEN / RADCOE in the same order, so IDID = -i names the
 * same argument i on both sides; the Fortran headers document every argument, option slot,
 * statistics slot and IDID value. Matrices are column-major with the given leading
 * dimension; nothing is transposed. Scalars in by value; outputs through pointers.
 * The C++ port (cpp/ode/radau_port.hpp) takes the same callbacks and option/statistics slots. */
#ifndef PCSIM_RADAU_H
#define PCSIM_RADAU_H

#include "pcsim_ode_status.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Callbacks. The kernel passes every argument by reference; ctx points to the opaque context
 * pointer given to pcsim_radau_integrate. Callbacks must not throw or longjmp.
 *   fcn:    f[0..n) = f(*t, y). *ierr = 0 ok, 1 cannot evaluate here (step retried smaller;
 *           persistent: rhs_failed), anything else fatal (callback_error).
 *   jac:    dfdy[ldj x n] = df/dy at (*t, y). *ierr = 0 ok, 1 failed (jacobian_failed), else
 *           callback_error.
 *   gfcn:   g[0..ng) = the event functions at (*t, y). *ierr = 0 ok, else callback_error.
 *   solout: after each accepted step [*told, *t]; y[n] may be modified; cont[ldc x 4] are the
 *           continuation coefficients for pcsim_radau_dense. *irtrn = 0 proceed, 1 y modified,
 *           2 stop (IDID = 1), anything else fatal. */
typedef void (*pcsim_radau_fcn)(const int* n, const double* t, const double* y, double* f,
                                void* const* ctx, int* ierr);
typedef void (*pcsim_radau_jac)(const int* n, const double* t, const double* y, double* dfdy,
                                const int* ldj, void* const* ctx, int* ierr);
typedef void (*pcsim_radau_gfcn)(const int* n, const double* t, const double* y, const int* ng,
                                 double* g, void* const* ctx, int* ierr);
typedef void (*pcsim_radau_solout)(const int* n, const double* told, const double* t, double* y,
                                   const double* cont, const int* ldc, void* const* ctx,
                                   int* irtrn);

/* Integrates K y' = f(t, y) from *t to tend (RADIIA; fortran/radau.f documents every slot).
 *   fcn, jac, solout, gfcn  must all be non-null (jac is called only if ijac = 1, solout only
 *                     if iout = 1, gfcn only if ng > 0; pass a stub otherwise)
 *   ijac 0 finite differences / 1 jac;  imas 0 K = I / 1 K = am full / 2 K = diag(am[0..))
 *   itol 0 scalar / 1 vector;  iout 0 no solout / 1 solout after each accepted step
 *   ng    number of event functions (>= 0)
 *   t     in: t0, out: time reached            y [n]   in: y(t0), out: y(t)
 *   h     in: initial step (0: 1e-6), out: last proposed step
 *   rtol, atol [1] or [n], each > 0, rtol >= 10 uround
 *   am    [ldm x (n-m1)] if imas = 1 (the block below the m1 second-order rows), ldm >= n-m1;
 *         [n-m1] diagonal if imas = 2; not read if imas = 0
 *   work  [lwork]   lwork  >= 20 + 23 n + 4 n^2 + 4 ng; work[0..9] options (0 = default):
 *                   hmax, hfix, safe, thet, fnewt, quot1, quot2, facl, facr, uround
 *   zwork [lzwork]  complex workspace (interleaved re, im: 2 lzwork doubles),
 *                   lzwork >= n^2 + n
 *   iwork [liwork]  liwork >= 30 + 3 n + 2 ng; iwork[0..8] options (0 = default): nmax, nit,
 *                   nind2, nind3, classical step control (1), zero Newton start (1), m1, m2,
 *                   linear algebra (0 auto, 1 own LU, 2 LAPACK); iwork[30..30+ng) event
 *                   direction filter (0, +1, -1);
 *                   iwork[10..23] output statistics: f evaluations (without those for
 *                   finite-difference Jacobians), Jacobians, LU decompositions, linear solves,
 *                   steps, accepted, rejected, singular matrices, f evaluations for FD Jacobians,
 *                   error-test rejections, Newton rejections, f-failure/non-finite rejections,
 *                   event-function evaluations, what was non-finite (1 f, 2 J, 3 estimate);
 *                   iwork[30+ng..30+2ng) root directions on root_found
 *   idid  a code of the ODE status table (pcsim_ode_status.h): 0 success, 1 stopped by
 *         solout, 2 root found, -i argument i illegal, >= 3 a failure (see the table) */
void pcsim_radau_integrate(pcsim_radau_fcn fcn, pcsim_radau_jac jac, pcsim_radau_solout solout,
                           pcsim_radau_gfcn gfcn, void* ctx, int ijac, int imas, int itol,
                           int iout, int ng, int n, double* t, double tend, double* y, double* h,
                           const double* rtol, const double* atol, const double* am, int ldm,
                           double* work, int lwork, double* zwork, int lzwork, int* iwork,
                           int liwork, int* idid);

/* Dense output (RADDEN) of the step [told, tnew] at t from cont [ldc x 4] into yout [n].
 * info 0 ok, -i argument i illegal. */
void pcsim_radau_dense(int n, double t, double told, double tnew, const double* cont, int ldc,
                       double* yout, int* info);

/* The method coefficients (RADCOE): c [3], t [3 x 3], ti [3 x 3] (= t^-1), dd [3] error
 * weights, gam and alp +- i bet the eigenvalues of A^-1, with ti A^-1 t =
 * [gam 0 0; 0 alp -bet; 0 bet alp]. */
void pcsim_radau_coefficients(double* c, double* t, double* ti, double* dd, double* gam,
                              double* alp, double* bet);

#ifdef __cplusplus
}
#endif

#endif /* PCSIM_RADAU_H */
