// A model whose outputs see only the reactions of its own constraints: constraints a case adds
// to hold a slow coordinate rigidly are left out of the reaction R its derived quantities (the
// sieve's f* = |R_s|/R_u) are computed from, so that an output reports the contact's own force
// and not the holding force (R = gᵀλ split by constraint: R_own = R − Σ_held λ_r g_rᵀ).
#pragma once

#include <memory>
#include <vector>

#include "mech/forwarding_model.hpp"

namespace pcsim::steady {

class OwnReactionModel final : public mech::ForwardingModel {
 public:
  /// active: the run's active constraints (row order); held: those (indices into the model's
  /// constraints, a subset of active) whose share is removed before the outputs see R.
  OwnReactionModel(std::shared_ptr<const mech::Model> inner, std::vector<int> active,
                   std::vector<int> held);

  void derived(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
               const Eigen::VectorXd& qdd, const Eigen::VectorXd& R,
               Eigen::VectorXd& out) const override;

 private:
  std::vector<int> active_;
  std::vector<int> held_rows_;  ///< positions in active_ of the held constraints
};

}  // namespace pcsim::steady
