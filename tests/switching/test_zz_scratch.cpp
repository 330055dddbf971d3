#define BOOST_TEST_MODULE scratch
#include <boost/test/unit_test.hpp>
#include <cstdio>
#include <cmath>
#include "switching_util.hpp"
using namespace switching_test;
BOOST_AUTO_TEST_CASE(scratch) {
  const double kG = 9.81, kH = 1;
  for (double e : {0.5, 0.8}) {
    auto m = contact_model("bouncing_ball", {{"e_n", e}});
    SimulationOptions o; o.rtol = o.atol = 1e-10;
    SwitchingOptions sw; sw.zeno_time = 1e-9;
    const auto r = run(*m, Eigen::VectorXd::Constant(1, kH), Eigen::VectorXd::Zero(1), 5.0, o, sw);
    const double t1 = std::sqrt(2 * kH / kG), v1 = kG * t1;
    double te = t1, v = v1, worst = 0, worstv = 0, worsta = 0; int k = 0;
    for (auto& ev : r.events) { if (ev.kind != ContactEventKind::impact) continue; if (k < 10) { worst = std::max(worst, std::abs(ev.t - te)/te); worstv = std::max(worstv, std::abs(-ev.vn_before - v)/v1);} te += 2*e*v/kG; v*=e; ++k; }
    double apex = kH; for (int i = 1; i < 10; ++i) { apex *= e*e; worsta = std::max(worsta, std::abs(r.contacts[0].flights[i].max_gap - apex)); }
    const double tinf = t1 + 2*e*v1/(kG*(1-e));
    double tacc = 0; for (auto& ev : r.events) if (ev.kind == ContactEventKind::accumulation) tacc = ev.t;
    printf("ball e=%.1f: first 10 impacts rel time err %.2e, speed err %.2e (of v1), apex err %.2e m; impacts %d; accumulation %.12f exact %.12f diff %.2e\n", e, worst, worstv, worsta, k, tacc, tinf, tacc - tinf);
  }
}
