// Event functions (issue 12): the integrators return at the earliest sign change of g(t, y),
// located on the step's collocation polynomial, with y there from the dense output, the
// functions that changed sign and their directions; both kernels agree exactly. Oracles:
// closed-form event times of a falling body and of a harmonic oscillator.
#define BOOST_TEST_MODULE radau_events
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <vector>

#include "common/eigen_instances.hpp"

#include "ode/radau.hpp"

using namespace pcsim;

namespace {

const Kernel kKernels[] = {Kernel::fortran, Kernel::cpp};
constexpr double kG = 9.81;

// A body falling from height y0: u = (y, v), y' = v, v' = -g; event g0 = y (ground).
// Exact hit time sqrt(2 y0 / g) from rest. Radau IIA integrates this quadratic exactly (its
// collocation polynomial has degree 3), so the located time is limited only by the root
// tolerance 100 eps (|t| + |h|) of the kernels (docs/radau.md, Events).
OdeProblem falling(int ng = 1) {
  OdeProblem p;
  p.n = 2;
  p.rhs = [](double, const double* u, double* f) {
    f[0] = u[1];
    f[1] = -kG;
    return true;
  };
  p.event_count = ng;
  p.events = [ng](double, const double* u, double* g) {
    g[0] = u[0];
    if (ng > 1) g[1] = 2.0 * u[0];       // the same root, simultaneous
    if (ng > 2) g[2] = u[0] - 0.5;       // an earlier root at y = 0.5
  };
  return p;
}

RadauResult run(Kernel k, const OdeProblem& p, const Eigen::VectorXd& y0, double t0,
                double t_end, RadauOptions o = {}, const StepCallback& cb = {}) {
  o.kernel = k;
  return radau_integrate(p, t0, y0, t_end, o, cb);
}

}  // namespace

BOOST_AUTO_TEST_CASE(falling_body_hits_the_ground_at_sqrt_2h_over_g) {
  const double h0 = 2.0;
  const double t_hit = std::sqrt(2.0 * h0 / kG);
  RadauResult res[2];
  for (int k = 0; k < 2; ++k) {
    RadauOptions o;
    o.rtol = o.atol = 1e-8;
    res[k] = run(kKernels[k], falling(), Eigen::Vector2d(h0, 0.0), 0.0, 10.0, o);
    BOOST_TEST_REQUIRE((res[k].status == OdeStatus::root_found), res[k].message);
    BOOST_TEST(std::abs(res[k].t - t_hit) <= 1e-12, res[k].t << " vs " << t_hit);
    BOOST_TEST(res[k].root_directions.size() == 1u);
    BOOST_TEST(res[k].root_directions[0] == -1);
    BOOST_TEST(res[k].y[0] <= 0.0);  // the root is reported on the new-sign side
    BOOST_TEST(std::abs(res[k].y[0]) < 1e-12);
    BOOST_TEST(std::abs(res[k].y[1] + kG * t_hit) < 1e-10);  // dense-output velocity
  }
  BOOST_TEST(res[0].t == res[1].t);
  BOOST_TEST((res[0].y.array() == res[1].y.array()).all());
  BOOST_TEST(res[0].stats.event_evals == res[1].stats.event_evals);
}

BOOST_AUTO_TEST_CASE(simultaneous_roots_are_reported_together_and_the_earliest_wins) {
  // g0 = y and g1 = 2 y vanish together; g2 = y - 0.5 earlier: first return at g2's root,
  // then (restarting there) at the ground with g0 and g1 both flagged.
  const double h0 = 2.0;
  for (Kernel k : kKernels) {
    const OdeProblem p = falling(3);
    RadauOptions o;
    o.rtol = o.atol = 1e-8;
    const RadauResult a = run(k, p, Eigen::Vector2d(h0, 0.0), 0.0, 10.0, o);
    BOOST_TEST_REQUIRE((a.status == OdeStatus::root_found), a.message);
    BOOST_TEST(std::abs(a.t - std::sqrt(2.0 * (h0 - 0.5) / kG)) < 1e-12);
    BOOST_TEST((a.root_directions == std::vector<int>{0, 0, -1}));
    const RadauResult b = run(k, p, a.y, a.t, 10.0, o);
    BOOST_TEST_REQUIRE((b.status == OdeStatus::root_found), b.message);
    BOOST_TEST(std::abs(b.t - std::sqrt(2.0 * h0 / kG)) < 1e-12);
    BOOST_TEST((b.root_directions == std::vector<int>{-1, -1, 0}));
  }
}

