// Benchmark of Radau IIA on the Test Set's index-3 mechanisms (Andrews' squeezer, the car
// axis; tests/ode/mechanisms.hpp), Test Set protocol rtol = atol = h0 = 1e-4 .. 1e-10, scd at
// t_end. Three configurations, timed alternately in this one process (thread CPU time, median):
//   lapack : the path before the own LU: LAPACK LU + solves, the mass matrix as a full matrix
//            (DGEMV products), no second-order structure   -- the baseline ("today's path")
//   own    : the own small-matrix LU (fortran/radau_lu.f), the diagonal mass as a diagonal
//   own+M1 : the same with the second-order structure M1/M2 (reduced systems)
// and prints each configuration's time as a ratio to the baseline, per kernel, with steps and
// scd (targets of issue 14: own <= 0.6, own+M1 <= 0.35, steps and scd no worse).
//
//   bench_radau_mechanisms [--min-seconds S] [--markdown] [--lu-crossover]
//
// --lu-crossover times the real + complex LU pair with one solve each on DENSE random matrices
// of order 4 .. 160, the own LU (radau_lu) against LAPACK's dgetrf/zgetrf + dgetrs/zgetrs, and
// prints the ratio: where it passes 1 is the size above which the kernels' automatic choice
// hands the systems to LAPACK (64; sparse iteration matrices favour the own LU far longer).
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <fstream>
#include <string>
#include <vector>

#include <complex>
#include <random>

#include "../tests/ode/mechanisms.hpp"
#include "ode/radau_lu.hpp"

extern "C" {
void dgetrf_(const int*, const int*, double*, const int*, int*, int*);
void dgetrs_(const char*, const int*, const int*, const double*, const int*, const int*, double*,
             const int*, int*, std::size_t);
void zgetrf_(const int*, const int*, std::complex<double>*, const int*, int*, int*);
void zgetrs_(const char*, const int*, const int*, const std::complex<double>*, const int*,
             const int*, std::complex<double>*, const int*, int*, std::size_t);
}

using namespace pcsim;
using namespace pcsim::testproblems;

namespace {

double thread_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind("model name", 0) == 0) return line.substr(line.find(':') + 2);
  return "unknown CPU";
}

struct Config {
  const char* name;
  bool second_order;
  RadauOptions::LinearAlgebra la;
  bool diagonal_mass;
};

