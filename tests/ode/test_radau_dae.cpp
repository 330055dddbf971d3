// Radau IIA on index-1 DAEs with a singular mass matrix K: a constructed DAE with an exact
// solution, and the planar pendulum (multiplier eliminated at acceleration level) against its
// exact minimal-coordinate solution, through both kernels.
#define BOOST_TEST_MODULE radau_dae
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

#include "problems.hpp"

using namespace pcsim;
using namespace pcsim::testproblems;

namespace {

// Same agreement criterion as test_radau_reference (reasoning there): same accepted and
// rejected counts, step end times and solutions at every accepted step within 1e-9 relative
// (componentwise, scaled by max(|a|, |b|, atol)).
constexpr double kKernelAgreement = 1e-9;

// Global error allowances.
// (a) Short runs (the index-1 DAE: 3 time units, one revolution): max error <= 100 rtol, i.e.
//     at least -log10(rtol) - 2 correct digits (reasoning in test_radau_reference). For index-1
//     DAEs Radau IIA keeps order 5 in the algebraic variables too (stiffly accurate; H&W II,
//     VI.1), so the same allowance applies to z.
constexpr double kGlobalFactor = 100.0;
// (b) The pendulum is conservative: nothing damps the local errors, which add up over its
//     2.5 periods (~200-800 steps). The kernels control the local error against
//     rtol' = 0.1 rtol^(2/3) (RADAU5's transformation, transformed_rtol in problems.hpp), which
//     is looser than rtol for rtol < 1e-3 (rtol' = 1e-7 at rtol = 1e-9). So the achieved error
//     there is ~rtol', not ~rtol (measured 0.1-2 rtol'), and the allowance is 10 rtol', i.e. at
//     least (2/3)(-log10 rtol) digits: 4 at rtol = 1e-6, 6 at 1e-9, 6.7 at 1e-10.
double pendulum_allowance(double rtol) { return 10.0 * transformed_rtol(rtol); }

/// Runs rp with both kernels, checks agreement, returns both runs (Fortran first).
std::pair<TracedRun, TracedRun> run_both_and_compare(const ReferenceProblem& rp, double rtol,
                                                     double atol, RadauOptions options = {}) {
  TracedRun f = run_traced(rp, Kernel::fortran, rtol, atol, {}, options);
  TracedRun c = run_traced(rp, Kernel::cpp, rtol, atol, {}, options);
  BOOST_TEST_CONTEXT(rp.name << " rtol=" << rtol) {
    BOOST_TEST((f.result.status == OdeStatus::success), f.result.message);
    BOOST_TEST((c.result.status == OdeStatus::success), c.result.message);
    BOOST_TEST(f.result.stats.accepted == c.result.stats.accepted);
    BOOST_TEST(f.result.stats.rejected == c.result.stats.rejected);
    BOOST_TEST(trace_disagreement(f, c, atol) <= kKernelAgreement);
  }
  return {std::move(f), std::move(c)};
}

/// Max over accepted steps of the componentwise error against an exact solution, each
/// component scaled by max(1, |exact|) (a mixed absolute/relative error: the problems here are
/// O(1) and some components pass through 0).
template <class Exact>
double max_trace_error(const TracedRun& r, Exact exact, Eigen::Index ncomp) {
  double e = 0.0;
  for (std::size_t k = 0; k < r.t.size(); ++k) {
    const Eigen::VectorXd ex = exact(r.t[k]);
    for (Eigen::Index i = 0; i < ncomp; ++i)
      e = std::max(e, std::abs(r.y[k](i) - ex(i)) / std::max(1.0, std::abs(ex(i))));
  }
  return e;
}

}  // namespace

BOOST_AUTO_TEST_CASE(minimal_coordinate_oracles_agree) {
  // The pendulum oracle (Jacobi elliptic closed form) against an independent method (RK4 with
  // Richardson extrapolation, h = 5/20000): their agreement bounds the oracle's own error.
  // Measured ~1e-13; RK4-Richardson truncation at this h is ~1e-14 and the rounding of
  // 4e4 steps ~1e-13, so 1e-11 is a safe bound, 3 decades below what the DAE tests compare.
  const PendulumParameters P;
  for (double t : {0.37, 1.0, 2.5, 5.0}) {
    const PendulumState a = pendulum_exact(P, t);
    const PendulumState b = pendulum_rk4_richardson(P, t, 20000);
    BOOST_TEST(std::abs(a.phi - b.phi) <= 1e-11, "t=" << t);
    BOOST_TEST(std::abs(a.phidot - b.phidot) <= 1e-11, "t=" << t);
  }
  // And the closed form satisfies the energy integral phi'^2 = 2 (g/L)(cos phi - cos phi0).
  for (double t : {0.37, 1.0, 2.5, 5.0}) {
    const PendulumState a = pendulum_exact(P, t);
    const double rhs = 2.0 * P.g / P.L * (std::cos(a.phi) - std::cos(P.phi0));
    BOOST_TEST(std::abs(a.phidot * a.phidot - rhs) <= 1e-12);
  }
}

