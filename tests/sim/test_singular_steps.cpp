// Issue 21: near a singular position the step-size control does not collapse. A02 with N = 1
// (cases/fourbar_a02_N1.toml) crosses its singular positions (every bar on the x axis, rank 8 ->
// 7) ten times in 10 s; the steps the integrator takes within 0.05 s of each located crossing
// are compared with the width of the window where σ_min < 1e-6 σ_max (the filter's), at rtol
// 1e-4, 1e-8 and 1e-12, and the run's step counts are bounded. Why they do not collapse
// (docs/redundant.md): q̈ stays a bounded, smooth function of the state there (the structured
// solve is exact where the rows are independent, the filter σ⁴/(σ⁴ + μ⁴) bounds and smooths the
// vanishing direction's share), so at worst the error estimate resolves the filtered window
// with steps of a fraction of its width, never a spike.
#define BOOST_TEST_MODULE singular_steps
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <unistd.h>

#include <fstream>

#include "mech/dynamics.hpp"
#include "modelfile/model_file.hpp"
#include "sim/case.hpp"
#include "sim/run.hpp"

using namespace pcsim;
using namespace pcsim::sim;

BOOST_AUTO_TEST_CASE(a02_n1_steps_near_singular_positions_stay_near_the_run_s_median) {
  const Case c = load_case(std::filesystem::path(PCSIM_SOURCE_DIR) / "cases" / "fourbar_a02_N1.toml");
  const auto model = c.model->instantiate(c.setup.parameters, c.setup.q0, 0.0, c.table, "");
  for (double rtol : {1e-4, 1e-8, 1e-12}) {
    mech::SimulationOptions o = simulation_options(c.setup);
    o.rtol = rtol;
    std::vector<std::pair<double, double>> steps;
    const mech::SimulationResult r =
        mech::simulate(*model, c.setup.q0, c.setup.qd0, o, [&](const mech::StepView& v) {
          if (v.t > v.t_prev) steps.emplace_back(v.t_prev, v.t);
          return true;
        });
    BOOST_REQUIRE_MESSAGE((r.status == mech::SimulationStatus::success), r.message);
    BOOST_TEST(r.rank_changes.size() == 10u, "rtol " << rtol);
    std::vector<double> h;
    for (const auto& s : steps) h.push_back(s.second - s.first);
    std::vector<double> sorted = h;
    std::sort(sorted.begin(), sorted.end());
    const double median = sorted[sorted.size() / 2];
    double near_min = INFINITY;
    for (const mech::RankChange& ch : r.rank_changes)
      for (const auto& s : steps)
        if (s.second > ch.t - 0.05 && s.first < ch.t + 0.05) near_min = std::min(near_min, s.second - s.first);
    BOOST_TEST_MESSAGE("rtol " << rtol << ": " << steps.size() << " accepted steps, "
                               << r.stats.rejected << " rejected; median step " << median
                               << " s, smallest within 0.05 s of a crossing " << near_min
                               << " s, smallest overall " << sorted.front() << " s");
    double window = INFINITY;  // the narrowest interval where σ_min < 1e-6 σ_max
    for (const mech::RankChange& ch : r.rank_changes) window = std::min(window, ch.t_to - ch.t_from);
    // No collapse: near a crossing the steps may shrink to resolve the filtered window
    // (measured: at rtol 1e-4 one crossing of ten is resolved down to 3.7e-7 s, a fifth of its
    // 1.8e-6 s window, in about 30 steps, then the steps grow back), never far below the
    // window's width (a collapse, as with a filter of 1e-10, went to 1e-14 s), and the run's
    // step count stays that of a smooth run (84..200 accepted steps measured).
    BOOST_TEST(near_min >= 0.05 * window, "rtol " << rtol << ": " << near_min << " vs window " << window);
    BOOST_TEST(steps.size() < 300u, "rtol " << rtol);
    BOOST_TEST(r.stats.rejected < 60, "rtol " << rtol);
  }
}

