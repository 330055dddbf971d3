// Benchmark of the Radau IIA integrator: van der Pol and Robertson at rtol = 1e-4, 1e-7, 1e-10,
// both kernels side by side in one process; counters, median wall times, the C++/Fortran time
// ratio, and significant correct digits against the reference solutions of
// tests/ode/problems.hpp. Not a test: run it by hand (see docs/radau-validation.md).
//
//   bench_radau [--markdown] [--min-seconds S] [--reference] [--tolerance-table]
//
// --tolerance-table prints, for rtol = atol = 1e-2 .. 1e-12, the error reached at t_end on
// problems with an exact solution (the index-1 DAE of problems.hpp, and the pendulum DAE
// against its elliptic-function solution): the table of docs/radau.md that shows what RADAU5's
// tolerance transformation rtol' = 0.1 rtol^(2/3) delivers.
//
// --reference prints the computed reference of van der Pol y(0) = (2, -0.66) (rtol = atol =
// 1e-13, both kernels) that problems.hpp stores, and the published-reference check of that
// setting on y(0) = (2, 0).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <ctime>
#include <string>
#include <vector>

#include "../tests/ode/problems.hpp"

using namespace pcsim;
using namespace pcsim::testproblems;

namespace {

struct Setting {
  ReferenceProblem rp;
  double atol_factor;  // atol = atol_factor * rtol
  std::string atol_text;
};

double thread_cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

/// Wall time and CPU time of this thread for one integration, in seconds. On a shared machine
/// the wall time includes waiting for a core; the thread CPU time does not, so the ratio is
/// taken from it.
struct Timing {
  double wall = 0.0;
  double cpu = 0.0;
};
Timing time_one(const ReferenceProblem& rp, const RadauOptions& o) {
  const double c0 = thread_cpu_seconds();
  const auto t0 = std::chrono::steady_clock::now();
  const RadauResult r = radau_integrate(rp.problem, rp.t0, rp.y0, rp.t_end, o);
  const auto t1 = std::chrono::steady_clock::now();
  const double c1 = thread_cpu_seconds();
  if (r.status != OdeStatus::success) return {-1.0, -1.0};
  return {std::chrono::duration<double>(t1 - t0).count(), c1 - c0};
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

std::string pair_text(long a, long b) {
  return a == b ? std::to_string(a) : std::to_string(a) + "/" + std::to_string(b);
}

int reference_mode() {
  RadauOptions o;
  o.rtol = o.atol = 1e-13;
  o.max_steps = 1000000;
  const ReferenceProblem issue = van_der_pol_issue();
  const ReferenceProblem pub = van_der_pol_published();
  std::printf("van der Pol eps=1e-6, t=2, scaled form, rtol=atol=1e-13, analytic Jacobian\n");
  Eigen::VectorXd y[2];
  int k = 0;
  for (Kernel kernel : {Kernel::fortran, Kernel::cpp}) {
    o.kernel = kernel;
    const RadauResult r = radau_integrate(issue.problem, issue.t0, issue.y0, issue.t_end, o);
    const RadauResult q = radau_integrate(pub.problem, pub.t0, pub.y0, pub.t_end, o);
    std::printf("%-7s y0=(2,-0.66): status=%s y1=%.16e y2=%.16e accepted=%ld\n",
                to_string(kernel), to_string(r.status), r.y(0), r.y(1), r.stats.accepted);
    std::printf("%-7s y0=(2,0):     status=%s y1=%.16e y2=%.16e rel.err vs published=%.2e\n",
                to_string(kernel), to_string(q.status), q.y(0), q.y(1),
                max_relative_error(q.y, pub.y_ref));
    y[k++] = r.y;
  }
  std::printf("kernel disagreement (2,-0.66): %.2e relative\n", kernel_disagreement(y[0], y[1]));
  std::printf("difference to published (2,0) reference: %.2e relative\n",
              max_relative_error(y[0], pub.y_ref));
  return 0;
}

int tolerance_table() {
  const ReferenceProblem dae = index1_dae();
  ReferenceProblem pend = pendulum_dae();
  const PendulumParameters P;
  const Eigen::Matrix<double, 5, 1> pex = pendulum_cartesian(P, pendulum_exact(P, pend.t_end));
  pend.y_ref = pex;
  std::printf("| rtol = atol | rtol' (kernel) | index-1 DAE: max rel. error at t = 3 | steps | "
              "pendulum DAE: max rel. error of (x, y, vx, vy) at t = 5 | steps |\n");
  std::printf("|---|---|---|---|---|---|\n");
  for (int e = 2; e <= 12; ++e) {
    const double tol = std::pow(10.0, -e);
    RadauOptions o;
    o.rtol = o.atol = tol;
    const RadauResult a = radau_integrate(dae.problem, dae.t0, dae.y0, dae.t_end, o);
    const RadauResult b = radau_integrate(pend.problem, pend.t0, pend.y0, pend.t_end, o);
    const double eb = max_relative_error(b.y.head(4), pend.y_ref.head(4));
    std::printf("| 1e-%d | %.1e | %.1e | %ld | %.1e | %ld |\n", e, transformed_rtol(tol),
                max_relative_error(a.y, dae.y_ref), a.stats.steps, eb, b.stats.steps);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  bool markdown = false;
  double min_seconds = 0.5;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--markdown")) {
      markdown = true;
    } else if (!std::strcmp(argv[i], "--min-seconds") && i + 1 < argc) {
      min_seconds = std::atof(argv[++i]);
    } else if (!std::strcmp(argv[i], "--reference")) {
      return reference_mode();
    } else if (!std::strcmp(argv[i], "--tolerance-table")) {
      return tolerance_table();
    } else {
      std::fprintf(stderr, "usage: %s [--markdown] [--min-seconds S] [--reference] [--tolerance-table]\n", argv[0]);
      return 2;
    }
  }

  const std::vector<Setting> settings = {
      {van_der_pol_issue(), 1.0, "rtol"},
      {van_der_pol_published(), 1.0, "rtol"},
      {robertson(), 1e-14, "1e-14*rtol"},
  };
  std::printf("bench_radau: %s; compiler %s; each time is the median of >= 5 runs per kernel\n",
              cpu_model().c_str(), __VERSION__);
  std::printf("and >= %.2f s wall per kernel per row, the two kernels alternating; CPU = this\n"
              "thread's CPU time (immune to other processes), wall in parentheses.\n",
              min_seconds);
  std::printf("Counters a/b: Fortran/C++ when they differ. digits = -log10(max rel. error)\n\n");
  if (markdown) {
    std::printf("| problem | rtol | atol | steps | accepted | rejected | f-evals | LU | "
                "Fortran CPU (wall) [ms] | C++ CPU (wall) [ms] | C++/Fortran (CPU) | digits |\n");
    std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  } else {
    std::printf("%-20s %7s %10s %6s %6s %5s %7s %6s %16s %16s %7s %7s\n", "problem", "rtol",
                "atol", "steps", "acc", "rej", "f-evals", "LU", "F cpu(wall)[ms]",
                "C++ cpu(wall)[ms]", "C++/F", "digits");
  }

  for (const Setting& s : settings) {
    for (double rtol : {1e-4, 1e-7, 1e-10}) {
      RadauOptions of, oc;
      of.kernel = Kernel::fortran;
      oc.kernel = Kernel::cpp;
      of.rtol = oc.rtol = rtol;
      of.atol = oc.atol = s.atol_factor * rtol;
      const ReferenceProblem& rp = s.rp;
      const RadauResult rf = radau_integrate(rp.problem, rp.t0, rp.y0, rp.t_end, of);
      const RadauResult rc = radau_integrate(rp.problem, rp.t0, rp.y0, rp.t_end, oc);
      if (rf.status != OdeStatus::success || rc.status != OdeStatus::success) {
        std::printf("%-20s rtol=%g: FAILED fortran=%s (%s) cpp=%s (%s)\n", rp.name.c_str(), rtol,
                    to_string(rf.status), rf.message.c_str(), to_string(rc.status),
                    rc.message.c_str());
        continue;
      }
      std::vector<double> wf, wc, cf, cc;
      double total_f = 0.0, total_c = 0.0;
      while (wf.size() < 5 || total_f < min_seconds || total_c < min_seconds) {
        const Timing a = time_one(rp, of);
        const Timing b = time_one(rp, oc);
        wf.push_back(a.wall);
        cf.push_back(a.cpu);
        wc.push_back(b.wall);
        cc.push_back(b.cpu);
        total_f += a.wall;
        total_c += b.wall;
        if (wf.size() >= 5000) break;
      }
      const double mf = 1e3 * median(cf), mc = 1e3 * median(cc);
      const double mwf = 1e3 * median(wf), mwc = 1e3 * median(wc);
      const double df = correct_digits(rf.y, rp.y_ref), dc = correct_digits(rc.y, rp.y_ref);
      char digits[32];
      if (std::abs(df - dc) < 0.005)
        std::snprintf(digits, sizeof digits, "%.2f", df);
      else
        std::snprintf(digits, sizeof digits, "%.2f/%.2f", df, dc);
      char atol_text[32];
      std::snprintf(atol_text, sizeof atol_text, "%.0e", of.atol);
      const RadauStats& a = rf.stats;
      const RadauStats& b = rc.stats;
      if (markdown) {
        std::printf("| %s | %.0e | %s | %s | %s | %s | %s | %s | %.3f (%.3f) | %.3f (%.3f) | %.2f | %s |\n",
                    rp.name.c_str(), rtol, atol_text, pair_text(a.steps, b.steps).c_str(),
                    pair_text(a.accepted, b.accepted).c_str(),
                    pair_text(a.rejected, b.rejected).c_str(),
                    pair_text(a.f_evals, b.f_evals).c_str(),
                    pair_text(a.lu_decompositions, b.lu_decompositions).c_str(), mf, mwf, mc,
                    mwc, mc / mf, digits);
      } else {
        std::printf("%-20s %7.0e %10s %6s %6s %5s %7s %6s %7.3f(%7.3f) %7.3f(%7.3f) %7.2f %7s\n",
                    rp.name.c_str(), rtol, atol_text, pair_text(a.steps, b.steps).c_str(),
                    pair_text(a.accepted, b.accepted).c_str(),
                    pair_text(a.rejected, b.rejected).c_str(),
                    pair_text(a.f_evals, b.f_evals).c_str(),
                    pair_text(a.lu_decompositions, b.lu_decompositions).c_str(), mf, mwf, mc,
                    mwc, mc / mf, digits);
      }
      std::fflush(stdout);
    }
  }
  return 0;
}
