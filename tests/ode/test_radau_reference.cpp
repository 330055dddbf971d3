// Radau IIA on the stiff reference problems (van der Pol, Robertson) against published reference
// values, through both kernels, which must take the same steps and agree to 1e-9.
#define BOOST_TEST_MODULE radau_reference
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <cstdio>
#include <vector>

#include "problems.hpp"

using namespace pcsim;
using namespace pcsim::testproblems;

namespace {

// Cross-kernel agreement required by issue 3: the same number of accepted (and rejected)
// steps, and solutions within 1e-9 relative -- checked here at EVERY accepted step (step end
// times and solutions, componentwise, scaled by max(|a|, |b|, atol): components below atol
// are below the resolution the error control asks for). Why per step and why 1e-9 is the
// right bound: the error estimate is a difference of O(|y|) quantities of size O(rtol' |y|),
// so any rounding difference between the kernels is amplified by ~1/rtol' in the step-size
// choice and carried from step to step. With the first kernel version (Eigen LU in the port)
// this gave step-time differences up to 7e-7 at rtol = 1e-8 on van der Pol while end values
// still agreed to 1e-14; since the port calls the same LAPACK/BLAS routines in the same order,
// the two kernels round identically (measured: bitwise equal traces on every problem here).
// 1e-9 is the issue's contract; a real algorithmic difference shows as >= 1e-6.
constexpr double kKernelAgreement = 1e-9;

// The global error of a tolerance-controlled one-step method is the sum of the local errors
// over the run, each kept below ~rtol in the weighted norm; for these problems (one fast
// transition for vdP, 1e11 time units for Robertson) Hairer & Wanner report achieved errors
// within about two decades of Tol for RADAU5 (Solving ODEs II, IV.10 work-precision diagrams).
// So the checks below ask for max relative error <= kGlobalFactor * rtol, i.e. at least
// -log10(rtol) - 2 correct digits.
constexpr double kGlobalFactor = 100.0;

/// Runs rp with both kernels, checks that they agree, and returns the Fortran run.
TracedRun run_both_and_compare(const ReferenceProblem& rp, double rtol, double atol) {
  const TracedRun f = run_traced(rp, Kernel::fortran, rtol, atol);
  const TracedRun c = run_traced(rp, Kernel::cpp, rtol, atol);
  BOOST_TEST_CONTEXT(rp.name << " rtol=" << rtol << " atol=" << atol) {
    BOOST_TEST((f.result.status == OdeStatus::success), f.result.message);
    BOOST_TEST((c.result.status == OdeStatus::success), c.result.message);
    BOOST_TEST(f.result.stats.accepted == c.result.stats.accepted);
    BOOST_TEST(f.result.stats.rejected == c.result.stats.rejected);
    BOOST_TEST(trace_disagreement(f, c, atol) <= kKernelAgreement);
  }
  return f;
}

}  // namespace

BOOST_AUTO_TEST_CASE(vdpol_matches_published_reference_at_t2) {
  // Oracle: E. Hairer's reference for VDPOL, y(0) = (2, 0), eps = 1e-6, t = 2 (problems.hpp).
  const ReferenceProblem rp = van_der_pol_published();
  for (double rtol : {1e-6, 1e-8, 1e-10}) {
    const TracedRun r = run_both_and_compare(rp, rtol, rtol);
    const double err = max_relative_error(r.result.y, rp.y_ref);
    BOOST_TEST_MESSAGE("vdpol (2,0) rtol=" << rtol << " max rel err=" << err
                                           << " accepted=" << r.result.stats.accepted);
    BOOST_TEST(err <= kGlobalFactor * rtol, "rtol=" << rtol << " err=" << err);
  }
}

BOOST_AUTO_TEST_CASE(vdpol_issue_configuration_matches_computed_reference) {
  // y(0) = (2, -0.66): reference computed at rtol = atol = 1e-13 (problems.hpp). Comparing
  // runs at 1e-6..1e-10 with it checks convergence to it at the rate the tolerance asks.
  const ReferenceProblem rp = van_der_pol_issue();
  BOOST_REQUIRE_MESSAGE(rp.y_ref(0) != 0.0, "the computed reference is not filled in");
  for (double rtol : {1e-6, 1e-8, 1e-10}) {
    const TracedRun r = run_both_and_compare(rp, rtol, rtol);
    const double err = max_relative_error(r.result.y, rp.y_ref);
    BOOST_TEST_MESSAGE("vdpol (2,-0.66) rtol=" << rtol << " max rel err=" << err);
    BOOST_TEST(err <= kGlobalFactor * rtol, "rtol=" << rtol << " err=" << err);
  }
}