// IFToMM A02 with N parallelograms as a model file (the model of scripts/fourbar_a02_model.py,
// without its outputs and drawing): 2N+1 rods of 1 kg and 1 m in absolute coordinates.
static std::string a02_model_text(int N) {
  std::string c = "[model]\nname = \"a02\"\ncoordinates = [";
  for (int k = 0; k <= N; ++k) c += "\"xc" + std::to_string(k) + "\", \"yc" + std::to_string(k) + "\", \"tc" + std::to_string(k) + "\", ";
  for (int j = 1; j <= N; ++j) c += "\"xk" + std::to_string(j) + "\", \"yk" + std::to_string(j) + "\", \"tk" + std::to_string(j) + "\", ";
  c += "]\n[model.parameters]\nm = 1.0\nL = 1.0\ng = 9.81\n[model.define]\nJ = \"m*L^2/12\"\nh = \"L/2\"\n";
  std::string T, V;
  const auto body = [&](const std::string& x, const std::string& y, const std::string& t) {
    T += (T.empty() ? "" : " + ") + ("0.5*m*(" + x + "_d^2 + " + y + "_d^2) + 0.5*J*" + t + "_d^2");
    V += (V.empty() ? "" : " + ") + y;
  };
  for (int k = 0; k <= N; ++k) body("xc" + std::to_string(k), "yc" + std::to_string(k), "tc" + std::to_string(k));
  for (int j = 1; j <= N; ++j) body("xk" + std::to_string(j), "yk" + std::to_string(j), "tk" + std::to_string(j));
  c += "[model.energy]\nkinetic = \"" + T + "\"\npotential = \"m*g*(" + V + ")\"\n";
  const auto con = [&](const std::string& name, const std::string& e) {
    c += "[[model.constraint]]\nname = \"" + name + "\"\nholonomic = \"" + e + "\"\n";
  };
  for (int k = 0; k <= N; ++k) {
    const std::string s = std::to_string(k);
    con("A" + s + "_x", "xc" + s + " - h*cos(tc" + s + ") - " + s + "*L");
    con("A" + s + "_y", "yc" + s + " - h*sin(tc" + s + ")");
  }
  for (int j = 1; j <= N; ++j) {
    const std::string a = std::to_string(j - 1), b = std::to_string(j), k = std::to_string(j);
    con("B" + a + "_x", "xk" + k + " - h*cos(tk" + k + ") - xc" + a + " - h*cos(tc" + a + ")");
    con("B" + a + "_y", "yk" + k + " - h*sin(tk" + k + ") - yc" + a + " - h*sin(tc" + a + ")");
    con("C" + b + "_x", "xk" + k + " + h*cos(tk" + k + ") - xc" + b + " - h*cos(tc" + b + ")");
    con("C" + b + "_y", "yk" + k + " + h*sin(tk" + k + ") - yc" + b + " - h*sin(tc" + b + ")");
  }
  return c;
}

