// Benchmark of the README's main job (issue 14): the paper's case (cases/sieve_1995.toml, 10 s
// of motion, time series and summary written) on today's default path against the path of the
// first release, in one process, as a ratio; with the accuracy of each path's summary against a
// reference run at rtol 1e-11, and the rows that show where the time went.
//
// Usage: bench_sieve [CASE.toml] [repeats]   (default cases/sieve_1995.toml, 5)
//
// Each row is the whole computation of `pcsim run` after the process started: loading and
// validating the case, building the model, integrating, the summary, and writing both output
// files (into a temporary directory). Times: wall clock and process CPU (the time-series writer
// runs on a thread of its own), the minimum over the repeats.
//   release  the first release's path: the C++ closed form (3.4) through the engine's automatic
//            differentiation, Radau with LAPACK's LU on the full system, the dense compatibility
//            solve ([G; D^T] R = [-G0; 0] with Huang's D)  (variant closed_form, solver.method =
//            radau, solver.linear_algebra = lapack)
//   default  today's default: the model file (derived at build time, its tape compiled to native
//            code for the built-in models), solver.method =
//            auto (the explicit Dormand-Prince 8(5,3) pair on this case), the structured
//            reaction solve, the time series formatted on its own thread
// and two rows between them (the default with Radau; the C++ closed form with the default
// integrator) that separate the gains.
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "sieve/support/variants.hpp"
#include "sim/case.hpp"
#include "sim/run.hpp"

using namespace pcsim;
using namespace pcsim::sim;
namespace fs = std::filesystem;

namespace {

double cpu_now() {
  timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}
double wall_now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

struct Config {
  const char* label;
  std::vector<Override> overrides;
  std::string variant;
  bool before_issue_14 = false;  ///< the engine's path before issue 14 (dense solve, projection every step)
};

struct Row {
  double wall = 1e300, cpu = 1e300;
  nlohmann::json summary;
};

double max_rel_error(const nlohmann::json& s, const nlohmann::json& ref, std::string* which) {
  // The summary values of the sieve's contract that are results (not statistics).
  const char* keys[] = {"/amplitude/x", "/amplitude/y", "/amplitude/theta", "/theta_mean",
                        "/theta_max_abs", "/R_u_min", "/R_u_max", "/fstar_max"};
  double worst = 0.0;
  for (const char* k : keys) {
    const nlohmann::json::json_pointer p(k);
    const double a = s.at(p).get<double>(), b = ref.at(p).get<double>();
    const double e = std::abs(a - b) / std::abs(b);
    if (e > worst) {
      worst = e;
      *which = k + 1;
    }
  }
  return worst;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string file =
      argc > 1 ? argv[1] : std::string(PCSIM_SOURCE_DIR) + "/cases/sieve_1995.toml";
  const int repeats = argc > 2 ? std::max(1, std::atoi(argv[2])) : 5;
  pcsim::sieve::testing::register_sieve_variants();
  const fs::path out = fs::temp_directory_path() / ("pcsim_bench_sieve_" + std::to_string(::getpid()));

  // The reference: the same case at rtol 1e-11 (Radau, default path).
  const nlohmann::json ref = to_json(run_case(load_case(file, {{"solver.rtol", "1e-11"},
                                                               {"solver.atol", "1e-13"},
                                                               {"solver.method", "radau"}})));
  const std::vector<Config> configs = {
      {"release path (AD closed form, Radau, LAPACK, dense solve)",
       {{"solver.method", "radau"}, {"solver.linear_algebra", "lapack"}},
       "closed_form", true},
      {"C++ AD closed form, default integrator", {}, "closed_form"},
      {"default with Radau (model-file tape, own LU, M1/M2)", {{"solver.method", "radau"}}, ""},
      {"default (model-file tape, auto = explicit 8(5,3))", {}, ""},
  };
  std::vector<Row> rows(configs.size());
  for (int r = 0; r < repeats; ++r) {
    for (std::size_t c = 0; c < configs.size(); ++c) {  // interleaved: load drifts hit all rows
      const double w0 = wall_now(), c0 = cpu_now();
      const Case cs = load_case(file, configs[c].overrides);
      RunOptions o = configs[c].before_issue_14 ? pcsim::sieve::testing::path_before_issue_14() : RunOptions{};
      o.out_dir = out;
      o.variant = configs[c].variant;
      nlohmann::json s = to_json(run_case(cs, o));
      const double w = wall_now() - w0, cp = cpu_now() - c0;
      rows[c].wall = std::min(rows[c].wall, w);
      rows[c].cpu = std::min(rows[c].cpu, cp);
      rows[c].summary = std::move(s);
    }
  }
  std::error_code ec;
  fs::remove_all(out, ec);

  std::printf("bench_sieve: %s, %d repeats (minimum), whole run_case with both output files\n\n",
              file.c_str(), repeats);
  std::printf("| path | wall [ms] | CPU [ms] | release / this (wall) | steps | f-evals | max rel. error vs rtol 1e-11 |\n");
  std::printf("|---|---:|---:|---:|---:|---:|---|\n");
  for (std::size_t c = 0; c < configs.size(); ++c) {
    std::string which;
    const double err = max_rel_error(rows[c].summary, ref, &which);
    std::printf("| %s | %.1f | %.1f | %.2f | %ld | %ld | %.1e (%s) |\n", configs[c].label,
                1e3 * rows[c].wall, 1e3 * rows[c].cpu, rows[0].wall / rows[c].wall,
                rows[c].summary["stats"]["steps"].get<long>(),
                rows[c].summary["stats"]["f_evals"].get<long>(), err, which.c_str());
  }
  const bool same_verdicts = rows.back().summary["contact_kept"] == rows[0].summary["contact_kept"] &&
                             rows.back().summary["rolling_kept"] == rows[0].summary["rolling_kept"];
  std::printf("\nspeed-up of the default path over the release path: %.1fx (wall), %.1fx (CPU); "
              "verdicts %s\n",
              rows[0].wall / rows.back().wall, rows[0].cpu / rows.back().cpu,
              same_verdicts ? "identical" : "DIFFERENT");
  return 0;
}
