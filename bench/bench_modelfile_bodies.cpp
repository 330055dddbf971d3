// Bodies and joints (issue 22): load time (parse, expand, derive, compile) of chains of N planar
// bodies, absolute coordinates (N bodies x 3, 2N revolute rows) and relative ones (N revolute
// tree joints, N coordinates), with the growth exponent; and the sieve written as bodies
// (models/sieve_1995_bodies.toml) against models/sieve_1995.toml on the main job's integration
// (10 s, contact + rolling, rtol 1e-6, atol 1e-8): the ratio of the run times.
//   build/bench_modelfile_bodies [repeats]
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "bench_timing.hpp"
#include "mech/simulation.hpp"
#include "modelfile/expression_model.hpp"
#include "modelfile/model_file.hpp"

namespace {

std::string chain(int n, bool relative) {
  std::string t = "[model]\nname = \"chain\"\n[model.parameters]\nm = 1.0\nL = 0.5\ng = 9.81\n";
  for (int k = 1; k <= n; ++k) {
    const std::string b = "b" + std::to_string(k);
    t += "[model.body." + b + "]\nmass = \"m\"\ninertia = \"m*L^2/12\"\n"
         "markers = { top = [0, \"L/2\"], bottom = [0, \"-L/2\"] }\n";
    t += "[model.joint.j" + std::to_string(k) + "]\ntype = \"revolute\"\n";
    if (k > 1) t += "body1 = \"b" + std::to_string(k - 1) + "\"\nmarker1 = \"bottom\"\n";
    t += "body2 = \"" + b + "\"\nmarker2 = \"top\"\n";
    if (relative) t += "coordinates = [\"a" + std::to_string(k) + "\"]\n";
  }
  t += "[model.force.gravity]\ntype = \"gravity\"\ng = [0, \"-g\"]\n";
  return t;
}

double fit_exponent(const std::vector<double>& x, const std::vector<double>& y) {
  // least squares slope of log y on log x
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double k = static_cast<double>(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double lx = std::log(x[i]), ly = std::log(y[i]);
    sx += lx;
    sy += ly;
    sxx += lx * lx;
    sxy += lx * ly;
  }
  return (k * sxy - sx * sy) / (k * sxx - sx * sx);
}

}  // namespace

int main(int argc, char** argv) {
  using namespace pcsim;
  const int repeats = argc > 1 ? std::atoi(argv[1]) : 3;
  for (bool relative : {false, true}) {
    std::printf("%s coordinates: chain of N planar bodies on revolute joints\n",
                relative ? "relative (tree joints)" : "absolute (x, y, th per body)");
    std::printf("| N | n | rows | tape instructions | load [s] |\n|---|---|---|---|---|\n");
    std::vector<double> ns, ts;
    for (int n : {5, 10, 20, 40, 81}) {
      const std::string text = chain(n, relative);
      double best = 1e300;
      std::shared_ptr<const modelfile::ModelDescription> d;
      try {
        for (int r = 0; r < repeats; ++r) {
          const double t0 = pcsim_bench::process_cpu_seconds();
          d = modelfile::load_model_text(text, "chain.toml");
          best = std::min(best, pcsim_bench::process_cpu_seconds() - t0);
        }
      } catch (const std::exception& e) {
        std::printf("| %d | refused: %.160s... |\n", n, e.what());
        std::fflush(stdout);
        continue;
      }
      std::printf("| %d | %d | %zu | %zu | %.3f |\n", n, d->n(), d->constraints().size(),
                  d->compiled().tape.instruction_count(), best);
      std::fflush(stdout);
      ns.push_back(n);
      ts.push_back(best);
    }
    std::printf("load time grows as N^%.2f\n\n", fit_exponent(ns, ts));
  }

  // The sieve's main job: bodies vs the energy-form file.
  const std::string dir = PCSIM_SOURCE_DIR "/models/";
  const auto a = modelfile::load_model_file(dir + "sieve_1995_bodies.toml");
  const auto b = modelfile::load_model_file(dir + "sieve_1995.toml");
  Eigen::VectorXd q0(6), qd0 = Eigen::VectorXd::Zero(6);
  q0 << 0.0, 0.0, 0.0, 0.4, 0.15, 0.0;
  const auto ma = a->instantiate({}, q0), mb = b->instantiate({}, q0);
  mech::SimulationOptions o;
  o.t_end = 10.0;
  o.rtol = 1e-6;
  o.atol = 1e-8;
  o.active_constraints = {"contact", "rolling"};
  // The main job's method (cases/sieve_1995.toml: solver.method = "auto", the explicit 8(5,3)
  // pair): there the right-hand side, tape included, is most of the cost; under Radau its
  // linear algebra is (the tape then weighs less than 1 % of either run).
  o.method = OdeMethod::automatic;
  // Alternating runs (file, bodies, file, ...), the best of each: a machine whose load drifts
  // during the benchmark then weighs on both alike.
  long evals[2] = {0, 0}, steps[2] = {0, 0};
  double best[2] = {1e300, 1e300};
  for (int r = 0; r < std::max(repeats, 9); ++r) {
    for (int k = 0; k < 2; ++k) {
      const double t0 = pcsim_bench::process_cpu_seconds();
      const auto res = mech::simulate(k == 0 ? *mb : *ma, q0, qd0, o);
      best[k] = std::min(best[k], pcsim_bench::process_cpu_seconds() - t0);
      if (res.status != mech::SimulationStatus::success) std::printf("run failed: %s\n", res.message.c_str());
      evals[k] = res.stats.f_evals;
      steps[k] = res.stats.steps;
    }
  }
  const double tb = best[0], ta = best[1];
  std::printf("sieve main job (10 s, contact + rolling, auto method, rtol 1e-6): sieve_1995.toml %.4f s, "
              "sieve_1995_bodies.toml %.4f s, ratio bodies/file %.3f\n", tb, ta, ta / tb);
  std::printf("steps: file %ld, bodies %ld; right-hand sides: file %ld, bodies %ld; per right-hand "
              "side: ratio bodies/file %.3f\n", steps[0], steps[1], evals[0], evals[1],
              (ta / static_cast<double>(evals[1])) / (tb / static_cast<double>(evals[0])));
  std::printf("tape instructions: file %zu, bodies %zu\n", b->compiled().tape.instruction_count(),
              a->compiled().tape.instruction_count());
  auto blocks = [](const modelfile::CompiledModel& c) {
    std::string s = "prelude " + std::to_string(c.tape.prelude.size()) + ", kinetic " +
                    std::to_string(c.tape.blocks[c.kinetic_block].code.size()) + ", forces " +
                    std::to_string(c.tape.blocks[c.forces_block].code.size()) + ", rows";
    for (const auto& cb : c.constraint_blocks)
      s += " " + std::to_string(c.tape.blocks[cb.rows].code.size());
    return s;
  };
  std::printf("  file:   %s\n  bodies: %s\n", blocks(b->compiled()).c_str(), blocks(a->compiled()).c_str());
  return 0;
}
