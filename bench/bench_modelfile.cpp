// Benchmark of model files: the paper's sieve written as a model file (models/sieve_1995.toml,
// evaluated from its tape) against the compiled C++ closed form (tests/sieve/support/model.hpp through
// make_model, i.e. the engine's AD) and the hand-derived C++ model (tests/sieve/support/analytic_model.cpp),
// in one process: the cost of one evaluation of M, h (kinetic_terms), Q (forces) and the two
// constraint rows, of one engine right-hand side (the default structured compatibility solve),
// and of a whole mech::simulate of 1 s of the sieve (default options, fortran kernels). Ratios are against the AD closed form (the target: model file <= 1.5x) and
// against the hand-derived model. CPU time, best of `repeats`. Not a test: prints numbers.
// Usage: bench_modelfile [repeats]
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <functional>
#include <string>

#include "mech/dynamics.hpp"
#include "mech/simulation.hpp"
#include "modelfile/expression_model.hpp"
#include "modelfile/model_file.hpp"
#include "sieve/support/model.hpp"
#include "bench_timing.hpp"

using namespace pcsim;

namespace {

double seconds_per_call(const std::function<void()>& f, int repeats) {
  return pcsim_bench::seconds_per_call(f, repeats, 200, 0.2);
}

struct Entry {
  std::string label;
  std::shared_ptr<const mech::Model> model;
  double t_model = 0, t_rhs = 0, t_run = 0;
  mech::SimulationResult run;
};

}  // namespace

int main(int argc, char** argv) {
  const int repeats = argc > 1 ? std::max(1, std::atoi(argv[1])) : 3;
  const std::string file = std::string(PCSIM_SOURCE_DIR) + "/models/sieve_1995.toml";
  const auto desc = modelfile::load_model_file(file);
  sieve::SieveSettings set;  // the paper's parameters and the documented defaults
  set.q0 = {0, 0, 0, 0.4, 0.15, 0};
  Eigen::VectorXd q0(6);
  for (int i = 0; i < 6; ++i) q0[i] = set.q0[i];
  std::vector<Entry> entries(3);
  entries[0].label = "C++ closed form (3.4), AD";
  entries[0].model = sieve::make_sieve_model(set, sieve::ModelForm::closed_form);
  entries[1].label = "C++ hand-derived";
  entries[1].model = sieve::make_sieve_model(set, sieve::ModelForm::analytic);
  entries[2].label = "model file sieve_1995.toml";
  entries[2].model = desc->instantiate({}, q0, 0.0);
  const auto& tape = desc->compiled().tape;
  std::printf("models/sieve_1995.toml: tape of %zu instructions (prelude %zu, M and h %zu, Q %zu), "
              "%u slots\n",
              tape.instruction_count(), tape.prelude.size(),
              tape.blocks[desc->compiled().kinetic_block].code.size(),
              tape.blocks[desc->compiled().forces_block].code.size(), tape.n_slots);

  // A state of the running sieve (small desk motion, roller on the deck, moving).
  Eigen::VectorXd q(6), qd(6);
  q << 2e-5, -1e-5, -9e-5, 0.41, 0.15, -0.1;
  qd << 3e-3, -2e-3, 1e-3, 0.004, 0.0, -0.04;
  const double t = 1.234;
  for (Entry& e : entries) {
    const mech::Model& m = *e.model;
    const std::vector<int> active = {m.constraint_index("contact"), m.constraint_index("rolling")};
    Eigen::MatrixXd M(6, 6), g(2, 6);
    Eigen::VectorXd h(6), Q(6), g0(2), gamma(2);
    e.t_model = seconds_per_call([&] {
      m.kinetic_terms(t, q, qd, M, h);
      m.forces(t, q, qd, Q);
      m.constraint_rows(active, t, q, qd, g, g0, gamma);
    }, repeats);
    mech::Dynamics dyn(m, Kernel::cpp);
    const mech::ActiveSet set_active = mech::ActiveSet::of(m, active);
    e.t_rhs = seconds_per_call([&] {
      dyn.evaluate(set_active, t, q, qd);
      dyn.solve(mech::ReactionMethod::compatibility_structured);  // the engine's default
    }, repeats);
    mech::SimulationOptions o;
    o.t_end = 1.0;
    o.rtol = 1e-6;
    o.atol = 1e-8;
    o.kernel = Kernel::fortran;
    o.active_constraints = {"contact", "rolling"};
    e.t_run = 1e300;
    for (int rep = 0; rep < repeats; ++rep) {
      const double c0 = pcsim_bench::process_cpu_seconds();
      e.run = mech::simulate(m, q0, Eigen::VectorXd::Zero(6), o);
      e.t_run = std::min(e.t_run, pcsim_bench::process_cpu_seconds() - c0);
    }
  }
  const Entry& ad = entries[0];
  const Entry& hand = entries[1];
  std::printf("\nThe sieve (n = 6, contact and rolling), CPU time, best of %d\n", repeats);
  std::printf("%-28s %12s %8s %8s | %10s %8s | %10s %8s %7s %8s\n", "model", "M,h,Q,g [ns]", "/AD",
              "/hand", "RHS [us]", "/AD", "1 s run [s]", "/AD", "steps", "f-evals");
  for (const Entry& e : entries) {
    std::printf("%-28s %12.0f %8.3f %8.2f | %10.3f %8.3f | %10.4f %8.3f %7ld %8ld %s\n",
                e.label.c_str(), e.t_model * 1e9, e.t_model / ad.t_model, e.t_model / hand.t_model,
                e.t_rhs * 1e6, e.t_rhs / ad.t_rhs, e.t_run, e.t_run / ad.t_run, e.run.stats.steps,
                e.run.stats.f_evals,
                e.run.status == mech::SimulationStatus::success ? "" : e.run.message.c_str());
  }
  const Entry& mf = entries[2];
  const double dq = (mf.run.q_end - ad.run.q_end).cwiseAbs().maxCoeff();
  std::printf("\nmodel file vs AD after 1 s: max |q difference| = %.2e (the same equations, "
              "rounded differently)\n", dq);
  std::printf("target (issue 11): model file / AD <= 1.5 for M, h, Q: %s (%.3f)\n",
              mf.t_model / ad.t_model <= 1.5 ? "met" : "NOT met", mf.t_model / ad.t_model);
  return 0;
}
