// `pcsim run CASE.toml [--set KEY=VALUE]... [--out DIR] [--kernel fortran|cpp] [--form ode|dae]`
// (architecture.md section 4): load and validate the case, run it, write the output files and
// print the engineer's report.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "cli/commands.hpp"
#include "common/error.hpp"
#include "sim/case.hpp"
#include "sim/run.hpp"

namespace {

struct RunArgs {
  std::string case_file;
  std::vector<std::string> sets;
  std::vector<std::string> added;
  std::string out_dir;
  std::string kernel;
  std::string form;
};

void run(const RunArgs& a) {
  // --constraint NAME=EXPR adds a holonomic constraint: the same as
  // --set constraints.added.NAME="EXPR".
  std::vector<pcsim::sim::Override> overrides = pcsim::sim::command_line_overrides(a.sets, a.added);
  // --kernel and --form are the same as --set solver.kernel=... / solver.form=... and win.
  if (!a.kernel.empty()) overrides.emplace_back("solver.kernel", a.kernel);
  if (!a.form.empty()) overrides.emplace_back("solver.form", a.form);
  const pcsim::sim::Case c = pcsim::sim::load_case(a.case_file, overrides);
  pcsim::sim::RunOptions options;
  options.out_dir = a.out_dir.empty() ? std::filesystem::path("out") / c.name
                                      : std::filesystem::path(a.out_dir);
  pcsim::sim::RunResult result;
  try {
    result = pcsim::sim::run_case(c, options);
  } catch (const pcsim::sim::UnreliableResult& e) {
    // The run completed but its tolerance does not control the result: the report is printed
    // (with its UNRELIABLE line naming solver.atol and a value that would do) so the user sees
    // what was computed, and the run still fails with exit 3 and the reason on stderr.
    std::fputs(pcsim::sim::human_report(c, e.result()).c_str(), stdout);
    std::fflush(stdout);
    throw;
  }
  std::fputs(pcsim::sim::human_report(c, result).c_str(), stdout);
  if (const auto& e = result.initial_state) {  // initial.from = "equilibrium"
    std::printf("  started from the static equilibrium (initial.from): force imbalance %.2g",
                e->force_imbalance);
    for (const auto& [name, force] : e->holding_forces)
      std::printf(", %s held by %.4g", name.c_str(), force);
    std::printf("\n");
  }
  const char* series = c.setup.npy ? "timeseries.npy" : "timeseries.csv";  // output.format
  if (!result.switching.is_null() || (!result.rank.is_null() && !result.rank["changes"].empty()))
    std::printf("  wrote %s, %s and %s\n", (*options.out_dir / "summary.json").string().c_str(),
                (*options.out_dir / series).string().c_str(),
                (*options.out_dir / "events.csv").string().c_str());
  else
    std::printf("  wrote %s and %s\n", (*options.out_dir / "summary.json").string().c_str(),
                (*options.out_dir / series).string().c_str());
}

void setup(CLI::App& app) {
  auto args = std::make_shared<RunArgs>();
  CLI::App* sub = app.add_subcommand(
      "run", "Run a case file (TOML): writes DIR/timeseries.csv and DIR/summary.json and prints "
             "an engineer's report");
  sub->add_option("case", args->case_file, "the case file, e.g. cases/sieve_1995.toml")
      ->required();
  sub->add_option("--set", args->sets,
                  "override a case key by its dotted path, e.g. --set parameters.omega=300 "
                  "(repeatable)")
      ->type_name("KEY=VALUE")
      ->allow_extra_args(false);  // one KEY=VALUE per --set, so the case file can follow
  sub->add_option("--constraint", args->added,
                  "add a holonomic constraint Phi(q, t) = 0 to a model-file model, e.g. "
                  "--constraint 'hold=s - 0.4' (repeatable; the same as --set "
                  "constraints.added.NAME=EXPR)")
      ->type_name("NAME=EXPR")
      ->allow_extra_args(false);
  sub->add_option("--out", args->out_dir, "output directory (default: out/<case name>)")
      ->type_name("DIR");
  sub->add_option("--kernel", args->kernel, "numerical kernels: fortran or cpp (solver.kernel)")
      ->type_name("fortran|cpp");
  sub->add_option("--form", args->form, "formulation: ode or dae (solver.form)")
      ->type_name("ode|dae");
  sub->callback([args]() { run(*args); });
}

const bool registered = pcsim::cli::register_command(10, &setup);

}  // namespace