BOOST_AUTO_TEST_CASE(root_inside_the_first_step_is_located_on_its_polynomial) {
  // h0 = 1 covers the hit at 0.1428 s of a fall from 0.1 m: the first step's polynomial.
  for (Kernel k : kKernels) {
    RadauOptions o;
    o.h0 = 1.0;
    o.rtol = o.atol = 1e-6;
    const RadauResult r = run(k, falling(), Eigen::Vector2d(0.1, 0.0), 0.0, 1.0, o);
    BOOST_TEST_REQUIRE((r.status == OdeStatus::root_found), r.message);
    BOOST_TEST(r.stats.accepted == 1);
    BOOST_TEST(std::abs(r.t - std::sqrt(0.2 / kG)) < 1e-12);
  }
}

BOOST_AUTO_TEST_CASE(bouncing_restart_does_not_fire_the_same_root_again) {
  // After each impact the caller reverses the velocity and restarts at the root: the root
  // just returned lies at the restart time and must not fire again; the next impact follows
  // a full flight of 2 v/g later (elastic bounce: every flight lasts 2 sqrt(2 h0/g)).
  const double h0 = 1.0;
  const double t1 = std::sqrt(2.0 * h0 / kG);
  for (Kernel k : kKernels) {
    RadauOptions o;
    o.rtol = o.atol = 1e-9;
    Eigen::VectorXd y = Eigen::Vector2d(h0, 0.0);
    double t = 0.0;
    for (int bounce = 0; bounce < 4; ++bounce) {
      const RadauResult r = run(k, falling(), y, t, 100.0, o);
      BOOST_TEST_REQUIRE((r.status == OdeStatus::root_found), r.message);
      const double expected = t1 * (2 * bounce + 1);
      BOOST_TEST(std::abs(r.t - expected) < 1e-10, "bounce " << bounce << ": " << r.t);
      t = r.t;
      y = r.y;
      y[1] = -y[1];  // elastic impact
    }
  }
}

BOOST_AUTO_TEST_CASE(direction_filter_reports_only_the_requested_crossings) {
  // Harmonic oscillator y = cos t: g = y crosses zero decreasing at pi/2, increasing at 3pi/2.
  OdeProblem p;
  p.n = 2;
  p.rhs = [](double, const double* u, double* f) {
    f[0] = u[1];
    f[1] = -u[0];
    return true;
  };
  p.event_count = 1;
  p.events = [](double, const double* u, double* g) { g[0] = u[0]; };
  p.event_direction = {+1};
  RadauResult res[2];
  for (int k = 0; k < 2; ++k) {
    RadauOptions o;
    o.rtol = o.atol = 1e-10;
    res[k] = run(kKernels[k], p, Eigen::Vector2d(1.0, 0.0), 0.0, 10.0, o);
    BOOST_TEST_REQUIRE((res[k].status == OdeStatus::root_found), res[k].message);
    // located to the root tolerance; y itself carries the integration error (~1e-10)
    BOOST_TEST(std::abs(res[k].t - 1.5 * M_PI) < 1e-8);
    BOOST_TEST(res[k].root_directions[0] == +1);
  }
  BOOST_TEST(res[0].t == res[1].t);
}

BOOST_AUTO_TEST_CASE(step_callback_sees_the_step_shortened_to_the_root) {
  // The step containing the root is reported as [t_prev, t_root], its dense output the same
  // polynomial: at the root it equals the returned y, in between it matches the exact fall.
  const double h0 = 2.0;
  for (Kernel k : kKernels) {
    double last_t = -1.0, mid_err = 0.0;
    Eigen::Vector2d at_end;
    RadauOptions o;
    o.rtol = o.atol = 1e-8;
    const RadauResult r =
        run(k, falling(), Eigen::Vector2d(h0, 0.0), 0.0, 10.0, o, [&](StepInfo& s) {
          last_t = s.t;
          double mid[2];
          const double tm = 0.5 * (s.t_prev + s.t);
          s.dense(tm, mid);
          mid_err = std::max(mid_err, std::abs(mid[0] - (h0 - 0.5 * kG * tm * tm)));
          s.dense(s.t, at_end.data());
          return StepAction::proceed;
        });
    BOOST_TEST_REQUIRE((r.status == OdeStatus::root_found), r.message);
    BOOST_TEST(last_t == r.t);
    BOOST_TEST(std::abs(at_end[0] - r.y[0]) < 1e-14);
    BOOST_TEST(mid_err < 1e-12);
  }
}