BOOST_AUTO_TEST_CASE(vdpol_run_reproduces_published_radau5_output) {
  // Oracle: the published output of Hairer & Wanner's original Fortran RADAU5 for its own
  // driver dr1_radau5 (this exact problem: scaled vdP, eps = 1e-6, y(0) = (2, -0.66), t = 2,
  // rtol = atol = 1e-4, h0 = 1e-6, analytic Jacobian), as printed by that driver (quoted e.g.
  // in the differential-equations Rust crate, examples/13, "Fortran Radau5 output"):
  //   X = 2.00    Y =  0.1706161101E+01 -0.8928074777E+00
  //   fcn= 2218 jac= 161 step= 275 accpt= 238 rejct=  8 dec= 248 sol=  660
  // Our kernels implement the same algorithm (coefficients, Newton strategy, error estimate,
  // Gustafsson control, tolerance transformation), so at this loose tolerance they must take
  // the very same steps: equal counters, and y(2) equal to the printed 10 digits (+- half a
  // unit in the last printed digit: 5e-10 for y1, 5e-11 for y2; allowed 2x that). Counters
  // whose definitions differ from RADAU5's are not compared: RADAU5's rejct counts only
  // error-test rejections (ours counts every non-accepted step: here 275 - 238 = 37) and its
  // sol omits the solves of the error estimate. A mismatch means the step-size or Newton
  // strategy departs from RADAU5: investigate it, do not just update the numbers.
  const ReferenceProblem rp = van_der_pol_issue();
  RadauOptions o;
  o.h0 = 1e-6;
  for (Kernel kernel : {Kernel::fortran, Kernel::cpp}) {
    const TracedRun r = run_traced(rp, kernel, 1e-4, 1e-4, {}, o);
    BOOST_TEST_CONTEXT(to_string(kernel)) {
      BOOST_TEST((r.result.status == OdeStatus::success), r.result.message);
      BOOST_TEST(r.result.stats.f_evals == 2218);
      BOOST_TEST(r.result.stats.jacobians == 161);
      BOOST_TEST(r.result.stats.steps == 275);
      BOOST_TEST(r.result.stats.accepted == 238);
      BOOST_TEST(r.result.stats.lu_decompositions == 248);
      BOOST_TEST(std::abs(r.result.y(0) - 0.1706161101e+01) <= 1e-9);
      BOOST_TEST(std::abs(r.result.y(1) - (-0.8928074777e+00)) <= 1e-10);
    }
  }
}

BOOST_AUTO_TEST_CASE(vdpol_computed_reference_is_consistent_with_published_neighbour) {
  // An oracle independent of our integrator for the computed (2, -0.66) reference: the
  // published (2, 0) solution plus the initial-layer asymptotics. Near t = 0, y1 ~ 2 and
  // eps y2' = -3 y2 - 2, so y2 relaxes to the slow manifold y2 = y1/(1 - y1^2) = -2/3 as
  // y2 = -2/3 + (y2(0) + 2/3) exp(-3 t/eps), during which y1 moves by (y2(0) + 2/3) eps/3 more
  // than on the manifold. Both runs then follow the same slow solution, shifted in time by
  //   dt = [(0 + 2/3) - (-0.66 + 2/3)] (eps/3) / (2/3) = 0.66 eps / 2 = 3.3e-7
  // (the (2, 0) run lags), so y_issue(2) - y_pub(2) = y'(2) dt with, on the slow manifold,
  //   y1' = y2,  y2' = (1 + y1^2)/(1 - y1^2)^2 y1'.
  // Predicted: (-2.9463e-7, -3.1553e-7). Neglected: relative O(eps) = 1e-6 terms (the layer
  // rate 1 - y1^2 moves with y1, the O(eps) slow-manifold correction differs only at second
  // order) and the curvature y'' dt^2 / 2 ~ 1e-13. Bound: 1e-4 of the shift (3e-11 absolute),
  // two decades above the neglected terms; it verifies the computed reference to ~10 digits
  // independently of our integrator (a scratch check while writing this test matched to 2e-6
  // of the shift).
  const ReferenceProblem issue = van_der_pol_issue();
  const ReferenceProblem published = van_der_pol_published();
  BOOST_REQUIRE_MESSAGE(issue.y_ref(0) != 0.0, "the computed reference is not filled in");
  const double eps = 1e-6;
  const double dt = 0.66 * eps / 2.0;
  const double y1 = published.y_ref(0), y2 = published.y_ref(1);
  const double y1dot = y2;
  const double y2dot = (1.0 + y1 * y1) / ((1.0 - y1 * y1) * (1.0 - y1 * y1)) * y1dot;
  const Eigen::Vector2d predicted(y1dot * dt, y2dot * dt);
  const Eigen::Vector2d measured = issue.y_ref - published.y_ref;
  BOOST_TEST_MESSAGE("ref(2,-0.66) - ref(2,0): measured " << measured.transpose()
                                                          << ", predicted " << predicted.transpose());
  for (int i = 0; i < 2; ++i)
    BOOST_TEST(std::abs(measured(i) - predicted(i)) <= 1e-4 * std::abs(predicted(i)));
}

