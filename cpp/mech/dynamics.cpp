#include "mech/dynamics.hpp"

#include <algorithm>
#include <atomic>
#include <type_traits>
#include <cmath>
#include <sstream>

#include <Eigen/Eigenvalues>
#include "common/eigen_instances.hpp"
#include <Eigen/SVD>

#include "common/format.hpp"
#include "linalg/huang.hpp"
#include "mech/detail/small_dense.hpp"

namespace pcsim::mech {

namespace {

std::string fmt(double v) { return format_significant(v, 6); }

}  // namespace

std::string coordinate_list(const Model& model, const Eigen::VectorXd& v, double threshold) {
  std::string out;
  for (int i = 0; i < v.size() && i < model.n(); ++i) {
    if (!std::isfinite(v[i]) || std::abs(v[i]) > threshold) {  // NaN and ±inf always named
      if (!out.empty()) out += ", ";
      out += "'" + model.coordinates()[i] + "'";
    }
  }
  return out;
}

namespace {
unsigned long next_active_set_id() {
  static std::atomic<unsigned long> counter{0};
  return ++counter;
}
}  // namespace

ActiveSet::ActiveSet(std::vector<int> rows, bool constant_rows)
    : rows_(std::move(rows)), constant_rows_(constant_rows), id_(next_active_set_id()) {}

ActiveSet ActiveSet::of(const Model& model, std::vector<int> rows) {
  bool constant = true;
  for (int i : rows) constant = constant && model.constraints()[i].constant_row;
  return ActiveSet(std::move(rows), constant);
}

Dynamics::Dynamics(const Model& model, Kernel kernel, Stabilization stabilization, double alpha,
                   double beta)
    : model_(&model),
      kernel_(kernel),
      stabilization_(stabilization),
      alpha_(alpha),
      beta_(beta),
      n_(model.n()),
      llt_(model.n()),    // constructed in place: assigning a fresh LLT would copy its
      llt_s_(model.n()),  // uninitialized info flag (UBSan)
      lu_(model.n()) {
  M.resize(n_, n_);
  A.resize(n_, n_);
  L_.resize(n_, n_);
  inv_.resize(n_);
  h.resize(n_);
  Q.resize(n_);
  f.resize(n_);
  R.resize(n_);
  qdd.resize(n_);
  a0_.resize(n_);
  rhs_.resize(n_);
  tmp_.resize(n_);
  resize_for(0);
}

void Dynamics::resize_for(int s) {
  if (s == s_) return;
  s_ = s;
  g.resize(s_, n_);
  G.resize(s_, n_);
  g0.resize(s_);
  gamma.resize(s_);
  G0.resize(s_);
  MinvgT_.resize(n_, s_);
  S_.resize(s_, s_);
  inv_s_.resize(s_);
  sdiag_.resize(s_);
  lambda.resize(s_);
}

ModelIssue Dynamics::fail(ModelIssue issue, std::string message) {
  message_ = std::move(message);
  return issue;
}

ModelIssue Dynamics::evaluate(const ActiveSet& active, double t, const Eigen::VectorXd& q,
                              const Eigen::VectorXd& qd) {
  active_ = &active;
  resize_for(active.size());
  t_ = t;
  if (limit_on_) {
    lq_ = q;
    lqd_ = qd;
  }
  // Large models with sparse structure: M and g as sparse values only (no n x n work); the
  // dense M and g are filled from them only where a dense path needs them (densify()).
  sparse_eval_ = sparse_evaluation && n_ >= sparse_min_n && model_->has_sparse_structure();
  if (sparse_eval_) {
    mass_sp_.evaluate(*model_, t, q, qd, h);
    model_->forces(t, q, qd, Q);
    rows_sp_.evaluate(*model_, active.rows(), t, q, qd, g0, gamma);
    dense_stale_ = true;
    // Non-finite values: the dense checks below name the culprits (a rare path).
    if (!mass_sp_.all_finite() || (s_ > 0 && !rows_sp_.all_finite())) densify();
  } else {
    dense_stale_ = false;
    model_->kinetic_terms(t, q, qd, M, h);
    model_->forces(t, q, qd, Q);
    if (s_ > 0) model_->constraint_rows(active.rows(), t, q, qd, g, g0, gamma);
  }
  // Messages are built only on failure: this runs once per right-hand side evaluation.
  const auto at = [t] { return " at t = " + fmt(t); };
  if (dense_stale_) return evaluate_sparse_checks(active, t, q, qd);
  // The common case in one pass: a NaN or an infinity anywhere makes the sum NaN or infinite,
  // and a sum of finite values is finite unless it overflows (then the checks below pass). Only
  // a non-finite sum looks for the culprit (issue 23: the separate passes were ~5 % of a
  // right-hand side of the paper's sieve).
  if (std::isfinite(M.sum() + h.sum() + Q.sum() +
                    (s_ > 0 ? g.sum() + g0.sum() + gamma.sum() : 0.0))) {
    return evaluate_finish(active, t, q, qd);
  }
  if (!M.allFinite()) {
    Eigen::VectorXd bad = M.rowwise().sum();
    return fail(ModelIssue::non_finite, "the mass matrix M = d2T/dqd2 is not finite" + at() +
                                            " (rows of " + coordinate_list(*model_, bad, INFINITY) +
                                            ")");
  }
  if (!h.allFinite()) {
    return fail(ModelIssue::non_finite, "the velocity terms h of the kinetic energy are not finite" +
                                            at() + " (coordinate " +
                                            coordinate_list(*model_, h, INFINITY) + ")");
  }
  if (!Q.allFinite()) {
    return fail(ModelIssue::non_finite,
                "the generalized forces Q (-dV/dq - dF/dqd + applied) are not finite" + at() +
                    " (coordinate " + coordinate_list(*model_, Q, INFINITY) + ")");
  }
  // Large models: one contiguous pass over g first (a row-wise pass strides through the
  // column-major s x n matrix); the row is looked for only on failure. Small ones: row-wise.
  const bool rows_finite = n_ >= sparse_min_n && g.allFinite() && g0.allFinite() && gamma.allFinite();
  for (int r = 0; r < s_ && !rows_finite; ++r) {
    if (!g.row(r).allFinite() || !std::isfinite(g0[r]) || !std::isfinite(gamma[r])) {
      return fail(ModelIssue::non_finite, "constraint '" + model_->constraints()[active.rows()[r]].name +
                                              "' gives a non-finite row g, g0 or gamma" + at());
    }
  }
  return evaluate_finish(active, t, q, qd);
}

// The rest of evaluate() on the dense values, all finite: Baumgarte's terms, f = Q − h.
ModelIssue Dynamics::evaluate_finish(const ActiveSet& active, double t, const Eigen::VectorXd& q,
                                     const Eigen::VectorXd& qd) {
  if (stabilization_ == Stabilization::baumgarte && s_ > 0) {
    gamma.noalias() += 2.0 * alpha_ * (g * qd);
    gamma += 2.0 * alpha_ * g0;
    for (int r = 0; r < s_; ++r) {
      if (model_->constraints()[active.rows()[r]].kind == ConstraintKind::holonomic) {
        gamma[r] += beta_ * beta_ * model_->position_residual(active.rows()[r], t, q);
      }
    }
  }
  f = Q - h;
  return ModelIssue::none;
}

// The rest of evaluate() on the sparse values (M and g finite already).
ModelIssue Dynamics::evaluate_sparse_checks(const ActiveSet& active, double t,
                                            const Eigen::VectorXd& q, const Eigen::VectorXd& qd) {
  const auto at = [t] { return " at t = " + fmt(t); };
  if (!h.allFinite()) {
    return fail(ModelIssue::non_finite, "the velocity terms h of the kinetic energy are not finite" +
                                            at() + " (coordinate " +
                                            coordinate_list(*model_, h, INFINITY) + ")");
  }
  if (!Q.allFinite()) {
    return fail(ModelIssue::non_finite,
                "the generalized forces Q (-dV/dq - dF/dqd + applied) are not finite" + at() +
                    " (coordinate " + coordinate_list(*model_, Q, INFINITY) + ")");
  }
  for (int r = 0; r < s_; ++r) {
    if (!std::isfinite(g0[r]) || !std::isfinite(gamma[r])) {
      return fail(ModelIssue::non_finite, "constraint '" + model_->constraints()[active.rows()[r]].name +
                                              "' gives a non-finite row g, g0 or gamma" + at());
    }
  }
  if (stabilization_ == Stabilization::baumgarte && s_ > 0) {
    gamma.noalias() += 2.0 * alpha_ * (rows_sp_.matrix() * qd);
    gamma += 2.0 * alpha_ * g0;
    for (int r = 0; r < s_; ++r) {
      if (model_->constraints()[active.rows()[r]].kind == ConstraintKind::holonomic) {
        gamma[r] += beta_ * beta_ * model_->position_residual(active.rows()[r], t, q);
      }
    }
  }
  f = Q - h;
  return ModelIssue::none;
}

void Dynamics::densify() {
  if (!dense_stale_) return;
  mass_sp_.to_dense(M);
  if (s_ > 0) rows_sp_.to_dense(g);
  dense_stale_ = false;
}

ModelIssue Dynamics::factorize_mass() {
  densify();
  llt_.compute(M);
  bool ok = llt_.info() == Eigen::Success;
  if (ok) {
    // LLT accepts tiny positive pivots; demand a condition-like margin (the pivot ratio).
    const auto d = llt_.matrixLLT().diagonal().cwiseAbs2();  // an expression: no allocation
    ok = d.minCoeff() > 1e-13 * d.maxCoeff();
  }
  if (ok) return ModelIssue::none;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(M);
  std::string who;
  if (es.info() == Eigen::Success) {
    const Eigen::VectorXd v = es.eigenvectors().col(0);
    who = " (its null direction involves coordinate " + coordinate_list(*model_, v, 0.1) +
          "; smallest eigenvalue " + fmt(es.eigenvalues()[0]) + ", largest " +
          fmt(es.eigenvalues()[n_ - 1]) + ")";
  }
  return fail(ModelIssue::singular_mass_matrix,
              "the mass matrix M = d2T/dqd2 is singular or not positive definite at t = " +
                  fmt(t_) + who + ": every coordinate needs inertia");
}

std::string Dynamics::dependent_rows() const {
  const_cast<Dynamics*>(this)->densify();  // M, g: a cache of the sparse values
  // The rows of g (each scaled to unit length, so a constraint's units do not matter) that take
  // part in a linear dependency: the left singular vectors of the (near-)zero singular values
  // have their large components on exactly those rows. A row that vanishes is named alone.
  if (s_ == 0) return "";
  Eigen::MatrixXd gs = g;
  std::vector<bool> involved(static_cast<std::size_t>(s_), false);
  for (int r = 0; r < s_; ++r) {
    const double nr = gs.row(r).norm();
    if (!(nr > 1e-12 * std::max(1.0, g.norm()))) {
      involved[static_cast<std::size_t>(r)] = true;  // a zero row depends on any other
      gs.row(r).setZero();
    } else {
      gs.row(r) /= nr;
    }
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(gs, Eigen::ComputeFullU);
  const Eigen::VectorXd sv = svd.singularValues();
  const double smax = sv.size() > 0 ? sv[0] : 0.0;
  // The dependency was detected by the caller (at its own tolerance): the combinations of
  // (near-)zero singular values, and at least the smallest one, hold the rows that take part.
  for (int k = 0; k < s_; ++k) {
    const double sk = k < sv.size() ? sv[k] : 0.0;
    if (sk > 1e-8 * std::max(1.0, smax) && k != s_ - 1) continue;
    const Eigen::VectorXd u = svd.matrixU().col(k);
    const double umax = u.cwiseAbs().maxCoeff();
    for (int r = 0; r < s_; ++r)
      if (std::abs(u[r]) > 0.1 * umax) involved[static_cast<std::size_t>(r)] = true;
  }
  std::string names;
  for (int r = 0; r < s_; ++r)
    if (involved[static_cast<std::size_t>(r)])
      names += (names.empty() ? "'" : ", '") + model_->constraints()[active_->rows()[r]].name + "'";
  return names;
}

std::string Dynamics::dependency_message() const {
  const std::string names = dependent_rows();
  std::string first;
  for (std::size_t i = 1; i < names.size() && names[i] != '\''; ++i) first += names[i];
  return "the active constraints " + (names.empty() ? std::string("(which could not be told)") : names) +
         " are linearly dependent at t = " + fmt(t_) +
         ": their reactions are not determined there. Switch one of them off (e.g. --set "
         "constraints." + (first.empty() ? std::string("NAME") : first) +
         "=false), or change the model or the initial state so that they stay independent";
}

ModelIssue Dynamics::null_basis() {
  if (D_for_ == active_->id() && active_->constant_rows()) return ModelIssue::none;
  HuangOptions ho;
  ho.kernel = kernel_;
  const HuangResult hr = huang_solve(g, Eigen::VectorXd::Zero(s_), ho);
  if (hr.info < 0) {
    return fail(ModelIssue::kernel_failure,
                "the Huang kernel rejected argument " + std::to_string(-hr.info));
  }
  if (hr.rank < s_) {
    std::string names;
    for (int r = 0; r < s_ && r < static_cast<int>(hr.row_dependent.size()); ++r) {
      if (hr.row_dependent[r]) {
        names += (names.empty() ? "'" : ", '") + model_->constraints()[active_->rows()[r]].name + "'";
      }
    }
    const std::string involved = dependent_rows();
    return fail(ModelIssue::dependent_constraints,
                dependency_message() + " (rank " + std::to_string(hr.rank) + " < " +
                    std::to_string(s_) + (names.empty() || names == involved
                                              ? std::string()
                                              : "; " + names + " depend on the rows before them") +
                    ")");
  }
  const NullBasisResult nb = huang_null_basis(hr.H, hr.rank, ho);
  if (nb.info != 0 || nb.D.cols() != n_ - s_ || nb.D.rows() != n_) {
    return fail(ModelIssue::kernel_failure, "the Huang null-space basis failed (info " +
                                                std::to_string(nb.info) + ")");
  }
  D = nb.D;
  D_for_ = active_->id();
  return ModelIssue::none;
}

ModelIssue Dynamics::prepare_compatibility() {
  densify();
  if (ModelIssue e = factorize_mass(); e != ModelIssue::none) return e;
  a0_ = llt_.solve(f);
  if (s_ == 0) return ModelIssue::none;
  if (ModelIssue e = null_basis(); e != ModelIssue::none) return e;
  MinvgT_ = llt_.solve(g.transpose());
  G = MinvgT_.transpose();  // g M⁻¹ (M symmetric)
  G0.noalias() = g * a0_;
  G0 += gamma;
  return ModelIssue::none;
}

ModelIssue Dynamics::solve_compatibility() {
  if (ModelIssue e = prepare_compatibility(); e != ModelIssue::none) return e;
  if (s_ == 0) {
    R.setZero();
    qdd = a0_;
    return ModelIssue::none;
  }
  A.topRows(s_) = G;
  A.bottomRows(n_ - s_) = D.transpose();
  rhs_.head(s_) = -G0;
  rhs_.tail(n_ - s_).setZero();
  lu_.compute(A);
  R = lu_.solve(rhs_);
  tmp_ = f + R;
  qdd = llt_.solve(tmp_);
  if (!R.allFinite() || !qdd.allFinite()) {
    return fail(ModelIssue::dependent_constraints,
                dependency_message() + " (the compatibility system [G; D^T] R = [-G0; 0] is singular)");
  }
  return ModelIssue::none;
}

// The structured solve on raw storage; N > 0 fixes n at compile time (unrolled loops for the
// common small models), N = 0 takes n at run time.
template <int N, int NS>
bool Dynamics::structured_kernel() {
  const int n = N > 0 ? N : n_, s = NS >= 0 ? NS : s_;
  const double* gp = g.data();  // s x n, column-major: g(r, k) = gp[r + k s]
  double* L = L_.data();
  const double* Mp = M.data();
  PCSIM_UNROLL
  for (int k = 0; k < n * n; ++k) L[k] = Mp[k];
  if (!detail::cholesky_upper<N>(L, n, n, 1e-13, inv_.data())) return false;
  double* a0 = a0_.data();
  const double* fp = f.data();
  PCSIM_UNROLL
  for (int k = 0; k < n; ++k) a0[k] = fp[k];
  detail::cholesky_solve<N>(L, inv_.data(), n, n, a0);
  double* W = MinvgT_.data();  // n x s: column r = M⁻¹ g_rᵀ
  PCSIM_UNROLL
  for (int r = 0; r < s; ++r) {
    double* w = W + static_cast<std::ptrdiff_t>(r) * n;
    PCSIM_UNROLL
    for (int k = 0; k < n; ++k) w[k] = gp[r + k * s];
    detail::cholesky_solve<N>(L, inv_.data(), n, n, w);
  }
  double* S = S_.data();
  PCSIM_UNROLL
  for (int i = 0; i < s; ++i) {
    double v = gamma[i];
    PCSIM_UNROLL
    for (int k = 0; k < n; ++k) v += gp[i + k * s] * a0[k];
    G0[i] = v;
    PCSIM_UNROLL
    for (int j = 0; j <= i; ++j) {
      const double* w = W + static_cast<std::ptrdiff_t>(j) * n;
      double sij = 0.0;
      PCSIM_UNROLL
      for (int k = 0; k < n; ++k) sij += gp[i + k * s] * w[k];
      S[j + i * s] = sij;  // the upper triangle (j <= i), as cholesky_upper reads
    }
  }
  double* sd = sdiag_.data();
  PCSIM_UNROLL
  for (int i = 0; i < s; ++i) sd[i] = S[i + i * s];
  singular_s_ = !detail::cholesky_upper<(NS > 0 ? NS : 0)>(S, s, s, 1e-13, inv_s_.data());
  // Hand over to the rank-revealing solve where a row is nearly a combination of the rows
  // before it: its pivot U_jj² is the squared distance of row j (in the M⁻¹ metric) from the
  // span of the earlier rows, U_jj²/S_jj = sin² of that angle (independent of the row's scale).
  for (int i = 0; i < s && !singular_s_; ++i)  // (an early exit: gcc cannot unroll it)
    singular_s_ = 1.0 < kSwitch * sd[i] * inv_s_[i] * inv_s_[i];  // U_jj² < kSwitch S_jj
  if (singular_s_) return true;
  double* lam = lambda.data();
  PCSIM_UNROLL
  for (int i = 0; i < s; ++i) lam[i] = -G0[i];
  detail::cholesky_solve<(NS > 0 ? NS : 0)>(S, inv_s_.data(), s, s, lam);
  PCSIM_UNROLL
  for (int k = 0; k < n; ++k) {
    double rk = 0.0, ak = a0[k];
    PCSIM_UNROLL
    for (int r = 0; r < s; ++r) {
      rk += gp[r + k * s] * lam[r];
      ak += W[k + r * n] * lam[r];
    }
    R[k] = rk;
    qdd[k] = ak;
  }
  return true;
}

// The sparse structured solve (large models); false: the dense kernel is to solve instead.
// Out of line: the small models' hot path stays as it was.
__attribute__((noinline)) bool Dynamics::solve_sparse_structured(ModelIssue& issue) {
  used_sparse = true;
  const auto outcome = dense_stale_ ? sparse_.solve(mass_sp_.lower(), rows_sp_.matrix(), f, gamma,
                                                    kSwitch, G0, lambda, R, qdd)
                                    : sparse_.solve(M, g, f, gamma, kSwitch, G0, lambda, R, qdd);
  if (outcome != SparseCompatibility::Outcome::solved) densify();  // the dense paths decide
  switch (outcome) {
    case SparseCompatibility::Outcome::solved:
      rank = s_;
      rank_revealing = false;
      issue = ModelIssue::none;
      return true;
    case SparseCompatibility::Outcome::singular_mass:
      // The dense criterion decides (its message names the coordinates); where it accepts
      // M after all (another pivot order), the dense kernel solves.
      if (factorize_mass() != ModelIssue::none) {
        issue = fail(ModelIssue::singular_mass_matrix, message_);
        return true;
      }
      break;
    case SparseCompatibility::Outcome::dependent_rows:
      issue = solve_rank_revealing();
      return true;
    case SparseCompatibility::Outcome::not_sparse:
      break;
  }
  used_sparse = false;
  return false;
}

ModelIssue Dynamics::solve_compatibility_structured() {
  // [G; Dᵀ] R = [−G0; 0] with the columns of D spanning null(g): Dᵀ R = 0 says R is orthogonal
  // to null(g), i.e. R = gᵀ λ for some λ, and then G R = g M⁻¹ gᵀ λ = −G0. The same R as the
  // dense solve, without forming D (test_reactions proves the two equal). The small SPD
  // systems are factored and solved by the loops of detail/small_dense.hpp (the hot path).
  if (s_ == 0) {
    // No constraint: q̈ = M⁻¹ f.
  }
  if (n_ >= sparse_min_n) {
    ModelIssue issue;
    if (solve_sparse_structured(issue)) return issue;
  }
  densify();
  used_sparse = false;
  // Compile-time sizes for the common small models (the loops unroll), run-time otherwise.
  bool ok;
  auto by_s = [this](auto n_tag) {
    constexpr int N = decltype(n_tag)::value;
    switch (s_) {
      case 1: return structured_kernel<N, 1>();
      case 2: return structured_kernel<N, 2>();
      case 3: return structured_kernel<N, 3>();
      default: return structured_kernel<N, -1>();
    }
  };
  switch (n_) {
    case 2: ok = by_s(std::integral_constant<int, 2>{}); break;
    case 3: ok = by_s(std::integral_constant<int, 3>{}); break;
    case 4: ok = by_s(std::integral_constant<int, 4>{}); break;
    case 5: ok = by_s(std::integral_constant<int, 5>{}); break;
    case 6: ok = by_s(std::integral_constant<int, 6>{}); break;
    default: ok = structured_kernel<0, -1>(); break;
  }
  if (!ok) {
    factorize_mass();  // the same criterion; it writes the message naming the coordinates
    return fail(ModelIssue::singular_mass_matrix, message_);
  }
  if (singular_s_) return solve_rank_revealing();  // dependent or nearly dependent rows
  rank = s_;
  rank_revealing = false;
  if (s_ == 0) {
    R.setZero();
    qdd = a0_;
  }
  return ModelIssue::none;
}

ModelIssue Dynamics::solve_kkt() {
  // [M  gᵀ] [q̈]   [ f ]
  // [g  0 ] [μ ] = [−γ ],   R = −gᵀμ (μ = −λ): the Lagrange-multiplier formulation.
  if (ModelIssue e = factorize_mass(); e != ModelIssue::none) return e;
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(n_ + s_, n_ + s_);
  K.topLeftCorner(n_, n_) = M;
  K.topRightCorner(n_, s_) = g.transpose();
  K.bottomLeftCorner(s_, n_) = g;
  Eigen::VectorXd b(n_ + s_);
  b << f, -gamma;
  const Eigen::FullPivLU<Eigen::MatrixXd> lu(K);
  if (!lu.isInvertible()) {
    return fail(ModelIssue::dependent_constraints, dependency_message() + " (the KKT matrix is singular)");
  }
  const Eigen::VectorXd x = lu.solve(b);
  qdd = x.head(n_);
  R = -(g.transpose() * x.tail(s_));
  return ModelIssue::none;
}

ModelIssue Dynamics::solve_udwadia_kalaba() {
  // q̈ = a + M^{-1/2} (g M^{-1/2})⁺ (−γ − g a),  a = M⁻¹ f,  R = M (q̈ − a).
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(M);
  if (es.info() != Eigen::Success || !(es.eigenvalues()[0] > 1e-13 * es.eigenvalues()[n_ - 1])) {
    return factorize_mass() == ModelIssue::none
               ? fail(ModelIssue::singular_mass_matrix, "M is not positive definite")
               : ModelIssue::singular_mass_matrix;
  }
  const Eigen::MatrixXd Mhalf = es.operatorSqrt();
  const Eigen::MatrixXd Minvhalf = es.operatorInverseSqrt();
  const Eigen::VectorXd a = Minvhalf * (Minvhalf * f);
  if (s_ == 0) {
    R.setZero();
    qdd = a;
    return ModelIssue::none;
  }
  const Eigen::MatrixXd B = g * Minvhalf;
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(B, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::VectorXd sv = svd.singularValues();
  const double cut = 1e-12 * sv[0];
  Eigen::VectorXd sinv(sv.size());
  for (int i = 0; i < sv.size(); ++i) sinv[i] = sv[i] > cut ? 1.0 / sv[i] : 0.0;
  const Eigen::VectorXd rhs = -gamma - g * a;
  const Eigen::VectorXd y =
      svd.matrixV() * (sinv.asDiagonal() * (svd.matrixU().transpose() * rhs));
  R = Mhalf * y;
  qdd = a + Minvhalf * y;
  return ModelIssue::none;
}

ModelIssue Dynamics::solve_rank_revealing() {
  densify();
  if (ModelIssue e = factorize_mass(); e != ModelIssue::none) return e;
  a0_ = llt_.solve(f);
  rank_revealing = true;
  nullity = 0;
  if (s_ == 0) {
    rank = 0;
    R.setZero();
    qdd = a0_;
    return ModelIssue::none;
  }
  G0.noalias() = g * a0_;
  G0 += gamma;
  // Row scaling: a constraint's units (or a factor 2 on its row) do not change the tolerances.
  Eigen::VectorXd scale(s_);
  const double gmax = g.cwiseAbs().maxCoeff();
  for (int r = 0; r < s_; ++r) {
    const double nr = g.row(r).norm();
    scale[r] = nr > 1e-300 && nr > 1e-14 * gmax ? 1.0 / nr : 0.0;  // a vanishing row: no force
  }
  const Eigen::MatrixXd gsT = (scale.asDiagonal() * g).transpose();  // n x s
  const auto L = llt_.matrixL();
  const Eigen::MatrixXd Bt = L.solve(gsT);  // L⁻¹ g_sᵀ = Bᵀ (n x s)
  const Eigen::VectorXd b = -(scale.asDiagonal() * G0);
  const Eigen::BDCSVD<Eigen::MatrixXd> svd(Bt, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::VectorXd sv = svd.singularValues();
  const double smax = sv.size() > 0 ? sv[0] : 0.0;
  const double mu = kFilter * smax;
  rank = 0;
  const Eigen::VectorXd c = svd.matrixV().transpose() * b;  // v_iᵀ b
  Eigen::VectorXd ycoef(sv.size()), lcoef(sv.size());
  for (int i = 0; i < sv.size(); ++i) {
    const double si = sv[i];
    if (si > kRankTol * smax) ++rank;
    // φ = σ⁴/(σ⁴ + μ⁴): 1 − (μ/σ)⁴ above μ, a smooth cut below it.
    const double s2 = si * si, den = s2 * s2 + mu * mu * mu * mu;
    ycoef[i] = den > 0.0 ? s2 * si * c[i] / den : 0.0;  // φ_i c_i / σ_i
    // λ along a dependent direction (σ at rounding level) is the indeterminate part: the
    // minimum-norm split leaves it out.
    lcoef[i] = den > 0.0 && si > kRankTol * smax ? s2 * c[i] / den : 0.0;  // φ_i c_i / σ_i²
  }
  Eigen::VectorXd extra;  // the share in the limit basis, if add_vanishing_limit sets it
  if (limit_on_) add_vanishing_limit(svd.matrixU(), svd.matrixV(), sv, scale, ycoef, lcoef, extra);
  Eigen::VectorXd y = svd.matrixU() * ycoef;
  if (extra.size() == n_) y += extra;
  lambda = scale.asDiagonal() * (svd.matrixV() * lcoef);
  R = L * y;
  qdd = a0_ + L.transpose().solve(y);
  if (!R.allFinite() || !qdd.allFinite()) {
    return fail(ModelIssue::non_finite, "the rank-revealing reaction solve gave non-finite values at t = " + fmt(t_));
  }
  nullity = s_ - rank;
  // Consistency of what the filter dropped (docs/redundant.md): the scaled compatibility
  // residual B y − b along v_i is (φ_i − 1) c_i. Consistent data has c_i = σ_i (u_iᵀ y*) for the
  // exact y*, so along a dropped direction (σ_i < μ, φ_i < 1/2) the residual is below
  // μ |y*| = 1e-6 σ_max |y*|; a state off the constraints by a relative ε (drift, a Radau stage
  // value: ε up to about rtol ≤ 1e-4) moves c_i by about ε times the terms of b. The residual
  // is compared with those terms, ref = |a0| + max_r |γ_r|/|g_r| + σ_max |y| (|S g a0| ≤ |a0|
  // per row, |B y| ≤ σ_max |y|), at kConsistency = 1e-2: a factor 100 above the loosest
  // tolerance's drift, while a contradiction (0 = −γ ≠ 0 at a singular position: the
  // acceleration the constraints ask for does not exist) is of the size of the terms.
  double gref = 0.0;
  for (int r = 0; r < s_; ++r) gref = std::max(gref, scale[r] * std::abs(gamma[r]));
  const double ref = a0_.norm() + gref + smax * y.norm();
  int worst = -1, worst_row = -1;
  double worst_ratio = 0.0;
  for (int i = 0; i < sv.size(); ++i) {
    if (!(sv[i] < mu)) continue;
    const double s2 = sv[i] * sv[i], den = s2 * s2 + mu * mu * mu * mu;
    const double left = std::abs(c[i]) * (mu * mu * mu * mu / den);  // (1 − φ_i) |c_i|
    const double ratio = left / std::max(ref, 1e-300);
    if (left > kConsistency * ref && ratio > worst_ratio) {
      worst_ratio = ratio;
      worst = i;
    }
  }
  // A row that vanishes (scale 0: no direction, no force) states 0 · q̈ = −G0_r.
  const double gscale = gmax * qdd.norm() + gamma.cwiseAbs().maxCoeff();
  for (int r = 0; r < s_; ++r) {
    if (scale[r] != 0.0) continue;
    if (std::abs(G0[r]) > kConsistency * gscale && std::abs(G0[r]) > 0.0) {
      worst = -1;
      worst_row = r;
      break;
    }
  }
  if (worst >= 0 || worst_row >= 0) {
    std::string names;
    if (worst_row >= 0) {
      names = "'" + model_->constraints()[active_->rows()[worst_row]].name + "'";
    } else {
      const Eigen::VectorXd v = svd.matrixV().col(worst);
      const double vmax = v.cwiseAbs().maxCoeff();
      for (int r = 0; r < s_; ++r)
        if (std::abs(v[r]) > 0.1 * vmax)
          names += (names.empty() ? "'" : ", '") + model_->constraints()[active_->rows()[r]].name + "'";
    }
    return fail(ModelIssue::inconsistent_constraints,
                "the active constraints " + names + " are dependent at t = " + fmt(t_) +
                    " and contradict each other at the acceleration level: no acceleration "
                    "satisfies them (a singular position the motion cannot pass, or a drive "
                    "that asks for the impossible; the part of g q'' + gamma left unsatisfied "
                    "is " + fmt(worst_row >= 0 ? 1.0 : worst_ratio) + " of its terms, tolerance " +
                    fmt(kConsistency) + ")");
  }
  return ModelIssue::none;
}

std::vector<int> Dynamics::dependent_row_indices(int numerical_rank) const {
  const_cast<Dynamics*>(this)->densify();  // M, g: a cache of the sparse values
  // Which rows to call dependent: column-pivoted QR of the row-scaled gᵀ picks a well-conditioned
  // set of `numerical_rank` rows first; the rows it leaves are the dependent ones (deterministic).
  std::vector<int> out;
  if (s_ == 0 || numerical_rank >= s_) return out;
  Eigen::MatrixXd gsT = g.transpose();
  for (int r = 0; r < s_; ++r) {
    const double nr = gsT.col(r).norm();
    if (nr > 0.0) gsT.col(r) /= nr;
  }
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(gsT);
  const auto& perm = qr.colsPermutation().indices();
  for (int k = std::max(numerical_rank, 0); k < s_; ++k) out.push_back(perm[k]);
  std::sort(out.begin(), out.end());
  return out;
}

double Dynamics::smallest_singular_value() const {
  const_cast<Dynamics*>(this)->densify();  // M, g: a cache of the sparse values
  if (s_ == 0) return INFINITY;
  Eigen::MatrixXd gs = g;
  for (int r = 0; r < s_; ++r) {
    const double nr = gs.row(r).norm();
    if (nr > 0.0) gs.row(r) /= nr;
  }
  const Eigen::BDCSVD<Eigen::MatrixXd> svd(gs);
  const Eigen::VectorXd sv = svd.singularValues();
  return s_ > sv.size() ? 0.0 : sv[sv.size() - 1];
}

void Dynamics::lambda_from_R() {
  if (s_ == 0) return;
  // g gᵀ λ = g R: exact for the reactions of independent ideal constraints (R in range(gᵀ)).
  if (rank_revealing) return;  // λ is the minimum-norm split already
  lambda = (g * g.transpose()).ldlt().solve(g * R);
}

ModelIssue Dynamics::solve(ReactionMethod method) {
  ModelIssue e = ModelIssue::none;
  rank = s_;
  nullity = 0;
  rank_revealing = false;
  if (method != ReactionMethod::compatibility_structured) densify();
  switch (method) {
    case ReactionMethod::compatibility_structured:
      e = solve_compatibility_structured();  // λ first, then R
      // With the vanishing limit on, near a singular position the rank-revealing solve takes
      // over from sin θ < 0.1 (kLimitSwitch), so its blend starts where the structured solve
      // still holds (the two agree to 1e-16 relative there).
      if (limit_on_ && e == ModelIssue::none && !rank_revealing && s_ > 0 &&
          min_pivot_ratio() < limit_switch_)
        return solve_rank_revealing();
      return e;
    case ReactionMethod::compatibility:
      e = solve_compatibility();
      // The paper's [G; Dᵀ] needs D of dimension n − s; with dependent rows (Huang's rank < s)
      // the same R comes from the rank-revealing solve.
      if (e == ModelIssue::dependent_constraints) return solve_rank_revealing();
      break;
    case ReactionMethod::kkt:
      e = solve_kkt();
      break;
    case ReactionMethod::udwadia_kalaba:
      e = solve_udwadia_kalaba();
      break;
  }
  if (e == ModelIssue::none) lambda_from_R();
  return e;
}

ModelIssue Dynamics::solve_sliding(ReactionMethod method, int imposed,
                                   const std::vector<SlidingFriction>& sliding) {
  densify();
  return method == ReactionMethod::compatibility ? solve_sliding_dense(imposed, sliding)
                                                 : solve_sliding_structured(imposed, sliding);
}

ModelIssue Dynamics::solve_sliding_structured(int imposed,
                                              const std::vector<SlidingFriction>& sliding) {
  const int sA = imposed;
  llt_.compute(M);
  if (llt_.info() != Eigen::Success) return fail(ModelIssue::singular_mass_matrix, "M is not positive definite");
  const Eigen::MatrixXd gA = g.topRows(sA);
  Eigen::MatrixXd B = gA.transpose();  // n x sA: g_Aᵀ + F
  for (const SlidingFriction& c : sliding) {
    B.col(c.normal_row) += -c.coefficient * c.w1 * g.row(c.friction_row).transpose();
    if (c.friction_row2 >= 0) B.col(c.normal_row) += -c.coefficient * c.w2 * g.row(c.friction_row2).transpose();
  }
  const Eigen::VectorXd a0 = llt_.solve(f);
  const Eigen::MatrixXd MinvB = llt_.solve(B);
  const Eigen::MatrixXd S = gA * MinvB;
  const Eigen::VectorXd rhs = -(gA * a0 + gamma.head(sA));
  const Eigen::FullPivLU<Eigen::MatrixXd> lu(S);
  if (!lu.isInvertible())
    return fail(ModelIssue::dependent_constraints,
                "the compatibility system with sliding friction is singular (the friction force "
                "cancels the normal one: Painleve's paradox, or dependent constraints)");
  lambda.head(sA) = lu.solve(rhs);
  R = B * lambda.head(sA);
  qdd = a0 + MinvB * lambda.head(sA);
  for (const SlidingFriction& c : sliding) {
    lambda[c.friction_row] = -c.coefficient * c.w1 * lambda[c.normal_row];
    if (c.friction_row2 >= 0) lambda[c.friction_row2] = -c.coefficient * c.w2 * lambda[c.normal_row];
  }
  if (!R.allFinite() || !qdd.allFinite())
    return fail(ModelIssue::non_finite, "the reactions with sliding friction are not finite");
  return ModelIssue::none;
}

ModelIssue Dynamics::solve_sliding_dense(int imposed, const std::vector<SlidingFriction>& sliding) {
  const int sA = imposed, s_all = s_;
  ModelIssue e = prepare_compatibility();
  if (e != ModelIssue::none) return e;
  const Eigen::MatrixXd C = (g * g.transpose()).ldlt().solve(g);  // s_all x n
  Eigen::MatrixXd Ad(n_, n_);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n_);
  Ad.topRows(sA) = G.topRows(sA);
  rhs.head(sA) = -G0.head(sA);
  Ad.middleRows(sA, n_ - s_all) = D.transpose();
  int r = n_ - (s_all - sA);
  for (const SlidingFriction& c : sliding) {
    Ad.row(r++) = C.row(c.friction_row) + c.coefficient * c.w1 * C.row(c.normal_row);
    if (c.friction_row2 >= 0) Ad.row(r++) = C.row(c.friction_row2) + c.coefficient * c.w2 * C.row(c.normal_row);
  }
  const Eigen::PartialPivLU<Eigen::MatrixXd> lu(Ad);
  R = lu.solve(rhs);
  qdd = llt_.solve(f + R);
  lambda = C * R;
  if (!R.allFinite() || !qdd.allFinite() ||
      (Ad * R - rhs).cwiseAbs().maxCoeff() > 1e-8 * (1.0 + rhs.cwiseAbs().maxCoeff() +
                                                    (Ad.cwiseAbs() * R.cwiseAbs()).maxCoeff()))
    return fail(ModelIssue::dependent_constraints,
                "the compatibility system [G; D^T; friction] R = [-G0; 0; 0] is singular");
  return ModelIssue::none;
}

void Dynamics::dae_residuals(const Eigen::VectorXd& a, const Eigen::VectorXd& Rv,
                             Eigen::Ref<Eigen::VectorXd> res_dyn,
                             Eigen::Ref<Eigen::VectorXd> res_con) const {
  res_dyn.noalias() = M * a;
  res_dyn -= f;
  res_dyn -= Rv;
  if (s_ > 0) {
    res_con.head(s_).noalias() = G * Rv;
    res_con.head(s_) += G0;
    res_con.tail(n_ - s_).noalias() = D.transpose() * Rv;
  } else {
    res_con = Rv;
  }
}

double Dynamics::position_residual(double t, const Eigen::VectorXd& q) const {
  double r = 0.0;
  if (!active_) return r;
  hol_.clear();
  for (int i : active_->rows())
    if (model_->constraints()[i].kind == ConstraintKind::holonomic) hol_.push_back(i);
  phi_.resize(hol_.size());
  model_->position_residuals(hol_, t, q, phi_.data());  // one call: the state set up once
  for (double p : phi_) r = std::max(r, std::abs(p));
  return r;
}

double Dynamics::velocity_residual(const Eigen::VectorXd& qd) const {
  if (s_ == 0) return 0.0;
  if (dense_stale_) return (rows_sp_.matrix() * qd + g0).cwiseAbs().maxCoeff();
  return (g * qd + g0).cwiseAbs().maxCoeff();
}

}  // namespace pcsim::mech

namespace pcsim::mech {

void Dynamics::add_vanishing_limit(const Eigen::MatrixXd& U, const Eigen::MatrixXd& V,
                                   const Eigen::VectorXd& sv, const Eigen::VectorXd& scale,
                                   Eigen::VectorXd& ycoef, Eigen::VectorXd& lcoef,
                                   Eigen::VectorXd& extra) {
  extra.resize(0);
  const int ns = static_cast<int>(sv.size());
  if (ns == 0 || !(sv[0] > 0.0) || lq_.size() != n_) return;
  const double smax = sv[0], nu = kLimitWidth * smax;
  const double outer = kLimitOuter * nu, inner = kLimitInner * nu;
  // The vanishing directions: below the band's outer edge, less the persistent ones (the last
  // persistent_nullity_ singular values, the rows dependent from the start).
  const int last = ns - std::min(persistent_nullity_, ns);
  std::vector<int> K;
  for (int i = 0; i < last; ++i)
    if (sv[i] < outer) K.push_back(i);
  const int m = static_cast<int>(K.size());
  if (m == 0) return;
  ++limit_solves;
  const auto L = llt_.matrixL();
  // y⊥ (the other directions' shares, as solved) and q̈⊥ = a0 + L⁻ᵀ y⊥; W = L⁻ᵀ U_K.
  Eigen::VectorXd yperp = Eigen::VectorXd::Zero(n_);
  for (int i = 0; i < ns; ++i)
    if (std::find(K.begin(), K.end(), i) == K.end()) yperp += ycoef[i] * U.col(i);
  const Eigen::VectorXd qdd_perp = a0_ + L.transpose().solve(yperp);
  Eigen::MatrixXd UK(n_, m), VK(s_, m);
  for (int k = 0; k < m; ++k) {
    UK.col(k) = U.col(K[k]);
    VK.col(k) = V.col(K[k]);
  }
  // ġ and γ̇ along the motion (1, q̇, q̈⊥) by central differences. The step in time: the state
  // moves by 1e-5 of its scale (truncation ~1e-10 relative, rounding ~1e-11).
  const double qs = 1.0 + lq_.cwiseAbs().maxCoeff(), vs = 1.0 + lqd_.cwiseAbs().maxCoeff();
  const double rate = std::max({lqd_.cwiseAbs().maxCoeff() / qs, qdd_perp.cwiseAbs().maxCoeff() / vs, 1e-3});
  const double dt = 1e-5 / rate;
  lgp_.resize(s_, n_);
  lgm_.resize(s_, n_);
  lg0_.resize(s_);
  lgamp_.resize(s_);
  lgamm_.resize(s_);
  const std::vector<int>& rows = active_->rows();
  model_->constraint_rows(rows, t_ + dt, lq_ + dt * lqd_, lqd_ + dt * qdd_perp, lgp_, lg0_, lgamp_);
  model_->constraint_rows(rows, t_ - dt, lq_ - dt * lqd_, lqd_ - dt * qdd_perp, lgm_, lg0_, lgamm_);
  const Eigen::MatrixXd gdot = (lgp_ - lgm_) / (2.0 * dt);
  const Eigen::VectorXd gamdot = (lgamp_ - lgamm_) / (2.0 * dt);
  // The directions u_k of the share. Where the vanishing σ_k are clear of rounding they are the
  // SVD's. At the singular position itself (σ_k at rounding level) the SVD's u_k are any
  // vectors orthogonal to the range of B0ᵀ, a space that also holds the mechanism's free motion
  // (Lᵀq̇: no ideal reaction acts along it); their limit is the span of P Ḃᵀ V_K with P the
  // projector off the kept directions (differentiate Bᵀ v_k = σ_k u_k: P Ḃᵀ v_k = σ̇_k u_k; of
  // Ḃ = (S g L⁻ᵀ)˙ only S ġ L⁻ᵀ survives P and V_K), orthonormalized.
  // Taken only when every vanishing direction is inside the inner edge (the share is then U_K z
  // whole); a cluster that straddles the blend keeps the SVD's directions, whose weights are
  // per direction.
  const bool limit_basis = sv[K.back()] <= kRankTol * smax && sv[K.front()] <= inner;
  if (limit_basis) {
    Eigen::MatrixXd Dk = L.solve(gdot.transpose() * (scale.asDiagonal() * VK));  // L⁻¹ ġᵀ S V_K
    for (int i = 0; i < K.front(); ++i) Dk -= U.col(i) * (U.col(i).transpose() * Dk);
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(Dk);
    UK = qr.householderQ() * Eigen::MatrixXd::Identity(n_, m);
  }
  const Eigen::MatrixXd W = L.transpose().solve(UK);
  // ∂γ/∂q̇ W: γ is quadratic in q̇ for ideal holonomic and linear velocity constraints, so the
  // central difference is exact up to rounding whatever the step; 1e-4 of the velocity scale.
  Eigen::MatrixXd GW(s_, m);
  for (int k = 0; k < m; ++k) {
    const double wn = W.col(k).cwiseAbs().maxCoeff();
    if (!(wn > 0.0)) {
      GW.col(k).setZero();
      continue;
    }
    const double eps = 1e-4 * vs / wn;
    lv_ = lqd_ + eps * W.col(k);
    model_->constraint_rows(rows, t_, lq_, lv_, lgp_, lg0_, lgamp_);
    lv_ = lqd_ - eps * W.col(k);
    model_->constraint_rows(rows, t_, lq_, lv_, lgm_, lg0_, lgamm_);
    GW.col(k) = (lgamp_ - lgamm_) / (2.0 * eps);
  }
  const Eigen::MatrixXd SVK = scale.asDiagonal() * VK;  // S V_K
  const Eigen::MatrixXd Ak = SVK.transpose() * (gdot * W + GW);
  const Eigen::VectorXd r = SVK.transpose() * (gdot * qdd_perp + gamdot);
  if (!Ak.allFinite() || !r.allFinite()) {
    ++limit_fallbacks;
    return;
  }
  // No transversal crossing (at rest at a singular position, a tangency): A is singular and the
  // limit is not defined; the filter stays.
  const Eigen::JacobiSVD<Eigen::MatrixXd> asvd(Ak, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::VectorXd as = asvd.singularValues();
  if (!(as[m - 1] > 1e-8 * as[0])) {
    ++limit_fallbacks;
    return;
  }
  const Eigen::VectorXd z = -asvd.solve(r);
  if (!z.allFinite()) {
    ++limit_fallbacks;
    return;
  }
  const double mu = kFilter * smax;
  if (limit_basis) {
    // Every vanishing direction inside the inner edge: the share is U_K z in the limit basis.
    for (int i : K) {
      ycoef[i] = 0.0;
      lcoef[i] = 0.0;
    }
    extra = UK * z;  // added to y by the caller
    return;
  }
  for (int k = 0; k < m; ++k) {
    const int i = K[k];
    const double si = sv[i];
    double w = 1.0;
    if (si > inner) {
      const double x = (outer - si) / (outer - inner);  // 1 at the inner edge, 0 at the outer
      w = x * x * (3.0 - 2.0 * x);
    }
    ycoef[i] = w * z[k] + (1.0 - w) * ycoef[i];
    // λ along it: y_i/σ_i where σ is clear of the filter, cut smoothly below μ (the multipliers
    // of rows that become dependent grow without bound; R = gᵀ λ holds outside σ < μ).
    lcoef[i] = si > kRankTol * smax ? ycoef[i] * si / (si * si + mu * mu) : 0.0;
  }
}

}  // namespace pcsim::mech
