// A model that forwards every call to another model: the base of wrappers that change one
// aspect of a model (its forces, its outputs) and keep the rest, tangents included.
#pragma once

#include <memory>
#include <utility>
#include <vector>

#include "mech/model.hpp"

namespace pcsim::mech {

class ForwardingModel : public Model {
 public:
  explicit ForwardingModel(std::shared_ptr<const Model> inner) : inner_(std::move(inner)) {
    name_ = inner_->name();
    coordinates_ = inner_->coordinates();
    constraints_ = inner_->constraints();
    derived_names_ = inner_->derived_names();
  }

  const Model& inner() const { return *inner_; }
  const std::shared_ptr<const Model>& inner_ptr() const { return inner_; }

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
    inner_->forces_tangent(t, q, qd, V, Q, dQ);
  }
  void constraint_rows_tangent(const std::vector<int>& active, double t, const Eigen::VectorXd& q,
                               const Eigen::VectorXd& qd, const Eigen::MatrixXd& V,
                               Eigen::MatrixXd& g, Eigen::VectorXd& g0, Eigen::VectorXd& gamma,
                               std::vector<Eigen::MatrixXd>& dg, Eigen::MatrixXd& dg0,
                               Eigen::MatrixXd& dgamma) const override {
    inner_->constraint_rows_tangent(active, t, q, qd, V, g, g0, gamma, dg, dg0, dgamma);
  }

 protected:
  std::shared_ptr<const Model> inner_;
};

}  // namespace pcsim::mech
