// Exact derivatives of the ODE form's right-hand side f(t, y) = (q̇, q̈(q, q̇, t)): the
// structured reaction solve (R = gᵀ λ, (g M⁻¹ gᵀ) λ = −(g M⁻¹ (Q − h) + γ)) differentiated
// through its linear algebra with the model's exact tangents of M, h, Q, g, g0, γ. For
// variational equations (monodromy matrices), analytic Jacobians and sensitivities.
#pragma once

#include <string>
#include <vector>

#include "common/eigen_instances.hpp"

#include "mech/dynamics.hpp"
#include "mech/model.hpp"
#include "mech/status.hpp"

namespace pcsim::mech {

/// The workspace (one per thread) of the exact tangent of the ODE form. With the active rows g,
/// γ (Baumgarte terms included when asked) the accelerations solve
///
///     M q̈ = f + gᵀ λ,   g q̈ = −γ,          f = Q − h,
///
/// and a direction (δq, δq̇, δt) changes them by the solution of the same structured system
///
///     M dq̈ = b1 + gᵀ dλ,  g dq̈ = b2,   b1 = df + dgᵀ λ − dM q̈,  b2 = −dγ − dg q̈,
///
/// i.e. dλ = (g M⁻¹ gᵀ)⁻¹ (b2 − g M⁻¹ b1), dq̈ = M⁻¹ (b1 + gᵀ dλ), with the factorizations of
/// M and g M⁻¹ gᵀ computed once for all directions. Exact to rounding: no finite differences.
/// The model must have tangents (Model::has_tangents(); models from model files do).
class RhsTangent {
 public:
  /// Throws std::invalid_argument if the model has no tangents (say so to the user rather than
  /// fall back to finite differences). Baumgarte terms are differentiated when stabilization
  /// == baumgarte (γ + 2α (g q̇ + g0) + β² Φ on holonomic rows).
  explicit RhsTangent(const Model& model, Stabilization stabilization = Stabilization::none,
                      double alpha = 0.0, double beta = 0.0);

  /// Values q̈, λ, R = gᵀλ at (t, q, q̇) and, for each column of V ((2n + 1) x k: δq, δq̇, δt),
  /// their directional derivatives dqdd (n x k), dlambda (s x k), dR (n x k). k may be 0.
  ModelIssue evaluate(const ActiveSet& active, double t, const Eigen::VectorXd& q,
                      const Eigen::VectorXd& qd, const Eigen::MatrixXd& V);

  /// After evaluate(): the constrained response to extra generalized forces B (n x p): the
  /// change of q̈ (X, n x p) and of λ (L, s x p) per unit force, i.e. the solution of
  /// M X = B + gᵀ L, g X = 0 (X = C B with C = M⁻¹ − M⁻¹gᵀ(g M⁻¹ gᵀ)⁻¹ g M⁻¹).
  void respond(const Eigen::MatrixXd& B, Eigen::MatrixXd& X, Eigen::MatrixXd* L = nullptr) const;

  /// The Jacobian ∂f/∂y (2n x 2n, y = (q, q̇)) of the ODE form f = (q̇, q̈) at (t, q, q̇), and
  /// ∂f/∂t (2n) if dfdt is given.
  ModelIssue jacobian(const ActiveSet& active, double t, const Eigen::VectorXd& q,
                      const Eigen::VectorXd& qd, Eigen::MatrixXd& J,
                      Eigen::VectorXd* dfdt = nullptr);

  const std::string& message() const { return message_; }
  int n() const { return n_; }
  int s() const { return s_; }

  // Results of the last evaluate().
  Eigen::VectorXd qdd, lambda, R;
  Eigen::MatrixXd dqdd, dlambda, dR;

 private:
  ModelIssue fail(ModelIssue issue, std::string message);

  const Model* model_;
  Stabilization stabilization_;
  double alpha_, beta_;
  int n_, s_ = 0;
  std::string message_;

  Eigen::MatrixXd M_, g_, dh_, dQ_, dg0_, dgamma_, B1_, B2_, X_, MinvgT_, S_, Vjac_, T_;
  Eigen::VectorXd h_, Q_, g0_, gamma_, f_, a0_, G0_, rM_, rS_;
  std::vector<Eigen::MatrixXd> dM_, dg_;
  // Cholesky factors (lower triangles) of M (in M_) and of g M⁻¹ gᵀ (in S_): small dense
  // matrices, factored and solved by plain loops without allocation.
  mutable Eigen::MatrixXd R1_, R2_;
};

}  // namespace pcsim::mech
