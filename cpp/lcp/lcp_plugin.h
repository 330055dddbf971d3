/* The ABI between pcsim and its LCP plugin (pcsim_lcp_siconos.so, built from
 * cpp/lcp/siconos_plugin.c): the one shared object that calls Siconos numerics. pcsim loads
 * it with dlopen() only when a linear complementarity problem has to be solved, so a run that
 * never needs one never loads Siconos or the OpenBLAS it links (see cpp/lcp/lcp.hpp).
 * Plain C, column-major arrays, no ownership transfer. */
#ifndef PCSIM_LCP_PLUGIN_H
#define PCSIM_LCP_PLUGIN_H

#ifdef __cplusplus
extern "C" {
#endif

/* Raised whenever a function's signature or meaning below changes. */
#define PCSIM_LCP_PLUGIN_ABI 1

/* Solver choice (the Siconos solver ids are the plugin's business). */
#define PCSIM_LCP_LEMKE 0       /* lexicographic Lemke (complementary pivoting) */
#define PCSIM_LCP_ENUMERATIVE 1 /* enumeration of the complementary bases */

/* The plugin's ABI version: PCSIM_LCP_PLUGIN_ABI. Symbol "pcsim_lcp_plugin_abi". */
typedef int (*pcsim_lcp_plugin_abi_fn)(void);

/* Solves the LCP  w = M z + q,  z >= 0,  w >= 0,  z^T w = 0  of order n.
 *   n            order, >= 1
 *   M            n x n, column-major (leading dimension n); not modified
 *   q            n; not modified
 *   solver       PCSIM_LCP_LEMKE or PCSIM_LCP_ENUMERATIVE
 *   tolerance    the solver's tolerance on its complementarity error (> 0)
 *   max_iter     the most pivots (Lemke) or bases (enumerative), >= 1
 *   z, w         out: n each
 *   error        out: Siconos's complementarity error of (z, w) (lcp_compute_error)
 *   iterations   out: pivots or bases used
 *   message      out: a NUL-terminated reason when the return value is not 0 (may be NULL)
 *   message_len  size of message
 * Returns 0 (solved to the tolerance), -1 (bad arguments), -2 (Siconos raised a fatal error),
 * or the Siconos driver's info > 0 (no solution found: the solver's own code).
 * Symbol "pcsim_lcp_plugin_solve". Not re-entrant (Siconos keeps global error state): the
 * caller serializes calls. */
typedef int (*pcsim_lcp_plugin_solve_fn)(int n, const double* M, const double* q, int solver,
                                         double tolerance, int max_iter, double* z, double* w,
                                         double* error, int* iterations, char* message,
                                         int message_len);

#ifdef __cplusplus
}
#endif

#endif /* PCSIM_LCP_PLUGIN_H */
