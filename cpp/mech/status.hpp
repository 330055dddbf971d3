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

/// What went wrong with a model or constraint set, found before (or during) integration.
enum class ModelIssue {
  none,
  unknown_constraint,        ///< an active constraint name the model does not offer
  singular_mass_matrix,      ///< M not symmetric positive definite
  dependent_constraints,     ///< an active row depends linearly on earlier ones (rank < s)
  inconsistent_constraints,  ///< dependent rows whose right-hand sides contradict
  non_finite,                ///< NaN or Inf in T's derivatives, Q, g, g0 or γ
  not_constant_row,          ///< a row declared constant_row varies with q or t
  kernel_failure,            ///< the Huang kernel returned an error
};
const char* to_string(ModelIssue issue);

/// How a simulation ended.
enum class SimulationStatus {
  success,              ///< reached t_end
  stopped_by_observer,  ///< the step observer returned false
  invalid_model,        ///< the model or constraint set is bad at the start (issue says which)
  inconsistent_start,   ///< the initial state cannot be projected onto the constraints
  integration_failed,   ///< the integrator failed (integrator_status and message say why)
  model_failed,         ///< the model could not be evaluated during the run (issue, time)
  projection_failed,    ///< the drift projection after a step failed (issue, time)
  observer_error,       ///< the step observer threw
};
const char* to_string(SimulationStatus status);

}  // namespace pcsim::mech
