// Benchmark of the mechanics engine: the cost of one right-hand-side evaluation (ODE form: AD
// of T, V, F, constraints + the compatibility solve) for each validation model and a sieve-like
// model (n = 6, s = 2, the energies of shared/design/sieve-model.md), the cost of the three
// reaction formulations relative to compatibility (same process, same states), and full 10 s
// runs of the sieve-like model. Not a test: prints numbers. Usage: bench_mech [repeats]
#include <chrono>
#include <ctime>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <random>

#include "mech/dynamics.hpp"
#include "mech/models/registry.hpp"
#include "mech/simulation.hpp"
#include "bench_timing.hpp"

using namespace pcsim;
using namespace pcsim::mech;

namespace {

// The sieve's geometric model with the documented default parameters (sieve-model.md 1-2, 5).
struct SieveLike {
  static constexpr int kCoordinates = 6;
  double m0 = 1.27, m1 = 400, m2 = 0.5, J0 = 0.127e-3, J1 = 200, J2 = 0.25e-4, r = 0.1, e = 0.01;
  double cx = 5e4, cy = 5e4, ct = 5e4, bx = 1e5, by = 1e5, bt = 1e4, w = 280, grav = 9.81;
  double x0 = 0.10, y0 = 0.20, yc = 0.0, b = -0.20, yb = 0.0, a = 0.50, xc = 0.0, xb = 0.0;
  double u0 = 0.15, s0 = 0.40;
  std::string name() const { return "sieve_like"; }
  std::vector<std::string> coordinates() const { return {"x", "y", "theta", "s", "u", "phi"}; }
  std::vector<ConstraintInfo> constraints() const {
    return {{"contact", ConstraintKind::holonomic, true},
            {"rolling", ConstraintKind::velocity, true}};
  }
  template <class S> S kinetic_energy(const VecX<S>& q, const VecX<S>& qd, const S& t) const {
    using std::cos;
    using std::sin;
    const S c = cos(q[2]), sn = sin(q[2]), wt = w * t + q[2];
    // velocities of the exciter mass m0 and the roller centre (desk point (s, u))
    const S X0d = qd[0] + (y0 * c - x0 * sn) * qd[2] + e * sin(wt) * (w + qd[2]);
    const S Y0d = qd[1] - (y0 * sn + x0 * c) * qd[2] + e * cos(wt) * (w + qd[2]);
    const S X2d = qd[0] + qd[3] * sn + qd[4] * c + (q[3] * c - q[4] * sn) * qd[2];
    const S Y2d = qd[1] + qd[3] * c - qd[4] * sn - (q[3] * sn + q[4] * c) * qd[2];
    return 0.5 * m0 * (X0d * X0d + Y0d * Y0d) + 0.5 * m1 * (qd[0] * qd[0] + qd[1] * qd[1]) +
           0.5 * m2 * (X2d * X2d + Y2d * Y2d) + 0.5 * J1 * qd[2] * qd[2] +
           0.5 * J0 * (w + qd[2]) * (w + qd[2]) + 0.5 * J2 * (qd[2] + qd[5]) * (qd[2] + qd[5]);
  }
  template <class S> S potential_energy(const VecX<S>& q, const S& t) const {
    using std::cos;
    using std::sin;
    const S c = cos(q[2]), sn = sin(q[2]);
    const S X0 = q[0] + y0 * sn + x0 * c - e * cos(w * t + q[2]);
    const S X2 = q[0] + q[3] * sn + q[4] * c;
    const S dx = q[0] + yc * sn + b * c - b, dy = q[1] - xc * sn + a * c - a;
    const double sigma0 = (m0 + m1 + m2) * grav / cx;
    return grav * (m0 * X0 + m1 * q[0] + m2 * X2) + 0.5 * cx * (dx - sigma0) * (dx - sigma0) +
           0.5 * cy * dy * dy + 0.5 * ct * q[2] * q[2];
  }
  template <class S> S dissipation(const VecX<S>& q, const VecX<S>& qd, const S& t) const {
    using std::cos;
    using std::sin;
    const S vbx = qd[0] + (yb * cos(q[2]) - b * sin(q[2])) * qd[2];
    const S vby = qd[1] - (xb * cos(q[2]) + a * sin(q[2])) * qd[2];
    return 0.5 * bx * vbx * vbx + 0.5 * by * vby * vby + 0.5 * bt * qd[2] * qd[2];
  }
  template <class S> S holonomic(int i, const VecX<S>& q, const S& t) const { return q[4] - u0; }
  template <class S>
  void velocity_form(int i, const VecX<S>& q, const S& t, VecX<S>& g_row, S& g0) const {
    for (int k = 0; k < 6; ++k) g_row[k] = S(0.0);
    g_row[3] = S(1.0);
    g_row[5] = S(-r);
    g0 = S(0.0);
  }
};

double seconds_per_call(const std::function<void()>& f, int repeats) {
  return pcsim_bench::seconds_per_call(f, repeats, 100, 0.1);
}

struct Entry {
  std::string label;
  std::shared_ptr<const Model> model;
  std::vector<std::string> active;
};

}  // namespace

