// How pcsim scales with the size of a machine (issue 23): the pendulum chain of N links
// (tests/modelfile/chain_model.hpp, the generator of models/pendulum_chain_30.toml; 3N
// coordinates, 2N joint constraints) for N = 10, 30, 100, 300, 1000, and the IFToMM A02 four-bar
// chain (scripts/fourbar_a02_model.py N: 3(2N+1) coordinates, 6N+2 constraints) for N = 1, 4, 10,
// 40. Each size is run as a user runs it: `pcsim run CASE --out DIR` in a process of its own
// (no shell), timed from outside (wall clock, and the child's CPU from the kernel's accounting).
// Printed per size, in CPU seconds: load = whole process - integration (process start, reading
// and deriving the model, writing the output; the integration's CPU taken as its share of the
// wall time, summary.json's stats.wall_seconds), the integration's cost per step and per
// simulated second, and the accuracy reached (the drift of the chain's energy, which is
// conserved, relative to its potential energy scale); then the exponents fitted (least squares
// in log-log) from N = 30 up. Sizes predicted (from the last two measured) to overrun the time
// budget are printed as skipped.
//
// Accuracy stated: solver.rtol = 1e-8, atol = 1e-10 (the chain from a straight line at 0.5 rad
// from the vertical, released at rest; A02 as cases/fourbar_a02_N1.toml), 1 s of motion (A02: 1 s).
//
// Usage: bench_scale [--pcsim PATH] [--budget SECONDS] [--t-end T] [--save] [--figures FILE]
//   --pcsim    the executable (default: pcsim next to this benchmark)
//   --budget   total wall seconds for all sizes (default 300)
//   --save     write the figures measured to FILE (default bench/figures/scale.json in the
//              source tree) for the next commit's ratios; without it they are only read
#include <fcntl.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "../tests/modelfile/chain_model.hpp"

extern char** environ;

namespace fs = std::filesystem;

namespace {

struct Timed {
  int status = -1;
  double wall = 0, cpu = 0;
};

// Runs argv (no shell), its output streams to `log`; wall and CPU seconds of the child.
Timed run(const std::vector<std::string>& args, const fs::path& log) {
  std::vector<char*> argv;
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&fa, 1, 2);
  Timed t;
  const auto t0 = std::chrono::steady_clock::now();
  pid_t pid;
  if (posix_spawn(&pid, argv[0], &fa, nullptr, argv.data(), environ) != 0) {
    posix_spawn_file_actions_destroy(&fa);
    return t;
  }
  int st = 0;
  rusage ru{};
  wait4(pid, &st, 0, &ru);
  t.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  t.cpu = static_cast<double>(ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) +
          1e-6 * static_cast<double>(ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
  t.status = WIFEXITED(st) ? WEXITSTATUS(st) : 128;
  posix_spawn_file_actions_destroy(&fa);
  return t;
}

std::string chain_case(int N, double t_end) {
  // All links on a straight line at angle a from the downward vertical, at rest: consistent.
  const double a = 0.5, h = 0.05;
  std::ostringstream s;
  s.precision(17);
  s << "model = \"chain.toml\"\n[initial]\n";
  for (int i = 1; i <= N; ++i) {
    s << "x" << i << " = " << (2 * i - 1) * h * std::sin(a) << "\n";
    s << "y" << i << " = " << -(2 * i - 1) * h * std::cos(a) << "\n";
    s << "th" << i << " = " << a << "\n";
  }
  s << "[solver]\nt_end = " << t_end << "\nrtol = 1.0e-8\natol = 1.0e-10\n";
  s << "[output]\ndt = " << t_end / 100 << "\n";
  return s.str();
}

struct Figure {
  bool ran = false;
  double load = 0, per_step = 0, per_second = 0, cpu = 0, accuracy = NAN;
  long steps = 0;
};

// Least-squares slope of log(y) against log(N) over the sizes from n_from up.
double exponent(const std::map<int, Figure>& f, double Figure::*field, int n_from) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int k = 0;
  for (const auto& [n, fig] : f) {
    if (!fig.ran || n < n_from || !(fig.*field > 0)) continue;
    const double x = std::log(n), y = std::log(fig.*field);
    sx += x; sy += y; sxx += x * x; sxy += x * y; ++k;
  }
  if (k < 2) return n_from > 0 ? exponent(f, field, 0) : NAN;  // too few sizes: all of them
  return (k * sxy - sx * sy) / (k * sxx - sx * sx);
}

}  // namespace

