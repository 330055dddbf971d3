/* pcsim_lcp_siconos: the LCP plugin over Siconos numerics (Debian libsiconos-numerics-dev).
 * The only code of pcsim that includes a Siconos header or calls Siconos; see lcp_plugin.h
 * for the ABI and cpp/lcp/lcp.hpp for how and when pcsim loads it. */
#include <setjmp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <siconos/SiconosConfig.h>
#include <siconos/numerics/LCP_Solvers.h>
#include <siconos/numerics/LinearComplementarityProblem.h>
#include <siconos/numerics/NonSmoothDrivers.h>
#include <siconos/numerics/NumericsMatrix.h>
#include <siconos/numerics/NumericsVerbose.h>
#include <siconos/numerics/SolverOptions.h>
#include <siconos/numerics/lcp_cst.h>
#include <siconos/numerics/sn_error_handling.h>

#include "lcp_plugin.h"

#if defined(__GNUC__)
#define PCSIM_EXPORT __attribute__((visibility("default")))
#else
#define PCSIM_EXPORT
#endif

static void say(char* message, int len, const char* text) {
  if (message && len > 0) {
    strncpy(message, text, (size_t)len - 1);
    message[len - 1] = '\0';
  }
}

PCSIM_EXPORT int pcsim_lcp_plugin_abi(void) { return PCSIM_LCP_PLUGIN_ABI; }

PCSIM_EXPORT int pcsim_lcp_plugin_solve(int n, const double* M, const double* q, int solver,
                                        double tolerance, int max_iter, double* z, double* w,
                                        double* error, int* iterations, char* message,
                                        int message_len) {
  if (n < 1 || !M || !q || !z || !w || !error || !iterations || !(tolerance > 0.0) ||
      max_iter < 1 || (solver != PCSIM_LCP_LEMKE && solver != PCSIM_LCP_ENUMERATIVE)) {
    say(message, message_len, "bad arguments to pcsim_lcp_plugin_solve");
    return -1;
  }
  numerics_set_verbose(0);
  NumericsMatrix* A = NM_create(NM_DENSE, n, n);
  double* qq = (double*)malloc(sizeof(double) * (size_t)n);
  SolverOptions* options =
      solver_options_create(solver == PCSIM_LCP_LEMKE ? SICONOS_LCP_LEMKE : SICONOS_LCP_ENUM);
  if (!A || !A->matrix0 || !qq || !options) {
    if (A) NM_free(A);
    free(qq);
    if (options) solver_options_delete(options);
    free(options);
    say(message, message_len, "out of memory");
    return -2;
  }
  memcpy(A->matrix0, M, sizeof(double) * (size_t)n * (size_t)n);
  memcpy(qq, q, sizeof(double) * (size_t)n);
  for (int i = 0; i < n; ++i) z[i] = w[i] = 0.0;
  options->iparam[SICONOS_IPARAM_MAX_ITER] = max_iter;
  options->dparam[SICONOS_DPARAM_TOL] = tolerance;
  LinearComplementarityProblem problem;
  problem.size = n;
  problem.M = A;
  problem.q = qq;
  int info;
  if (SN_SETJMP_EXTERNAL_START == 0) {
    info = linearComplementarity_driver(&problem, z, w, options);
    SN_SETJMP_EXTERNAL_STOP
    *error = options->dparam[SICONOS_DPARAM_RESIDU];
    *iterations = options->iparam[SICONOS_IPARAM_ITER_DONE];
    if (info != 0) {
      char text[160];
      snprintf(text, sizeof text, "the Siconos %s solver found no solution (info %d)",
               solver == PCSIM_LCP_LEMKE ? "Lemke" : "enumerative", info);
      say(message, message_len, text);
    }
  } else {
    SN_SETJMP_EXTERNAL_STOP
    char text[300];
    snprintf(text, sizeof text, "Siconos raised a fatal error: %s", sn_fatal_error_msg());
    say(message, message_len, text);
    info = -2;
  }
  solver_options_delete(options);  /* frees the members, not the structure itself (4.4) */
  free(options);
  NM_free(A);
  free(qq);
  return info;
}
