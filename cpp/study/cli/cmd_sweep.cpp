// `pcsim sweep`: a full grid of design points into a resumable sweep.csv, on threads and MPI ranks.
#include <CLI/CLI.hpp>

#include <cstdio>
#include <string>
#include <vector>

#include "cli/commands.hpp"
#include "common/error.hpp"
#include "common/format.hpp"
#include "sim/case.hpp"
#include "study/cluster.hpp"
#include "study/progress.hpp"
#include "study/sweep.hpp"
#include "sim/vary.hpp"

namespace {

struct SweepArgs {
  std::string case_file;
  std::vector<std::string> vary;
  std::vector<std::string> set;
  unsigned jobs = 0;
  bool restart = false;
  std::string out;
};

void run(const SweepArgs& a) {
  std::vector<pcsim::sim::Override> overrides;
  for (const auto& s : a.set) overrides.push_back(pcsim::sim::parse_override(s));
  const pcsim::sim::Case base = pcsim::sim::load_case(a.case_file, overrides);
  // Every specification is checked before MPI starts and before any point runs.
  const pcsim::sim::Grid grid = pcsim::sim::make_grid(a.vary, base);

  pcsim::study::Cluster cluster;
  pcsim::study::SweepOptions options;
  options.out_dir = a.out.empty() ? "out/" + base.name + "-sweep" : a.out;
  options.jobs = a.jobs;
  options.progress = pcsim::study::stderr_is_terminal();
  options.cluster = &cluster;
  options.restart = a.restart;
  const auto report =
      pcsim::study::run_sweep(base, grid, pcsim::study::case_runner(), options);
  if (!report.ok) throw pcsim::InputError(report.error);
  if (cluster.rank() == 0) {
    std::printf("sweep: %s (%zu from an earlier run, %zu run now",
                pcsim::counted(static_cast<long long>(report.points), "point").c_str(),
                report.skipped, report.ran);
    if (cluster.size() > 1) std::printf(" on %d ranks", cluster.size());
    std::printf("), %zu failed -> %s\n", report.failed, report.csv.string().c_str());
    if (report.dropped)
      std::printf("sweep: dropped %zu torn or malformed line(s) of the earlier file\n",
                  report.dropped);
    if (report.foreign)
      std::printf("sweep: kept %zu earlier row(s) not on this grid after the grid rows\n",
                  report.foreign);
  }
}

void setup(CLI::App& app) {
  auto args = std::make_shared<SweepArgs>();
  auto* sub = app.add_subcommand(
      "sweep", "Run a case over a full grid of design points into DIR/sweep.csv (resumable)");
  sub->add_option("case", args->case_file, "Case file (TOML)")->required();
  sub->add_option("--vary", args->vary,
                  "KEY=START:STOP:COUNT or KEY=v1,v2,... (any numeric dotted case key); "
                  "repeat for a grid, the last one varies fastest")
      ->required()
      ->allow_extra_args(false);  // one spec per --vary, so the case file can follow
  sub->add_option("--set", args->set, "KEY=VALUE override applied to every point")
      ->allow_extra_args(false);
  sub->add_option("--jobs,-j", args->jobs, "Threads (per MPI rank); default: all cores");
  sub->add_flag("--restart", args->restart,
                "Discard the rows of an earlier sweep of another case in --out and compute every "
                "point (without it such a sweep is refused)");
  sub->add_option("--out", args->out, "Output directory (default out/<case>-sweep)");
  sub->callback([args] { run(*args); });
}

[[maybe_unused]] const bool registered = pcsim::cli::register_command(30, &setup);

}  // namespace
