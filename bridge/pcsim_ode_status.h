/* pcsim_ode_status.h: THE table of integrator statuses (the one source).
 *
 * Every ODE/DAE kernel of pcsim (Radau IIA, the explicit Runge-Kutta pair) returns one of these
 * codes as IDID; the bridge passes it through unchanged; the C++ API (cpp/ode/status.hpp,
 * pcsim::OdeStatus) builds its enum, to_string() and meaning() from this X-macro; the Fortran
 * kernels INCLUDE fortran/pcsim_ode_status.fi (PARAMETER ODE_<NAME>); docs/radau.md shows the
 * table. tests/ode/test_ode_status_table.cpp parses the Fortran include and the docs table and
 * fails if either differs from this list (name, code, meaning), so edit here first.
 *
 * Codes: 0 success; 1, 2 ordinary returns before t_end (not failures); < 0 illegal argument
 * (IDID = -i names argument i, LAPACK style; the table lists -1 for the class); >= 3 failures,
 * after which t and y are the last accepted state.
 *
 * X(name, code, meaning): name is the C++ enumerator (the Fortran PARAMETER is ODE_ + NAME in
 * upper case), meaning the one-line explanation shown to users. */
#ifndef PCSIM_ODE_STATUS_H
#define PCSIM_ODE_STATUS_H

#define PCSIM_ODE_STATUS_TABLE(X)                                                              \
  X(success, 0, "reached t_end")                                                               \
  X(stopped_by_callback, 1, "the step callback asked to stop; t, y are the end of that step")   \
  X(root_found, 2, "an event function changed sign; t, y are at the earliest root")             \
  X(bad_input, -1, "argument i is illegal (IDID = -i); nothing was computed")                  \
  X(too_many_steps, 3, "more steps than the allowed maximum")                                  \
  X(step_too_small, 4, "the step size fell below 10 unit roundoffs of t")                      \
  X(newton_failure, 5, "the Newton iteration diverged repeatedly, also with a fresh Jacobian") \
  X(singular_matrix, 6, "the iteration matrix was exactly singular repeatedly")                \
  X(non_finite, 7, "f, the Jacobian or the error estimate stayed non-finite as h shrank")      \
  X(rhs_failed, 8, "the right-hand side reported it cannot evaluate, persistently")            \
  X(jacobian_failed, 9, "the Jacobian callback reported failure")                              \
  X(callback_error, 10, "a callback threw or returned an invalid code")                        \
  X(tolerance_too_small, 11, "a tolerance is not > 0, or rtol < 10 unit roundoffs")            \
  X(inconsistent_start, 12, "the algebraic equations do not hold at t0 within the tolerance")  \
  X(missing_index_counts, 13, "singular mass matrix, Newton fails at once: index-2/3 counts may be missing") \
  X(stiffness_detected, 14, "the explicit method detected stiffness (never from Radau)")

/* The codes as C enumerators, PCSIM_ODE_<name> (e.g. PCSIM_ODE_success), for C callers. */
#define PCSIM_ODE_STATUS_ENUMERATOR(name, code, meaning) PCSIM_ODE_##name = code,
enum pcsim_ode_status { PCSIM_ODE_STATUS_TABLE(PCSIM_ODE_STATUS_ENUMERATOR) };
#undef PCSIM_ODE_STATUS_ENUMERATOR

#endif /* PCSIM_ODE_STATUS_H */
