// The C++ port of the explicit Runge-Kutta kernel ERKDP8 of fortran/explicit_rk.f
// (Dormand-Prince 8(5,3)): same arguments, same argument checks (IDID = -i for the same i),
// same option and statistics slots, same algorithm and order of operations, so both kernels
// take the same steps and round identically.
#pragma once

#include "pcsim_kernels.h"

namespace pcsim::explicit_rk_port {

/// The stiffness test's bound on h|lambda| (STBND of ERKCOR): 0.954 x the length 6.394 of the
/// method's stability interval on the negative real axis.
inline constexpr double kStiffnessBound = 6.1;

/// Port of ERKDP8 (see its header in fortran/explicit_rk.f and bridge/pcsim_explicit_rk.h for
/// every argument). Returns IDID.
int integrate(pcsim_erk_fcn fcn, pcsim_erk_gfcn gfcn, pcsim_erk_solout solout, void* ctx,
              int itol, int iout, int n, int ng, double* t, double tend, double* y, double* h,
              const double* rtol, const double* atol, double* work, int lwork, int* iwork,
              int liwork);

/// Port of ERKDEN: the dense output of the step starting at told with step hd, at t.
/// Returns INFO.
int dense(int n, double t, double told, double hd, const double* cont, int ldc, double* yout);

/// Port of ERKCOE: a[16x16] column-major, b[16], c[16], bh[16], er[16], d[4x16].
void coefficients(double* a, double* b, double* c, double* bh, double* er, double* d);

}  // namespace pcsim::explicit_rk_port
