// Newton shooting on the constraint manifold and Floquet multipliers (see shooting.hpp).
#include "steady/shooting.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include <Eigen/Eigenvalues>
#include "common/eigen_instances.hpp"
#include <Eigen/SVD>

#include "common/format.hpp"
#include "mech/dynamics.hpp"
#include "mech/projection.hpp"
#include "mech/tangent.hpp"
#include "steady/forced_model.hpp"
#include "steady/variational.hpp"

namespace pcsim::steady {

namespace {

constexpr double kTwoPi = 6.28318530717958647692;

}  // namespace

Shooter::Shooter(OrbitProblem problem, ShootingOptions options)
    : problem_(std::move(problem)), options_(std::move(options)) {
  if (!problem_.model) throw std::invalid_argument("shooting: no model");
  if (!problem_.model->has_tangents())
    throw std::invalid_argument(
        "model '" + problem_.model->name() +
        "' has no exact tangents: the monodromy matrix needs the variational equations, which "
        "pcsim integrates with the exact derivatives of models from model files only (the C++ "
        "AD models have no forward mode); write the model as a model file");
  if (!(problem_.period > 0) || !std::isfinite(problem_.period))
    throw std::invalid_argument("shooting: the excitation period must be positive and finite");
  if (problem_.periods < 1) throw std::invalid_argument("shooting: periods must be >= 1");
  if (problem_.hold.size() != static_cast<Eigen::Index>(problem_.slow.size()))
    throw std::invalid_argument("shooting: one held value per slow coordinate");
  n_ = problem_.model->n();
  const double omega = problem_.velocity_scale > 0 ? problem_.velocity_scale : kTwoPi / orbit_period();
  scale_.resize(2 * n_);
  scale_.head(n_).setOnes();
  scale_.tail(n_).setConstant(1.0 / omega);
}

Eigen::VectorXd Shooter::weights(const Eigen::VectorXd& y) const {
  return (options_.atol + options_.rtol * y.array().abs()).inverse().matrix();
}

bool Shooter::project(OrbitPoint& x, std::string& message) const {
  if (x.H.size() != static_cast<Eigen::Index>(problem_.slow.size()))
    x.H = Eigen::VectorXd::Zero(problem_.slow.size());
  Eigen::VectorXd q = x.y.head(n_), qd = x.y.tail(n_);
  double dq = 0, dv = 0;
  mech::ProjectionWork w;
  const mech::ModelIssue e =
      mech::project_state(*problem_.model, problem_.active, problem_.t0, q, qd, options_.kernel,
                          options_.projection_tol, dq, dv, message, w);
  if (e != mech::ModelIssue::none) return false;
  x.y.head(n_) = q;
  x.y.tail(n_) = qd;
  return true;
}

bool Shooter::tangent_basis(const Eigen::VectorXd& y, const mech::Model& model,
                            Eigen::MatrixXd& B, std::string& message) const {
  const int n = n_;
  const auto& active = problem_.active;
  const int s = static_cast<int>(active.size());
  if (s == 0) {
    B = Eigen::MatrixXd::Identity(2 * n, 2 * n);
    return true;
  }
  const Eigen::VectorXd q = y.head(n), qd = y.tail(n);
  Eigen::MatrixXd V = Eigen::MatrixXd::Zero(2 * n + 1, n);
  V.topRows(n).setIdentity();
  Eigen::MatrixXd g, dg0, dgamma;
  Eigen::VectorXd g0, gamma;
  std::vector<Eigen::MatrixXd> dg;
  model.constraint_rows_tangent(active, problem_.t0, q, qd, V, g, g0, gamma, dg, dg0, dgamma);
  std::vector<int> hol;
  for (int r = 0; r < s; ++r)
    if (model.constraints()[active[r]].kind == mech::ConstraintKind::holonomic) hol.push_back(r);
  const int sh = static_cast<int>(hol.size());
  // The manifold {Φ_h(q) = 0, g q̇ + g0 = 0}: its constraint Jacobian [[g_h, 0], [K, g]] with
  // K = ∂(g q̇ + g0)/∂q, in scaled coordinates (columns times S⁻¹).
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(sh + s, 2 * n);
  for (int r = 0; r < sh; ++r) A.row(r).head(n) = g.row(hol[r]);
  for (int l = 0; l < n; ++l) A.block(sh, l, s, 1) = dg[l] * qd + dg0.col(l);
  A.block(sh, n, s, n) = g;
  for (int c = 0; c < 2 * n; ++c) A.col(c) /= scale_[c];
  if (!A.allFinite()) {
    message = "the constraint rows are not finite at the start state";
    return false;
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeFullV);
  const Eigen::VectorXd sv = svd.singularValues();
  int rank = 0;
  for (int i = 0; i < sv.size(); ++i)
    if (sv[i] > 1e-10 * std::max(1.0, sv[0])) ++rank;
  if (rank < sh + s) {
    message = "the active constraints are dependent at the start state (rank " +
              std::to_string(rank) + " < " + std::to_string(sh + s) + ")";
    return false;
  }
  B = svd.matrixV().rightCols(2 * n - rank);
  return true;
}

Linearization Shooter::linearize(const OrbitPoint& x, const ParameterDerivative* dp,
                                 bool jacobian) const {
  if (!jacobian) dp = nullptr;
  Linearization L;
  const int n = n_;
  const int ns = static_cast<int>(problem_.slow.size());
  const double kT = orbit_period();
  const double t0 = problem_.t0, t1 = t0 + kT;
  L.scale = scale_;
  if (!tangent_basis(x.y, *problem_.model, L.basis, L.message)) return L;
  const int m = static_cast<int>(L.basis.cols());
  const int cols = jacobian ? m + ns + (dp ? 1 : 0) : 0;

  const auto model = with_forces(problem_.model, problem_.slow, x.H);
  VariationalSetup vs;
  vs.model = model.get();
  vs.active = problem_.active;
  vs.quadrature = problem_.slow;                      // the held means, with sensitivities
  for (int i = 0; i < n; ++i) vs.means.push_back(i);  // every coordinate's period mean
  vs.inverse_mass_quadrature = problem_.slow;
  Eigen::MatrixXd Y0 = Eigen::MatrixXd::Zero(2 * n, cols);
  if (jacobian)
    for (int j = 0; j < m; ++j) Y0.col(j) = L.basis.col(j).cwiseQuotient(scale_);
  if (jacobian && ns > 0) {
    vs.forces = Eigen::MatrixXd::Zero(n, cols);
    for (int k = 0; k < ns; ++k) vs.forces(problem_.slow[k], m + k) = 1.0;
  }
  Eigen::VectorXd column_scale = Eigen::VectorXd::Ones(cols);

  // The parameter column: ∂q̈/∂p by the central difference of the right-hand side of the models
  // at p ± h (the tape has no derivatives with respect to parameters), and the manifold's
  // motion ∂y0/∂p by projecting the start onto the constraints of each.
  std::shared_ptr<const mech::Model> mp, mm;
  std::unique_ptr<mech::Dynamics> dyn_p, dyn_m;
  std::unique_ptr<mech::ActiveSet> set_p, set_m;
  if (dp) {
    mp = with_forces(dp->model_plus, problem_.slow, x.H);
    mm = with_forces(dp->model_minus, problem_.slow, x.H);
    dyn_p = std::make_unique<mech::Dynamics>(*mp, options_.kernel);
    dyn_m = std::make_unique<mech::Dynamics>(*mm, options_.kernel);
    set_p = std::make_unique<mech::ActiveSet>(mech::ActiveSet::of(*mp, problem_.active));
    set_m = std::make_unique<mech::ActiveSet>(mech::ActiveSet::of(*mm, problem_.active));
    const double h = dp->h;
    vs.parameter_column = cols - 1;
    vs.parameter_term = [&, h](double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                               Eigen::VectorXd& out) {
      if (dyn_p->evaluate(*set_p, t, q, qd) != mech::ModelIssue::none ||
          dyn_p->solve(mech::ReactionMethod::compatibility_structured) != mech::ModelIssue::none)
        return false;
      if (dyn_m->evaluate(*set_m, t, q, qd) != mech::ModelIssue::none ||
          dyn_m->solve(mech::ReactionMethod::compatibility_structured) != mech::ModelIssue::none)
        return false;
      out = (dyn_p->qdd - dyn_m->qdd) / (2 * h);
      return true;
    };
    std::string msg;
    auto projected = [&](const mech::Model& mod, Eigen::VectorXd& y) {
      Eigen::VectorXd q = y.head(n), qd = y.tail(n);
      double a = 0, b = 0;
      mech::ProjectionWork w;
      const bool ok = mech::project_state(mod, problem_.active, t0, q, qd, options_.kernel,
                                          options_.projection_tol, a, b, msg, w) ==
                      mech::ModelIssue::none;
      y.head(n) = q;
      y.tail(n) = qd;
      return ok;
    };
    Eigen::VectorXd yp = x.y, ym = x.y;
    if (!projected(*dp->model_plus, yp) || !projected(*dp->model_minus, ym)) {
      L.message = "the parameter derivative: " + msg;
      return L;
    }
    Y0.col(cols - 1) = (yp - ym) / (2 * h);
    column_scale[cols - 1] = 0.0;  // set below, from the response to p
  }
  // Column sizes for the error control: the z columns are unit vectors in scaled coordinates;
  // a holding-force column's position part grows like C F t²/2 over the orbit.
  if (jacobian && ns > 0) {
    Eigen::MatrixXd E = Eigen::MatrixXd::Zero(n, ns), X;
    mech::RhsTangent tan(*model);
    const mech::ActiveSet set = mech::ActiveSet::of(*model, problem_.active);
    if (tan.evaluate(set, t0, x.y.head(n), x.y.tail(n), Eigen::MatrixXd(2 * n + 1, 0)) ==
        mech::ModelIssue::none) {
      for (int k = 0; k < ns; ++k) E(problem_.slow[k], k) = 1.0;
      tan.respond(E, X);
      for (int k = 0; k < ns; ++k) column_scale[m + k] = std::max(1e-300, X.col(k).norm() * kT * kT / 2);
    }
  }
  if (dp) {
    // The parameter column's size: its start value, or the state's scale per unit of p.
    column_scale[cols - 1] =
        std::max({Y0.col(cols - 1).head(n).norm(), options_.atol / std::max(1e-300, std::abs(dp->h)),
                  x.y.head(n).norm() * 1e-3});
  }
  VariationalOptions vo;
  vo.method = options_.method;
  vo.kernel = options_.kernel;
  vo.rtol = options_.rtol;
  vo.atol = options_.atol;
  vo.max_steps = options_.max_steps;
  vo.column_scale = column_scale;
  vo.velocity_scale = 1.0 / scale_[n];
  vo.control_sensitivities = options_.control_sensitivities;
  const VariationalResult vr = integrate_variational(vs, t0, t1, x.y, Y0, vo);
  L.steps = vr.steps;
  L.f_evals = vr.f_evals;
  L.used_explicit = vr.used_explicit;
  L.used_radau = vr.used_radau;
  if (vr.status != OdeStatus::success) {
    L.t_failed = vr.t;
    L.message = "the integration over the orbit period failed at t = " +
                format_significant(vr.t, 9) + " s: " + vr.message;
    return L;
  }
  L.y_end = vr.y;
  const Eigen::VectorXd dy = vr.y - x.y;
  const Eigen::MatrixXd SY = scale_.asDiagonal() * vr.Y;
  L.residual.resize(m + ns);
  L.residual.head(m) = L.basis.transpose() * scale_.cwiseProduct(dy);
  L.mean_q = vr.mean_integrals / kT;
  L.mean_slow = vr.w / kT;
  const Eigen::MatrixXd& Wslow = vr.W;
  if (ns > 0) L.residual.tail(ns) = L.mean_slow - problem_.hold;
  // The orbit's amplitude in scaled coordinates: |S (y0 − ȳ)|, ȳ = (mean q, 0) (exact for a
  // harmonic orbit: |q − q̄|² + |q̇/Ω|² = A²).
  {
    Eigen::VectorXd dev = x.y;
    dev.head(n) -= L.mean_q;
    L.amplitude = scale_.cwiseProduct(dev).norm();
  }
  if (!jacobian) {
    const Eigen::VectorXd w = weights(x.y);
    double sum = (w.cwiseProduct(dy)).squaredNorm();
    for (int k = 0; k < ns; ++k)
      sum += std::pow(L.residual[m + k] / (options_.atol + options_.rtol * std::abs(problem_.hold[k])), 2);
    L.residual_norm = std::sqrt(sum / (2 * n + ns));
    L.residual_max = dy.lpNorm<Eigen::Infinity>();
    L.ok = L.residual.allFinite();
    if (!L.ok) L.message = "the residual is not finite";
    return L;
  }
  L.jacobian.resize(m + ns, m + ns);
  L.monodromy = L.basis.transpose() * SY.leftCols(m);
  L.jacobian.topLeftCorner(m, m) = L.monodromy - Eigen::MatrixXd::Identity(m, m);
  if (ns > 0) {
    L.jacobian.topRightCorner(m, ns) = L.basis.transpose() * SY.middleCols(m, ns);
    L.jacobian.bottomLeftCorner(ns, m) = Wslow.leftCols(m) / kT;
    L.jacobian.bottomRightCorner(ns, ns) = Wslow.middleCols(m, ns) / kT;
    L.C_mean = vr.Cint / kT;
  }
  if (dp) {
    // y(t0 + k T(p)): the end moves with the period, at the rate f(t1, y1) k dT/dp.
    mech::Dynamics dyn(*model, options_.kernel);
    const mech::ActiveSet set = mech::ActiveSet::of(*model, problem_.active);
    Eigen::VectorXd f1(2 * n);
    f1.head(n) = vr.y.tail(n);
    if (dyn.evaluate(set, t1, vr.y.head(n), vr.y.tail(n)) != mech::ModelIssue::none ||
        dyn.solve(mech::ReactionMethod::compatibility_structured) != mech::ModelIssue::none) {
      L.message = "the model at the orbit's end: " + dyn.message();
      return L;
    }
    f1.tail(n) = dyn.qdd;
    const double dkT = problem_.periods * dp->dperiod;
    const Eigen::VectorXd dyend = vr.Y.col(cols - 1) + f1 * dkT;
    L.dr_dp.resize(m + ns);
    L.dr_dp.head(m) = L.basis.transpose() * scale_.cwiseProduct(dyend - Y0.col(cols - 1));
    for (int k = 0; k < ns; ++k) {
      const int i = problem_.slow[k];
      L.dr_dp[m + k] = Wslow(k, cols - 1) / kT + vr.y[i] * dkT / kT - vr.w[k] * dkT / (kT * kT) -
                       (dp->dhold.size() == ns ? dp->dhold[k] : 0.0);
    }
  }
  // Norms: the state's mismatch in the integrator's weights, the means in a position's weight.
  const Eigen::VectorXd w = weights(x.y);
  double sum = (w.cwiseProduct(dy)).squaredNorm();
  for (int k = 0; k < ns; ++k) {
    const double wk = 1.0 / (options_.atol + options_.rtol * std::abs(problem_.hold[k]));
    sum += std::pow(wk * L.residual[m + k], 2);
  }
  L.residual_norm = std::sqrt(sum / (2 * n + ns));
  L.residual_max = dy.lpNorm<Eigen::Infinity>();
  L.ok = L.residual.allFinite() && L.jacobian.allFinite();
  if (!L.ok) L.message = "the residual or the monodromy matrix is not finite";
  return L;
}

bool Shooter::advance(const OrbitPoint& x, const Linearization& L, const Eigen::VectorXd& delta,
                      double alpha, OrbitPoint& out, std::string& message) const {
  const int m = static_cast<int>(L.basis.cols());
  const int ns = static_cast<int>(problem_.slow.size());
  out.y = x.y + alpha * (L.basis * delta.head(m)).cwiseQuotient(scale_);
  out.H = x.H;
  if (ns > 0) out.H += alpha * delta.segment(m, ns);
  return project(out, message);
}

double Shooter::correction_norm(const OrbitPoint& x, const Linearization& L,
                                const Eigen::VectorXd& delta) const {
  const int n = n_;
  const int m = static_cast<int>(L.basis.cols());
  const int ns = static_cast<int>(problem_.slow.size());
  const Eigen::VectorXd dy = (L.basis * delta.head(m)).cwiseQuotient(scale_);
  const Eigen::VectorXd w = weights(x.y);
  double sum = w.cwiseProduct(dy).squaredNorm();
  if (ns > 0 && L.C_mean.rows() == ns) {
    // A holding force changed by δH moves the slow coordinate by C̄ δH (kT)²/2 over the orbit.
    const double kT = orbit_period();
    const Eigen::VectorXd drift = L.C_mean * delta.segment(m, ns) * (kT * kT / 2);
    for (int k = 0; k < ns; ++k) sum += std::pow(drift[k] * w[problem_.slow[k]], 2);
  }
  (void)n;
  return std::sqrt(sum / (2 * n_ + ns));
}

Floquet Shooter::floquet(const Linearization& L) const {
  Floquet F;
  const int m = static_cast<int>(L.monodromy.rows());
  if (m == 0) {
    F.stable = true;
    return F;
  }
  const Eigen::EigenSolver<Eigen::MatrixXd> es(L.monodromy, true);
  const Eigen::VectorXcd mu = es.eigenvalues();
  const Eigen::MatrixXcd U = es.eigenvectors();
  const int ns = static_cast<int>(problem_.slow.size());
  std::vector<FloquetMultiplier> all(m);
  for (int i = 0; i < m; ++i) {
    all[i].value = mu[i];
    all[i].modulus = std::abs(mu[i]);
    const Eigen::VectorXcd v = L.basis.cast<std::complex<double>>() * U.col(i);
    double slow = 0;
    for (int k = 0; k < ns; ++k)
      slow += std::norm(v[problem_.slow[k]]) + std::norm(v[n_ + problem_.slow[k]]);
    all[i].slow_weight = slow / std::max(1e-300, v.squaredNorm());
  }
  // The slow coordinates' pairs: the 2 ns multipliers whose eigenvectors lie most in them.
  std::vector<int> order(m);
  for (int i = 0; i < m; ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return all[a].slow_weight > all[b].slow_weight; });
  for (int i = 0; i < std::min(m, 2 * ns); ++i) all[order[i]].slow = true;
  std::stable_sort(all.begin(), all.end(),
                   [](const FloquetMultiplier& a, const FloquetMultiplier& b) { return a.modulus > b.modulus; });
  F.multipliers = all;
  F.max_modulus = 0.0;
  for (const auto& f : all)
    if (!f.slow) F.max_modulus = std::max(F.max_modulus, f.modulus);
  F.stable = F.max_modulus < 1.0;
  return F;
}

