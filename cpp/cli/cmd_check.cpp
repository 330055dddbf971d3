// `pcsim check CASE.toml [--set KEY=VALUE]... [--constraint NAME=EXPR]...` (issue 21): what the
// engine finds about a case at its initial state, without running it: coordinates and active
// constraints, the rank of the constraint Jacobian g, the degrees of freedom against the
// Grübler-style count n − m, the redundant rows by name, the smallest singular value of g (rows
// scaled to unit length: how near a singular position), whether M is positive definite, the
// initial constraint residuals and how far the consistent-initial-value correction moves the
// state. Exit 0 when the case can run, 2 (with the reason) when it cannot. Reads the case as
// `pcsim run` does; writes nothing.
#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Eigenvalues>

#include "cli/commands.hpp"
#include "common/error.hpp"
#include "common/format.hpp"
#include "mech/dynamics.hpp"
#include "mech/simulation.hpp"
#include "sim/case.hpp"

namespace {

struct CheckArgs {
  std::string case_file;
  std::vector<std::string> sets;
  std::vector<std::string> added;
};

std::string num(double v) { return pcsim::format_significant(v, 4); }

void check(const CheckArgs& a) {
  using namespace pcsim;
  const std::vector<sim::Override> overrides = sim::command_line_overrides(a.sets, a.added);
  const sim::Case c = sim::load_case(a.case_file, overrides);
  const sim::Setup& set = c.setup;
  const auto model = c.model->instantiate(set.parameters, set.q0, 0.0, c.table, "");
  const int n = model->n();
  const int m = static_cast<int>(set.active.size());
  std::printf("pcsim check: case '%s', model '%s'\n", c.name.c_str(), model->name().c_str());
  std::printf("  coordinates: %d; active constraints: %d\n", n, m);

  // M at the initial state (positive definite: its smallest eigenvalue > 0).
  mech::Dynamics free(*model, set.kernel);
  const mech::ActiveSet none;
  free.evaluate(none, 0.0, set.q0, set.qd0);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(free.M, Eigen::EigenvaluesOnly);
  const double emin = es.eigenvalues()[0], emax = es.eigenvalues()[n - 1];
  const bool spd = es.info() == Eigen::Success && emin > 1e-13 * emax;
  std::printf("  mass matrix M: %s (eigenvalues %s ... %s)\n",
              spd ? "positive definite" : "NOT positive definite", num(emin).c_str(),
              num(emax).c_str());

  const mech::CheckResult chk = mech::check_model(*model, set.active, 0.0, set.q0, set.qd0, set.kernel);
  if (chk.issue == mech::ModelIssue::none && m > 0) {
    std::vector<int> idx = chk.active;
    mech::Dynamics dyn(*model, set.kernel);
    const mech::ActiveSet as = mech::ActiveSet::of(*model, idx);
    dyn.evaluate(as, 0.0, set.q0, set.qd0);
    std::printf("  rank of the active constraints at the initial state: %d of %d\n", chk.rank, m);
    std::printf("  degrees of freedom: %d (n - rank); Gruebler-style count n - m = %d%s\n",
                n - chk.rank, n - m,
                chk.rank < m ? " (redundant constraints: the count is too low)" : "");
    if (!chk.redundant.empty()) {
      std::string names;
      for (int r : chk.redundant)
        names += (names.empty() ? "'" : ", '") + model->constraints()[idx[r]].name + "'";
      std::printf("  redundant rows: %s (consistent: R is unique, its split by constraint is\n"
                  "    statically indeterminate; the minimum-norm split is reported, null space of\n"
                  "    dimension %d)\n",
                  names.c_str(), m - chk.rank);
    } else {
      std::printf("  redundant rows: none\n");
    }
    const double smin = dyn.smallest_singular_value();
    std::printf("  smallest singular value of g (rows scaled to unit length): %s%s\n", num(smin).c_str(),
                chk.rank < m ? " (the redundant rows)" : smin < 1e-6 ? " (at or near a singular position)" : "");
    std::printf("  initial residuals: position %s, velocity %s\n",
                num(dyn.position_residual(0.0, set.q0)).c_str(),
                num(dyn.velocity_residual(set.qd0)).c_str());
  } else if (m == 0) {
    std::printf("  no active constraints: %d degrees of freedom\n", n);
  }
  if (!spd && chk.issue == mech::ModelIssue::none) {
    throw InputError("case '" + c.name + "' cannot run: the mass matrix is not positive definite at the initial state");
  }
  if (chk.issue != mech::ModelIssue::none) {
    throw InputError("case '" + c.name + "' cannot run: " + chk.message);
  }
  const mech::ProjectionResult pr =
      mech::project_consistent(*model, set.active, 0.0, set.q0, set.qd0, set.kernel);
  if (pr.issue != mech::ModelIssue::none) {
    throw InputError("case '" + c.name + "' cannot run: consistent initial values: " + pr.message);
  }
  std::printf("  consistent initial values: the correction moves q by %s and q_d by %s (2-norms)\n",
              num(pr.correction_pos).c_str(), num(pr.correction_vel).c_str());
  if (!chk.message.empty()) std::printf("  note: %s\n", chk.message.c_str());
  std::printf("  the case can run\n");
}

void setup(CLI::App& app) {
  auto args = std::make_shared<CheckArgs>();
  CLI::App* sub = app.add_subcommand(
      "check", "Check a case file without running it: coordinates, constraints, rank and "
               "redundant rows, degrees of freedom, nearness to a singular position, the mass "
               "matrix and the initial state (exit 0: it can run; 2: it cannot, with the reason)");
  sub->add_option("case", args->case_file, "the case file, e.g. cases/fourbar_a02_N1.toml")
      ->required();
  sub->add_option("--set", args->sets, "override a case key by its dotted path (repeatable)")
      ->type_name("KEY=VALUE")
      ->allow_extra_args(false);
  sub->add_option("--constraint", args->added,
                  "add a holonomic constraint Phi(q, t) = 0 to a model-file model (repeatable)")
      ->type_name("NAME=EXPR")
      ->allow_extra_args(false);
  sub->callback([args]() { check(*args); });
}

const bool registered = pcsim::cli::register_command(12, &setup);

}  // namespace
