// `pcsim response CASE.toml --vary KEY=START:STOP:COUNT|KEY=v1,v2,... [--set ...] [--out DIR]
// [--periods k] [--method M] [--jobs N]`: the steady state along one case key (docs/steady.md):
// pseudo-arclength continuation over a range (folds passed), independent solves in parallel for
// listed values; response.csv and response.json, and a short report. `pcsim plot DIR` draws it.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "cli/commands.hpp"
#include "common/error.hpp"
#include "common/format.hpp"
#include "sim/case.hpp"
#include "steady/response.hpp"

namespace {

struct ResponseArgs {
  std::string case_file;
  std::string vary;
  std::vector<std::string> sets;
  std::vector<std::string> added;
  std::string out_dir;
  int periods = 1;
  std::string method = "auto";
  unsigned jobs = 0;
};

void run(const ResponseArgs& a) {
  // --constraint NAME=EXPR adds a holonomic constraint: the same as
  // --set constraints.added.NAME="EXPR".
  std::vector<pcsim::sim::Override> overrides = pcsim::sim::command_line_overrides(a.sets, a.added);
  const auto method = pcsim::parse_ode_method(a.method);
  if (!method) throw pcsim::InputError("--method: expected radau, explicit or auto, got '" + a.method + "'");
  if (a.periods < 1) throw pcsim::InputError("--periods: expected an integer >= 1, got " + std::to_string(a.periods));
  const pcsim::sim::Case c = pcsim::sim::load_case(a.case_file, overrides);
  pcsim::steady::ResponseOptions o;
  o.vary = a.vary;
  o.periods = a.periods;
  o.method = *method;
  o.jobs = a.jobs;
  o.out_dir = a.out_dir.empty() ? std::filesystem::path("out") / (c.name + "-response")
                                : std::filesystem::path(a.out_dir);
  const pcsim::steady::ResponseResult r = pcsim::steady::response_case(c, o);
  const auto& m = r.meta;
  using pcsim::format_significant;
  std::printf("pcsim response: case '%s', %s over %s from %s to %s: %s (%s)\n",
              c.name.c_str(), r.key.c_str(), r.key.c_str(),
              format_significant(m["values"][0].get<double>(), 6).c_str(),
              format_significant(m["values"][1].get<double>(), 6).c_str(),
              pcsim::counted(m["points"].get<int>(), "orbit").c_str(),
              m["mode"].get<std::string>().c_str());
  if (!r.complete) std::printf("  the branch ended early: %s\n", r.message.c_str());
  std::printf("  stable: %d, unstable: %d, failed: %d\n",
              m["points"].get<int>() - m["unstable_points"].get<int>() - m["failed_points"].get<int>(),
              m["unstable_points"].get<int>(), m["failed_points"].get<int>());
  for (const auto& f : m["folds"])
    std::printf("  fold (turning point) at %s = %s\n", r.key.c_str(),
                format_significant(f["at"].get<double>(), 6).c_str());
  for (const auto& res : m["resonances"])
    std::printf("  resonance of %s at %s = %s: amplitude %s\n", res["coordinate"].get<std::string>().c_str(),
                r.key.c_str(), format_significant(res["at"].get<double>(), 6).c_str(),
                format_significant(res["amplitude"].get<double>(), 4).c_str());
  if (m.contains("smallest_contact_margin"))
    std::printf("  smallest contact margin min R_u/(m2 g) = %s at %s = %s\n",
                format_significant(m["smallest_contact_margin"]["margin"].get<double>(), 4).c_str(),
                r.key.c_str(), format_significant(m["smallest_contact_margin"]["at"].get<double>(), 6).c_str());
  std::printf("  %s s wall\n", format_significant(m["wall_seconds"].get<double>(), 3).c_str());
  std::printf("  wrote %s and %s\n", (*o.out_dir / "response.csv").string().c_str(),
              (*o.out_dir / "response.json").string().c_str());
}

void setup(CLI::App& app) {
  auto args = std::make_shared<ResponseArgs>();
  CLI::App* sub = app.add_subcommand(
      "response", "The steady state along one case key (a frequency response): pseudo-arclength "
                  "continuation over KEY=START:STOP:COUNT (folds passed), or independent solves "
                  "in parallel at KEY=v1,v2,...; writes DIR/response.csv and DIR/response.json");
  sub->add_option("case", args->case_file, "the case file, e.g. cases/sieve_1995.toml")->required();
  sub->add_option("--vary", args->vary,
                  "the key and its range or values, e.g. parameters.omega=20:400:77 (the largest "
                  "step is (STOP - START)/(COUNT - 1); smaller where the response bends)")
      ->type_name("KEY=START:STOP:COUNT|KEY=v1,v2,...")
      ->required();
  sub->add_option("--set", args->sets, "override a case key by its dotted path (repeatable)")
      ->type_name("KEY=VALUE")
      ->allow_extra_args(false);
  sub->add_option("--constraint", args->added, "add a holonomic constraint to a model-file model")
      ->type_name("NAME=EXPR")
      ->allow_extra_args(false);
  sub->add_option("--out", args->out_dir, "output directory (default: out/<case name>-response)")
      ->type_name("DIR");
  sub->add_option("--periods", args->periods, "the orbits' period in excitation periods")->type_name("k");
  sub->add_option("--method", args->method, "the shooting integrator: auto, explicit or radau")
      ->type_name("auto|explicit|radau");
  sub->add_option("--jobs", args->jobs, "threads for independent points and the period summaries (0: all cores)")
      ->type_name("N");
  sub->callback([args]() { run(*args); });
}

const bool registered = pcsim::cli::register_command(16, &setup);

}  // namespace
