#include "steady/own_reaction_model.hpp"

#include <algorithm>

namespace pcsim::steady {

OwnReactionModel::OwnReactionModel(std::shared_ptr<const mech::Model> inner, std::vector<int> active,
                                   std::vector<int> held)
    : ForwardingModel(std::move(inner)), active_(std::move(active)) {
  for (int h : held) {
    const auto it = std::find(active_.begin(), active_.end(), h);
    if (it != active_.end()) held_rows_.push_back(static_cast<int>(it - active_.begin()));
  }
}

void OwnReactionModel::derived(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                               const Eigen::VectorXd& qdd, const Eigen::VectorXd& R,
                               Eigen::VectorXd& out) const {
  const int n = inner_->n(), s = static_cast<int>(active_.size());
  if (held_rows_.empty() || s == 0 || !R.allFinite()) {
    inner_->derived(t, q, qd, qdd, R, out);
    return;
  }
  Eigen::MatrixXd g(s, n);
  Eigen::VectorXd g0(s), gamma(s);
  inner_->constraint_rows(active_, t, q, qd, g, g0, gamma);
  // R = gᵀ λ for ideal constraints: λ = (g gᵀ)⁻¹ g R (exact for R in the row space of g).
  const Eigen::VectorXd lambda = (g * g.transpose()).ldlt().solve(g * R);
  Eigen::VectorXd own = R;
  for (int r : held_rows_) own -= lambda[r] * g.row(r).transpose();
  inner_->derived(t, q, qd, qdd, own, out);
}

}  // namespace pcsim::steady
