#define BOOST_TEST_MODULE scratch
#include <boost/test/unit_test.hpp>
#include <cstdio>
#include "switching_util.hpp"
using namespace switching_test;
BOOST_AUTO_TEST_CASE(scratch) {
  const double e = 0.5, kG = 9.81, kH = 1;
  auto m = contact_model("bouncing_ball", {{"e_n", e}});
  SimulationOptions o; o.rtol = o.atol = 1e-10;
  SwitchingOptions sw; sw.zeno_time = 1e-8;
  const auto r = run(*m, Eigen::VectorXd::Constant(1, kH), Eigen::VectorXd::Zero(1), 4.0, o, sw);
  const double t1 = std::sqrt(2 * kH / kG), v1 = kG * t1;
  double te = t1, v = v1;
  for (auto& ev : r.events) {
    printf("%-13s t=%.17g exact %.17g dt=%.3e vb=%.6e va=%.6e (exact vb %.6e)\n", to_string(ev.kind), ev.t, te, ev.t-te, ev.vn_before, ev.vn_after, -v);
    te += 2*e*v/kG; v*=e;
  }
  printf("segments %ld late %ld steps %ld\n", r.segments, r.late_roots, r.stats.steps);
}