BOOST_AUTO_TEST_CASE(index1_dae_matches_exact_solution) {
  // Exact solution in problems.hpp. Checked at every accepted step, all four components
  // including the algebraic variable z, for both kernels.
  const ReferenceProblem rp = index1_dae();
  auto exact = [](double t) { return Eigen::VectorXd(index1_dae_exact(t)); };
  for (double rtol : {1e-6, 1e-8, 1e-10}) {
    const auto [f, c] = run_both_and_compare(rp, rtol, rtol);
    const double err = max_trace_error(f, exact, 4);
    double zerr = 0.0;
    for (std::size_t k = 0; k < f.t.size(); ++k)
      zerr = std::max(zerr, std::abs(f.y[k](3) - index1_dae_exact(f.t[k])(3)));
    BOOST_TEST_MESSAGE("index-1 DAE rtol=" << rtol << " max err=" << err << " (z: " << zerr
                                           << ") accepted=" << f.result.stats.accepted);
    BOOST_TEST(err <= kGlobalFactor * rtol, "rtol=" << rtol << " err=" << err);
    BOOST_TEST(max_relative_error(f.result.y, rp.y_ref) <= kGlobalFactor * rtol);
  }
}

BOOST_AUTO_TEST_CASE(index1_dae_error_decreases_with_requested_tolerance) {
  // As for the ODEs: the error must fall at every step of 1e-2 in rtol and by at least 4 of
  // the 6 decades from 1e-4 to 1e-10.
  const ReferenceProblem rp = index1_dae();
  auto exact = [](double t) { return Eigen::VectorXd(index1_dae_exact(t)); };
  std::vector<double> errs;
  for (double rtol : {1e-4, 1e-6, 1e-8, 1e-10}) {
    const TracedRun r = run_traced(rp, Kernel::cpp, rtol, rtol);
    BOOST_REQUIRE_MESSAGE(r.result.status == OdeStatus::success, r.result.message);
    errs.push_back(max_trace_error(r, exact, 4));
    BOOST_TEST_MESSAGE("index-1 DAE rtol=" << rtol << " err=" << errs.back());
  }
  for (std::size_t i = 1; i < errs.size(); ++i) BOOST_TEST(errs[i] < errs[i - 1]);
  BOOST_TEST(errs.back() <= 1e-4 * errs.front());
}

BOOST_AUTO_TEST_CASE(dense_output_of_dae_tracks_exact_solution) {
  // The collocation polynomial between steps (order 3 = stage order, so its error is larger
  // than at the step ends but still controlled by the step-size choice) at 4 interior points
  // of every step, against the exact solution, z included.
  const ReferenceProblem rp = index1_dae();
  const double rtol = 1e-8;
  for (Kernel kernel : {Kernel::fortran, Kernel::cpp}) {
    double worst = 0.0;
    const TracedRun r = run_traced(rp, kernel, rtol, rtol, [&](const StepInfo& s) {
      double out[4];
      for (double theta : {0.2, 0.4, 0.6, 0.8}) {
        const double ts = s.t_prev + theta * (s.t - s.t_prev);
        s.dense(ts, out);
        const Eigen::Vector4d ex = index1_dae_exact(ts);
        for (int i = 0; i < 4; ++i) {
          worst = std::max(worst, std::abs(out[i] - ex(i)) / std::max(1.0, std::abs(ex(i))));
          // The one-component accessor must give the same value.
          BOOST_TEST(s.dense(i, ts) == out[i]);
        }
      }
    });
    BOOST_TEST((r.result.status == OdeStatus::success), r.result.message);
    BOOST_TEST_MESSAGE(to_string(kernel) << " dense-output max err=" << worst);
    // The dense output is accurate to O(h^4) locally; with the step sizes the order-5 error
    // control picks, it is still within the global allowance.
    BOOST_TEST(worst <= kGlobalFactor * rtol);
  }
}