int main(int argc, char** argv) {
  fs::path pcsim = fs::path(argv[0]).parent_path() / "pcsim";
  fs::path figures = fs::path(PCSIM_SOURCE_DIR) / "bench" / "figures" / "scale.json";
  double budget = 300, t_end = 1.0;
  bool save = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--pcsim" && i + 1 < argc) pcsim = argv[++i];
    else if (a == "--budget" && i + 1 < argc) budget = std::atof(argv[++i]);
    else if (a == "--t-end" && i + 1 < argc) t_end = std::atof(argv[++i]);
    else if (a == "--figures" && i + 1 < argc) figures = argv[++i];
    else if (a == "--save") save = true;
    else {
      std::fprintf(stderr, "usage: bench_scale [--pcsim PATH] [--budget S] [--t-end T] [--save] [--figures FILE]\n");
      return 2;
    }
  }
  pcsim = fs::absolute(pcsim);
  nlohmann::json previous;
  if (std::ifstream in(figures); in) {
    try { in >> previous; } catch (...) { previous = nullptr; }
  }
  const fs::path dir = fs::temp_directory_path() / ("pcsim_bench_scale_" + std::to_string(getpid()));
  fs::create_directories(dir);
  const auto start = std::chrono::steady_clock::now();
  auto remaining = [&] {
    return budget - std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  nlohmann::json out;
  out["t_end"] = t_end;
  out["rtol"] = 1e-8;
  out["atol"] = 1e-10;

  struct Family {
    std::string name;
    std::vector<int> sizes;
  };
  const std::vector<Family> families = {{"chain", {10, 30, 100, 300, 1000}},
                                        {"fourbar_a02", {1, 4, 10, 40}}};
  for (const auto& fam : families) {
    std::printf("%s: %s run, rtol 1e-8, atol 1e-10, %g s of motion\n", fam.name.c_str(),
                pcsim.filename().c_str(), t_end);
    std::printf("%6s %10s %10s %14s %14s %10s %12s  %s\n", "N", "load s", "all cpu s", "per step s",
                "per sim s", "steps", "accuracy", "ratio to saved (per sim s)");
    std::map<int, Figure> figs;
    double last_total = 0;
    int last_n = 0;
    for (int N : fam.sizes) {
      // The run's predicted wall time, from the last size by the exponent measured so far (3 if
      // unknown): skipped if it would overrun the budget.
      if (last_n > 0) {
        double p = exponent(figs, &Figure::per_second, 0);
        if (!(p > 0)) p = 3;
        const double predicted = last_total * std::pow(static_cast<double>(N) / last_n, std::max(p, 1.0));
        if (predicted > remaining()) {
          std::printf("%6d skipped (predicted %.0f s, %.0f s of the budget left)\n", N, predicted, remaining());
          continue;
        }
      }
      const fs::path d = dir / (fam.name + std::to_string(N));
      fs::create_directories(d);
      std::string case_text;
      if (fam.name == "chain") {
        std::ofstream(d / "chain.toml") << pcsim::modelfile::testing::pendulum_chain_toml(N);
        case_text = chain_case(N, t_end);
      } else {
        // scripts/fourbar_a02_model.py writes the model and its case's [initial] table.
        const fs::path script = fs::path(PCSIM_SOURCE_DIR) / "scripts" / "fourbar_a02_model.py";
        const Timed m = run({"/usr/bin/python3", script.string(), std::to_string(N)}, d / "chain.toml");
        const Timed i = run({"/usr/bin/python3", script.string(), std::to_string(N), "--initial"}, d / "initial.toml");
        if (m.status != 0 || i.status != 0) {
          std::printf("%6d skipped (scripts/fourbar_a02_model.py failed)\n", N);
          continue;
        }
        std::ifstream in(d / "initial.toml");
        std::stringstream ss;
        ss << in.rdbuf();
        case_text = "model = \"chain.toml\"\n" + ss.str() + "[solver]\nt_end = " + std::to_string(t_end) +
                    "\nrtol = 1.0e-8\natol = 1.0e-10\n[output]\ndt = " + std::to_string(t_end / 100) + "\n";
      }
      std::ofstream(d / "case.toml") << case_text;
      const Timed t = run({pcsim.string(), "run", (d / "case.toml").string(), "--out", (d / "out").string()},
                          d / "log.txt");
      last_total = t.wall;
      last_n = N;
      Figure f;
      nlohmann::json summary;
      if (std::ifstream in(d / "out" / "summary.json"); in) {
        try { in >> summary; } catch (...) {}
      }
      if (t.status != 0 || summary.is_null()) {
        std::printf("%6d failed (exit %d; see %s)\n", N, t.status, (d / "log.txt").c_str());
        continue;
      }
      const double wall = summary["stats"]["wall_seconds"].get<double>();
      f.ran = true;
      f.steps = summary["stats"]["steps"].get<long>();
      // CPU figures (other jobs on the machine inflate wall times, not CPU): the integration's
      // share of the process's CPU taken as its share of the wall time (steady load assumed).
      const double integration_cpu = t.cpu * std::min(1.0, wall / t.wall);
      f.load = t.cpu - integration_cpu;
      f.cpu = t.cpu;
      f.per_step = f.steps > 0 ? integration_cpu / static_cast<double>(f.steps) : NAN;
      f.per_second = integration_cpu / t_end;
      // Accuracy: the energy's spread over the run (conserved exactly) against the chain's
      // potential energy scale m g N L (chain only: A02's outputs have no energy).
      if (fam.name == "chain" && summary.contains("extremes") && summary["extremes"].contains("energy")) {
        const auto& e = summary["extremes"]["energy"];
        f.accuracy = (e["max"].get<double>() - e["min"].get<double>()) / (9.81 * N * 0.1);
      }
      figs[N] = f;
      std::string ratio = "-";
      const std::string key = fam.name + "/" + std::to_string(N);
      if (previous.is_object() && previous.contains("figures") && previous["figures"].contains(key)) {
        const double old = previous["figures"][key]["per_second"].get<double>();
        char b[64];
        std::snprintf(b, sizeof b, "%.2f (saved %.4g s)", old / f.per_second, old);
        ratio = b;
      }
      std::printf("%6d %10.3f %10.3f %14.4g %14.4g %10ld %12.2g  %s\n", N, f.load, f.cpu, f.per_step,
                  f.per_second, f.steps, f.accuracy, ratio.c_str());
      std::fflush(stdout);
      out["figures"][key] = {{"load", f.load}, {"per_step", f.per_step}, {"per_second", f.per_second},
                             {"steps", f.steps}, {"cpu", f.cpu}, {"accuracy", std::isfinite(f.accuracy) ? nlohmann::json(f.accuracy) : nlohmann::json(nullptr)}};
    }
    const int from = fam.name == "chain" ? 30 : 4;
    std::printf("  fitted exponents from N = %d up (all sizes if fewer than two): load N^%.2f, per step N^%.2f, per simulated second N^%.2f\n\n",
                from, exponent(figs, &Figure::load, from), exponent(figs, &Figure::per_step, from),
                exponent(figs, &Figure::per_second, from));
  }
  fs::remove_all(dir);
  if (save) {
    fs::create_directories(figures.parent_path());
    std::ofstream(figures) << out.dump(2) << "\n";
    std::printf("figures saved to %s\n", figures.c_str());
  }
  return 0;
}
