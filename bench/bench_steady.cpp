// Benchmark: the paper's case's steady state by `pcsim steady` (Newton shooting and the summary
// of one period) against today's way, the 10 s run of `pcsim run` read over its last 5 periods,
// in one process; the ratio of their times, and the accuracy of each against a reference
// steady state computed at rtol 1e-11 (the roller held where the 10 s run ends). The same for
// the theta-locked variant (where nothing drifts and the run's only error is its transient).
//
// Usage: bench_steady [repeats]   (default 5). Times are thread CPU times, the minimum over
// the repeats (the machine is shared; wall time is inflated by preemption). No files written.
#include <time.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "common/error.hpp"
#include "common/format.hpp"
#include "sieve/support/variants.hpp"
#include "sim/case.hpp"
#include "sim/run.hpp"
#include "steady/steady_case.hpp"
#include "bench_timing.hpp"

using namespace pcsim;

namespace {

using pcsim_bench::thread_cpu_seconds;
template <class F> double min_time(int repeats, F&& f) {
  return pcsim_bench::min_thread_time(repeats, std::forward<F>(f));
}

// The summary quantities compared, by JSON path.
const std::vector<std::pair<std::string, std::vector<std::string>>> kQuantities = {
    {"amplitude x", {"amplitude", "x"}},   {"amplitude y", {"amplitude", "y"}},
    {"amplitude theta", {"amplitude", "theta"}}, {"R_u min", {"R_u_min"}},
    {"R_u max", {"R_u_max"}},              {"f* max", {"fstar_max"}}};

double get(const nlohmann::json& s, const std::vector<std::string>& path) {
  const nlohmann::json* v = &s;
  for (const auto& k : path) v = &(*v)[k];
  return v->get<double>();
}

double worst_error(const nlohmann::json& s, const nlohmann::json& ref, std::string* which = nullptr) {
  double w = 0;
  for (const auto& [name, path] : kQuantities) {
    if (std::abs(get(ref, path)) < 1e-15) continue;  // identically zero (theta locked): noise
    const double e = std::abs(get(s, path) - get(ref, path)) / std::abs(get(ref, path));
    if (e > w) {
      w = e;
      if (which) *which = name;
    }
  }
  return w;
}

void compare(const std::string& file, const std::string& label, int repeats) {
  sieve::testing::register_sieve_variants();
  const sim::Case c = sim::load_case(file);
  nlohmann::json run;
  const double t_run = min_time(repeats, [&] { run = sim::to_json(sim::run_case(c)); });
  // The 10 s run on the path of the time issue 13 was filed (before issue 14's speed-ups: the AD
  // closed form, Radau, LAPACK, the dense compatibility solve; bench_sieve's "release path").
  const sim::Case old_case = sim::load_case(file, {{"solver.method", "radau"}, {"solver.linear_algebra", "lapack"}});
  const sim::RunOptions old_opt = sieve::testing::path_before_issue_14();
  const double t_old = min_time(std::min(repeats, 3), [&] { sim::run_case(old_case, old_opt); });
  // The roller held where the run ends (theta locked: the position changes nothing).
  const sim::Case held = sim::load_case(file, {{"initial.s0", format_number(run["q_end"]["s"].get<double>())}});
  steady::SteadyOptions o;
  nlohmann::json st;
  const double t_steady = min_time(repeats, [&] { st = steady::steady_case(held, o); });
  steady::SteadyOptions shoot_only = o;
  shoot_only.summary = false;
  const double t_shoot = min_time(repeats, [&] { steady::steady_case(held, shoot_only); });
  const sim::Case tight = sim::load_case(file, {{"initial.s0", format_number(run["q_end"]["s"].get<double>())},
                                                {"solver.rtol", "1e-11"}, {"solver.atol", "1e-15"}});
  const nlohmann::json ref = steady::steady_case(tight, o)["summary"];
  std::string w_run, w_steady;
  const double e_run = worst_error(run, ref, &w_run), e_steady = worst_error(st["summary"], ref, &w_steady);
  std::printf("%s\n", label.c_str());
  std::printf("  %-44s %9s %9s  %-34s\n", "", "CPU [s]", "ratio", "largest error vs reference");
  std::printf("  %-44s %9.4f %9.2f  %.2e (%s)\n", "pcsim run, 10 s, last 5 periods", t_run, 1.0, e_run,
              w_run.c_str());
  std::printf("  %-44s %9.4f %9.2f  (the same window)\n", "  the same on the path before issue 14", t_old,
              t_run / t_old);
  std::printf("  %-44s %9.4f %9.2f  %.2e (%s)\n", "pcsim steady: shooting + one-period summary", t_steady,
              t_run / t_steady, e_steady, w_steady.c_str());
  std::printf("  %-44s %9.4f %9.2f\n", "  of which Newton shooting", t_shoot, t_run / t_shoot);
  std::printf("  shooting: %d Newton iterations, %ld integrations, %ld steps, %ld evaluations; "
              "run: %ld steps, %ld f-evaluations\n",
              st["newton"]["iterations"].get<int>(), st["shooting"]["integrations"].get<long>(),
              st["shooting"]["steps"].get<long>(), st["shooting"]["f_evals"].get<long>(),
              run["stats"]["steps"].get<long>(), run["stats"]["f_evals"].get<long>());
  std::printf("  speed-up %.1fx at %s accuracy (errors %.1e vs %.1e); %.0fx against the run before "
              "issue 14\n",
              t_run / t_steady, e_steady <= e_run ? "better" : "worse", e_steady, e_run, t_old / t_steady);
  // Equal accuracy: pcsim steady at looser tolerances (its error stays far below the run's: the
  // run's error is drift or transient, which its own tolerance does not reduce).
  std::vector<std::pair<double, double>> steady_points = {{t_steady, e_steady}};  // (time, error)
  for (const char* rtol : {"1e-5", "1e-4", "1e-3"}) {
    const sim::Case loose = sim::load_case(file, {{"initial.s0", format_number(run["q_end"]["s"].get<double>())},
                                                  {"solver.rtol", rtol}});
    nlohmann::json sl;
    const double t = min_time(repeats, [&] { sl = steady::steady_case(loose, o); });
    std::string w;
    const double e = worst_error(sl["summary"], ref, &w);
    steady_points.emplace_back(t, e);
    std::printf("  %-44s %9.4f %9.2f  %.2e (%s)%s\n", ("pcsim steady at rtol " + std::string(rtol)).c_str(), t,
                t_run / t, e, w.c_str(), e <= e_run ? "" : "  [less accurate than the run]");
  }
  // The cheapest pcsim steady at least as accurate as a given error.
  const auto steady_at = [&](double err) {
    double best = -1;
    for (const auto& [t, e] : steady_points)
      if (e <= err && (best < 0 || t < best)) best = t;
    return best;
  };
  // Longer runs: their error against the reference held where each ends. Where it is the
  // transient (theta locked) it falls with the slowest mode until the run's integration error
  // (rtol 1e-6) is reached; where it is the drift (the paper's case) the roller leaves the deck
  // first. Each run is set against the cheapest pcsim steady that is at least as accurate.
  std::printf("  equal accuracy: each run against the cheapest pcsim steady above at least as accurate\n");
  std::printf("  %-44s %9.4f %9s  %.2e  steady %.1fx faster\n", "pcsim run, 10 s", t_run, "", e_run,
              t_run / steady_at(e_run));
  for (const char* t_end : {"15", "20", "30"}) {
    const sim::Case longer = sim::load_case(file, {{"solver.t_end", t_end}});
    nlohmann::json lr;
    double t = 0;
    try {
      t = min_time(std::min(repeats, 3), [&] { lr = sim::to_json(sim::run_case(longer)); });
    } catch (const NumericalError& e) {  // the paper's roller leaves the deck near 15 s
      std::printf("  %-44s   %s\n", ("pcsim run, " + std::string(t_end) + " s").c_str(), e.what());
      break;
    }
    const sim::Case lref = sim::load_case(file, {{"initial.s0", format_number(lr["q_end"]["s"].get<double>())},
                                                 {"solver.rtol", "1e-11"}, {"solver.atol", "1e-15"}});
    const double e = worst_error(lr, steady::steady_case(lref, o)["summary"]);
    const double ts = steady_at(e);
    std::printf("  %-44s %9.4f %9s  %.2e  steady %.1fx faster\n", ("pcsim run, " + std::string(t_end) + " s").c_str(),
                t, "", e, t / ts);
  }
  std::printf("\n");
}

}  // namespace

