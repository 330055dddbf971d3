// The exact tangent of the ODE form's right-hand side (see tangent.hpp).
#include "mech/tangent.hpp"
#include "common/format.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace pcsim::mech {

namespace {

std::string fmt(double v) { return format_significant(v, 6); }

// Cholesky factorization A = L Lᵀ in place (the lower triangle of A becomes L; rdiag holds
// 1/L_jj), with the engine's acceptance test: every pivot positive and the pivot ratio above
// 1e-13. Column-oriented loops over contiguous memory, no allocation.
bool cholesky(Eigen::MatrixXd& A, Eigen::VectorXd& rdiag) {
  const int n = static_cast<int>(A.rows());
  rdiag.resize(n);
  double dmin = INFINITY, dmax = 0;
  double* a = A.data();
  for (int j = 0; j < n; ++j) {
    double* cj = a + static_cast<std::size_t>(j) * n;  // column j
    // cj[j..n) -= L(j..n, 0..j) L(j, 0..j)ᵀ
    for (int k = 0; k < j; ++k) {
      const double* ck = a + static_cast<std::size_t>(k) * n;
      const double ljk = ck[j];
      for (int i = j; i < n; ++i) cj[i] -= ck[i] * ljk;
    }
    const double d = cj[j];
    if (!(d > 0)) return false;
    dmin = std::min(dmin, d);
    dmax = std::max(dmax, d);
    const double l = std::sqrt(d), r = 1.0 / l;
    cj[j] = l;
    rdiag[j] = r;
    for (int i = j + 1; i < n; ++i) cj[i] *= r;
  }
  return n == 0 || dmin > 1e-13 * dmax;
}

// B := (L Lᵀ)⁻¹ B, column by column (L the lower triangle of F, rdiag its reciprocal diagonal).
void cholesky_solve(const Eigen::MatrixXd& F, const Eigen::VectorXd& rdiag, Eigen::Ref<Eigen::MatrixXd> B) {
  const int n = static_cast<int>(F.rows());
  const double* f = F.data();
  for (int c = 0; c < B.cols(); ++c) {
    double* b = B.col(c).data();
    for (int j = 0; j < n; ++j) {  // L y = b
      const double yj = b[j] * rdiag[j];
      b[j] = yj;
      const double* fj = f + static_cast<std::size_t>(j) * n;
      for (int i = j + 1; i < n; ++i) b[i] -= fj[i] * yj;
    }
    for (int i = n - 1; i >= 0; --i) {  // Lᵀ x = y
      const double* fi = f + static_cast<std::size_t>(i) * n;
      double v = b[i];
      for (int k = i + 1; k < n; ++k) v -= fi[k] * b[k];
      b[i] = v * rdiag[i];
    }
  }
}

}  // namespace

RhsTangent::RhsTangent(const Model& model, Stabilization stabilization, double alpha, double beta)
    : model_(&model),
      stabilization_(stabilization),
      alpha_(alpha),
      beta_(beta),
      n_(model.n()) {
  if (!model.has_tangents()) {
    throw std::invalid_argument(
        "model '" + model.name() +
        "' has no exact tangents (only models from model files have them; the C++ models "
        "differentiate T by automatic differentiation without a forward mode): write it as a "
        "model file for exact Jacobians and variational equations");
  }
  M_.resize(n_, n_);
  h_.resize(n_);
  Q_.resize(n_);
  qdd.resize(n_);
  R.resize(n_);
}

ModelIssue RhsTangent::fail(ModelIssue issue, std::string message) {
  message_ = std::move(message);
  return issue;
}