// The vanishing limit (Dynamics::set_vanishing_limit, docs/redundant.md "Inside a crossing's
// window"): at and near A02's singular positions (every bar on the x axis at θ = 0, π) the
// reaction R of the solve with the limit on against R of the independent one-degree-of-freedom
// model at the same state: all cranks at angle θ with rate ω, the couplers translating;
// θ̈ = −g c cos θ/(L ((N+1)/3 + N)), c = (N+1)/2 + N (Lagrange's equation of the chain, the
// oracle of scripts/a02_validate.py), so q̈ is known in closed form and R = M q̈ − Q. The states
// lie on the constraints to rounding, so the exact share c_k/σ_k is accurate to about eps/σ_k
// outside the window.
BOOST_AUTO_TEST_CASE(a02_reaction_at_and_near_singular_positions_is_the_one_dof_model_s_with_the_limit) {
  for (int N : {1, 4}) {
    const std::filesystem::path dir = std::filesystem::temp_directory_path() /
        ("pcsim_limit_test_" + std::to_string(N) + "_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    {
      std::ofstream(dir / "a02.toml") << a02_model_text(N);
    }
    const auto desc = modelfile::load_model_file(dir / "a02.toml");
    std::filesystem::remove_all(dir);
    const auto model = desc->instantiate({});
    const int n = model->n();
    BOOST_REQUIRE(n == 3 * (2 * N + 1));
    const double m = 1.0, L = 1.0, h = 0.5, J = m * L * L / 12.0, g = 9.81;
    const double cc = (N + 1) / 2.0 + N, Ieff = (N + 1) / 3.0 + N;
    std::vector<int> rows(model->constraints().size());
    for (std::size_t i = 0; i < rows.size(); ++i) rows[i] = static_cast<int>(i);
    const mech::ActiveSet set = mech::ActiveSet::of(*model, rows);
    mech::Dynamics on(*model, Kernel::cpp), off(*model, Kernel::cpp);
    on.set_vanishing_limit(true, 0);
    double worst_off = 0.0;
    for (double base : {0.0, M_PI}) {
      for (double d : {0.0, 1e-9, -1e-7, 1e-6, -1e-5, 1e-4, -3e-4, 1e-3, -2e-3, 3e-3, -1e-2}) {
        const double th = base + d, w = -1.2;
        const double thdd = -g * cc * std::cos(th) / (L * Ieff);
        // Bodies in the model's order: cranks 0..N (centre at k L + h (cos θ, sin θ)), then
        // couplers 1..N (centre at (j − 1/2) L + L (cos θ, sin θ), angle 0).
        Eigen::VectorXd q(n), qd(n), qdd(n), R(n);
        for (int b = 0; b < 2 * N + 1; ++b) {
          const bool crank = b <= N;
          const double r = crank ? h : L, x0 = crank ? b * L : (b - N - 0.5) * L;
          q.segment<3>(3 * b) << x0 + r * std::cos(th), r * std::sin(th), crank ? th : 0.0;
          qd.segment<3>(3 * b) << -r * std::sin(th) * w, r * std::cos(th) * w, crank ? w : 0.0;
          qdd.segment<3>(3 * b) << -r * (std::sin(th) * thdd + std::cos(th) * w * w),
              r * (std::cos(th) * thdd - std::sin(th) * w * w), crank ? thdd : 0.0;
          R.segment<3>(3 * b) << m * qdd[3 * b], m * qdd[3 * b + 1] + m * g, J * qdd[3 * b + 2];
        }
        double e[2];
        mech::Dynamics* dd[2] = {&on, &off};
        for (int k = 0; k < 2; ++k) {
          BOOST_REQUIRE((dd[k]->evaluate(set, 0.0, q, qd) == mech::ModelIssue::none));
          const mech::ModelIssue issue = dd[k]->solve(mech::ReactionMethod::compatibility_structured);
          BOOST_REQUIRE_MESSAGE((issue == mech::ModelIssue::none), dd[k]->message());
          e[k] = (dd[k]->R - R).norm() / R.norm();
        }
        BOOST_TEST_MESSAGE("N " << N << " theta " << th << " sigma_min " << on.smallest_singular_value()
                                << " |dR|/|R| limit " << e[0] << " filter " << e[1]);
        BOOST_TEST_CONTEXT("N " << N << " theta " << th) {
          // At the singular position the limit is the exact reaction to the central differences'
          // accuracy (measured 9e-13); near it its error is first order in the distance (the
          // share at the crossing instant, the term Σ_K ż dropped): measured 1.3e-3 .. 2.3e-3
          // times |θ − θ0| up to 3e-3 rad, where the blend to the exact share begins.
          BOOST_TEST(e[0] <= 1e-10 + 5e-3 * std::abs(d));
        }
        if (d == 0.0) worst_off = std::max(worst_off, e[1]);
      }
    }
    BOOST_TEST(on.limit_solves > 0);
    BOOST_TEST(on.limit_fallbacks == 0);
    // Without the limit the filter drops the rigidity share inside σ < 1e-6 σ_max: for N = 4 an
    // error of the size of R itself at the singular positions (the test can fail); for N = 1 that
    // share is zero (the two cranks carry the coupler symmetrically) and the filter is exact.
    if (N == 4) BOOST_TEST(worst_off > 0.05);  // measured 0.074
  }
}
