// A model with constant generalized forces added to Q: the holding forces of slow coordinates
// (a constant force on a coordinate is the reaction of the integral constraint that fixes its
// mean over the period; docs/steady.md "Slow coordinates"). Everything else, tangents included,
// is the wrapped model's.
#pragma once

#include <memory>
#include <vector>

#include "mech/forwarding_model.hpp"

namespace pcsim::steady {

class ForcedModel final : public mech::ForwardingModel {
 public:
  /// Q of `inner` plus H[k] on coordinate coordinates[k].
  ForcedModel(std::shared_ptr<const mech::Model> inner, std::vector<int> coordinates,
              Eigen::VectorXd H);

  void forces(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
              Eigen::VectorXd& Q) const override {
    inner_->forces(t, q, qd, Q);
    add(Q);
  }
  void forces_tangent(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                      const Eigen::MatrixXd& V, Eigen::VectorXd& Q,
                      Eigen::MatrixXd& dQ) const override {
    inner_->forces_tangent(t, q, qd, V, Q, dQ);  // the added forces are constant: dQ unchanged
    add(Q);
  }

 private:
  void add(Eigen::VectorXd& Q) const {
    for (std::size_t k = 0; k < coordinates_idx_.size(); ++k) Q[coordinates_idx_[k]] += H_[k];
  }
  std::vector<int> coordinates_idx_;
  Eigen::VectorXd H_;
};

/// The inner model with the holding forces added (the model itself when there are none).
std::shared_ptr<const mech::Model> with_forces(std::shared_ptr<const mech::Model> inner,
                                               const std::vector<int>& coordinates,
                                               const Eigen::VectorXd& H);

}  // namespace pcsim::steady
