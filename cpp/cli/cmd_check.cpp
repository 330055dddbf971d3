// `pcsim check CASE.toml [--set KEY=VALUE]... [--constraint NAME=EXPR]...` (issue 21): what the
// engine finds about a case at its initial state, without running it: coordinates and active
// constraints, the rank of the constraint Jacobian g, the degrees of freedom against the
// Grübler-style count n − m, the redundant rows by name, the smallest singular value of g (rows
// scaled to unit length: how near a singular position), whether M is positive definite, the
// initial constraint residuals and how far the consistent-initial-value correction moves the
// state. Exit 0 when the case can run, 2 (with the reason) when it cannot. Reads the case as
// `pcsim run` does; writes nothing.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "cli/commands.hpp"
#include "common/error.hpp"
#include "sim/case.hpp"
#include "sim/check.hpp"

namespace {

struct CheckArgs {
  std::string case_file;
  std::vector<std::string> sets;
  std::vector<std::string> added;
};

// The check itself is the case layer's (sim/check.hpp): this prints its text and turns a case
// that cannot run into the exit-2 error.
void check(const CheckArgs& a) {
  using namespace pcsim;
  const std::vector<sim::Override> overrides = sim::command_line_overrides(a.sets, a.added);
  const sim::Case c = sim::load_case(a.case_file, overrides);
  const sim::CheckReport r = sim::check_case(c);
  std::fputs(sim::format_check(r).c_str(), stdout);
  if (!r.can_run) throw InputError(sim::check_refusal(r));
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
