// Throughput of a 64-point sweep (8 omegas x 8 roller positions of cases/sieve_1995.toml) in
// design points per second, with 1 job and with all cores, printed as a ratio against the
// 1-job baseline measured in the same process.
// Usage: bench_study [T_END]   (default: the case's own solver.t_end, 10 s of model time per
// point; a shorter T_END gives a quicker, overhead-heavier measurement).
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "sim/case.hpp"
#include "study/sweep.hpp"
#include "sim/vary.hpp"

int main(int argc, char** argv) {
  using namespace pcsim::study;
  using namespace pcsim::sim;
  std::vector<pcsim::sim::Override> overrides;
  if (argc > 1) overrides.push_back({"solver.t_end", argv[1]});
  const auto base = pcsim::sim::load_case(
      std::filesystem::path(PCSIM_SOURCE_DIR) / "cases" / "sieve_1995.toml", overrides);
  const std::string t_end =
      pcsim::format_number(base.table.at_path("solver.t_end").value<double>().value_or(0.0));
  const Grid grid = make_grid({"parameters.omega=250:320:8", "initial.s0=-0.35:0.35:8"}, base);
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  const auto scratch = std::filesystem::temp_directory_path() / "pcsim_bench_study";

  auto measure = [&](unsigned jobs) {
    std::filesystem::remove_all(scratch);
    SweepOptions o;
    o.out_dir = scratch;
    o.jobs = jobs;
    const auto t0 = std::chrono::steady_clock::now();
    const auto r = run_sweep(base, grid, case_runner(), o);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!r.ok || r.ran != grid.size()) {
      std::fprintf(stderr, "bench_study: sweep failed: %s\n", r.error.c_str());
      std::exit(1);
    }
    std::printf("  jobs %2u: %3zu points in %7.2f s = %7.3f points/s (%zu failed)\n", jobs,
                grid.size(), s, static_cast<double>(grid.size()) / s, r.failed);
    return static_cast<double>(grid.size()) / s;
  };

  std::printf("bench_study: 64-point sweep of sieve_1995, solver.t_end = %s s, %u cores\n",
              t_end.c_str(), cores);
  const double one = measure(1);
  const double all = measure(cores);
  std::printf("throughput ratio (jobs %u / jobs 1): %.2f  (ideal %u)\n", cores, all / one, cores);
  std::filesystem::remove_all(scratch);
  return 0;
}