BOOST_AUTO_TEST_CASE(robertson_matches_published_reference_at_1e11) {
  // Oracle: Bari test set ROBER at t = 1e11 (problems.hpp). y2 ~ 8e-14 there, so atol must be
  // far below it for y2 to be controlled relatively: atol = 1e-14 * rtol resolves all three
  // components to ~rtol relative. Required: >= -log10(rtol) - 2 digits in every component.
  const ReferenceProblem rp = robertson();
  for (double rtol : {1e-6, 1e-8, 1e-10}) {
    const double atol = 1e-14 * rtol;
    const TracedRun r = run_both_and_compare(rp, rtol, atol);
    const double err = max_relative_error(r.result.y, rp.y_ref);
    BOOST_TEST_MESSAGE("robertson rtol=" << rtol << " max rel err=" << err
                                         << " accepted=" << r.result.stats.accepted);
    BOOST_TEST(err <= kGlobalFactor * rtol, "rtol=" << rtol << " err=" << err);
  }
}

BOOST_AUTO_TEST_CASE(robertson_dense_output_matches_published_value_at_t40) {
  // Second oracle inside the run: Robertson at t = 40, the classical reference of Hairer &
  // Wanner, Solving ODEs II (quoted there to 10 digits; independent codes agree to ~1e-11):
  //   y(40) = (0.7158270687, 9.185534764e-6, 0.2841637457).
  // t = 40 falls inside some step of the run to 1e11, so it is read from the dense output
  // (order 3 between the step ends, still controlled by the step sizes). Allowance 100 rtol plus
  // 2e-10 for the 10-digit rounding of the reference.
  const ReferenceProblem rp = robertson();
  const Eigen::Vector3d y40(0.7158270687, 9.185534764e-6, 0.2841637457);
  for (double rtol : {1e-6, 1e-8, 1e-10}) {
    for (Kernel kernel : {Kernel::fortran, Kernel::cpp}) {
      Eigen::Vector3d at40 = Eigen::Vector3d::Constant(std::nan(""));
      const TracedRun r = run_traced(rp, kernel, rtol, 1e-14 * rtol, [&](const StepInfo& s) {
        if (s.t_prev < 40.0 && 40.0 <= s.t) s.dense(40.0, at40.data());
      });
      const double err = max_relative_error(at40, y40);
      BOOST_TEST_MESSAGE(to_string(kernel) << " robertson y(40) rtol=" << rtol
                                           << " max rel err=" << err);
      BOOST_TEST_CONTEXT(to_string(kernel) << " rtol=" << rtol) {
        BOOST_TEST((r.result.status == OdeStatus::success), r.result.message);
        BOOST_TEST(at40.allFinite());  // t = 40 was inside an accepted step
        BOOST_TEST(err <= kGlobalFactor * rtol + 2e-10);
      }
    }
  }
}

BOOST_AUTO_TEST_CASE(robertson_with_finite_difference_jacobian_matches_reference) {
  // The finite-difference Jacobian path on the same oracle. Perturbations of
  // sqrt(u max(1e-5, |y_i|)) ~ 5e-11 are far larger than y2 (~1e-13 .. 4e-5), so the Jacobian
  // is poor; that slows Newton and blurs the error estimate (measured ~3 rtol instead of
  // ~0.02 rtol with the analytic Jacobian) but must stay within the same allowance.
  ReferenceProblem rp = robertson();
  rp.problem.jacobian = nullptr;
  for (double rtol : {1e-6, 1e-8, 1e-10}) {
    const TracedRun r = run_both_and_compare(rp, rtol, 1e-14 * rtol);
    const double err = max_relative_error(r.result.y, rp.y_ref);
    BOOST_TEST_MESSAGE("robertson FD Jacobian rtol=" << rtol << " max rel err=" << err);
    BOOST_TEST(err <= kGlobalFactor * rtol, "rtol=" << rtol << " err=" << err);
  }
}

