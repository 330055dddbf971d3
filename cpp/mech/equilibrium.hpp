// The static equilibrium of a constrained system at rest, solved with the engine: the
// generalized forces at rest (averaged over one excitation period when the model is excited)
// balanced by ideal constraint reactions, the holonomic constraints satisfied, chosen
// coordinates held at given values. A physical start for transient runs and shooting.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "common/eigen_instances.hpp"

#include "mech/model.hpp"
#include "mech/status.hpp"

namespace pcsim::mech {

struct EquilibriumOptions {
  double t0 = 0.0;
  /// > 0: the forces are averaged over [t0, t0 + period] (a time-dependent excitation at rest
  /// averages out; what remains is its mean); NaN or 0: the forces at t0.
  double period = std::numeric_limits<double>::quiet_NaN();
  /// Points of the periodic trapezoid rule for the average: exact for trigonometric
  /// polynomials in t of degree < samples (the sieve's excitation has degree 1).
  int samples = 64;
  /// Coordinates held at their value in the guess (the model's slow coordinates): their force
  /// balance is replaced by q_k = value, and the force that holds them is reported.
  std::vector<int> held;
  int max_iterations = 50;
  double tol = 1e-13;  ///< relative size of the last Newton correction of q
};

struct EquilibriumResult {
  ModelIssue issue = ModelIssue::none;
  std::string message;            ///< why not found (names the coordinate with the largest imbalance)
  Eigen::VectorXd q;              ///< the equilibrium
  Eigen::VectorXd lambda;         ///< the reactions R = gᵀ λ at rest, by active constraint
  Eigen::VectorXd holding_force;  ///< per held coordinate: the generalized force that holds it
  double residual = 0.0;          ///< max-norm force imbalance of the free coordinates
  double force_scale = 0.0;       ///< the largest generalized force at rest (for relative checks)
  int iterations = 0;
};

/// Newton's method on the equilibrium conditions
///
///     F(q) + g(q)ᵀ λ = 0   (rows of the coordinates not held),   F = mean over t of (Q − h)(q, 0, t)
///     q_k = value_k        (held coordinates)
///     Φ(q, t0) = 0         (active holonomic constraints),
///
/// unknowns q and λ (one per active constraint; a velocity-form constraint can hold a static
/// load too), with the exact Jacobian from the model's tangents (the model must have them:
/// Model::has_tangents()). With velocity-form constraints there are more unknowns than
/// equations and the Newton corrections are the minimum-norm ones: the equilibrium nearest to
/// the guess. Never throws for numerical trouble.
EquilibriumResult static_equilibrium(const Model& model, const std::vector<int>& active,
                                     const Eigen::VectorXd& q_guess,
                                     const EquilibriumOptions& options = {});

}  // namespace pcsim::mech
