// Benchmark: the sieve_1995 case (10 s of motion) for each kernel x form on the default path
// (the AD-derived closed form (3.4)), plus the AD-derived geometric form and the hand-derived
// analytic fast path as extra rows, side by side in one process, printed as ratios to the
// first (fortran, ode, closed_form); plus what bounds it: steps,
// f-evaluations, the cost of one f-evaluation (M, h, Q, constraint rows and the reaction solve
// at one state), and the share of the summary's dense-output sampling.
//
// Usage: bench_sieve [CASE.toml] [repeats]   (default cases/sieve_1995.toml, 3)
// Times are thread CPU times (the machine is shared; wall time is inflated by preemption),
// the minimum over the repeats.
#include <time.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "mech/simulation.hpp"
#include "sim/case.hpp"
#include "sieve/source.hpp"
#include "sieve/model.hpp"
#include "sim/run.hpp"
#include "sieve/settings.hpp"

using namespace pcsim;
using namespace pcsim::sieve;
using namespace pcsim::sim;

namespace {

double cpu_now() {
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

template <class F> double min_time(int repeats, F&& f) {
  double best = 1e300;
  for (int r = 0; r < repeats; ++r) {
    const double t0 = cpu_now();
    f();
    best = std::min(best, cpu_now() - t0);
  }
  return best;
}

}  // namespace

int main(int argc, char** argv) {
  const std::string file =
      argc > 1 ? argv[1] : std::string(PCSIM_SOURCE_DIR) + "/cases/sieve_1995.toml";
  const int repeats = argc > 2 ? std::max(1, std::atoi(argv[2])) : 3;
  pcsim::sieve::register_sieve();
  const Case base = load_case(file);
  std::printf("bench_sieve: %s, t_end = %g s, best of %d (thread CPU time)\n\n", file.c_str(),
              settings_from_case(base).solver.t_end, repeats);

  // Cost of one f-evaluation's mechanics: M, h, Q, g, γ and the compatibility solve for R.
  {
    const SieveSettings set = settings_from_case(base);
    std::printf("cost of one reaction evaluation (M, h, Q, g, R; ~ one ODE-form f):\n");
    for (ModelForm mf : {ModelForm::closed_form, ModelForm::geometric, ModelForm::analytic}) {
      const auto model = make_sieve_model(set, mf);
      Eigen::VectorXd q(6), qd(6);
      for (int i = 0; i < 6; ++i) { q(i) = set.q0[i]; qd(i) = 0.01 * (i + 1); }
      const auto active = active_constraints(set.constraints);
      for (Kernel k : {Kernel::fortran, Kernel::cpp}) {
        const int n = 20000;
        double sink = 0;
        const double t = min_time(repeats, [&] {
          for (int i = 0; i < n; ++i)
            sink += mech::reactions(*model, active, 1e-4 * i, q, qd,
                                    mech::ReactionMethod::compatibility, k).R(4);
        });
        Eigen::MatrixXd M(6, 6);
        Eigen::VectorXd h(6), Q(6);
        const double tk = min_time(repeats, [&] {
          for (int i = 0; i < n; ++i) {
            model->kinetic_terms(1e-4 * i, q, qd, M, h);
            model->forces(1e-4 * i, q, qd, Q);
            sink += h(0) + Q(0);
          }
        });
        std::vector<int> idx;
        for (const std::string& name : active)
          for (std::size_t i = 0; i < model->constraints().size(); ++i)
            if (model->constraints()[i].name == name) idx.push_back(static_cast<int>(i));
        const auto ns = static_cast<Eigen::Index>(idx.size());
        Eigen::MatrixXd g(ns, 6);
        Eigen::VectorXd g0(ns), gam(ns);
        const double tm = min_time(repeats, [&] {
          for (int i = 0; i < n; ++i) {
            model->kinetic_terms(1e-4 * i, q, qd, M, h);
            sink += h(0);
          }
        });
        const double tg = min_time(repeats, [&] {
          for (int i = 0; i < n; ++i) {
            model->constraint_rows(idx, 1e-4 * i, q, qd, g, g0, gam);
            sink += gam(0);
          }
        });
        std::printf("  %-11s model, %-7s kernel: %7.2f us per evaluation; model: M, h %6.2f us, "
                    "Q %5.2f us, g, gamma %5.2f us; engine %5.2f us\n",
                    to_string(mf), to_string(k), 1e6 * t / n, 1e6 * tm / n,
                    1e6 * (tk - tm) / n, 1e6 * tg / n, 1e6 * (t - tk - tg) / n);
        if (!std::isfinite(sink)) std::printf("  (non-finite results)\n");
      }
    }
  }

  struct Row {
    std::string label;
    double run = 0, sim = 0;
    long steps = 0, f = 0, lu = 0;
  };
  struct Config {
    Kernel k;
    Form fm;
    ModelForm mf;
  };
  std::vector<Config> configs;
  const ModelForm def = ModelForm::closed_form;  // the default path: AD closed form
  for (Kernel k : {Kernel::fortran, Kernel::cpp})
    for (Form fm : {Form::ode, Form::dae}) configs.push_back({k, fm, def});
  configs.push_back({Kernel::fortran, Form::ode, ModelForm::geometric});
  configs.push_back({Kernel::fortran, Form::ode, ModelForm::analytic});
  configs.push_back({Kernel::cpp, Form::ode, ModelForm::analytic});
  std::vector<Row> rows;
  for (const Config& cf : configs) {
    {
      const Kernel k = cf.k;
      const Form fm = cf.fm;
      Case c = base;
      set_value(c, {"solver.kernel", to_string(k)});
      set_value(c, {"solver.form", to_string(fm)});
      Row r;
      r.label = std::string(to_string(k)) + " / " + to_string(fm) + " / " + to_string(cf.mf);
      RunOptions ro;
      ro.variant = to_string(cf.mf);
      nlohmann::json s;
      r.run = min_time(repeats, [&] { s = run_case(c, ro); });
      r.steps = s["stats"]["steps"];
      r.f = s["stats"]["f_evals"];
      r.lu = s["stats"]["lu_decompositions"];
      // The bare integration, without the summary's dense-output sampling.
      const SieveSettings set = settings_from_case(c);
      const auto model = make_sieve_model(set, cf.mf);
      mech::SimulationOptions so;
      so.kernel = k;
      so.form = fm;
      so.t_end = set.solver.t_end;
      so.rtol = set.solver.rtol;
      so.atol = set.solver.atol;
      so.active_constraints = active_constraints(set.constraints);
      Eigen::VectorXd q0(6), qd0(6);
      for (int i = 0; i < 6; ++i) { q0(i) = set.q0[i]; qd0(i) = set.qd0[i]; }
      r.sim = min_time(repeats, [&] { mech::simulate(*model, q0, qd0, so); });
      rows.push_back(r);
    }
  }
  std::printf("\n%-30s %9s %8s %9s %7s %10s %9s %10s %8s\n", "kernel / form / model", "run [s]", "ratio",
              "steps", "LU", "f-evals", "us per f", "simulate", "summary");
  for (const Row& r : rows)
    std::printf("%-30s %9.3f %8.2f %9ld %7ld %10ld %9.2f %9.3fs %7.0f%%\n", r.label.c_str(), r.run,
                r.run / rows[0].run, r.steps, r.lu, r.f, 1e6 * r.sim / r.f, r.sim,
                100 * (r.run - r.sim) / r.run);
  std::printf("\nratio: run time / (fortran / ode / closed_form, the default path). 'us per f': simulate time / f-evaluations "
              "(all integrator work included). 'summary': share of run_case spent outside the "
              "bare integration (dense-output sampling of the verdicts and window extremes).\n");
  std::printf("target: < 0.2 s per case on one core\n");
  return 0;
}