int main(int argc, char** argv) {
  const int repeats = argc > 1 ? std::max(1, std::atoi(argv[1])) : 3;
  std::vector<Entry> entries = {
      {"pendulum (n=2, s=1)", create_model("pendulum"), {"length"}},
      {"rolling_disk (n=3, s=2)", create_model("rolling_disk"), {"contact", "rolling"}},
      {"slider_crank (n=5, s=4, g(q))", create_model("slider_crank"), {"A_x", "A_y", "B_x", "B_y"}},
      {"sieve_like (n=6, s=2)", make_model(SieveLike{}), {"contact", "rolling"}},
  };
  std::printf("One right-hand-side evaluation (ODE form), CPU microseconds, best of %d; kernel cpp\n",
              repeats);
  std::printf("%-32s %9s %9s %9s %9s | %8s %8s\n", "model", "AD T", "AD Q", "AD g", "RHS",
              "KKT/cmp", "UK/cmp");
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-0.5, 0.5);
  for (const Entry& en : entries) {
    const Model& m = *en.model;
    std::vector<int> active;
    for (const auto& name : en.active) active.push_back(m.constraint_index(name));
    Eigen::VectorXd q(m.n()), qd(m.n());
    for (int i = 0; i < m.n(); ++i) {
      q[i] = u(rng);
      qd[i] = u(rng);
    }
    if (en.label.rfind("sieve", 0) == 0) q << 0.0, 0.0, 0.0, 0.4, 0.15, 0.0;
    const double t = 0.3;
    Dynamics dyn(m, Kernel::cpp);
    const ActiveSet set = ActiveSet::of(m, active);
    Eigen::MatrixXd M(m.n(), m.n());
    Eigen::VectorXd h(m.n()), Q(m.n()), g0(active.size()), gam(active.size());
    Eigen::MatrixXd g(active.size(), m.n());
    const double t_T = seconds_per_call([&] { m.kinetic_terms(t, q, qd, M, h); }, repeats);
    const double t_Q = seconds_per_call([&] { m.forces(t, q, qd, Q); }, repeats);
    const double t_g = seconds_per_call([&] { m.constraint_rows(active, t, q, qd, g, g0, gam); }, repeats);
    auto rhs = [&](ReactionMethod method) {
      return seconds_per_call([&] {
        dyn.evaluate(set, t, q, qd);
        dyn.solve(method);
      }, repeats);
    };
    const double t_c = rhs(ReactionMethod::compatibility);
    const double t_k = rhs(ReactionMethod::kkt);
    const double t_u = rhs(ReactionMethod::udwadia_kalaba);
    std::printf("%-32s %9.2f %9.2f %9.2f %9.2f | %8.2f %8.2f\n", en.label.c_str(), t_T * 1e6,
                t_Q * 1e6, t_g * 1e6, t_c * 1e6, t_k / t_c, t_u / t_c);
  }

  std::printf("\nsieve_like, 10 s of motion (446 excitation periods), rtol = atol = 1e-6, "
              "projection on\n");
  std::printf("%-8s %-6s %8s %8s %8s %9s %9s %8s %10s\n", "kernel", "form", "wall [s]", "cpu [s]", "steps",
              "f_evals", "jacobians", "LU", "residual");
  const auto sieve = make_model(SieveLike{});
  for (Form form : {Form::ode, Form::dae}) {
    for (Kernel kernel : {Kernel::fortran, Kernel::cpp}) {
      SimulationOptions o;
      o.kernel = kernel;
      o.form = form;
      o.t_end = 10.0;
      o.rtol = o.atol = 1e-6;
      o.active_constraints = {"contact", "rolling"};
      Eigen::VectorXd q0(6);
      q0 << 0.0, 0.0, 0.0, 0.4, 0.15, 0.0;
      const auto start = std::chrono::steady_clock::now();
      const double cpu0 = pcsim_bench::process_cpu_seconds();
      const SimulationResult r = simulate(*sieve, q0, Eigen::VectorXd::Zero(6), o);
      const double cpu = pcsim_bench::process_cpu_seconds() - cpu0;
      const double wall =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      std::printf("%-8s %-6s %8.3f %8.3f %8ld %9ld %9ld %8ld %10.1e %s\n", to_string(kernel),
                  form == Form::ode ? "ode" : "dae", wall, cpu, r.stats.steps, r.stats.f_evals,
                  r.stats.jacobians, r.stats.lu_decompositions, r.residual_pos_max,
                  r.status == SimulationStatus::success ? "" : r.message.c_str());
    }
  }
  return 0;
}
