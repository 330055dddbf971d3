// Every failure class of the Radau IIA API has its own status, the same in both kernels, with
// an honest message naming the time: non-finite values (f, Jacobian, persisting after step
// reductions), the right-hand side and the Jacobian reporting failure, Newton failure,
// inconsistent DAE starts and missing index counts. Each case also checks that the two kernels
// end at the same time with the same counters (they make the same decisions).
#define BOOST_TEST_MODULE radau_failures
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <limits>
#include <string>

#include "common/eigen_instances.hpp"

#include "ode/radau.hpp"
#include "problems.hpp"

using namespace pcsim;

namespace {

const Kernel kKernels[] = {Kernel::fortran, Kernel::cpp};
const double kNaN = std::numeric_limits<double>::quiet_NaN();

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

RadauResult run(Kernel k, const OdeProblem& p, const Eigen::VectorXd& y0, double t_end,
                RadauOptions o = {}, const StepCallback& cb = {}) {
  o.kernel = k;
  return radau_integrate(p, 0.0, y0, t_end, o, cb);
}

// The two kernels' results of the same call: same status, time, state and counters.
void check_kernels_agree(const RadauResult& f, const RadauResult& c) {
  BOOST_TEST((f.status == c.status));
  BOOST_TEST(f.t == c.t);
  BOOST_TEST(f.stats.steps == c.stats.steps);
  BOOST_TEST(f.stats.f_evals == c.stats.f_evals);
  BOOST_TEST(f.stats.evaluation_rejections == c.stats.evaluation_rejections);
  BOOST_TEST(f.stats.newton_rejections == c.stats.newton_rejections);
  if (f.y.allFinite() && c.y.allFinite()) BOOST_TEST((f.y.array() == c.y.array()).all());
}

OdeProblem decay() {
  OdeProblem p;
  p.n = 1;
  p.rhs = [](double, const double* y, double* f) {
    f[0] = -y[0];
    return true;
  };
  return p;
}

}  // namespace

BOOST_AUTO_TEST_CASE(nan_at_a_stage_is_retried_with_a_smaller_step_and_succeeds) {
  // y' = -y, but f is NaN more than 0.1 beyond the last accepted time (a model leaving its
  // domain on too long a step). Before this was handled the Fortran kernel returned success
  // with NaN in y. Oracle: exp(-2) to 100 * rtol; both kernels take the same steps.
  RadauResult res[2];
  for (int k = 0; k < 2; ++k) {
    double t_acc = 0.0;
    OdeProblem p = decay();
    p.rhs = [&t_acc](double t, const double* y, double* f) {
      f[0] = t > t_acc + 0.1 ? kNaN : -y[0];
      return true;
    };
    RadauOptions o;
    o.h0 = 0.5;
    o.rtol = o.atol = 1e-8;
    res[k] = run(kKernels[k], p, Eigen::VectorXd::Ones(1), 2.0, o, [&](StepInfo& s) {
      t_acc = s.t;
      return StepAction::proceed;
    });
    BOOST_TEST((res[k].status == OdeStatus::success), res[k].message);
    BOOST_TEST(res[k].stats.evaluation_rejections >= 1);
    BOOST_TEST(std::abs(res[k].y[0] - std::exp(-2.0)) < 1e-6);
  }
  check_kernels_agree(res[0], res[1]);
}

BOOST_AUTO_TEST_CASE(persistent_nan_in_f_ends_with_non_finite_and_the_time) {
  // f is NaN for every t > 0.5: no step size helps. The run must stop near 0.5 (the last
  // accepted time lies within the smallest step tried, < 0.5), not return NaN with success.
  RadauResult res[2];
  for (int k = 0; k < 2; ++k) {
    OdeProblem p = decay();
    p.rhs = [](double t, const double* y, double* f) {
      f[0] = t > 0.5 ? kNaN : -y[0];
      return true;
    };
    res[k] = run(kKernels[k], p, Eigen::VectorXd::Ones(1), 2.0);
    BOOST_TEST((res[k].status == OdeStatus::non_finite), res[k].message);
    BOOST_TEST(res[k].t <= 0.5);
    BOOST_TEST(res[k].t > 0.4);
    BOOST_TEST(res[k].y.allFinite());
    BOOST_TEST(contains(res[k].message, "right-hand side was not finite"), res[k].message);
    BOOST_TEST((contains(res[k].message, "t = 0.4") || contains(res[k].message, "t = 0.5")),
               res[k].message);
  }
  check_kernels_agree(res[0], res[1]);
}

