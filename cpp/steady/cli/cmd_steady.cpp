// `pcsim steady CASE.toml [--set KEY=VALUE]... [--out DIR] [--periods k] [--method M]`: the
// periodic steady state of a case by Newton shooting (docs/steady.md): steady.json (the orbit,
// Floquet multipliers, Newton history, slow coordinates, and the summary of one period) and
// one period of the time series (timeseries.csv, or timeseries.npy with output.format = "npy",
// as pcsim run writes it), written as a whole; the engineer's report.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "cli/commands.hpp"
#include "common/error.hpp"
#include "sim/case.hpp"
#include "steady/steady_case.hpp"

namespace {

struct SteadyArgs {
  std::string case_file;
  std::vector<std::string> sets;
  std::vector<std::string> added;
  std::string out_dir;
  int periods = 1;
  std::string method = "auto";
  int max_iterations = 30;
  int transient_periods = 256;
};

void run(const SteadyArgs& a) {
  // --constraint NAME=EXPR adds a holonomic constraint: the same as
  // --set constraints.added.NAME="EXPR".
  std::vector<pcsim::sim::Override> overrides = pcsim::sim::command_line_overrides(a.sets, a.added);
  const auto method = pcsim::parse_ode_method(a.method);
  if (!method) throw pcsim::InputError("--method: expected radau, explicit or auto, got '" + a.method + "'");
  if (a.periods < 1) throw pcsim::InputError("--periods: expected an integer >= 1, got " + std::to_string(a.periods));
  if (a.max_iterations < 1) throw pcsim::InputError("--max-iterations: expected an integer >= 1");
  const pcsim::sim::Case c = pcsim::sim::load_case(a.case_file, overrides);
  pcsim::steady::SteadyOptions o;
  o.periods = a.periods;
  o.method = *method;
  o.max_iterations = a.max_iterations;
  if (a.transient_periods < 0) throw pcsim::InputError("--transient-periods: expected an integer >= 0");
  o.max_transient_periods = a.transient_periods;
  o.out_dir = a.out_dir.empty() ? std::filesystem::path("out") / (c.name + "-steady")
                                : std::filesystem::path(a.out_dir);
  const nlohmann::json s = pcsim::steady::steady_case(c, o);
  std::fputs(pcsim::steady::steady_report(c, s).c_str(), stdout);
  std::printf("  wrote %s and %s\n", (*o.out_dir / "steady.json").string().c_str(),
              (*o.out_dir / (c.setup.npy ? "timeseries.npy" : "timeseries.csv")).string().c_str());
}

void setup(CLI::App& app) {
  auto args = std::make_shared<SteadyArgs>();
  CLI::App* sub = app.add_subcommand(
      "steady", "The periodic steady state of a case by Newton shooting: the orbit, its Floquet "
                "multipliers and stability, and the summary of one period (as pcsim run reports "
                "it); writes DIR/steady.json and one period of DIR/timeseries.csv (timeseries.npy "
                "with output.format = \"npy\")");
  sub->add_option("case", args->case_file, "the case file, e.g. cases/sieve_1995.toml")->required();
  sub->add_option("--set", args->sets, "override a case key by its dotted path (repeatable)")
      ->type_name("KEY=VALUE")
      ->allow_extra_args(false);
  sub->add_option("--constraint", args->added,
                  "add a holonomic constraint to a model-file model (repeatable)")
      ->type_name("NAME=EXPR")
      ->allow_extra_args(false);
  sub->add_option("--out", args->out_dir, "output directory (default: out/<case name>-steady)")
      ->type_name("DIR");
  sub->add_option("--periods", args->periods,
                  "the orbit's period in excitation periods (k > 1: a subharmonic orbit)")
      ->type_name("k");
  sub->add_option("--method", args->method,
                  "the shooting integrator: auto (explicit, Radau where stiff; the default), "
                  "explicit or radau")
      ->type_name("auto|explicit|radau");
  sub->add_option("--max-iterations", args->max_iterations, "Newton iterations before giving up (30)")
      ->type_name("N");
  sub->add_option("--transient-periods", args->transient_periods,
                  "when Newton fails from the start: integrate up to this many orbit periods "
                  "(8, 16, 32, ...) and try again from there (256; 0: never)")
      ->type_name("N");
  sub->callback([args]() { run(*args); });
}

const bool registered = pcsim::cli::register_command(15, &setup);

}  // namespace
