// `pcsim modes CASE.toml [--set KEY=VALUE]... [--out DIR] [--excitation off|PHASE]
// [--cyclic NAME]... [--vary KEY=START:STOP:COUNT]`: the natural frequencies, damping ratios
// and mode shapes of the constrained system about a rest state or a steady motion
// (modes/modes_case.hpp): the report, DIR/modes.json and DIR/modes.csv; with --vary the
// eigenvalues traced over a key, DIR/modes_vary.csv and DIR/modes_vary.json (pcsim plot DIR
// draws them).
#include <CLI/CLI.hpp>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "cli/commands.hpp"
#include "common/error.hpp"
#include "modes/modes_case.hpp"
#include "sim/case.hpp"

namespace {

struct ModesArgs {
  std::string case_file;
  std::vector<std::string> sets;
  std::vector<std::string> added;
  std::string out_dir;
  std::string excitation;
  std::vector<std::string> cyclic;
  bool no_cyclic = false;
  std::string vary;
};

void run(const ModesArgs& a) {
  const std::vector<pcsim::sim::Override> overrides = pcsim::sim::command_line_overrides(a.sets, a.added);
  pcsim::modes::ModesOptions o;
  if (!a.excitation.empty()) o.excitation = a.excitation;
  if (!a.cyclic.empty()) o.cyclic = a.cyclic;
  if (a.no_cyclic) {
    if (!a.cyclic.empty()) throw pcsim::InputError("--no-cyclic and --cyclic: expected one of them");
    o.cyclic = std::vector<std::string>{};
  }
  std::optional<pcsim::modes::VarySpec> vary;
  if (!a.vary.empty()) vary = pcsim::modes::parse_vary(a.vary);
  const pcsim::sim::Case c = pcsim::sim::load_case(a.case_file, overrides);
  o.out_dir = a.out_dir.empty() ? std::filesystem::path("out") / (c.name + "-modes") : std::filesystem::path(a.out_dir);
  if (vary) {
    const nlohmann::json j = pcsim::modes::modes_vary(c, o, *vary);
    std::fputs(pcsim::modes::vary_report(j).c_str(), stdout);
    std::printf("  wrote %s and %s\n", (*o.out_dir / "modes_vary.csv").string().c_str(),
                (*o.out_dir / "modes_vary.json").string().c_str());
    return;
  }
  const nlohmann::json j = pcsim::modes::modes_case(c, o);
  std::fputs(pcsim::modes::modes_report(c, j).c_str(), stdout);
  std::printf("  wrote %s and %s\n", (*o.out_dir / "modes.json").string().c_str(),
              (*o.out_dir / "modes.csv").string().c_str());
}

void setup(CLI::App& app) {
  auto args = std::make_shared<ModesArgs>();
  CLI::App* sub = app.add_subcommand(
      "modes", "Natural frequencies, damping ratios and mode shapes of the constrained system about a rest "
               "state (the case's initial state, or initial.from = \"equilibrium\") or a steady motion "
               "([modes] cyclic), on the tangent space of the constraints with exact derivatives; writes "
               "DIR/modes.json and DIR/modes.csv (with --vary: DIR/modes_vary.csv and DIR/modes_vary.json)");
  sub->add_option("case", args->case_file, "the case file, e.g. cases/sieve_1995_theta_locked.toml")->required();
  sub->add_option("--set", args->sets, "override a case key by its dotted path (repeatable)")
      ->type_name("KEY=VALUE")
      ->allow_extra_args(false);
  sub->add_option("--constraint", args->added, "add a holonomic constraint to a model-file model (repeatable)")
      ->type_name("NAME=EXPR")
      ->allow_extra_args(false);
  sub->add_option("--out", args->out_dir, "output directory (default: out/<case name>-modes)")->type_name("DIR");
  sub->add_option("--excitation", args->excitation,
                  "off (the model averaged over one excitation period; the default) or the excitation's phase "
                  "in rad at which it is held (overrides [modes] excitation)")
      ->type_name("off|PHASE");
  sub->add_option("--cyclic", args->cyclic,
                  "a coordinate that moves at a constant rate in the steady motion (repeatable; overrides "
                  "[modes] cyclic)")
      ->type_name("NAME")
      ->allow_extra_args(false);
  sub->add_flag("--no-cyclic", args->no_cyclic, "ignore [modes] cyclic: linearize about a rest state");
  sub->add_option("--vary", args->vary,
                  "trace the eigenvalues over a numeric case key, COUNT equally spaced values, paired by "
                  "continuity")
      ->type_name("KEY=START:STOP:COUNT");
  sub->callback([args]() { run(*args); });
}

const bool registered = pcsim::cli::register_command(17, &setup);

}  // namespace