ModelIssue RhsTangent::evaluate(const ActiveSet& active, double t, const Eigen::VectorXd& q,
                                const Eigen::VectorXd& qd, const Eigen::MatrixXd& V) {
  const int n = n_;
  const int k = static_cast<int>(V.cols());
  s_ = active.size();
  const int s = s_;
  model_->kinetic_terms_tangent(t, q, qd, V, M_, h_, dM_, dh_);
  model_->forces_tangent(t, q, qd, V, Q_, dQ_);
  if (s > 0) {
    model_->constraint_rows_tangent(active.rows(), t, q, qd, V, g_, g0_, gamma_, dg_, dg0_, dgamma_);
  } else {
    g_.resize(0, n);
    g0_.resize(0);
    gamma_.resize(0);
    dg_.assign(k, Eigen::MatrixXd(0, n));
    dg0_.resize(0, k);
    dgamma_.resize(0, k);
  }
  if (!M_.allFinite() || !h_.allFinite() || !Q_.allFinite() || !g_.allFinite() ||
      !g0_.allFinite() || !gamma_.allFinite()) {
    return fail(ModelIssue::non_finite, "the model is not finite at t = " + fmt(t));
  }
  if (stabilization_ == Stabilization::baumgarte && s > 0) {
    // γ_B = γ + 2α (g q̇ + g0) + β² Φ (holonomic rows), and its tangent: 2α (dg q̇ + g δq̇ + dg0)
    // + β² (∂Φ/∂q δq + ∂Φ/∂t δt) with ∂Φ/∂q = g, ∂Φ/∂t = g0 for a holonomic row.
    gamma_.noalias() += 2.0 * alpha_ * (g_ * qd);
    gamma_ += 2.0 * alpha_ * g0_;
    for (int j = 0; j < k; ++j) {
      dgamma_.col(j).noalias() += 2.0 * alpha_ * (dg_[j] * qd + g_ * V.col(j).segment(n, n));
      dgamma_.col(j) += 2.0 * alpha_ * dg0_.col(j);
    }
    for (int r = 0; r < s; ++r) {
      const int i = active.rows()[r];
      if (model_->constraints()[i].kind != ConstraintKind::holonomic) continue;
      gamma_[r] += beta_ * beta_ * model_->position_residual(i, t, q);
      for (int j = 0; j < k; ++j)
        dgamma_(r, j) += beta_ * beta_ * (g_.row(r).dot(V.col(j).head(n)) + g0_[r] * V(2 * n, j));
    }
  }
  // The values: the structured compatibility solve, as Dynamics computes it.
  if (!cholesky(M_, rM_)) {
    return fail(ModelIssue::singular_mass_matrix,
                "the mass matrix M = d2T/dqd2 is singular or not positive definite at t = " + fmt(t));
  }
  f_ = Q_ - h_;
  a0_ = f_;
  cholesky_solve(M_, rM_, a0_);
  lambda.resize(s);
  if (s > 0) {
    MinvgT_ = g_.transpose();
    cholesky_solve(M_, rM_, MinvgT_);
    S_.noalias() = g_ * MinvgT_;
    if (!cholesky(S_, rS_)) {
      return fail(ModelIssue::dependent_constraints,
                  "the active constraints are linearly dependent at t = " + fmt(t) +
                      " (g M^-1 g^T is singular)");
    }
    G0_.noalias() = g_ * a0_;
    G0_ += gamma_;
    lambda = -G0_;
    cholesky_solve(S_, rS_, lambda);
    R.noalias() = g_.transpose() * lambda;
    qdd = a0_;
    qdd.noalias() += MinvgT_ * lambda;
  } else {
    R.setZero();
    qdd = a0_;
  }
  // The tangents: b1 = df + dgᵀλ − dM q̈, b2 = −dγ − dg q̈ for every direction at once.
  B1_ = dQ_ - dh_;
  B2_.resize(s, k);
  for (int j = 0; j < k; ++j) {
    B1_.col(j).noalias() -= dM_[j] * qdd;
    if (s > 0) {
      B1_.col(j).noalias() += dg_[j].transpose() * lambda;
      B2_.col(j).setZero();  // (= −(dg q̈) would evaluate the product into a temporary)
      B2_.col(j).noalias() -= dg_[j] * qdd;
    }
  }
  if (s > 0) B2_ -= dgamma_;
  X_ = B1_;  // M⁻¹ b1
  cholesky_solve(M_, rM_, X_);
  dqdd = X_;
  dlambda.resize(s, k);
  dR.resize(n, k);
  if (s > 0) {
    dlambda = B2_;
    dlambda.noalias() -= g_ * X_;
    cholesky_solve(S_, rS_, dlambda);
    dqdd.noalias() += MinvgT_ * dlambda;
    dR.noalias() = g_.transpose() * dlambda;
    for (int j = 0; j < k; ++j) dR.col(j).noalias() += dg_[j].transpose() * lambda;
  } else {
    dR.setZero();
  }
  if (!qdd.allFinite() || !dqdd.allFinite()) {
    return fail(ModelIssue::non_finite, "the accelerations or their tangents are not finite at t = " + fmt(t));
  }
  return ModelIssue::none;
}

void RhsTangent::respond(const Eigen::MatrixXd& B, Eigen::MatrixXd& X, Eigen::MatrixXd* L) const {
  X = B;
  cholesky_solve(M_, rM_, X);
  if (s_ > 0) {
    R2_.noalias() = g_ * X;
    R2_ = -R2_;
    cholesky_solve(S_, rS_, R2_);
    X.noalias() += MinvgT_ * R2_;
    if (L) *L = R2_;
  } else if (L) {
    L->resize(0, B.cols());
  }
}

ModelIssue RhsTangent::jacobian(const ActiveSet& active, double t, const Eigen::VectorXd& q,
                                const Eigen::VectorXd& qd, Eigen::MatrixXd& J,
                                Eigen::VectorXd* dfdt) {
  const int n = n_;
  const int k = dfdt ? 2 * n + 1 : 2 * n;
  Vjac_.setZero(2 * n + 1, k);
  for (int j = 0; j < k; ++j) Vjac_(j, j) = 1.0;
  const ModelIssue e = evaluate(active, t, q, qd, Vjac_);
  if (e != ModelIssue::none) return e;
  J.setZero(2 * n, 2 * n);
  J.topRightCorner(n, n).setIdentity();
  J.bottomRows(n) = dqdd.leftCols(2 * n);
  if (dfdt) {
    dfdt->setZero(2 * n);
    dfdt->tail(n) = dqdd.col(2 * n);
  }
  return ModelIssue::none;
}

}  // namespace pcsim::mech
