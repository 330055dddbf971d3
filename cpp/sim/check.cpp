// The check of a case at its initial state (sim/check.hpp): computed once, printed by
// `pcsim check` (format_check), bound in Python (case.check()).
#include "sim/check.hpp"

#include <Eigen/Eigenvalues>
#include "common/eigen_instances.hpp"

#include "common/format.hpp"
#include "mech/dynamics.hpp"
#include "mech/simulation.hpp"

namespace pcsim::sim {

namespace {
std::string num(double v) { return format_significant(v, 4); }
}  // namespace

CheckReport check_case(const Case& c) {
  const Setup& set = c.setup;
  const auto model = c.model->instantiate(set.parameters, set.q0, 0.0, c.table, "");
  const int n = model->n();
  const int m = static_cast<int>(set.active.size());
  CheckReport r;
  r.case_name = c.name;
  r.model = model->name();
  r.coordinates = model->coordinates();
  r.active = set.active;
  r.gruebler = n - m;

  // M at the initial state (positive definite: its smallest eigenvalue > 0).
  mech::Dynamics free(*model, set.kernel);
  const mech::ActiveSet none;
  free.evaluate(none, 0.0, set.q0, set.qd0);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(free.M, Eigen::EigenvaluesOnly);
  r.mass_eigenvalue_min = es.eigenvalues()[0];
  r.mass_eigenvalue_max = es.eigenvalues()[n - 1];
  r.mass_positive_definite =
      es.info() == Eigen::Success && r.mass_eigenvalue_min > 1e-13 * r.mass_eigenvalue_max;

  const mech::CheckResult chk = mech::check_model(*model, set.active, 0.0, set.q0, set.qd0, set.kernel);
  if (chk.issue == mech::ModelIssue::none && m > 0) {
    const std::vector<int>& idx = chk.active;
    mech::Dynamics dyn(*model, set.kernel);
    const mech::ActiveSet as = mech::ActiveSet::of(*model, idx);
    dyn.evaluate(as, 0.0, set.q0, set.qd0);
    r.rank = chk.rank;
    r.dof = n - chk.rank;
    for (int k : chk.redundant) r.redundant.push_back(model->constraints()[idx[k]].name);
    r.null_space_dimension = m - chk.rank;
    r.smallest_singular_value = dyn.smallest_singular_value();
    r.position_residual = dyn.position_residual(0.0, set.q0);
    r.velocity_residual = dyn.velocity_residual(set.qd0);
  } else if (m == 0) {
    r.rank = 0;
    r.dof = n;
    r.null_space_dimension = 0;
  }
  if (!r.mass_positive_definite && chk.issue == mech::ModelIssue::none) {
    r.reason = "the mass matrix is not positive definite at the initial state";
    return r;
  }
  if (chk.issue != mech::ModelIssue::none) {
    r.reason = chk.message;
    return r;
  }
  const mech::ProjectionResult pr =
      mech::project_consistent(*model, set.active, 0.0, set.q0, set.qd0, set.kernel);
  if (pr.issue != mech::ModelIssue::none) {
    r.reason = "consistent initial values: " + pr.message;
    return r;
  }
  r.correction_pos = pr.correction_pos;
  r.correction_vel = pr.correction_vel;
  r.note = chk.message;
  r.can_run = true;
  return r;
}

std::string format_check(const CheckReport& r) {
  const int n = static_cast<int>(r.coordinates.size());
  const int m = static_cast<int>(r.active.size());
  std::string s;
  s += "pcsim check: case '" + r.case_name + "', model '" + r.model + "'\n";
  s += "  coordinates: " + std::to_string(n) + "; active constraints: " + std::to_string(m) + "\n";
  s += std::string("  mass matrix M: ") +
       (r.mass_positive_definite ? "positive definite" : "NOT positive definite") + " (eigenvalues " +
       num(r.mass_eigenvalue_min) + " ... " + num(r.mass_eigenvalue_max) + ")\n";
  if (m > 0 && r.rank && r.smallest_singular_value) {
    const int rank = *r.rank;
    s += "  rank of the active constraints at the initial state: " + std::to_string(rank) + " of " +
         std::to_string(m) + "\n";
    s += "  degrees of freedom: " + std::to_string(n - rank) +
         " (n - rank); Gruebler-style count n - m = " + std::to_string(n - m) +
         (rank < m ? " (redundant constraints: the count is too low)" : "") + "\n";
    if (!r.redundant.empty()) {
      std::string names;
      for (const auto& name : r.redundant) names += (names.empty() ? "'" : ", '") + name + "'";
      s += "  redundant rows: " + names +
           " (consistent: R is unique, its split by constraint is\n"
           "    statically indeterminate; the minimum-norm split is reported, null space of\n"
           "    dimension " + std::to_string(m - rank) + ")\n";
    } else {
      s += "  redundant rows: none\n";
    }
    const double smin = *r.smallest_singular_value;
    s += "  smallest singular value of g (rows scaled to unit length): " + num(smin) +
         (rank < m ? " (the redundant rows)" : smin < 1e-6 ? " (at or near a singular position)" : "") +
         "\n";
    s += "  initial residuals: position " + num(*r.position_residual) + ", velocity " +
         num(*r.velocity_residual) + "\n";
  } else if (m == 0) {
    s += "  no active constraints: " + std::to_string(n) + " degrees of freedom\n";
  }
  if (!r.can_run) return s;
  s += "  consistent initial values: the correction moves q by " + num(*r.correction_pos) +
       " and q_d by " + num(*r.correction_vel) + " (2-norms)\n";
  if (!r.note.empty()) s += "  note: " + r.note + "\n";
  s += "  the case can run\n";
  return s;
}

std::string check_refusal(const CheckReport& r) {
  return r.can_run ? std::string() : "case '" + r.case_name + "' cannot run: " + r.reason;
}

nlohmann::json to_json(const CheckReport& r) {
  auto opt = [](const auto& o) { return o ? nlohmann::json(*o) : nlohmann::json(nullptr); };
  nlohmann::json j;
  j["case"] = r.case_name;
  j["model"] = r.model;
  j["coordinates"] = r.coordinates;
  j["active_constraints"] = r.active;
  j["mass_positive_definite"] = r.mass_positive_definite;
  j["mass_eigenvalues"] = {{"min", r.mass_eigenvalue_min}, {"max", r.mass_eigenvalue_max}};
  j["rank"] = opt(r.rank);
  j["dof"] = opt(r.dof);
  j["gruebler"] = r.gruebler;
  j["redundant"] = r.redundant;
  j["null_space_dimension"] = opt(r.null_space_dimension);
  j["smallest_singular_value"] = opt(r.smallest_singular_value);
  j["initial_residuals"] = {{"position", opt(r.position_residual)},
                            {"velocity", opt(r.velocity_residual)}};
  j["correction"] = {{"position", opt(r.correction_pos)}, {"velocity", opt(r.correction_vel)}};
  j["note"] = r.note;
  j["can_run"] = r.can_run;
  j["reason"] = r.reason;
  return j;
}

}  // namespace pcsim::sim
