#include "mech/projection.hpp"
#include "common/eigen_instances.hpp"

#include <cmath>
#include <sstream>

#include <Eigen/SVD>

#include "linalg/huang.hpp"

namespace pcsim::mech {

namespace {

// Minimum-norm least-squares solution of A x = b by the SVD of the row-scaled A, with singular
// values below rel_tol σ_max dropped (truncated pseudo-inverse): the rank-revealing step of the
// projection (issue 21). Returns the residual |S_r (A x − b)|∞ of the scaled rows, which is
// rounding for consistent rows and the size of the contradiction otherwise; worst = the row with
// the largest scaled residual.
double truncated_min_norm(const Eigen::MatrixXd& A, const Eigen::VectorXd& b, double rel_tol,
                          Eigen::VectorXd& x, int& rank, int& worst,
                          std::vector<int>* involved = nullptr) {
  const int m = static_cast<int>(A.rows());
  Eigen::VectorXd scale(m);
  for (int r = 0; r < m; ++r) {
    const double nr = A.row(r).norm();
    scale[r] = nr > 0.0 ? 1.0 / nr : 1.0;
  }
  const Eigen::MatrixXd As = scale.asDiagonal() * A;
  const Eigen::VectorXd bs = scale.asDiagonal() * b;
  const Eigen::BDCSVD<Eigen::MatrixXd> svd(As, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::VectorXd sv = svd.singularValues();
  const double smax = sv.size() > 0 ? sv[0] : 0.0;
  const Eigen::VectorXd c = svd.matrixU().transpose() * bs;
  Eigen::VectorXd coef = Eigen::VectorXd::Zero(sv.size());
  rank = 0;
  for (int i = 0; i < sv.size(); ++i) {
    if (sv[i] > rel_tol * smax && sv[i] > 0.0) {
      coef[i] = c[i] / sv[i];
      ++rank;
    }
  }
  x = svd.matrixV() * coef;
  if (involved) {
    // The rows that take part in the dropped (dependent) directions: the large components of
    // their left singular vectors (the rows a contradiction lies between).
    involved->clear();
    const int cols = static_cast<int>(svd.matrixU().cols());
    for (int r = 0; r < m; ++r) {
      bool in = false;
      for (int i = rank; i < cols && !in; ++i) {
        const double umax = svd.matrixU().col(i).cwiseAbs().maxCoeff();
        in = std::abs(svd.matrixU()(r, i)) > 0.1 * umax;
      }
      if (in) involved->push_back(r);
    }
  }
  const Eigen::VectorXd res = (As * x - bs).cwiseAbs();
  res.maxCoeff(&worst);
  return res.maxCoeff();
}

// The velocity stage's rows, shared by both projections: g and g0 of the active rows at
// (t, q, qd) into `w`, checked finite, and the residual to remove, rv = −(g q̇ + g0).
ModelIssue velocity_residual_rows(const Model& model, const std::vector<int>& active, double t,
                                  const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                  ProjectionWork& w, Eigen::VectorXd& rv, std::string& message) {
  const int s = static_cast<int>(active.size());
  w.g.resize(s, model.n());
  w.g0.resize(s);
  w.gamma.resize(s);
  model.constraint_rows(active, t, q, qd, w.g, w.g0, w.gamma);
  if (!w.g.allFinite() || !w.g0.allFinite()) {
    message = "a constraint row is not finite during the projection at t = " + std::to_string(t);
    return ModelIssue::non_finite;
  }
  rv = -(w.g * qd + w.g0);
  return ModelIssue::none;
}

std::string row_names(const Model& model, const std::vector<int>& rows_of,
                      const std::vector<int>& idx) {
  std::string out;
  for (int r : idx) out += (out.empty() ? "'" : ", '") + model.constraints()[rows_of[r]].name + "'";
  return out;
}

}  // namespace

bool near_singular(const Model& model, const std::vector<int>& active, double t,
                   const Eigen::VectorXd& q, const Eigen::VectorXd& qd, ProjectionWork& w) {
  const int s = static_cast<int>(active.size());
  if (s == 0) return false;
  w.g.resize(s, model.n());
  w.g0.resize(s);
  w.gamma.resize(s);
  model.constraint_rows(active, t, q, qd, w.g, w.g0, w.gamma);
  if (!w.g.allFinite()) return false;  // the projection reports it
  Eigen::MatrixXd gs = w.g;
  for (int r = 0; r < s; ++r) {
    const double nr = gs.row(r).norm();
    if (nr > 0.0) gs.row(r) /= nr;
  }
  if (s > model.n()) return true;
  const Eigen::BDCSVD<Eigen::MatrixXd> svd(gs);
  const Eigen::VectorXd sv = svd.singularValues();
  return !(sv[sv.size() - 1] > kNearSingular * sv[0]);
}

ModelIssue project_state_rank_revealing(const Model& model, const std::vector<int>& active,
                                        double t, Eigen::VectorXd& q, Eigen::VectorXd& qd,
                                        double tol, double& dq, double& dv, std::string& message,
                                        ProjectionWork& w) {
  // Gauss–Newton on the holonomic Φ with minimum-norm steps through the truncated SVD: where
  // rows are dependent (everywhere, or at a singular position) the step is taken in the span of
  // the independent directions only, so it stays bounded; Newton's quadratic convergence is
  // kept where g has full rank. Truncation at 1e-5 σ_max (row-scaled): a direction nearly
  // lost at a singular position is not corrected (its residual, drift of 1e-9 or less, would be
  // divided by σ: a step of O(1) in q or q̇ — A02 with N = 4 lost its whole kinetic energy in
  // one such velocity projection with a truncation of 1e-10); the state is corrected along it
  // once the position is regular again.
  const int n = model.n();
  const int s = static_cast<int>(active.size());
  constexpr double kTrunc = 1e-5;
  dq = dv = 0.0;
  if (s == 0) return ModelIssue::none;
  std::vector<int> hol;
  for (int i : active)
    if (model.constraints()[i].kind == ConstraintKind::holonomic) hol.push_back(i);
  const Eigen::VectorXd q_start = q;
  Eigen::VectorXd x;
  int rank = 0, worst = 0;
  std::vector<int> involved;
  if (!hol.empty()) {
    const int sh = static_cast<int>(hol.size());
    w.g.resize(sh, n);
    w.g0.resize(sh);
    w.gamma.resize(sh);
    Eigen::VectorXd phi(sh);
    bool converged = false;
    double res = 0.0;
    for (int it = 0; it < 50 && !converged; ++it) {
      for (int r = 0; r < sh; ++r) phi[r] = model.position_residual(hol[r], t, q);
      model.constraint_rows(hol, t, q, qd, w.g, w.g0, w.gamma);
      if (!phi.allFinite() || !w.g.allFinite()) {
        message = "a holonomic constraint is not finite during the projection at t = " +
                  std::to_string(t);
        return ModelIssue::non_finite;
      }
      res = truncated_min_norm(w.g, -phi, kTrunc, x, rank, worst, &involved);
      q += x;
      converged = x.lpNorm<Eigen::Infinity>() <= tol * (1.0 + q.lpNorm<Eigen::Infinity>());
    }
    for (int r = 0; r < sh; ++r) phi[r] = model.position_residual(hol[r], t, q);
    model.constraint_rows(hol, t, q, qd, w.g, w.g0, w.gamma);
    Eigen::VectorXd scaled(sh);
    for (int r = 0; r < sh; ++r) {
      const double nr = w.g.row(r).norm();
      scaled[r] = std::abs(phi[r]) / (nr > 0.0 ? nr : 1.0);
    }
    const double left = scaled.maxCoeff(&worst);
    // Converged, or stalled on a residual of 1e-7 of the coordinates' size at most (drift left
    // in a truncated direction; a contradiction is of the size of the geometry):
    // a consistent dependent set at a singular position converges only linearly.
    if (!converged && !(left <= 1e-7 * (1.0 + q.lpNorm<Eigen::Infinity>()))) {
      message = "no position satisfies the active constraints near t = " + std::to_string(t) +
                ": constraint '" + model.constraints()[hol[worst]].name +
                "' stays violated by " + std::to_string(phi[worst]) +
                " after the rank-revealing projection (rank " + std::to_string(rank) + " of " +
                std::to_string(sh) + " rows" +
                (involved.empty() ? std::string()
                                  : "; dependent there: " + row_names(model, hol, involved)) +
                ")";
      return ModelIssue::inconsistent_constraints;
    }
    (void)res;
    dq = (q - q_start).norm();
  }
  Eigen::VectorXd rv;
  if (const ModelIssue e = velocity_residual_rows(model, active, t, q, qd, w, rv, message);
      e != ModelIssue::none)
    return e;
  const double res = truncated_min_norm(w.g, rv, kTrunc, x, rank, worst, &involved);
  if (!(res <= 1e-8 * (1.0 + qd.lpNorm<Eigen::Infinity>()))) {
    message = "no velocity satisfies the active constraints at t = " + std::to_string(t) +
              ": constraint '" + model.constraints()[active[worst]].name +
              "' stays violated after the rank-revealing projection (rank " +
              std::to_string(rank) + " of " + std::to_string(s) + " rows" +
              (involved.empty() ? std::string()
                                : "; dependent there: " + row_names(model, active, involved)) +
              ")";
    return ModelIssue::inconsistent_constraints;
  }
  qd += x;
  dv = x.norm();
  return ModelIssue::none;
}

ModelIssue resolve_constraints(const Model& model, const std::vector<std::string>& names,
                               std::vector<int>& active, std::string& message) {
  active.clear();
  for (const std::string& name : names) {
    const int i = model.constraint_index(name);
    if (i < 0) {
      message = "model '" + model.name() + "' has no constraint '" + name + "' (it offers:";
      for (const ConstraintInfo& c : model.constraints()) message += " '" + c.name + "'";
      message += ")";
      return ModelIssue::unknown_constraint;
    }
    for (int j : active) {
      if (j == i) {
        message = "constraint '" + name + "' is listed twice (dependent constraints)";
        return ModelIssue::dependent_constraints;
      }
    }
    active.push_back(i);
  }
  return ModelIssue::none;
}

ModelIssue project_state(const Model& model, const std::vector<int>& active, double t,
                         Eigen::VectorXd& q, Eigen::VectorXd& qd, Kernel kernel, double tol,
                         double& dq, double& dv, std::string& message, ProjectionWork& w) {
  // The Huang path first (every model that ran before issue 21 takes it, bit for bit); where it
  // fails (dependent rows near a singular position make its steps blow up, or its dependence
  // test calls a nearly dependent row contradictory), the rank-revealing projection from the
  // same start decides.
  // A correction larger than 1e-4 of the state near a singular position is Huang's step
  // following nearly dependent rows (A02 with N = 4 lost its whole kinetic energy in one such
  // velocity projection): there the rank-revealing path decides too. The SVD of that test is
  // taken only after such a correction (rare), so regular models pay nothing.
  const Eigen::VectorXd q_in = q, qd_in = qd;
  const ModelIssue e = project_state_huang(model, active, t, q, qd, kernel, tol, dq, dv, message, w);
  const bool large = e == ModelIssue::none &&
                     (dq > 1e-4 * (1.0 + q_in.norm()) || dv > 1e-4 * (1.0 + qd_in.norm()));
  if (e != ModelIssue::inconsistent_constraints &&
      !(large && near_singular(model, active, t, q_in, qd_in, w)))
    return e;
  q = q_in;
  qd = qd_in;
  return project_state_rank_revealing(model, active, t, q, qd, tol, dq, dv, message, w);
}

ModelIssue project_state_huang(const Model& model, const std::vector<int>& active, double t,
                               Eigen::VectorXd& q, Eigen::VectorXd& qd, Kernel kernel, double tol,
                               double& dq, double& dv, std::string& message, ProjectionWork& w) {
  const int n = model.n();
  const int s = static_cast<int>(active.size());
  dq = dv = 0.0;
  if (s == 0) return ModelIssue::none;
  std::vector<int> hol;
  for (int i : active) {
    if (model.constraints()[i].kind == ConstraintKind::holonomic) hol.push_back(i);
  }
  HuangOptions ho;
  ho.kernel = kernel;
  // Large sparse models: the sparse minimum-norm solve; Huang's where it declines (dependence).
  const auto min_norm = [&](const Eigen::MatrixXd& g, const Eigen::VectorXd& b) {
    HuangResult hr;
    if (n >= w.sparse_min_n && w.sparse.solve(g, b, hr.x)) return hr;
    return huang_solve(g, b, ho);
  };
  // Models with sparse structure: the rows as sparse values; the dense g only where the sparse
  // solve declines.
  const bool sparse_rows = n >= w.sparse_min_n && model.has_sparse_structure();
  const auto min_norm_sparse = [&](const SparseRows& rows, const Eigen::VectorXd& b) {
    HuangResult hr;
    if (w.sparse.solve(rows.matrix(), b, hr.x)) return hr;
    rows.to_dense(w.g);
    return huang_solve(w.g, b, ho);
  };
  const Eigen::VectorXd q_start = q;
  if (!hol.empty()) {
    const int sh = static_cast<int>(hol.size());
    w.g.resize(sh, n);
    w.g0.resize(sh);
    w.gamma.resize(sh);
    Eigen::VectorXd phi(sh);
    bool converged = false;
    for (int it = 0; it < 30 && !converged; ++it) {
      model.position_residuals(hol, t, q, phi.data());
      if (!phi.allFinite()) break;  // diverged: the rank-revealing path decides
      if (sparse_rows) {
        w.rows_holonomic.evaluate(model, hol, t, q, qd, w.g0, w.gamma);
      } else {
        model.constraint_rows(hol, t, q, qd, w.g, w.g0, w.gamma);
      }
      if (!phi.allFinite() || (sparse_rows ? !w.rows_holonomic.all_finite() : !w.g.allFinite())) {
        message = "a holonomic constraint is not finite during the projection at t = " +
                  std::to_string(t);
        return ModelIssue::non_finite;
      }
      const HuangResult hr = sparse_rows ? min_norm_sparse(w.rows_holonomic, -phi) : min_norm(w.g, -phi);
      if (hr.info < 0) {
        message = "the Huang kernel rejected argument " + std::to_string(-hr.info);
        return ModelIssue::kernel_failure;
      }
      if (hr.info > 0) {
        message = "constraint '" + model.constraints()[hol[hr.info - 1]].name +
                  "' contradicts the constraints before it (no position satisfies all)";
        return ModelIssue::inconsistent_constraints;
      }
      q += hr.x;
      converged = hr.x.lpNorm<Eigen::Infinity>() <= tol * (1.0 + q.lpNorm<Eigen::Infinity>());
    }
    if (!converged) {
      message = "the position projection onto the constraints did not converge at t = " +
                std::to_string(t);
      return ModelIssue::inconsistent_constraints;
    }
    dq = (q - q_start).norm();
  }
  Eigen::VectorXd rv;
  if (sparse_rows) {
    w.g0.resize(s);
    w.gamma.resize(s);
    w.rows_active.evaluate(model, active, t, q, qd, w.g0, w.gamma);
    if (!w.rows_active.all_finite() || !w.g0.allFinite()) {
      message = "a constraint row is not finite during the projection at t = " + std::to_string(t);
      return ModelIssue::non_finite;
    }
    rv = -(w.rows_active.matrix() * qd + w.g0);
  } else if (const ModelIssue e = velocity_residual_rows(model, active, t, q, qd, w, rv, message);
             e != ModelIssue::none) {
    return e;
  }
  const HuangResult hr = sparse_rows ? min_norm_sparse(w.rows_active, rv) : min_norm(w.g, rv);
  if (hr.info < 0) {
    message = "the Huang kernel rejected argument " + std::to_string(-hr.info);
    return ModelIssue::kernel_failure;
  }
  if (hr.info > 0) {
    message = "constraint '" + model.constraints()[active[hr.info - 1]].name +
              "' contradicts the constraints before it (no velocity satisfies all)";
    return ModelIssue::inconsistent_constraints;
  }
  qd += hr.x;
  dv = hr.x.norm();
  return ModelIssue::none;
}

bool row_within_projection_tol(const Eigen::Ref<const Eigen::RowVectorXd>& g, double g0,
                               bool position, double pos_residual, double t,
                               const Eigen::VectorXd& q, const Eigen::VectorXd& qd, double tol) {
  const Eigen::RowVectorXd ag = g.cwiseAbs();
  const double vel = std::abs(g.dot(qd) + g0);
  const double vel_scale = ag.dot(qd.cwiseAbs()) + std::abs(g0);
  if (!(vel <= tol * (1.0 + vel_scale))) return false;
  if (!position) return true;
  const double pos_scale = ag.dot(q.cwiseAbs()) + std::abs(g0) * std::abs(t);
  return std::abs(pos_residual) <= tol * (1.0 + pos_scale);
}

bool rows_within_projection_tol(const SparseMatrixD& g, const Eigen::VectorXd& g0,
                                const std::vector<char>& position, const Eigen::VectorXd& phi,
                                double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                double tol) {
  // The sums of row_within_projection_tol, column by column over the compressed g.
  const int s = static_cast<int>(g.rows());
  Eigen::VectorXd vel = g0, vel_scale = g0.cwiseAbs(), pos_scale = std::abs(t) * g0.cwiseAbs();
  for (int j = 0; j < g.outerSize(); ++j)
    for (SparseMatrixD::InnerIterator it(g, j); it; ++it) {
      const int r = static_cast<int>(it.row());
      vel[r] += it.value() * qd[j];
      vel_scale[r] += std::abs(it.value()) * std::abs(qd[j]);
      pos_scale[r] += std::abs(it.value()) * std::abs(q[j]);
    }
  for (int r = 0; r < s; ++r) {
    if (!(std::abs(vel[r]) <= tol * (1.0 + vel_scale[r]))) return false;
    if (position[static_cast<std::size_t>(r)] && !(std::abs(phi[r]) <= tol * (1.0 + pos_scale[r])))
      return false;
  }
  return true;
}

}  // namespace pcsim::mech
