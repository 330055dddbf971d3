// A model whose outputs see only the reactions of its own constraints: constraints a case adds
// to hold a slow coordinate rigidly are left out of the reaction R its derived quantities (the
// sieve's f* = |R_s|/R_u) are computed from, so that an output reports the contact's own force
// and not the holding force (R = gᵀλ split by constraint: R_own = R − Σ_held λ_r g_rᵀ).
#pragma once

#include <memory>
#include <vector>

#include "mech/model.hpp"

namespace pcsim::steady {

class OwnReactionModel final : public mech::Model {
 public:
  /// active: the run's active constraints (row order); held: those (indices into the model's
  /// constraints, a subset of active) whose share is removed before the outputs see R.
  OwnReactionModel(std::shared_ptr<const mech::Model> inner, std::vector<int> active,
                   std::vector<int> held);

  void kinetic_terms(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                     Eigen::MatrixXd& M, Eigen::VectorXd& h) const override {
    inner_->kinetic_terms(t, q, qd, M, h);
  }
  void forces(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
              Eigen::VectorXd& Q) const override {
    inner_->forces(t, q, qd, Q);
  }
  void constraint_rows(const std::vector<int>& active, double t, const Eigen::VectorXd& q,
                       const Eigen::VectorXd& qd, Eigen::MatrixXd& g, Eigen::VectorXd& g0,
                       Eigen::VectorXd& gamma) const override {
    inner_->constraint_rows(active, t, q, qd, g, g0, gamma);
  }
  double position_residual(int i, double t, const Eigen::VectorXd& q) const override {
    return inner_->position_residual(i, t, q);
  }
  void derived(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
               const Eigen::VectorXd& qdd, const Eigen::VectorXd& R,
               Eigen::VectorXd& out) const override;
  bool has_tangents() const override { return inner_->has_tangents(); }
  void kinetic_terms_tangent(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                             const Eigen::MatrixXd& V, Eigen::MatrixXd& M, Eigen::VectorXd& h,
                             std::vector<Eigen::MatrixXd>& dM,
                             Eigen::MatrixXd& dh) const override {
    inner_->kinetic_terms_tangent(t, q, qd, V, M, h, dM, dh);
  }
  void forces_tangent(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                      const Eigen::MatrixXd& V, Eigen::VectorXd& Q,
                      Eigen::MatrixXd& dQ) const override {
    inner_->forces_tangent(t, q, qd, V, Q, dQ);
  }
  void constraint_rows_tangent(const std::vector<int>& active, double t, const Eigen::VectorXd& q,
                               const Eigen::VectorXd& qd, const Eigen::MatrixXd& V,
                               Eigen::MatrixXd& g, Eigen::VectorXd& g0, Eigen::VectorXd& gamma,
                               std::vector<Eigen::MatrixXd>& dg, Eigen::MatrixXd& dg0,
                               Eigen::MatrixXd& dgamma) const override {
    inner_->constraint_rows_tangent(active, t, q, qd, V, g, g0, gamma, dg, dg0, dgamma);
  }

 private:
  std::shared_ptr<const mech::Model> inner_;
  std::vector<int> active_;
  std::vector<int> held_rows_;  ///< positions in active_ of the held constraints
};

}  // namespace pcsim::steady
