// The shooting Jacobian and the parameter derivative that continuation borders it with: both
// equal central differences of the shooting residual (an oracle only: whole-orbit differences
// at a tight tolerance, with the residual expressed in one tangent basis), for the Duffing
// oscillator (omega moves the period) and the sieve (a force parameter, and the held value).
#define BOOST_TEST_MODULE steady_derivatives
#include <boost/test/unit_test.hpp>

#include <cmath>

#if PCSIM_WITH_SIEVE
#include "sieve/source.hpp"
#endif
#include "sim/case.hpp"
#include "steady/steady_case.hpp"

using namespace pcsim;
using namespace pcsim::steady;

namespace {

// The residual r(x, p) in the fixed tangent basis B of L0 (the residual's own basis changes
// with the point; for a difference quotient it must be one basis).
Eigen::VectorXd residual_in(const Linearization& L0, const Linearization& L, int ns) {
  const int m = static_cast<int>(L0.basis.cols());
  Eigen::VectorXd r(m + ns);
  // r_y = B0ᵀ S (y_end − y0) with S y differences; L.residual holds B(L)ᵀ S Δy: rebuild Δy.
  const Eigen::VectorXd Sdy = L.basis * L.residual.head(L.basis.cols());
  r.head(m) = L0.basis.transpose() * Sdy;
  r.tail(ns) = L.residual.tail(ns);
  return r;
}

void check(const sim::Case& c, const std::string& key, double p, double h_rel, double tol,
           double offset = 0.0) {
  const CaseOrbit base(c, 1, key);
  ShootingOptions so = shooting_options(base.setup(), OdeMethod::explicit_rk);
  so.rtol = 1e-12;
  so.atol = 1e-16;
  // One scaling of the state for every p (as the continuation fixes it along a branch).
  const double omega_scale = 6.28318530717958647692 / base.problem(p).period;
  auto problem = [&](double v) {
    OrbitProblem pr = base.problem(v);
    pr.velocity_scale = omega_scale;
    return pr;
  };
  OrbitResult r = find_orbit(problem(p), base.guess(), so);
  BOOST_REQUIRE_MESSAGE(r.converged, r.message);
  // offset: the derivatives at a state off the orbit too (a continuation's predictor).
  r.point.y *= (1 + offset);
  const int ns = static_cast<int>(r.point.H.size());
  Shooter sh(problem(p), so);
  const ParameterDerivative d = base.derivative(p);
  const Linearization L = sh.linearize(r.point, &d);
  BOOST_REQUIRE_MESSAGE(L.ok, L.message);
  const double h = h_rel * std::max(std::abs(p), 1e-3);
  Shooter shp(problem(p + h), so), shm(problem(p - h), so);
  OrbitPoint xp = r.point, xm = r.point;
  std::string msg;
  BOOST_REQUIRE(shp.project(xp, msg));
  BOOST_REQUIRE(shm.project(xm, msg));
  const Linearization Lp = shp.linearize(xp), Lm = shm.linearize(xm);
  BOOST_REQUIRE(Lp.ok && Lm.ok);
  // The manifold's motion with p enters through the projections; the residual differences are
  // taken in L's basis.
  const Eigen::VectorXd fd = (residual_in(L, Lp, ns) - residual_in(L, Lm, ns)) / (2 * h);
  const double scale = std::max(fd.cwiseAbs().maxCoeff(), L.dr_dp.cwiseAbs().maxCoeff());
  const double err = (fd - L.dr_dp).cwiseAbs().maxCoeff() / scale;
  BOOST_TEST_MESSAGE(key << " at " << p << ": dr/dp against central differences " << err);
  BOOST_TEST(err < tol);
  // The Jacobian in z and H, by differences along the basis and the holding forces.
  const int m = static_cast<int>(L.basis.cols());
  Eigen::MatrixXd Jfd(m + ns, m + ns);
  for (int j = 0; j < m + ns; ++j) {
    Eigen::VectorXd e = Eigen::VectorXd::Zero(m + ns);
    const double hz = j < m ? 1e-6 * std::max(1e-6, L.amplitude) : 1e-6 * std::max(1e-3, std::abs(r.point.H[j - m]));
    e[j] = hz;
    OrbitPoint a, b;
    BOOST_REQUIRE(sh.advance(r.point, L, e, 1.0, a, msg));
    BOOST_REQUIRE(sh.advance(r.point, L, -e, 1.0, b, msg));
    const Linearization La = sh.linearize(a), Lb = sh.linearize(b);
    Jfd.col(j) = (residual_in(L, La, ns) - residual_in(L, Lb, ns)) / (2 * hz);
  }
  const double jerr = (Jfd - L.jacobian).cwiseAbs().maxCoeff() / L.jacobian.cwiseAbs().maxCoeff();
  BOOST_TEST_MESSAGE(key << " at " << p << ": shooting Jacobian against central differences " << jerr);
  BOOST_TEST(jerr < tol);
}

}  // namespace

BOOST_AUTO_TEST_CASE(parameter_derivative_and_jacobian_of_the_duffing_residual_equal_differences) {
  const sim::Case c = sim::load_case(std::string(PCSIM_SOURCE_DIR) + "/tests/steady/duffing.toml");
  // Tolerance 1e-5: the differences' own error (step 1e-5 relative: truncation ~1e-10, the
  // integration error 1e-12 over the step ~1e-7 relative) with a margin.
  for (double omega : {0.6, 1.5}) check(c, "parameters.omega", omega, 1e-5, 1e-5);
  check(c, "parameters.omega", 0.6, 1e-5, 1e-5, 0.05);
  check(c, "parameters.F", 0.5, 1e-5, 1e-5);
}

#if PCSIM_WITH_SIEVE  // the sieve's (its built-in model)
BOOST_AUTO_TEST_CASE(parameter_derivative_and_jacobian_of_the_sieve_residual_equal_differences) {
  sieve::register_sieve();
  const sim::Case c = sim::load_case(std::string(PCSIM_SOURCE_DIR) + "/cases/sieve_1995.toml");
  check(c, "parameters.omega", 280.0, 1e-5, 1e-5);
  check(c, "parameters.e", 0.01, 1e-5, 1e-5);
  check(c, "initial.s0", 0.4, 1e-5, 1e-5);
}
#endif