int lu_crossover(double min_seconds) {
  std::mt19937 gen(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::printf("| n | own LU pair + solves [us] | LAPACK [us] | own/LAPACK |\n|---|---|---|---|\n");
  for (int n : {4, 8, 13, 16, 27, 32, 48, 64, 80, 96, 128, 160}) {
    const int nn = n * n;
    std::vector<double> a(nn), b(n), ai(nn);
    for (double& x : a) x = u(gen);
    for (double& x : ai) x = u(gen);
    for (double& x : b) x = u(gen);
    std::vector<double> w(nn), wi(nn), x(n), xi(n);
    std::vector<std::complex<double>> z(nn), zb(n);
    std::vector<int> ip(n), iwl(n);
    auto own = [&] {
      w = a;
      wi = ai;
      radau_lu::factor(n, w.data(), n, ip.data(), iwl.data());
      x = b;
      radau_lu::solve(n, w.data(), n, ip.data(), x.data());
      w = a;
      radau_lu::factor_complex(n, w.data(), wi.data(), n, ip.data(), iwl.data());
      x = b;
      xi = b;
      radau_lu::solve_complex(n, w.data(), wi.data(), n, ip.data(), x.data(), xi.data());
    };
    auto lap = [&] {
      int info = 0, one = 1;
      w = a;
      dgetrf_(&n, &n, w.data(), &n, ip.data(), &info);
      x = b;
      dgetrs_("N", &n, &one, w.data(), &n, ip.data(), x.data(), &n, &info, 1);
      for (int k = 0; k < nn; ++k) z[k] = std::complex<double>(a[k], ai[k]);
      zgetrf_(&n, &n, z.data(), &n, ip.data(), &info);
      for (int k = 0; k < n; ++k) zb[k] = std::complex<double>(b[k], b[k]);
      zgetrs_("N", &n, &one, z.data(), &n, ip.data(), zb.data(), &n, &info, 1);
    };
    std::vector<double> to, tl;
    double total = 0.0;
    while (to.size() < 20 || total < min_seconds) {
      double c0 = thread_cpu_seconds();
      for (int r = 0; r < 10; ++r) own();
      const double d0 = (thread_cpu_seconds() - c0) / 10;
      c0 = thread_cpu_seconds();
      for (int r = 0; r < 10; ++r) lap();
      const double d1 = (thread_cpu_seconds() - c0) / 10;
      to.push_back(d0);
      tl.push_back(d1);
      total += 10 * (d0 + d1);
    }
    const double mo = median(to), ml = median(tl);
    std::printf("| %d | %.2f | %.2f | %.2f |\n", n, 1e6 * mo, 1e6 * ml, mo / ml);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  double min_seconds = 0.3;
  bool markdown = false;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--min-seconds") && i + 1 < argc) {
      min_seconds = std::atof(argv[++i]);
    } else if (!std::strcmp(argv[i], "--markdown")) {
      markdown = true;
    } else if (!std::strcmp(argv[i], "--lu-crossover")) {
      return lu_crossover(min_seconds);
    } else {
      std::fprintf(stderr, "usage: %s [--min-seconds S] [--markdown] [--lu-crossover]\n", argv[0]);
      return 2;
    }
  }
  const Config configs[] = {
      {"lapack", false, RadauOptions::LinearAlgebra::lapack, false},
      {"own", false, RadauOptions::LinearAlgebra::own_lu, true},
      {"own+M1", true, RadauOptions::LinearAlgebra::own_lu, true},
  };
  std::printf("bench_radau_mechanisms: %s; compiler %s\n", cpu_model().c_str(), __VERSION__);
  std::printf("CPU ms = median thread CPU time per integration (>= 5 runs and >= %.2f s per cell,"
              " configurations alternating); ratio = CPU / CPU(lapack) of the same kernel.\n"
              "scd over the positions (Andrews q1..q7, car axis all 10), Test Set reference.\n\n",
              min_seconds);
  if (markdown) {
    std::printf("| problem | tol | kernel | steps lapack/own/own+M1 | scd lapack/own/own+M1 | "
                "CPU ms lapack | own/lapack | own+M1/lapack |\n|---|---|---|---|---|---|---|---|\n");
  } else {
    std::printf("%-9s %6s %-7s %-17s %-20s %9s %8s %8s\n", "problem", "tol", "kernel",
                "steps l/o/o+M1", "scd l/o/o+M1", "lapack ms", "own/l", "M1/l");
  }
  for (int pi = 0; pi < 2; ++pi) {
    for (int e = 4; e <= 10; ++e) {
      const double tol = std::pow(10.0, -e);
      for (Kernel kernel : {Kernel::fortran, Kernel::cpp}) {
        MechanismProblem probs[3];
        RadauOptions opts[3];
        RadauResult res[3];
        for (int c = 0; c < 3; ++c) {
          probs[c] = pi == 0 ? andrews(configs[c].second_order) : car_axis(configs[c].second_order);
          opts[c].kernel = kernel;
          opts[c].rtol = opts[c].atol = opts[c].h0 = tol;
          opts[c].linear_algebra = configs[c].la;
          opts[c].diagonal_mass = configs[c].diagonal_mass;
          res[c] = radau_integrate(probs[c].problem, 0.0, probs[c].y0, probs[c].t_end, opts[c]);
        }
        std::vector<double> cpu[3];
        double total = 0.0;
        while (cpu[0].size() < 5 || total < 3 * min_seconds) {
          for (int c = 0; c < 3; ++c) {
            const double c0 = thread_cpu_seconds();
            radau_integrate(probs[c].problem, 0.0, probs[c].y0, probs[c].t_end, opts[c]);
            const double dt = thread_cpu_seconds() - c0;
            cpu[c].push_back(dt);
            total += dt;
          }
          if (cpu[0].size() >= 2000) break;
        }
        const double m0 = median(cpu[0]), m1 = median(cpu[1]), m2 = median(cpu[2]);
        char steps[64], digits[64];
        std::snprintf(steps, sizeof steps, "%ld/%ld/%ld", res[0].stats.steps, res[1].stats.steps,
                      res[2].stats.steps);
        auto d = [&](int c) {
          return res[c].status == OdeStatus::success
                     ? scd(res[c].y, probs[c].y_ref, probs[c].scd_components)
                     : -99.0;
        };
        std::snprintf(digits, sizeof digits, "%.2f/%.2f/%.2f", d(0), d(1), d(2));
        const char* pname = pi == 0 ? "andrews" : "car axis";
        if (markdown)
          std::printf("| %s | 1e-%d | %s | %s | %s | %.3f | %.2f | %.2f |\n", pname, e,
                      to_string(kernel), steps, digits, 1e3 * m0, m1 / m0, m2 / m0);
        else
          std::printf("%-9s %6.0e %-7s %-17s %-20s %9.3f %8.2f %8.2f\n", pname, tol,
                      to_string(kernel), steps, digits, 1e3 * m0, m1 / m0, m2 / m0);
        std::fflush(stdout);
      }
    }
  }
  return 0;
}
