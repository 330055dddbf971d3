#include "mech/projection.hpp"

#include <cmath>
#include <sstream>

#include "linalg/huang.hpp"

namespace pcsim::mech {

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
  const Eigen::VectorXd q_start = q;
  if (!hol.empty()) {
    const int sh = static_cast<int>(hol.size());
    w.g.resize(sh, n);
    w.g0.resize(sh);
    w.gamma.resize(sh);
    Eigen::VectorXd phi(sh);
    bool converged = false;
    for (int it = 0; it < 30 && !converged; ++it) {
      for (int r = 0; r < sh; ++r) phi[r] = model.position_residual(hol[r], t, q);
      model.constraint_rows(hol, t, q, qd, w.g, w.g0, w.gamma);
      if (!phi.allFinite() || !w.g.allFinite()) {
        message = "a holonomic constraint is not finite during the projection at t = " +
                  std::to_string(t);
        return ModelIssue::non_finite;
      }
      const HuangResult hr = huang_solve(w.g, -phi, ho);
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
  w.g.resize(s, n);
  w.g0.resize(s);
  w.gamma.resize(s);
  model.constraint_rows(active, t, q, qd, w.g, w.g0, w.gamma);
  if (!w.g.allFinite() || !w.g0.allFinite()) {
    message = "a constraint row is not finite during the projection at t = " + std::to_string(t);
    return ModelIssue::non_finite;
  }
  const Eigen::VectorXd rv = -(w.g * qd + w.g0);
  const HuangResult hr = huang_solve(w.g, rv, ho);
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

}  // namespace pcsim::mech
