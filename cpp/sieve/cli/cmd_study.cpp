// `pcsim study incline`: theta free vs theta locked over design points (table and figure); a
// command of the sieve application (compiled into pcsim with it, pcsim_application in cmake/pcsim_helpers.cmake).
#include <CLI/CLI.hpp>

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "cli/commands.hpp"
#include "common/error.hpp"
#include "sim/case.hpp"
#include "study/cluster.hpp"
#include "sieve/incline/incline.hpp"
#include "study/progress.hpp"
#include "sim/vary.hpp"

namespace {

struct InclineArgs {
  std::string case_file;
  std::vector<std::string> vary;
  std::vector<std::string> set;
  unsigned jobs = 0;
  std::string out;
  bool no_plot = false;
  bool restart = false;
};

void run_incline(const InclineArgs& a) {
  std::vector<pcsim::sim::Override> overrides;
  for (const auto& s : a.set) {
    overrides.push_back(pcsim::sim::parse_override(s));
    if (overrides.back().first == "constraints.lock_theta")
      throw pcsim::InputError("--set " + s + ": the incline study sets constraints.lock_theta "
                              "itself (every design point runs with theta free and locked); "
                              "remove the override");
  }
  const pcsim::sim::Case base = pcsim::sim::load_case(a.case_file, overrides);
  pcsim::sieve::check_incline_case(base);
  std::vector<pcsim::sim::Axis> axes;
  if (a.vary.empty()) {
    axes.push_back(pcsim::sieve::default_incline_axis(base));
  } else {
    for (const auto& v : a.vary) {
      axes.push_back(pcsim::sim::parse_vary(v, base));
      if (axes.back().key == "constraints.lock_theta")
        throw pcsim::InputError("--vary: the incline study varies constraints.lock_theta itself");
    }
    std::vector<std::string> keys;
    for (const auto& ax : axes) keys.push_back(ax.key);
    pcsim::sim::check_distinct_keys(keys);
  }

  pcsim::study::Cluster cluster;
  pcsim::sieve::InclineOptions options;
  options.out_dir = a.out.empty() ? "out/" + base.name + "-incline" : a.out;
  options.jobs = a.jobs;
  options.progress = pcsim::study::stderr_is_terminal();
  options.cluster = &cluster;
  options.plot = !a.no_plot;
  options.restart = a.restart;
  const auto r = pcsim::sieve::run_incline_study(base, axes, pcsim::study::case_runner(), options);
  if (!r.ok) throw pcsim::InputError(r.error);
  if (cluster.rank() != 0) return;
  std::printf("study incline: %zu design points x (theta free, theta locked): %zu run now, %zu "
              "from an earlier run, %zu failed\n",
              r.points, r.sweep.ran, r.sweep.skipped, r.failed);
  std::printf("  runs:   %s\n  table:  %s\n", r.sweep.csv.string().c_str(),
              r.table.string().c_str());
  if (!r.plot.empty()) std::printf("  figure: %s\n", r.plot.string().c_str());
  if (!r.plot_error.empty()) std::fprintf(stderr, "pcsim: warning: %s\n", r.plot_error.c_str());
}

void setup(CLI::App& app) {
  auto* study = app.add_subcommand("study", "Design studies built on sweeps");
  study->require_subcommand(1);
  auto args = std::make_shared<InclineArgs>();
  auto* inc = study->add_subcommand(
      "incline",
      "Influence of incline vibration: each design point run with theta free and locked; "
      "contact margin min R_u/(m2 g), rolling margin 1 - max f*/f and their differences "
      "(DIR/incline.csv, DIR/incline.png)");
  inc->add_option("case", args->case_file, "Case file (TOML)")->required();
  inc->add_option("--vary", args->vary,
                  "Design points, as for sweep (default: initial.s0 from -(a-r) to a-r, 9 "
                  "points); e.g. parameters.omega=200:360:9 or parameters.y0=-0.4:0.4:9")
      ->allow_extra_args(false);  // one spec per --vary, so the case file can follow
  inc->add_option("--set", args->set, "KEY=VALUE override applied to every run")
      ->allow_extra_args(false);
  inc->add_option("--jobs,-j", args->jobs, "Threads (per MPI rank); default: all cores");
  inc->add_option("--out", args->out, "Output directory (default out/<case>-incline)");
  inc->add_flag("--no-plot", args->no_plot, "Write the table only");
  inc->add_flag("--restart", args->restart,
                "Discard the rows of an earlier study of another case in --out and compute "
                "every point");
  inc->callback([args] { run_incline(*args); });
}

[[maybe_unused]] const bool registered = pcsim::cli::register_command(40, &setup);

}  // namespace