BOOST_AUTO_TEST_CASE(pendulum_dae_matches_minimal_coordinates_position_and_tension) {
  // 5-unknown form (x, y, vx, vy, lambda) against the exact phi(t): positions, velocities, and
  // the tension lambda L = m (g cos phi + L phi'^2), at every accepted step. Scale: L = 0.8 m,
  // speeds ~3 m/s, lambda ~ 20-60 N/m; errors are scaled by max(1, |exact|).
  const PendulumParameters P;
  const ReferenceProblem rp = pendulum_dae(P);
  auto exact = [&P](double t) {
    return Eigen::VectorXd(pendulum_cartesian(P, pendulum_exact(P, t)));
  };
  std::vector<double> errs;
  for (double rtol : {1e-6, 1e-8, 1e-10}) {
    const auto [f, c] = run_both_and_compare(rp, rtol, rtol);
    const double err_pos = max_trace_error(f, exact, 4);
    errs.push_back(err_pos);
    double err_tension = 0.0, drift = 0.0;
    for (std::size_t k = 0; k < f.t.size(); ++k) {
      const Eigen::VectorXd ex = exact(f.t[k]);
      const double T_num = f.y[k](4) * P.L, T_ex = ex(4) * P.L;
      err_tension = std::max(err_tension, std::abs(T_num - T_ex) / std::max(1.0, std::abs(T_ex)));
      drift = std::max(drift, std::abs(std::hypot(f.y[k](0), f.y[k](1)) - P.L));
    }
    BOOST_TEST_MESSAGE("pendulum 5-var rtol=" << rtol << " pos/vel err=" << err_pos
                                              << " tension err=" << err_tension
                                              << " |r|-L drift=" << drift
                                              << " accepted=" << f.result.stats.accepted);
    BOOST_TEST(err_pos <= pendulum_allowance(rtol), "rtol=" << rtol);
    BOOST_TEST(err_tension <= pendulum_allowance(rtol), "rtol=" << rtol);
    // Acceleration-level constraints drift; the drift is part of the position error above.
    BOOST_TEST(drift <= pendulum_allowance(rtol));
  }
  // And the error falls with the tolerance: by >= 1 decade per 2 decades of rtol (rtol' falls
  // by 10^(4/3) = 21 per 2 decades of rtol).
  for (std::size_t i = 1; i < errs.size(); ++i) BOOST_TEST(errs[i] <= 0.1 * errs[i - 1]);
}

BOOST_AUTO_TEST_CASE(pendulum_engine_form_dae_matches_minimal_coordinates) {
  // The engine's DAE form y = (q, v, a, lambda), 3 algebraic unknowns, same oracle, plus the
  // accelerations against the exact ones: a = -(lambda/m) r - g e_y.
  const PendulumParameters P;
  const ReferenceProblem rp = pendulum_dae_accel(P);
  for (double rtol : {1e-6, 1e-9}) {
    const auto [f, c] = run_both_and_compare(rp, rtol, rtol);
    double err = 0.0;
    for (std::size_t k = 0; k < f.t.size(); ++k) {
      const Eigen::Matrix<double, 5, 1> ex = pendulum_cartesian(P, pendulum_exact(P, f.t[k]));
      const double ax = -ex(4) * ex(0) / P.m, ay = -P.g - ex(4) * ex(1) / P.m;
      const double exv[7] = {ex(0), ex(1), ex(2), ex(3), ax, ay, ex(4)};
      for (int i = 0; i < 7; ++i)
        err = std::max(err, std::abs(f.y[k](i) - exv[i]) / std::max(1.0, std::abs(exv[i])));
    }
    BOOST_TEST_MESSAGE("pendulum 7-var rtol=" << rtol << " max err=" << err
                                              << " accepted=" << f.result.stats.accepted);
    BOOST_TEST(err <= pendulum_allowance(rtol), "rtol=" << rtol);
  }
}

BOOST_AUTO_TEST_CASE(pendulum_dae_with_finite_difference_jacobian_matches_minimal_coordinates) {
  // Without the analytic Jacobian (finite differences inside the kernel) the Newton iteration
  // differs but the converged solution must meet the same accuracy, on both kernels.
  const PendulumParameters P;
  ReferenceProblem rp = pendulum_dae(P);
  rp.problem.jacobian = nullptr;
  auto exact = [&P](double t) {
    return Eigen::VectorXd(pendulum_cartesian(P, pendulum_exact(P, t)));
  };
  const double rtol = 1e-8;
  const auto [f, c] = run_both_and_compare(rp, rtol, rtol);
  const double err = max_trace_error(f, exact, 5);
  BOOST_TEST_MESSAGE("pendulum 5-var FD Jacobian rtol=" << rtol << " max err=" << err);
  BOOST_TEST(err <= pendulum_allowance(rtol));
}
