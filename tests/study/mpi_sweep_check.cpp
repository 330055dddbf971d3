// MPI 2 ranks = 1 job (run under mpirun -np 2 by CTest): the fake-runner sweep distributed over
// the ranks writes a sweep.csv byte-identical to the same sweep run by one process with one
// thread; a resumed distributed sweep (torn journal) too. Exit 0 on success, 1 on mismatch.
#include <cstdio>
#include <fstream>
#include <string>

#include "study/cluster.hpp"
#include "study/sweep.hpp"
#include "sim/vary.hpp"
#include "study_fixtures.hpp"

int main() {
  using namespace pcsim::study;
  using namespace pcsim::sim;
  Cluster cluster;
  if (cluster.size() != 2) {
    std::fprintf(stderr, "mpi_sweep_check: expected 2 ranks, got %d\n", cluster.size());
    return 1;
  }
  const auto root = std::filesystem::path(PCSIM_BINARY_DIR) / "test-scratch" / "mpi_check";
  if (cluster.rank() == 0) {
    std::filesystem::remove_all(root);
    std::filesystem::create_directories(root);
  }
  cluster.broadcast("ready");  // rank 1 waits until the directory is fresh
  const auto case_dir = root.parent_path() / ("mpi_case_rank" + std::to_string(cluster.rank()));
  std::filesystem::create_directories(case_dir);
  const auto base = study_test::minimal_case(case_dir);
  const Grid grid = make_grid({"parameters.omega=260,280,1100", "initial.s0=-0.3:0.3:5"}, base);

  SweepOptions distributed;
  distributed.out_dir = root / "ranks";
  distributed.jobs = 2;
  distributed.cluster = &cluster;
  const auto report = run_sweep(base, grid, study_test::FakeRunner{}, distributed);

  int failures = 0;
  if (!report.ok || report.points != 15 || report.ran != 15) {
    std::fprintf(stderr, "rank %d: distributed sweep failed: %s\n", cluster.rank(),
                 report.error.c_str());
    ++failures;
  }
  if (cluster.rank() == 0) {
    SweepOptions single;
    single.out_dir = root / "single";
    single.jobs = 1;
    const auto one = run_sweep(base, grid, study_test::FakeRunner{}, single);
    const std::string expected = study_test::slurp(one.csv);
    if (!one.ok || study_test::slurp(report.csv) != expected) {
      std::fprintf(stderr, "2-rank sweep.csv differs from the 1-job one\n");
      ++failures;
    }
    // Interrupt the distributed journal: keep the header, 4 rows and a torn fifth.
    const std::string& text = expected;
    std::size_t cut = 0;
    for (int n = 0; n < 5; ++n) cut = text.find('\n', cut) + 1;
    std::ofstream(report.csv, std::ios::binary) << text.substr(0, cut) << text.substr(cut, 20);
  }
  cluster.broadcast("truncated");
  const auto resumed = run_sweep(base, grid, study_test::FakeRunner{}, distributed);
  if (cluster.rank() == 0) {
    const std::string expected = study_test::slurp(root / "single" / "sweep.csv");
    if (!resumed.ok || resumed.skipped != 4 || resumed.ran != 11 ||
        study_test::slurp(resumed.csv) != expected) {
      std::fprintf(stderr, "resumed 2-rank sweep differs (skipped %zu, ran %zu)\n",
                   resumed.skipped, resumed.ran);
      ++failures;
    }
  }
  const std::string verdict = cluster.broadcast(std::to_string(failures));
  if (cluster.rank() == 0) std::printf("mpi_sweep_check: %s\n", verdict == "0" ? "ok" : "FAILED");
  return verdict == "0" ? 0 : 1;
}