namespace {

OrbitResult newton_shooting(const OrbitProblem& problem, const OrbitPoint& guess,
                            const ShootingOptions& options) {
  Shooter sh(problem, options);
  OrbitResult res;
  OrbitPoint x = guess;
  std::string msg;
  if (!sh.project(x, msg)) {
    res.message = "the start state cannot be projected onto the constraints: " + msg;
    return res;
  }
  auto account = [&res](const Linearization& L) {
    ++res.integrations;
    res.steps += L.steps;
    res.f_evals += L.f_evals;
    res.used_explicit = res.used_explicit || L.used_explicit;
    res.used_radau = res.used_radau || L.used_radau;
  };
  Linearization L = sh.linearize(x);
  account(L);
  double prev_corr = INFINITY;
  for (int it = 0;; ++it) {
    if (!L.ok) {
      res.message = "Newton shooting failed at iteration " + std::to_string(it) + ": " + L.message;
      res.point = x;
      return res;
    }
    NewtonRecord rec;
    rec.iteration = it;
    rec.residual = L.residual_norm;
    rec.residual_max = L.residual_max;
    rec.steps = L.steps;
    const Eigen::FullPivLU<Eigen::MatrixXd> lu(L.jacobian);
    Eigen::VectorXd delta = lu.solve(-L.residual);
    if (!lu.isInvertible() || !delta.allFinite()) {
      res.message =
          "Newton shooting: the shooting Jacobian (monodromy − I) is singular at iteration " +
          std::to_string(it) +
          ": the orbit has a neutral direction (a Floquet multiplier 1), e.g. a coordinate "
          "without restoring force; hold it as a slow coordinate ([model] slow) or constrain it";
      res.point = x;
      res.history.push_back(rec);
      res.last = L;
      return res;
    }
    const double corr = sh.correction_norm(x, L, delta);
    rec.correction = corr;
    res.residual = L.residual_norm;
    res.residual_max = L.residual_max;
    res.correction = corr;
    // Converged: the correction is a small fraction of the integration tolerance; or the
    // residual is below the tolerance and the corrections have stopped shrinking (what is left
    // is the integration's own error, amplified by the condition of monodromy − I).
    const bool small = corr <= options.newton_tol;
    const bool stalled = L.residual_norm <= 1.0 && corr <= 10.0 && corr > 0.5 * prev_corr;
    if (small || stalled) {
      OrbitPoint next;
      if (!sh.advance(x, L, delta, 1.0, next, msg)) next = x;
      res.history.push_back(rec);
      res.point = next;
      res.last = L;
      res.converged = true;
      if (stalled && !small)
        res.message = "converged to the accuracy of the integration (the correction stopped "
                      "shrinking at " + format_significant(corr, 3) + " of the tolerance)";
      break;
    }
    // In the quadratic regime (the correction within a thousand tolerances), take the full
    // step and check its residual with one integration of the orbit alone: below the
    // tolerance, Newton has converged (the monodromy is this iterate's, a correction away).
    if (corr <= 1e3) {
      OrbitPoint next;
      if (sh.advance(x, L, delta, 1.0, next, msg)) {
        const Linearization Lr = sh.linearize(next, nullptr, false);
        account(Lr);
        if (Lr.ok && Lr.residual_norm <= 1.0) {
          res.history.push_back(rec);
          NewtonRecord chk;
          chk.iteration = it + 1;
          chk.residual = Lr.residual_norm;
          chk.residual_max = Lr.residual_max;
          chk.steps = Lr.steps;
          chk.check = true;
          res.history.push_back(chk);
          res.point = next;
          res.last = L;
          res.residual = Lr.residual_norm;
          res.residual_max = Lr.residual_max;
          res.converged = true;
          break;
        }
      }
    }
    if (it >= options.max_iterations) {
      res.history.push_back(rec);
      res.point = x;
      res.last = L;
      res.message = "Newton shooting did not converge in " + counted(options.max_iterations, "iteration") +
                    ": residual reached " + format_significant(L.residual_norm, 3) +
                    " (weighted by atol + rtol |y|; max |y(kT) - y(0)| = " +
                    format_significant(L.residual_max, 3) + "), last correction " +
                    format_significant(corr, 3);
      return res;
    }
    // Line search on the weighted residual (full steps once the correction is below the
    // integration tolerance, where the residual is noise).
    double alpha = 1.0;
    bool accepted = false;
    Linearization Lt;
    OrbitPoint xt;
    for (int h = 0; h <= options.max_halvings; ++h, alpha *= 0.5) {
      if (!sh.advance(x, L, delta, alpha, xt, msg)) continue;
      Lt = sh.linearize(xt);
      account(Lt);
      if (Lt.ok && (Lt.residual_norm < (1 - 1e-4 * alpha) * L.residual_norm || corr * alpha <= 1.0)) {
        accepted = true;
        break;
      }
    }
    rec.damping = alpha;
    res.history.push_back(rec);
    if (!accepted) {
      res.point = x;
      res.last = L;
      res.message = "Newton shooting: the line search found no decrease of the residual after " +
                    counted(options.max_halvings, "halving") + " at iteration " +
                    std::to_string(it) + "; residual reached " +
                    format_significant(L.residual_norm, 3) + " (max |y(kT) - y(0)| = " +
                    format_significant(L.residual_max, 3) + ")" +
                    (Lt.ok ? std::string() : "; last trial: " + Lt.message);
      return res;
    }
    prev_corr = corr;
    x = xt;
    L = std::move(Lt);
  }
  res.floquet = sh.floquet(res.last);
  const int ns = static_cast<int>(problem.slow.size());
  if (ns > 0 && res.last.C_mean.rows() == ns) res.drift_acceleration = -res.last.C_mean * res.point.H;
  return res;
}

}  // namespace

