// check_model, reactions and project_consistent: the engine's one-state entry points.
#include <cmath>
#include <sstream>

#include "common/eigen_instances.hpp"
#include "linalg/huang.hpp"
#include "mech/dynamics.hpp"
#include "mech/projection.hpp"
#include "mech/simulation.hpp"

namespace pcsim::mech {

int Model::constraint_index(const std::string& constraint_name) const {
  for (std::size_t i = 0; i < constraints_.size(); ++i) {
    if (constraints_[i].name == constraint_name) return static_cast<int>(i);
  }
  return -1;
}

const char* to_string(Form form) { return form == Form::ode ? "ode" : "dae"; }

// Names and messages of the engine's statuses, expanded from the tables in mech/status.hpp.
#define PCSIM_MECH_NAME(name, text) \
  case E::name: return #name;
#define PCSIM_MECH_MESSAGE(name, text) \
  case E::name: return text;

const char* to_string(SimulationStatus status) {
  using E = SimulationStatus;
  switch (status) { PCSIM_SIMULATION_STATUS_TABLE(PCSIM_MECH_NAME) }
  return "unknown";
}

const char* message(SimulationStatus status) {
  using E = SimulationStatus;
  switch (status) { PCSIM_SIMULATION_STATUS_TABLE(PCSIM_MECH_MESSAGE) }
  return "unknown status";
}

const char* to_string(ModelIssue issue) {
  using E = ModelIssue;
  switch (issue) { PCSIM_MODEL_ISSUE_TABLE(PCSIM_MECH_NAME) }
  return "unknown";
}

const char* message(ModelIssue issue) {
  using E = ModelIssue;
  switch (issue) { PCSIM_MODEL_ISSUE_TABLE(PCSIM_MECH_MESSAGE) }
  return "unknown issue";
}

#undef PCSIM_MECH_NAME
#undef PCSIM_MECH_MESSAGE

namespace {

// Names of the earlier independent rows that row r of g is a combination of.
std::string combination_of(const Model& model, const std::vector<int>& active,
                           const Eigen::MatrixXd& g, const std::vector<bool>& dependent, int r) {
  std::vector<int> basis;
  for (int k = 0; k < r; ++k) {
    if (!dependent[k]) basis.push_back(k);
  }
  if (basis.empty()) return "";
  Eigen::MatrixXd B(g.cols(), static_cast<int>(basis.size()));
  for (std::size_t j = 0; j < basis.size(); ++j) B.col(static_cast<int>(j)) = g.row(basis[j]).transpose();
  const Eigen::VectorXd c = B.colPivHouseholderQr().solve(g.row(r).transpose());
  std::string names;
  for (std::size_t j = 0; j < basis.size(); ++j) {
    if (std::abs(c[static_cast<int>(j)]) > 1e-8) {
      names += (names.empty() ? "'" : ", '") + model.constraints()[active[basis[j]]].name + "'";
    }
  }
  return names;
}

}  // namespace

CheckResult check_model(const Model& model, const std::vector<std::string>& names, double t,
                        const Eigen::VectorXd& q, const Eigen::VectorXd& qd, Kernel kernel) {
  CheckResult out;
  const int n = model.n();
  if (q.size() != n || qd.size() != n) {
    out.issue = ModelIssue::non_finite;
    out.message = "model '" + model.name() + "' has " + std::to_string(n) +
                  " coordinates but the state has " + std::to_string(q.size()) + " and " +
                  std::to_string(qd.size());
    return out;
  }
  if (!q.allFinite() || !qd.allFinite() || !std::isfinite(t)) {
    out.issue = ModelIssue::non_finite;
    // q and qd separately: q + qd could hide an entry (inf + -inf is NaN, still listed, but
    // the list is empty when only t is not finite).
    const std::string list = coordinate_list(model, q.cwiseAbs() + qd.cwiseAbs(), INFINITY);
    out.message = "the state is not finite (" +
                  (list.empty() ? "the time t = " + std::to_string(t) : "coordinate " + list) + ")";
    return out;
  }
  out.issue = resolve_constraints(model, names, out.active, out.message);
  if (out.issue != ModelIssue::none) return out;
  const int s = static_cast<int>(out.active.size());
  Dynamics dyn(model, kernel);
  const ActiveSet set = ActiveSet::of(model, out.active);
  out.issue = dyn.evaluate(set, t, q, qd);
  if (out.issue == ModelIssue::none) {
    // Mass matrix first: a singular M is reported as such, not as a constraint problem.
    Dynamics free(model, kernel);
    const ActiveSet none;
    free.evaluate(none, t, q, qd);
    // Large models: the sparse solve's test of M (the dense one's message where it fails).
    out.issue = n >= free.sparse_min_n ? free.solve(ReactionMethod::compatibility_structured)
                                       : free.prepare_compatibility();
    if (out.issue != ModelIssue::none) {
      out.message = free.message();
      return out;
    }
  } else {
    out.message = dyn.message();
    return out;
  }
  if (s == 0) return out;
  // s > n is not refused by itself (issue 21): such rows are dependent, and the rank test
  // below tells redundant from contradictory.
  // Rank and row flags of g from the Huang kernel; consistency of g q̇ = −g0.
  HuangOptions ho;
  ho.kernel = kernel;
  // Large models (issue 23): rows of full rank by the sparse factorization of g gᵀ (every
  // pivot above 1e-10 of its diagonal entry, a row at least ~1e-5 rad off the span of those
  // factored before it) are consistent whatever g0 is; Huang's dense O(s² n) kernel is run
  // only where that test declines (dependent or nearly dependent rows: it decides and names them).
  HuangResult hr;
  Eigen::VectorXd x_sparse;
  SparseMinNorm full_rank;
  if (n >= dyn.sparse_min_n && s <= n && full_rank.solve(dyn.g, -dyn.g0, x_sparse)) {
    hr.rank = s;
  } else {
    hr = huang_solve(dyn.g, -dyn.g0, ho);
  }
  if (hr.info < 0) {
    out.issue = ModelIssue::kernel_failure;
    out.message = "the Huang kernel rejected argument " + std::to_string(-hr.info);
    return out;
  }
  if (hr.rank < s || hr.info > 0) {
    // Position-level consistency of the holonomic rows decides redundant vs contradictory.
    bool inconsistent = hr.info > 0;
    int bad = hr.info > 0 ? hr.info - 1 : -1;
    if (!inconsistent) {
      std::vector<int> hol;
      std::vector<int> rows;
      for (int r = 0; r < s; ++r) {
        if (model.constraints()[out.active[r]].kind == ConstraintKind::holonomic) {
          hol.push_back(out.active[r]);
          rows.push_back(r);
        }
      }
      if (!hol.empty()) {
        Eigen::MatrixXd gh(hol.size(), n);
        Eigen::VectorXd phi(hol.size());
        for (std::size_t k = 0; k < hol.size(); ++k) {
          gh.row(static_cast<int>(k)) = dyn.g.row(rows[k]);
          phi[static_cast<int>(k)] = model.position_residual(hol[k], t, q);
        }
        const HuangResult hp = huang_solve(gh, -phi, ho);
        if (hp.info > 0) {
          inconsistent = true;
          bad = rows[hp.info - 1];
        }
      }
    }
    std::vector<bool> dep = hr.row_dependent;
    dep.resize(s, false);
    if (inconsistent) {
      if (bad < 0) bad = 0;
      dep[bad] = true;
      const std::string with = combination_of(model, out.active, dyn.g, dep, bad);
      out.issue = ModelIssue::inconsistent_constraints;
      out.message = "constraint '" + model.constraints()[out.active[bad]].name +
                    "' contradicts " + (with.empty() ? "the constraints before it" : with) +
                    ": no motion satisfies all of them";
      return out;
    }
    // Consistent but dependent (issue 21): the run goes on; R is unique, the split by
    // constraint is the minimum-norm one (statically indeterminate). Say which rows.
    out.rank = hr.rank;
    for (int r = 0; r < s; ++r) {
      if (!dep[r]) continue;
      out.redundant.push_back(r);
      const std::string with = combination_of(model, out.active, dyn.g, dep, r);
      if (!out.message.empty()) out.message += "; ";
      out.message += "constraint '" + model.constraints()[out.active[r]].name +
                     "' is redundant (its row of g is a linear combination of " +
                     (with.empty() ? std::string("earlier rows") : with) + ")";
    }
    out.message = "dependent but consistent constraints (rank " + std::to_string(hr.rank) + " < " +
                  std::to_string(s) + "): " + out.message +
                  "; R is unique, its split by constraint is statically indeterminate";
  } else {
    out.rank = s;
  }
  // constant_row promises: compare g at a perturbed state (fixed, deterministic perturbation).
  Eigen::VectorXd q2 = q, qd2 = qd;
  for (int i = 0; i < n; ++i) {
    q2[i] += 0.0137 * (1.0 + 0.31 * i) * (1.0 + std::abs(q[i]));
    qd2[i] += 0.021 * (1.0 + 0.17 * i);
  }
  Eigen::MatrixXd g2(s, n);
  Eigen::VectorXd g02(s), gam2(s);
  model.constraint_rows(out.active, t + 0.0731, q2, qd2, g2, g02, gam2);
  for (int r = 0; r < s; ++r) {
    const ConstraintInfo& c = model.constraints()[out.active[r]];
    if (!c.constant_row) continue;
    const double scale = 1.0 + dyn.g.row(r).lpNorm<Eigen::Infinity>();
    if (!((g2.row(r) - dyn.g.row(r)).lpNorm<Eigen::Infinity>() <= 1e-12 * scale)) {
      out.issue = ModelIssue::not_constant_row;
      out.message = "constraint '" + c.name +
                    "' is declared constant_row but its row of g changes with q or t";
      return out;
    }
  }
  return out;
}

ReactionResult reactions(const Model& model, const std::vector<std::string>& active, double t,
                         const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                         ReactionMethod method, Kernel kernel) {
  ReactionResult out;
  std::vector<int> idx;
  out.issue = resolve_constraints(model, active, idx, out.message);
  if (out.issue != ModelIssue::none) return out;
  if (q.size() != model.n() || qd.size() != model.n()) {
    out.issue = ModelIssue::non_finite;
    out.message = "state size does not match the model's " + std::to_string(model.n()) +
                  " coordinates";
    return out;
  }
  Dynamics dyn(model, kernel);
  const ActiveSet set = ActiveSet::of(model, idx);
  out.issue = dyn.evaluate(set, t, q, qd);
  if (out.issue == ModelIssue::none) out.issue = dyn.solve(method);
  if (out.issue != ModelIssue::none) {
    out.message = dyn.message();
    return out;
  }
  out.R = dyn.R;
  out.qdd = dyn.qdd;
  out.lambda = dyn.lambda;
  return out;
}

ProjectionResult project_consistent(const Model& model, const std::vector<std::string>& active,
                                    double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                    Kernel kernel) {
  ProjectionResult out;
  std::vector<int> idx;
  out.issue = resolve_constraints(model, active, idx, out.message);
  if (out.issue != ModelIssue::none) return out;
  out.q = q;
  out.qd = qd;
  ProjectionWork work;
  out.issue = project_state(model, idx, t, out.q, out.qd, kernel, 1e-14, out.correction_pos,
                            out.correction_vel, out.message, work);
  return out;
}

}  // namespace pcsim::mech
