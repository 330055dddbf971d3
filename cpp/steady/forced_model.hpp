// A model with constant generalized forces added to Q: the holding forces of slow coordinates
// (a constant force on a coordinate is the reaction of the integral constraint that fixes its
// mean over the period; docs/steady.md "Slow coordinates"). Everything else, tangents included,
// is the wrapped model's.
#pragma once

#include <memory>
#include <vector>

#include "mech/model.hpp"

namespace pcsim::steady {

class ForcedModel final : public mech::Model {
 public:
  /// Q of `inner` plus H[k] on coordinate coordinates[k].
  ForcedModel(std::shared_ptr<const mech::Model> inner, std::vector<int> coordinates,
              Eigen::VectorXd H);

  const mech::Model& inner() const { return *inner_; }
  const std::shared_ptr<const mech::Model>& inner_ptr() const { return inner_; }

  void kinetic_terms(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                     Eigen::MatrixXd& M, Eigen::VectorXd& h) const override {
    inner_->kinetic_terms(t, q, qd, M, h);
  }
  void forces(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
              Eigen::VectorXd& Q) const override {
    inner_->forces(t, q, qd, Q);
    add(Q);
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
               Eigen::VectorXd& out) const override {
    inner_->derived(t, q, qd, qdd, R, out);
  }
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
    inner_->forces_tangent(t, q, qd, V, Q, dQ);  // the added forces are constant: dQ unchanged
    add(Q);
  }
  void constraint_rows_tangent(const std::vector<int>& active, double t, const Eigen::VectorXd& q,
                               const Eigen::VectorXd& qd, const Eigen::MatrixXd& V,
                               Eigen::MatrixXd& g, Eigen::VectorXd& g0, Eigen::VectorXd& gamma,
                               std::vector<Eigen::MatrixXd>& dg, Eigen::MatrixXd& dg0,
                               Eigen::MatrixXd& dgamma) const override {
    inner_->constraint_rows_tangent(active, t, q, qd, V, g, g0, gamma, dg, dg0, dgamma);
  }

 private:
  void add(Eigen::VectorXd& Q) const {
    for (std::size_t k = 0; k < coordinates_idx_.size(); ++k) Q[coordinates_idx_[k]] += H_[k];
  }
  std::shared_ptr<const mech::Model> inner_;
  std::vector<int> coordinates_idx_;
  Eigen::VectorXd H_;
};

/// The inner model with the holding forces added (the model itself when there are none).
std::shared_ptr<const mech::Model> with_forces(std::shared_ptr<const mech::Model> inner,
                                               const std::vector<int>& coordinates,
                                               const Eigen::VectorXd& H);

}  // namespace pcsim::steady
