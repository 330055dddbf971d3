// Benchmark of the explicit Dormand-Prince 8(5,3) pair against Radau IIA on non-stiff problems,
// in one process: for each problem, both methods run over a ladder of tolerances; for each
// target accuracy the cheapest run of each method that reaches it is chosen, and the table
// prints their f-evaluations, thread CPU times and the Radau/explicit ratios (equal achieved
// accuracy, not equal tolerance: Radau rescales its tolerance). Then the C++/Fortran time ratio
// of the explicit kernel. Not a test: run it by hand (see docs/explicit.md).
//
//   bench_explicit [--min-seconds S]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <functional>
#include <string>
#include <vector>

#include "../tests/ode/explicit_problems.hpp"
#include "ode/integrate.hpp"

using namespace pcsim;
using namespace pcsim::explicit_problems;

namespace {

double thread_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

struct Problem {
  std::string name;
  OdeProblem problem;
  double t0, t1;
  Eigen::VectorXd y0, y_ref;
  double floor;  // errors relative to max(|y_ref|, floor)
};

struct Point {
  double tol = 0, err = 0, cpu = 0;
  long f_evals = 0, steps = 0;
};

// The median CPU time of repeated runs until min_seconds have passed (at least 3 runs).
Point measure(const Problem& p, OdeMethod m, Kernel k, double tol, double min_seconds) {
  OdeOptions o;
  o.kernel = k;
  o.rtol = o.atol = tol;
  o.max_steps = 1000000;
  std::vector<double> times;
  OdeResult r;
  double total = 0.0;
  while (times.size() < 3 || total < min_seconds) {
    const double c0 = thread_cpu_seconds();
    r = ode_integrate(p.problem, p.t0, p.y0, p.t1, o, m);
    const double dt = thread_cpu_seconds() - c0;
    times.push_back(dt);
    total += dt;
    if (r.status != OdeStatus::success) {
      std::fprintf(stderr, "%s %s tol %g: %s\n", p.name.c_str(), to_string(m), tol, r.message.c_str());
      std::exit(1);
    }
  }
  std::sort(times.begin(), times.end());
  Point pt;
  pt.tol = tol;
  pt.err = scaled_error(r.y, p.y_ref, p.floor);
  pt.cpu = times[times.size() / 2];
  pt.f_evals = r.f_evals;
  pt.steps = r.steps;
  return pt;
}

const Point* cheapest_reaching(const std::vector<Point>& ladder, double target) {
  const Point* best = nullptr;
  for (const Point& p : ladder)
    if (p.err <= target && (!best || p.f_evals < best->f_evals)) best = &p;
  return best;
}

}  // namespace

int main(int argc, char** argv) {
  double min_seconds = 0.05;
  for (int i = 1; i < argc; ++i)
    if (!std::strcmp(argv[i], "--min-seconds") && i + 1 < argc) min_seconds = std::atof(argv[++i]);

  std::vector<Problem> problems;
  problems.push_back({"Arenstorf orbit, one period", arenstorf_problem(), 0.0, kArenstorfPeriod,
                      arenstorf_y0(), arenstorf_y0(), 1.0});
  problems.push_back({"oscillators, sieve eigenvalues, 1 s", oscillators_problem(), 0.0, 1.0,
                      Eigen::VectorXd::Zero(8), oscillators_solution(1.0), 1e-3});
  problems.push_back({"HNW exact problem, [0, 5]", hnw_exact_problem(), 0.0, 5.0,
                      hnw_exact_solution(0.0), hnw_exact_solution(5.0), 1.0});

  std::printf("## Explicit (DOP853) vs Radau IIA at equal achieved accuracy (Fortran kernels)\n\n");
  std::printf("| problem | target error | explicit tol | explicit f-evals | explicit CPU [ms] | "
              "Radau tol | Radau f-evals | Radau CPU [ms] | f-evals Radau/explicit | CPU Radau/explicit |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|\n");
  for (const Problem& p : problems) {
    std::vector<Point> ex, ra;
    for (int k = 8; k <= 26; ++k) {  // tol = 10^(-k/2): 1e-4 .. 1e-13
      const double tol = std::pow(10.0, -0.5 * k);
      ex.push_back(measure(p, OdeMethod::explicit_rk, Kernel::fortran, tol, min_seconds));
      ra.push_back(measure(p, OdeMethod::radau, Kernel::fortran, tol, min_seconds));
    }
    for (double target : {1e-3, 1e-5, 1e-7, 1e-9}) {
      const Point* e = cheapest_reaching(ex, target);
      const Point* r = cheapest_reaching(ra, target);
      if (!e || !r) {
        std::printf("| %s | %.0e | %s | | | %s | | | | |\n", p.name.c_str(), target,
                    e ? "" : "not reached at tol >= 1e-13", r ? "" : "not reached at tol >= 1e-13");
        continue;
      }
      std::printf("| %s | %.0e | %.1e | %ld | %.3f | %.1e | %ld | %.3f | %.2f | %.2f |\n",
                  p.name.c_str(), target, e->tol, e->f_evals, 1e3 * e->cpu, r->tol, r->f_evals,
                  1e3 * r->cpu, double(r->f_evals) / double(e->f_evals), r->cpu / e->cpu);
    }
  }

  std::printf("\n## Explicit kernel: C++ port vs Fortran (same steps, thread CPU time)\n\n");
  std::printf("| problem | tol | steps | f-evals | Fortran CPU [ms] | C++ CPU [ms] | C++/Fortran |\n");
  std::printf("|---|---|---|---|---|---|---|\n");
  for (const Problem& p : problems) {
    for (double tol : {1e-6, 1e-10}) {
      const Point f = measure(p, OdeMethod::explicit_rk, Kernel::fortran, tol, 4 * min_seconds);
      const Point c = measure(p, OdeMethod::explicit_rk, Kernel::cpp, tol, 4 * min_seconds);
      std::printf("| %s | %.0e | %ld | %ld | %.3f | %.3f | %.2f |\n", p.name.c_str(), tol,
                  f.steps, f.f_evals, 1e3 * f.cpu, 1e3 * c.cpu, c.cpu / f.cpu);
    }
  }
  return 0;
}
