// The engine's enums and statuses: the formulation and drift control a run uses, what can be
// wrong with a model or constraint set, and how a simulation ended (its own status, not the
// integrator's: the integrator's detail stays in SimulationResult::integrator_status).
#pragma once

namespace pcsim::mech {

enum class Form {
  ode,  ///< y = (q, q̇); R computed inside the right-hand side
  dae,  ///< y = (q, v, a, R), K = diag(I, I, 0, 0): q' = v, v' = a, 0 = M a + h − Q − R,
        ///< 0 = [G; Dᵀ] R + [G0; 0]  (index 1 in a and R), as in the paper
};
const char* to_string(Form form);

enum class Stabilization {
  none,        ///< acceleration-level constraints only: drift grows
  projection,  ///< minimum-norm (Huang) correction of q and q̇ after every accepted step
  baumgarte,   ///< g q̈ + γ + 2α (g q̇ + g0) + β² Φ = 0 instead of g q̈ + γ = 0
};

enum class ReactionMethod {
  compatibility,    ///< [G; Dᵀ] R = [−G0; 0], D from the Huang kernel (the paper's method),
                    ///< solved as one dense n x n system
  compatibility_structured,  ///< the same system solved through its structure: D spans null(g),
                             ///< so Dᵀ R = 0 means R = gᵀ λ, and G R = −G0 becomes the s x s
                             ///< system (g M⁻¹ gᵀ) λ = −G0 (no D, no n x n LU; same R)
  kkt,              ///< Lagrange multipliers: R = gᵀλ, (g M⁻¹ gᵀ) λ = −G0
  udwadia_kalaba,   ///< R = M^{1/2} (g M^{-1/2})⁺ (−G0)
};

/// What went wrong with a model or constraint set, found before (or during) integration: the
/// one table (name, message) the enum, to_string() and message() are expanded from.
#define PCSIM_MODEL_ISSUE_TABLE(X)                                                            \
  X(none, "none")                                                                             \
  /* an active constraint name the model does not offer */                                    \
  X(unknown_constraint, "unknown constraint")                                                 \
  /* M not symmetric positive definite */                                                     \
  X(singular_mass_matrix, "singular mass matrix")                                             \
  /* an active row depends linearly on earlier ones (rank < s) */                             \
  X(dependent_constraints, "dependent constraints")                                           \
  /* dependent rows whose right-hand sides contradict */                                      \
  X(inconsistent_constraints, "inconsistent constraints")                                     \
  /* NaN or Inf in T's derivatives, Q, g, g0 or γ */                                          \
  X(non_finite, "non-finite value (NaN or Inf)")                                              \
  /* a row declared constant_row varies with q or t */                                        \
  X(not_constant_row, "constraint row declared constant is not")                              \
  /* the Huang kernel (or the LCP library) returned an error */                               \
  X(kernel_failure, "Huang kernel failure")

enum class ModelIssue {
#define PCSIM_MECH_ENUMERATOR(name, message) name,
  PCSIM_MODEL_ISSUE_TABLE(PCSIM_MECH_ENUMERATOR)
#undef PCSIM_MECH_ENUMERATOR
};
/// The enumerator's name, e.g. "singular_mass_matrix" ("unknown" outside the table).
const char* to_string(ModelIssue issue);
/// The one-line message of the table, e.g. "singular mass matrix".
const char* message(ModelIssue issue);

/// How a simulation ended: the one table (name, message).
#define PCSIM_SIMULATION_STATUS_TABLE(X)                                                      \
  /* reached t_end */                                                                         \
  X(success, "success")                                                                       \
  /* the step observer returned false */                                                      \
  X(stopped_by_observer, "stopped by the observer")                                           \
  /* the model or constraint set is bad at the start (issue says which) */                    \
  X(invalid_model, "invalid model or constraint set")                                         \
  /* the initial state cannot be projected onto the constraints */                            \
  X(inconsistent_start, "inconsistent initial state")                                         \
  /* the integrator failed (integrator_status and message say why) */                         \
  X(integration_failed, "integration failed")                                                 \
  /* the model could not be evaluated during the run (issue, time) */                         \
  X(model_failed, "model evaluation failed")                                                  \
  /* the drift projection after a step failed (issue, time) */                                \
  X(projection_failed, "drift projection failed")                                             \
  /* the step observer threw */                                                               \
  X(observer_error, "step observer error")

enum class SimulationStatus {
#define PCSIM_MECH_ENUMERATOR(name, message) name,
  PCSIM_SIMULATION_STATUS_TABLE(PCSIM_MECH_ENUMERATOR)
#undef PCSIM_MECH_ENUMERATOR
};
/// The enumerator's name, e.g. "integration_failed" ("unknown" outside the table).
const char* to_string(SimulationStatus status);
/// The one-line message of the table, e.g. "integration failed" (the summary's failure status).
const char* message(SimulationStatus status);

}  // namespace pcsim::mech
