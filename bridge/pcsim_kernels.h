/* pcsim_kernels.h: the one C header through which the C++ layer calls the Fortran kernels.
 *
 * Every symbol is a bind(C) wrapper in a bridge module (bridge/huang_bridge.f90,
 * bridge/radau_bridge.f90, bridge/explicit_rk_bridge.f90); the wrappers only marshal arguments
 * (value scalars, c_int/c_double, integer enums) and the kernels do the work. Arrays are
 * column-major on both sides, so nothing is transposed. The declarations, with the array
 * shapes in comments, are kept next to each bridge module:
 *   pcsim_huang.h  -> pcsim_huang_solve, pcsim_huang_null_basis    (fortran/huang.f)
 *   pcsim_radau.h  -> pcsim_radau_integrate, pcsim_radau_dense, pcsim_radau_coefficients (fortran/radau.f)
 *   pcsim_explicit_rk.h -> pcsim_erk_integrate, pcsim_erk_dense, pcsim_erk_coefficients (fortran/explicit_rk.f)
 *   pcsim_ode_status.h -> the table of integrator statuses (IDID codes) of every ODE kernel
 */
#ifndef PCSIM_KERNELS_H
#define PCSIM_KERNELS_H

#include "pcsim_explicit_rk.h"
#include "pcsim_huang.h"
#include "pcsim_ode_status.h"
#include "pcsim_radau.h"

#endif /* PCSIM_KERNELS_H */