int main(int argc, char** argv) {
  // bench_steady --profile N [summary]: only pcsim steady's computation, N times (for a profiler).
  if (argc > 2 && std::string(argv[1]) == "--profile") {
    sieve::testing::register_sieve_variants();
    const sim::Case c = sim::load_case(std::string(PCSIM_SOURCE_DIR) + "/cases/sieve_1995.toml");
    steady::SteadyOptions o;
    o.summary = argc > 3;
    const int n = std::atoi(argv[2]);
    const double t0 = thread_cpu_seconds();
    for (int i = 0; i < n; ++i) steady::steady_case(c, o);
    std::printf("%.3f ms per steady state\n", 1e3 * (thread_cpu_seconds() - t0) / n);
    return 0;
  }
  const int repeats = argc > 1 ? std::max(1, std::atoi(argv[1])) : 5;
  std::printf("bench_steady: the steady state of the sieve, best of %d (thread CPU time); the "
              "reference is pcsim steady at rtol 1e-11, atol 1e-15, the roller held where the "
              "run ends\n\n",
              repeats);
  const std::string dir = std::string(PCSIM_SOURCE_DIR) + "/cases/";
  compare(dir + "sieve_1995.toml", "paper's case (cases/sieve_1995.toml): the roller drifts; the run's "
                                   "error is its drift and its transient", repeats);
  compare(dir + "sieve_1995_theta_locked.toml", "theta locked (cases/sieve_1995_theta_locked.toml): "
                                                "nothing drifts; the run's error is its transient", repeats);
  return 0;
}