BOOST_AUTO_TEST_CASE(infinite_f_at_the_start_is_non_finite_at_once) {
  for (Kernel k : kKernels) {
    OdeProblem p = decay();
    p.rhs = [](double, const double*, double* f) {
      f[0] = std::numeric_limits<double>::infinity();
      return true;
    };
    const RadauResult r = run(k, p, Eigen::VectorXd::Ones(1), 1.0);
    BOOST_TEST((r.status == OdeStatus::non_finite), r.message);
    BOOST_TEST(r.t == 0.0);
    BOOST_TEST(r.stats.steps == 0);
  }
}

BOOST_AUTO_TEST_CASE(non_finite_jacobian_and_failing_jacobian_have_their_own_statuses) {
  for (Kernel k : kKernels) {
    OdeProblem p = decay();
    p.jacobian = [](double, const double*, double* J) {
      J[0] = kNaN;
      return true;
    };
    const RadauResult rn = run(k, p, Eigen::VectorXd::Ones(1), 1.0);
    BOOST_TEST((rn.status == OdeStatus::non_finite), rn.message);
    BOOST_TEST(contains(rn.message, "Jacobian"), rn.message);

    // van der Pol recomputes its Jacobian often; this one cannot be computed beyond t = 0.3
    OdeProblem v = testproblems::van_der_pol_system(1e-3);
    std::function<bool(double, const double*, double*)> base = v.jacobian;
    v.jacobian = [base](double t, const double* y, double* J) {
      return base(t, y, J) && t < 0.3;
    };
    const RadauResult rf = run(k, v, Eigen::Vector2d(2.0, 0.0), 1.0);
    BOOST_TEST((rf.status == OdeStatus::jacobian_failed), rf.message);
    BOOST_TEST(rf.t >= 0.3);
    BOOST_TEST(rf.t < 1.0);
    BOOST_TEST(contains(rf.message, "t = "), rf.message);
  }
}

BOOST_AUTO_TEST_CASE(finite_difference_jacobian_with_nan_gives_non_finite) {
  // f is finite at y but NaN at every perturbed y (both difference directions).
  for (Kernel k : kKernels) {
    OdeProblem p = decay();
    p.rhs = [](double, const double* y, double* f) {
      f[0] = y[0] == 1.0 ? -1.0 : kNaN;
      return true;
    };
    const RadauResult r = run(k, p, Eigen::VectorXd::Ones(1), 1.0);
    BOOST_TEST((r.status == OdeStatus::non_finite), r.message);
    BOOST_TEST(r.stats.f_evals_jacobian == 2);
  }
}

BOOST_AUTO_TEST_CASE(rhs_failing_persistently_gives_rhs_failed_not_singular_matrix) {
  RadauResult res[2];
  for (int k = 0; k < 2; ++k) {
    OdeProblem p = decay();
    p.rhs = [](double t, const double* y, double* f) {
      f[0] = -y[0];
      return t <= 0.5;
    };
    res[k] = run(kKernels[k], p, Eigen::VectorXd::Ones(1), 2.0);
    BOOST_TEST((res[k].status == OdeStatus::rhs_failed), res[k].message);
    BOOST_TEST(res[k].t <= 0.5);
    BOOST_TEST(res[k].t > 0.4);
    BOOST_TEST(res[k].stats.evaluation_rejections >= 20);
  }
  check_kernels_agree(res[0], res[1]);
}