BOOST_AUTO_TEST_CASE(robertson_conserves_total_mass_over_whole_run) {
  // y1 + y2 + y3 = 1 is a linear invariant: Runge-Kutta stages preserve it exactly when the
  // stage equations are solved exactly, and simplified Newton with the exact Jacobian (whose
  // column sums are 0) keeps it too, so the drift is rounding plus Newton residual. Checked
  // after every accepted step, at each step's midpoint through the dense output, and at the
  // output times 10^k (k = -6..11) through the dense output, against rtol.
  const ReferenceProblem rp = robertson();
  for (Kernel kernel : {Kernel::fortran, Kernel::cpp}) {
    for (double rtol : {1e-4, 1e-8}) {
      double worst_step = 0.0, worst_dense = 0.0;
      int output_times_seen = 0;
      const TracedRun r = run_traced(
          rp, kernel, rtol, 1e-14 * rtol, [&](const StepInfo& s) {
            double out[3];
            const double mid = 0.5 * (s.t_prev + s.t);
            s.dense(mid, out);
            worst_dense = std::max(worst_dense, std::abs(out[0] + out[1] + out[2] - 1.0));
            for (int k = -6; k <= 11; ++k) {
              const double tk = std::pow(10.0, k);
              if (tk > s.t_prev && tk <= s.t) {
                s.dense(tk, out);
                worst_dense = std::max(worst_dense, std::abs(out[0] + out[1] + out[2] - 1.0));
                ++output_times_seen;
              }
            }
          });
      BOOST_TEST_CONTEXT(to_string(kernel) << " rtol=" << rtol) {
        BOOST_TEST((r.result.status == OdeStatus::success), r.result.message);
        for (const Eigen::VectorXd& y : r.y) worst_step = std::max(worst_step, std::abs(y.sum() - 1.0));
        BOOST_TEST_MESSAGE(to_string(kernel) << " rtol=" << rtol << " max |sum-1| at steps="
                                             << worst_step << " dense=" << worst_dense << " over "
                                             << r.t.size() << " steps");
        BOOST_TEST(output_times_seen == 18);  // every 10^k was inside some accepted step
        BOOST_TEST(r.t.size() > 20u);         // "many output times"
        BOOST_TEST(worst_step <= rtol);
        BOOST_TEST(worst_dense <= rtol);
      }
    }
  }
}

BOOST_AUTO_TEST_CASE(achieved_error_decreases_with_requested_tolerance) {
  // Tolerance proportionality against the published references: over rtol = 1e-4 ... 1e-10 the
  // achieved error must fall at every step of 1e-2 in rtol (no plateau), and by at least 4 of
  // the 6 decades overall (the kernels control rtol' = 0.1 rtol^(2/3), which falls by 4 decades
  // over these 6; RADAU5's transformation is calibrated so the achieved error follows rtol).
  struct Case {
    ReferenceProblem rp;
    double atol_factor;
  };
  const std::vector<Case> cases = {{van_der_pol_published(), 1.0}, {robertson(), 1e-14}};
  for (const Case& c : cases) {
    for (Kernel kernel : {Kernel::fortran, Kernel::cpp}) {
      std::vector<double> errs;
      for (double rtol : {1e-4, 1e-6, 1e-8, 1e-10}) {
        const TracedRun r = run_traced(c.rp, kernel, rtol, c.atol_factor * rtol);
        BOOST_REQUIRE_MESSAGE(r.result.status == OdeStatus::success, r.result.message);
        errs.push_back(max_relative_error(r.result.y, c.rp.y_ref));
        BOOST_TEST_MESSAGE(to_string(kernel) << " " << c.rp.name << " rtol=" << rtol << " err="
                                             << errs.back() << " digits="
                                             << correct_digits(r.result.y, c.rp.y_ref));
      }
      BOOST_TEST_CONTEXT(c.rp.name << " " << to_string(kernel)) {
        for (std::size_t i = 1; i < errs.size(); ++i) BOOST_TEST(errs[i] < errs[i - 1]);
        BOOST_TEST(errs.back() <= 1e-4 * errs.front());
      }
    }
  }
}