OrbitResult find_orbit(const OrbitProblem& problem, const OrbitPoint& guess,
                       const ShootingOptions& options) {
  OrbitResult r = newton_shooting(problem, guess, options);
  if (r.converged || options.max_transient_periods <= 0) return r;
  // Newton from the guess failed: let the transient decay (a stable orbit attracts it) over
  // 8, 16, 32, ... orbit periods and try again from there.
  const std::string first = r.message;
  long integrations = r.integrations, steps = r.steps, f_evals = r.f_evals;
  OrbitPoint x = guess;
  int total = 0;
  const int n = problem.model->n();
  const double kT = problem.periods * problem.period;
  for (int chunk = 8; total + chunk <= options.max_transient_periods; chunk *= 2) {
    Shooter sh(problem, options);
    std::string msg;
    if (!sh.project(x, msg)) break;
    const auto model = with_forces(problem.model, problem.slow, x.H);
    VariationalSetup vs;
    vs.model = model.get();
    vs.active = problem.active;
    for (int i = 0; i < n; ++i) vs.means.push_back(i);
    VariationalOptions vo;
    vo.method = options.method;
    vo.kernel = options.kernel;
    vo.rtol = options.rtol;
    vo.atol = options.atol;
    vo.max_steps = options.max_steps;
    // Whole orbit periods, ending at the phase t0 (the model is kT-periodic in t).
    const VariationalResult vr = integrate_variational(vs, problem.t0, problem.t0 + chunk * kT, x.y,
                                                       Eigen::MatrixXd(2 * n, 0), vo);
    ++integrations;
    steps += vr.steps;
    f_evals += vr.f_evals;
    if (vr.status != OdeStatus::success) break;
    total += chunk;
    x.y = vr.y;
    // A held slow coordinate drifts during the transient: put its mean back to the held value.
    for (std::size_t k = 0; k < problem.slow.size(); ++k)
      x.y[problem.slow[k]] += problem.hold[k] - vr.mean_integrals[problem.slow[k]] / (chunk * kT);
    r = newton_shooting(problem, x, options);
    integrations += r.integrations;
    steps += r.steps;
    f_evals += r.f_evals;
    if (r.converged) break;
  }
  r.integrations = integrations;
  r.steps = steps;
  r.f_evals = f_evals;
  r.transient_periods = total;
  if (!r.converged)
    r.message = first + "; after " + counted(total, "period") + " of transient integration: " + r.message;
  else if (total > 0)
    r.message = "Newton converged after " + counted(total, "orbit period") +
                " of transient integration from the start (from the start itself: " +
                first + ")" + (r.message.empty() ? "" : "; " + r.message);
  return r;
}

}  // namespace pcsim::steady
