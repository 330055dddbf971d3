// The C++ (Eigen) port of the Radau IIA kernel RADIIA of fortran/radau.f: same arguments, same
// argument checks (IDID = -i for the same i), same option and statistics slots, same algorithm
// and decisions, so both kernels take the same steps.
#pragma once

#include "pcsim_kernels.h"

namespace pcsim::radau_port {

/// Port of RADIIA (see its header in fortran/radau.f and bridge/pcsim_radau.h for every
/// argument). zwork holds complex numbers as interleaved (re, im) pairs, lzwork of them.
/// The linear algebra is the port of the same routines (radau_lu.cpp, or the same LAPACK/BLAS
/// calls on the LAPACK path) and every other operation is done in the same order, so the two
/// kernels round identically (see radau_port.cpp for why). Returns IDID.
int integrate(pcsim_radau_fcn fcn, pcsim_radau_jac jac, pcsim_radau_solout solout,
              pcsim_radau_gfcn gfcn, void* ctx, int ijac, int imas, int itol, int iout, int ng,
              int n, double* t, double tend, double* y, double* h, const double* rtol,
              const double* atol, const double* am, int ldm, double* work, int lwork,
              double* zwork, int lzwork, int* iwork, int liwork);

/// Port of RADDEN: the dense output of the step [told, tnew] at t. Returns INFO.
int dense(int n, double t, double told, double tnew, const double* cont, int ldc, double* yout);

/// Port of RADCOE: c[3], t[3x3], ti[3x3] column-major, dd[3], gam, alp, bet.
void coefficients(double* c, double* t, double* ti, double* dd, double* gam, double* alp,
                  double* bet);

}  // namespace pcsim::radau_port