BOOST_AUTO_TEST_CASE(diverging_newton_iteration_gives_newton_failure) {
  // y' = -y with a Jacobian of the wrong sign and size, J = +J0: the simplified Newton iteration
  // contracts by |1 - (gam/h + 1)/(gam/h - J0)|, > 1 while gam/h << J0. With a fixed step
  // (gam/h = 36) it diverges with a fresh Jacobian: newton_failure at once, named for its
  // cause (before, this ended as "step size too small").
  for (double j0 : {1e6}) {
    RadauResult res[2];
    for (int k = 0; k < 2; ++k) {
      OdeProblem p = decay();
      p.jacobian = [j0](double, const double*, double* J) {
        J[0] = j0;
        return true;
      };
      RadauOptions o;
      o.fixed_step = 0.1;
      res[k] = run(kKernels[k], p, Eigen::VectorXd::Ones(1), 1.0, o);
      BOOST_TEST((res[k].status == OdeStatus::newton_failure), res[k].message);
      BOOST_TEST(contains(res[k].message, "Newton"), res[k].message);
      BOOST_TEST(res[k].stats.newton_rejections >= 1);
      BOOST_TEST(res[k].stats.error_test_rejections == 0);
    }
    check_kernels_agree(res[0], res[1]);
  }
}

BOOST_AUTO_TEST_CASE(inconsistent_dae_start_is_refused_and_a_consistent_one_accepted) {
  // The index-1 DAE of problems.hpp: 0 = z^3 + z - p(t)(y1^2 + y2^2), z(0) = 1 exactly.
  const testproblems::ReferenceProblem rp = testproblems::index1_dae();
  for (Kernel k : kKernels) {
    Eigen::VectorXd y0 = rp.y0;
    y0[3] += 0.1;  // z off by 0.1, far beyond rtol = 1e-6
    RadauOptions o;
    o.kernel = k;
    const RadauResult bad = radau_integrate(rp.problem, 0.0, y0, 1.0, o);
    BOOST_TEST((bad.status == OdeStatus::inconsistent_start), bad.message);
    BOOST_TEST(bad.t == 0.0);
    BOOST_TEST(contains(bad.message, "algebraic"), bad.message);
    y0[3] = rp.y0[3] * (1.0 + 1e-12);  // off by rounding only
    const RadauResult good = radau_integrate(rp.problem, 0.0, y0, 1.0, o);
    BOOST_TEST((good.status == OdeStatus::success), good.message);
  }
}

BOOST_AUTO_TEST_CASE(index3_pendulum_without_index_counts_reports_missing_index_counts) {
  // Pendulum in index-3 form u = (x, y, vx, vy, lambda), K = diag(1,1,1,1,0),
  // 0 = x^2 + y^2 - L^2: without index3_count the error estimate of lambda (~1/h^2) rejects
  // every first step; with index2_count = 2 (velocities), index3_count = 1 it integrates.
  const testproblems::PendulumParameters P;
  OdeProblem p;
  p.n = 5;
  p.rhs = [P](double, const double* u, double* f) {
    f[0] = u[2];
    f[1] = u[3];
    f[2] = -u[4] * u[0] / P.m;
    f[3] = -P.g - u[4] * u[1] / P.m;
    f[4] = u[0] * u[0] + u[1] * u[1] - P.L * P.L;
    return true;
  };
  Eigen::VectorXd k = Eigen::VectorXd::Ones(5);
  k[4] = 0.0;
  p.mass = k.asDiagonal();
  Eigen::VectorXd y0(5);
  y0 << P.L * std::sin(P.phi0), -P.L * std::cos(P.phi0), 0.0, 0.0,
      P.m * P.g * std::cos(P.phi0) / P.L;
  RadauResult res[2];
  for (int i = 0; i < 2; ++i) {
    res[i] = run(kKernels[i], p, y0, 1.0);
    BOOST_TEST((res[i].status == OdeStatus::missing_index_counts), res[i].message);
    BOOST_TEST(contains(res[i].message, "index counts"), res[i].message);
    OdeProblem q = p;
    q.index2_count = 0;
    q.index3_count = 1;
    // variables ordered index-1 (x, y, vx, vy), then index-3 (lambda)
    const RadauResult ok = run(kKernels[i], q, y0, 1.0);
    BOOST_TEST((ok.status == OdeStatus::success), ok.message);
  }
  check_kernels_agree(res[0], res[1]);
}
