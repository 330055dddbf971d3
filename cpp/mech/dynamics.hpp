// The per-run workspace of the engine (the "Data" beside the immutable Model): evaluates M, h,
// Q, g, g0, γ at a state and solves for the reactions R and accelerations q̈ by one of the three
// formulations, without heap allocation after construction (except Huang calls when the
// constraint rows vary with q or t).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Dense>

#include "common/kernel.hpp"
#include "mech/model.hpp"
#include "mech/simulation.hpp"

namespace pcsim::mech {

class Dynamics {
 public:
  /// active: indices into model.constraints(). Baumgarte terms are added to γ when
  /// stabilization == baumgarte.
  Dynamics(const Model& model, std::vector<int> active, Kernel kernel,
           Stabilization stabilization = Stabilization::none, double alpha = 0.0,
           double beta = 0.0);

  /// Evaluates M, h, Q, f = Q − h, g, g0, γ (with Baumgarte terms) at (t, q, qd) and checks
  /// them for NaN/Inf. Returns the issue (and sets message()) or ModelIssue::none.
  ModelIssue evaluate(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd);

  /// After evaluate(): factorizes M and solves for R and q̈ (members R, qdd).
  ModelIssue solve(ReactionMethod method);

  /// After evaluate() and solve(compatibility) (which factorizes M and forms G, G0, D):
  /// the DAE residuals for given a and R: res_dyn = M a − f − R (n),
  /// res_con = [G R + G0; Dᵀ R] (n).
  void dae_residuals(const Eigen::VectorXd& a, const Eigen::VectorXd& Rv,
                     Eigen::Ref<Eigen::VectorXd> res_dyn, Eigen::Ref<Eigen::VectorXd> res_con) const;

  /// Factorizes M and forms G = g M⁻¹, G0 = g M⁻¹ f + γ and D (Huang) without solving for R.
  ModelIssue prepare_compatibility();

  /// max |Φ_i(q, t)| over the active holonomic constraints (0 if none).
  double position_residual(double t, const Eigen::VectorXd& q) const;
  /// max |g q̇ + g0| from the last evaluate().
  double velocity_residual(const Eigen::VectorXd& qd) const;

  const std::string& message() const { return message_; }
  int n() const { return n_; }
  int s() const { return s_; }
  const std::vector<int>& active() const { return active_; }

  // Results of the last evaluate() / solve(), readable by the caller.
  Eigen::MatrixXd M, g, D, G, A;
  Eigen::VectorXd h, Q, f, g0, gamma, G0, R, qdd;

 private:
  ModelIssue fail(ModelIssue issue, std::string message);
  ModelIssue factorize_mass();
  ModelIssue null_basis();
  ModelIssue solve_compatibility();
  ModelIssue solve_kkt();
  ModelIssue solve_udwadia_kalaba();

  const Model* model_;
  std::vector<int> active_;
  Kernel kernel_;
  Stabilization stabilization_;
  double alpha_, beta_;
  int n_, s_;
  bool constant_rows_;
  bool have_D_ = false;
  double t_ = 0.0;
  Eigen::VectorXd q_, qd_;
  std::string message_;

  Eigen::LLT<Eigen::MatrixXd> llt_;
  Eigen::PartialPivLU<Eigen::MatrixXd> lu_;
  Eigen::MatrixXd MinvgT_;  // M⁻¹ gᵀ (n x s)
  Eigen::VectorXd a0_, rhs_, tmp_;
};

/// "coordinate 'x'" style names for messages.
std::string coordinate_list(const Model& model, const Eigen::VectorXd& v, double threshold);

}  // namespace pcsim::mech
