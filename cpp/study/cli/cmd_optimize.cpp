// `pcsim optimize`: optimization in small with NLopt's COBYLA; prints each evaluation and
// writes the history and a ready-to-run case file of the best design.
#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "cli/commands.hpp"
#include "common/error.hpp"
#include "common/files.hpp"
#include "common/format.hpp"
#include "sim/case.hpp"
#include "study/optimize.hpp"
#include "study/table.hpp"
#include "sim/vary.hpp"

namespace {

struct OptimizeArgs {
  std::string case_file;
  std::vector<std::string> vary;
  std::vector<std::string> set;
  std::string objective;
  bool minimize = false;
  std::vector<std::string> constraints;
  bool no_default_constraints = false;
  unsigned seed = 1;
  int max_evals = 40;
  std::string out;
};

std::string num(double v) { return std::isnan(v) ? "nan" : pcsim::format_number(v); }

void run_optimize(const OptimizeArgs& a) {
  namespace st = pcsim::study;
  std::vector<pcsim::sim::Override> overrides;
  for (const auto& s : a.set) overrides.push_back(pcsim::sim::parse_override(s));
  const pcsim::sim::Case base = pcsim::sim::load_case(a.case_file, overrides);
  std::vector<pcsim::sim::Bounds> bounds;
  std::vector<std::string> keys;
  for (const auto& v : a.vary) {
    bounds.push_back(pcsim::sim::parse_bounds(v, base));
    keys.push_back(bounds.back().key);
  }
  pcsim::sim::check_distinct_keys(keys);
  st::OptimizeOptions o;
  o.objective = a.objective.empty() ? st::default_objective(base) : a.objective;
  if (o.objective.empty())
    throw pcsim::InputError("--objective: required for the " + base.model->origin() +
                            " (a sweep.csv summary column, e.g. " +
                            st::summary_columns(base).front() + ")");
  st::check_objective_name(o.objective, base);
  o.maximize = !a.minimize;
  o.constraints = a.no_default_constraints ? std::vector<st::Constraint>{} : st::default_constraints(base);
  for (const auto& c : a.constraints) o.constraints.push_back(st::parse_constraint(c, base));
  o.seed = a.seed;
  if (a.max_evals < 1) throw pcsim::InputError("--max-evals must be at least 1");
  o.max_evals = a.max_evals;
  const std::filesystem::path out = a.out.empty() ? "out/" + base.name + "-optimize" : a.out;
  // The directory is optimize's own (marked, locked for this run): never a run's or a sweep's.
  const pcsim::OwnedDirectory owned(out, "optimize");

  std::printf("optimize %s %s over", o.maximize ? "max" : "min", o.objective.c_str());
  for (const auto& b : bounds)
    std::printf(" %s in [%s, %s]", b.key.c_str(), num(b.low).c_str(), num(b.high).c_str());
  std::printf("\n  subject to");
  for (const auto& c : o.constraints) std::printf(" %s", c.text().c_str());
  std::printf("%s\n  COBYLA (NLopt), seed %u, at most %s\n",
              o.constraints.empty() ? " nothing" : "", o.seed, pcsim::counted(o.max_evals, "run").c_str());

  // History table: eval, design keys, objective, constraint quantities, feasible, error.
  std::vector<std::string> header = {"eval"};
  for (const auto& b : bounds) header.push_back(b.key);
  header.push_back(o.objective);
  for (const auto& c : o.constraints) header.push_back(c.text());
  header.push_back("feasible");
  header.push_back("error");
  std::ofstream history(out / "optimize.csv", std::ios::binary);
  history << st::csv_line(header) << "\n";

  const auto result = st::optimize(base, bounds, st::case_runner(), o, [&](const st::Evaluation& e) {
    std::vector<std::string> row = {std::to_string(e.number)};
    std::printf("%4d ", e.number);
    for (std::size_t i = 0; i < e.design.size(); ++i) {
      row.push_back(num(e.design[i]));
      std::printf(" %s=%-12.7g", bounds[i].key.c_str(), e.design[i]);
    }
    row.push_back(num(e.objective));
    std::printf(" %s=%-12.7g", o.objective.c_str(), e.objective);
    for (std::size_t k = 0; k < e.constraints.size(); ++k) {
      row.push_back(num(e.constraints[k]));
      std::printf(" %s=%.4g", o.constraints[k].name.c_str(), e.constraints[k]);
    }
    row.push_back(e.feasible ? "true" : "false");
    row.push_back(e.error);
    std::printf(" %s%s%s\n", e.feasible ? "feasible" : "infeasible",
                e.error.empty() ? "" : ": ", e.error.c_str());
    std::fflush(stdout);
    history << st::csv_line(row) << "\n" << std::flush;
  });

  std::printf("stopped: %s after %s\n", result.stop_reason.c_str(),
              pcsim::counted(static_cast<long long>(result.evaluations.size()), "run").c_str());
  if (!result.best) throw pcsim::NumericalError("no design point could be run", 0.0);
  const auto& best = result.evaluations[*result.best];
  std::printf("best (run %d, %s):", best.number, best.feasible ? "feasible" : "INFEASIBLE");
  for (std::size_t i = 0; i < best.design.size(); ++i)
    std::printf(" %s=%s", bounds[i].key.c_str(), num(best.design[i]).c_str());
  std::printf("  %s=%s (start: %s)\n", o.objective.c_str(), num(best.objective).c_str(),
              num(result.evaluations.front().objective).c_str());
  const auto best_file = out / "best.toml";
  // The best design is a case of its own: its own name, so running it does not overwrite the
  // original case's output directory.
  pcsim::sim::Case best_case = result.best_case;
  best_case.name = pcsim::sim::derived_case_name(base.name, "-optimized");
  pcsim::write_file_atomically(best_file, pcsim::sim::to_toml(best_case, "best design of pcsim optimize " + base.name));
  std::printf("  history: %s\n  best case: %s  (pcsim run %s)\n",
              (out / "optimize.csv").string().c_str(), best_file.string().c_str(),
              best_file.string().c_str());
}

void setup(CLI::App& app) {
  auto args = std::make_shared<OptimizeArgs>();
  auto* sub = app.add_subcommand(
      "optimize",
      "Optimization in small: improve a summary quantity over bounded keys with NLopt COBYLA, "
      "from the case's own values");
  sub->add_option("case", args->case_file, "Case file (TOML)")->required();
  sub->add_option("--vary", args->vary, "KEY=LOW:HIGH, a bounded design key (repeatable)")
      ->required()
      ->allow_extra_args(false);  // one spec per --vary, so the case file can follow
  sub->add_option("--set", args->set, "KEY=VALUE override applied to every run")
      ->allow_extra_args(false);
  sub->add_option("--objective", args->objective,
                  "Summary quantity to maximize (a sweep.csv column; default for the sieve: "
                  "contact_margin; required for other models)");
  sub->add_flag("--minimize", args->minimize, "Minimize the objective instead");
  sub->add_option("--constraint", args->constraints,
                  "'NAME>=VALUE' or 'NAME<=VALUE' on a summary quantity (repeatable; for the "
                  "sieve added to the defaults rolling_margin>=0.2, amplitude.theta<=0.001, "
                  "amplitude.x>=2e-05, amplitude.x<=0.0001)")
      ->allow_extra_args(false);
  sub->add_flag("--no-default-constraints", args->no_default_constraints,
                "Use only the --constraint options");
  sub->add_option("--seed", args->seed, "Random seed (NLopt), default 1");
  sub->add_option("--max-evals", args->max_evals, "Case runs at most (default 40)");
  sub->add_option("--out", args->out, "Output directory (default out/<case>-optimize)");
  sub->callback([args] { run_optimize(*args); });
}

[[maybe_unused]] const bool registered = pcsim::cli::register_command(50, &setup);

}  // namespace
