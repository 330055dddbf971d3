// Benchmark of loading spatial body models (expansion of bodies and joints to the energy form,
// symbolic derivation, tape): the Whipple bicycle as bodies (models/whipple_bodies.toml; the
// issue's bound: under 2 s), the spatial slider-crank, and a chain of N spatial links (Euler
// parameters, 7 coordinates each) hung from ground by spherical joints, N = 2, 4, 8, 16, with
// the exponent p of load time ~ N^p fitted on log-log; and the cost of one evaluation of the
// Whipple model's M, h, Q and rows. CPU seconds (process). Not a test: prints numbers.
// Usage: bench_modelfile_bodies_spatial [PCSIM_SOURCE_DIR]
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "bench_timing.hpp"
#include "mech/model.hpp"
#include "modelfile/model_file.hpp"

using namespace pcsim;

namespace {

double exponent(const std::vector<double>& x, const std::vector<double>& y) {
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

std::string chain_text(int N) {
  std::ostringstream s;
  s << "[model]\nname = \"spatial_chain_" << N << "\"\n[model.parameters]\nL = 0.3\nm = 1.0\n";
  for (int i = 0; i < N; ++i)
    s << "[model.body.link" << i << "]\nkind = \"spatial\"\nmass = \"m\"\n"
      << "inertia = [0.001, \"m*L^2/12\", \"m*L^2/12\"]\n"
      << "markers.top = [\"-L/2\", 0, 0]\nmarkers.bottom = [\"L/2\", 0, 0]\n";
  for (int i = 0; i < N; ++i)
    s << "[model.joint.j" << i << "]\ntype = \"spherical\"\nbody1 = \""
      << (i == 0 ? "ground" : "link" + std::to_string(i - 1)) << "\"\nmarker1 = \""
      << (i == 0 ? "origin" : "bottom") << "\"\nbody2 = \"link" << i << "\"\nmarker2 = \"top\"\n";
  s << "[model.force.gravity]\ntype = \"gravity\"\ng = [0, 0, -9.81]\n";
  return s.str();
}

double load_seconds(const std::function<void()>& f) {
  const double t0 = pcsim_bench::process_cpu_seconds();
  f();
  return pcsim_bench::process_cpu_seconds() - t0;
}

}  // namespace

int main(int argc, char** argv) {
  const std::filesystem::path root = argc > 1 ? argv[1] : PCSIM_SOURCE_DIR;
  std::shared_ptr<const modelfile::ModelDescription> whipple;
  const double tw = load_seconds([&] { whipple = modelfile::load_model_file(root / "models/whipple_bodies.toml"); });
  std::printf("Whipple bicycle as bodies (models/whipple_bodies.toml): %d coordinates, %zu constraints, "
              "loaded in %.3f s CPU (bound 2 s: %s)\n",
              whipple->n(), whipple->constraints().size(), tw, tw < 2.0 ? "met" : "NOT met");
  const double ts = load_seconds([&] { modelfile::load_model_file(root / "models/slider_crank_spatial.toml"); });
  std::printf("spatial slider-crank (models/slider_crank_spatial.toml): loaded in %.3f s CPU\n", ts);

  const auto model = whipple->instantiate({});
  const int n = model->n();
  Eigen::VectorXd q = Eigen::VectorXd::Zero(n), qd = Eigen::VectorXd::Constant(n, 0.1);
  q[3] = 1.0;
  Eigen::MatrixXd M(n, n);
  Eigen::VectorXd h(n), Q(n);
  std::vector<int> rows;
  for (int i = 0; i < static_cast<int>(model->constraints().size()); ++i) rows.push_back(i);
  const int s = static_cast<int>(rows.size());
  Eigen::MatrixXd g(s, n);
  Eigen::VectorXd g0(s), gamma(s);
  const double per_eval = pcsim_bench::seconds_per_call([&] {
    model->kinetic_terms(0.0, q, qd, M, h);
    model->forces(0.0, q, qd, Q);
    model->constraint_rows(rows, 0.0, q, qd, g, g0, gamma);
  }, 3);
  std::printf("Whipple bicycle: one evaluation of M, h, Q, g, g0, gamma: %.2f us\n", per_eval * 1e6);

  std::vector<double> Ns, ts_chain;
  std::printf("chain of N spatial links on spherical joints:\n  N  coordinates  rows  load (s CPU)\n");
  for (int N : {2, 4, 8, 16}) {
    std::shared_ptr<const modelfile::ModelDescription> d;
    const std::string text = chain_text(N);
    const double t = load_seconds([&] { d = modelfile::load_model_text(text, "chain.toml"); });
    std::printf("  %2d  %11d  %4zu  %.3f\n", N, d->n(), d->constraints().size(), t);
    Ns.push_back(N);
    ts_chain.push_back(t);
  }
  std::printf("load time ~ N^%.2f (least squares on log-log, N = 2..16)\n", exponent(Ns, ts_chain));
  return 0;
}
