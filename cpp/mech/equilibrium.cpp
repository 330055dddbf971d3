// The static equilibrium by Newton's method with the exact Jacobian (see equilibrium.hpp).
#include "mech/equilibrium.hpp"
#include "common/format.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace pcsim::mech {

namespace {

std::string fmt(double v) { return format_significant(v, 6); }

}  // namespace

EquilibriumResult static_equilibrium(const Model& model, const std::vector<int>& active,
                                     const Eigen::VectorXd& q_guess,
                                     const EquilibriumOptions& options) {
  EquilibriumResult res;
  const int n = model.n();
  const int s = static_cast<int>(active.size());
  res.q = q_guess;
  res.lambda = Eigen::VectorXd::Zero(s);
  if (!model.has_tangents()) {
    res.issue = ModelIssue::kernel_failure;
    res.message = "model '" + model.name() +
                  "' has no exact tangents, which the equilibrium's Newton iteration needs "
                  "(models from model files have them)";
    return res;
  }
  std::vector<bool> held(n, false);
  for (int k : options.held)
    if (k >= 0 && k < n) held[k] = true;
  std::vector<int> hol;  // rows of the holonomic constraints
  for (int r = 0; r < s; ++r)
    if (model.constraints()[active[r]].kind == ConstraintKind::holonomic) hol.push_back(r);
  const int sh = static_cast<int>(hol.size());
  const bool average = std::isfinite(options.period) && options.period > 0;
  const int samples = average ? std::max(1, options.samples) : 1;

  const Eigen::VectorXd qd = Eigen::VectorXd::Zero(n);
  Eigen::MatrixXd V = Eigen::MatrixXd::Zero(2 * n + 1, n);
  V.topRows(n).setIdentity();
  Eigen::MatrixXd M, dh, dQ, g, dg0, dgamma;
  Eigen::VectorXd h, Q, g0, gamma;
  std::vector<Eigen::MatrixXd> dM, dg;
  Eigen::VectorXd F(n);
  Eigen::MatrixXd dF(n, n);
  for (int it = 0; it <= options.max_iterations; ++it) {
    res.iterations = it;
    // F(q) = mean (Q − h)(q, 0, t) and its Jacobian, exact (tangents in the n directions e_l).
    F.setZero();
    dF.setZero();
    res.force_scale = 0;
    for (int k = 0; k < samples; ++k) {
      const double t = options.t0 + (average ? options.period * k / samples : 0.0);
      model.kinetic_terms_tangent(t, res.q, qd, V, M, h, dM, dh);
      model.forces_tangent(t, res.q, qd, V, Q, dQ);
      F += (Q - h) / samples;
      dF += (dQ - dh) / samples;
      res.force_scale = std::max(res.force_scale, std::max(Q.cwiseAbs().maxCoeff(), h.cwiseAbs().maxCoeff()));
    }
    if (s > 0) model.constraint_rows_tangent(active, options.t0, res.q, qd, V, g, g0, gamma, dg, dg0, dgamma);
    if (!F.allFinite() || !dF.allFinite() || (s > 0 && !g.allFinite())) {
      res.issue = ModelIssue::non_finite;
      res.message = "the forces or constraint rows are not finite at the equilibrium iterate";
      return res;
    }
    // Residual and Jacobian in the unknowns (q, λ).
    Eigen::VectorXd r(n + sh);
    Eigen::MatrixXd J = Eigen::MatrixXd::Zero(n + sh, n + s);
    Eigen::VectorXd balance = F;
    if (s > 0) balance.noalias() += g.transpose() * res.lambda;
    for (int i = 0; i < n; ++i) {
      if (held[i]) {
        r[i] = res.q[i] - q_guess[i];
        J(i, i) = 1.0;
      } else {
        r[i] = balance[i];
        J.row(i).head(n) = dF.row(i);
        for (int l = 0; l < n; ++l)
          if (s > 0) J(i, l) += dg[l].col(i).dot(res.lambda);
        if (s > 0) J.row(i).tail(s) = g.col(i).transpose();
      }
    }
    for (int a = 0; a < sh; ++a) {
      r[n + a] = model.position_residual(active[hol[a]], options.t0, res.q);
      J.row(n + a).head(n) = g.row(hol[a]);
    }
    res.residual = 0;
    for (int i = 0; i < n; ++i)
      if (!held[i]) res.residual = std::max(res.residual, std::abs(balance[i]));
    res.holding_force.resize(options.held.size());
    for (std::size_t k = 0; k < options.held.size(); ++k) res.holding_force[k] = -balance[options.held[k]];
    const Eigen::VectorXd delta = J.completeOrthogonalDecomposition().solve(-r);
    if (!delta.allFinite()) {
      res.issue = ModelIssue::dependent_constraints;
      res.message = "the equilibrium equations are singular";
      return res;
    }
    res.q += delta.head(n);
    if (s > 0) res.lambda += delta.tail(s);
    const double dq = delta.head(n).lpNorm<Eigen::Infinity>();
    if (dq <= options.tol * (1.0 + res.q.lpNorm<Eigen::Infinity>()) &&
        res.residual <= 1e-9 * std::max(1.0, res.force_scale)) {
      return res;
    }
  }
  // No convergence: name the coordinate with the largest imbalance.
  int worst = 0;
  Eigen::VectorXd balance = F;
  if (s > 0) balance.noalias() += g.transpose() * res.lambda;
  for (int i = 0; i < n; ++i)
    if (!held[i] && std::abs(balance[i]) > std::abs(balance[worst])) worst = i;
  res.issue = ModelIssue::inconsistent_constraints;
  res.message = "no static equilibrium found in " + std::to_string(options.max_iterations) +
                " Newton iterations: the largest force imbalance is " + fmt(balance[worst]) +
                " on coordinate '" + model.coordinates()[worst] +
                "' (a coordinate without restoring force has no equilibrium: declare it slow, "
                "[model] slow, to hold it, or constrain it)";
  return res;
}

}  // namespace pcsim::mech
