// Reference problems for validating the Radau IIA integrator: their definitions (f, analytic
// Jacobian, K), initial values, published reference values, exact or independent solutions, the
// error measures, and a runner that records every accepted step (for kernel comparisons).
// Shared by tests/ode/test_radau_reference*.cpp, test_radau_dae*.cpp and bench/bench_radau*.cpp.
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "common/eigen_instances.hpp"
#include <boost/math/special_functions/ellint_1.hpp>
#include <boost/math/special_functions/jacobi_elliptic.hpp>

#include "ode/radau.hpp"

namespace pcsim::testproblems {

/// A problem with its initial values, its end time and a reference solution at the end time.
struct ReferenceProblem {
  std::string name;
  OdeProblem problem;
  double t0 = 0.0;
  double t_end = 0.0;
  Eigen::VectorXd y0;
  Eigen::VectorXd y_ref;     ///< reference solution at t_end
  std::string ref_source;    ///< where y_ref comes from
};

// ---------------------------------------------------------------------------------------------
// Van der Pol, stiff, in the SCALED form of Hairer & Wanner (Solving ODEs II, IV.10, problem
// VDPOL; the RADAU5 driver dr1_radau5 uses the same form and y(0) = (2, -0.66)):
//     y1' = y2,     y2' = ((1 - y1^2) y2 - y1) / eps,     eps = 1e-6,  t in [0, 2].
// (The time-scaled form of y'' - mu (1 - y^2) y' + y = 0 with mu = 1/sqrt(eps).)
// ---------------------------------------------------------------------------------------------
inline OdeProblem van_der_pol_system(double eps) {
  OdeProblem p;
  p.n = 2;
  p.rhs = [eps](double, const double* y, double* f) {
    f[0] = y[1];
    f[1] = ((1.0 - y[0] * y[0]) * y[1] - y[0]) / eps;
    return true;
  };
  p.jacobian = [eps](double, const double* y, double* J) {  // column-major 2 x 2
    J[0] = 0.0;                                  // d f1 / d y1
    J[1] = (-2.0 * y[0] * y[1] - 1.0) / eps;     // d f2 / d y1
    J[2] = 1.0;                                  // d f1 / d y2
    J[3] = (1.0 - y[0] * y[0]) / eps;            // d f2 / d y2
    return true;
  };
  return p;
}

/// Published reference for y(0) = (2, 0), eps = 1e-6, t = 2 (scaled form): E. Hairer's
/// "exact" values for VDPOL (testset/stiff/vdpol/res_exact_pic, the t = 2 entry):
///   y1 = 0.1706167732170456e+01, y2 = -0.8928097010248257e+00.
/// The Bari "Test Set for IVP Solvers" (Mazzia & Magherini, release 2.x, problem VDPOL, which
/// stores y2 scaled by sqrt(eps)) gives 0.1706167732170469e+01, -0.8928097010248125e+00;
/// the two agree to 1.5e-14 relative, which bounds the uncertainty of the reference.
inline ReferenceProblem van_der_pol_published() {
  ReferenceProblem r;
  r.name = "vdpol y0=(2,0)";
  r.problem = van_der_pol_system(1e-6);
  r.t0 = 0.0;
  r.t_end = 2.0;
  r.y0 = Eigen::Vector2d(2.0, 0.0);
  r.y_ref = Eigen::Vector2d(0.1706167732170456e+01, -0.8928097010248257e+00);
  r.ref_source = "Hairer, VDPOL res_exact_pic (t=2); Bari test set VDPOL agrees to 1.5e-14";
  return r;
}

/// The configuration of issue 3 and of the RADAU5 driver: y(0) = (2, -0.66), eps = 1e-6, t = 2.
/// No published reference for exactly this configuration was found (the published drivers print
/// low-tolerance results only). y_ref was COMPUTED with this project's integrator at
/// rtol = atol = 1e-13 (analytic Jacobian) by
///   build/bench_radau --reference
/// which prints (1.7061674375430473, -0.89281001655124981) for both kernels (bitwise equal since
/// the port calls the same LAPACK/BLAS; the first kernel version gave (1.7061674375430462,
/// -0.89281001655149383) and (...0262, ...51049), i.e. rounding alone moves y_ref by ~3e-13).
/// The same run from y(0) = (2, 0) misses the published value below by 2.4e-13, which
/// estimates the error of y_ref: ~3e-13 relative, 12.5 digits. Independent cross-check
/// (test vdpol_computed_reference_is_consistent_with_published_neighbour): the published (2, 0)
/// value plus the initial-layer asymptotics predicts y_ref - y_pub = (-2.9463e-7, -3.1553e-7),
/// which y_ref meets to ~1e-6 of that shift (~3e-13 absolute).
inline constexpr double kVdpM066Ref1 = 1.7061674375430473e+00;
inline constexpr double kVdpM066Ref2 = -8.9281001655124981e-01;
inline ReferenceProblem van_der_pol_issue() {
  ReferenceProblem r;
  r.name = "vdpol y0=(2,-0.66)";
  r.problem = van_der_pol_system(1e-6);
  r.t0 = 0.0;
  r.t_end = 2.0;
  r.y0 = Eigen::Vector2d(2.0, -0.66);
  r.y_ref = Eigen::Vector2d(kVdpM066Ref1, kVdpM066Ref2);
  r.ref_source = "computed: this integrator, rtol=atol=1e-13, both kernels (bench_radau --reference)";
  return r;
}

// ---------------------------------------------------------------------------------------------
// Robertson's chemical kinetics (Hairer & Wanner II, IV.1 and IV.10 problem ROBER; Bari test set
// problem ROBER):
//   y1' = -0.04 y1 + 1e4 y2 y3,  y2' = 0.04 y1 - 1e4 y2 y3 - 3e7 y2^2,  y3' = 3e7 y2^2,
//   y(0) = (1, 0, 0), t in [0, 1e11].  y1 + y2 + y3 = 1 is a linear invariant.
// Reference at t = 1e11: Bari "Test Set for IVP Solvers" (Mazzia & Magherini, release 2.x),
// problem ROBER, routine solut in rober.f (the same values appear in many independent test
// suites that cite it):
//   y1 = 0.2083340149701255e-07, y2 = 0.8333360770334713e-13, y3 = 0.9999999791665050e+00.
// ---------------------------------------------------------------------------------------------
inline ReferenceProblem robertson() {
  ReferenceProblem r;
  r.name = "robertson";
  OdeProblem& p = r.problem;
  p.n = 3;
  p.rhs = [](double, const double* y, double* f) {
    f[0] = -0.04 * y[0] + 1.0e4 * y[1] * y[2];
    f[2] = 3.0e7 * y[1] * y[1];
    f[1] = -f[0] - f[2];
    return true;
  };
  p.jacobian = [](double, const double* y, double* J) {  // column-major 3 x 3
    J[0] = -0.04;  J[3] = 1.0e4 * y[2];                   J[6] = 1.0e4 * y[1];
    J[1] = 0.04;   J[4] = -1.0e4 * y[2] - 6.0e7 * y[1];   J[7] = -1.0e4 * y[1];
    J[2] = 0.0;    J[5] = 6.0e7 * y[1];                   J[8] = 0.0;
    return true;
  };
  r.t0 = 0.0;
  r.t_end = 1.0e11;
  r.y0 = Eigen::Vector3d(1.0, 0.0, 0.0);
  r.y_ref = Eigen::Vector3d(0.2083340149701255e-07, 0.8333360770334713e-13, 0.9999999791665050e+00);
  r.ref_source = "Bari Test Set for IVP Solvers, problem ROBER, t = 1e11";
  return r;
}

// ---------------------------------------------------------------------------------------------
// An index-1 DAE with an exact solution, constructed for these tests. Unknowns (y1, y2, y3, z),
// K = diag(1, 1, 1, 0):
//   y1' = z y2
//   y2' = -z y1
//   y3' = -1e4 (y3 - y1) + z y2          (stiff: eigenvalue -1e4)
//   0   = z^3 + z - p(t) (y1^2 + y2^2),  p(t) = ze(t)^3 + ze(t),  ze(t) = 1 + t/2
// dg/dz = 3 z^2 + 1 > 0, so z is an index-1 algebraic variable; the constraint is nonlinear in
// z and couples it to y. Since y1^2 + y2^2 is invariant, the exact solution from
// (1, 0, 1, 1) is, with theta(t) = t + t^2/4:
//   y1 = cos(theta), y2 = -sin(theta), y3 = cos(theta), z = 1 + t/2.
// ---------------------------------------------------------------------------------------------
inline Eigen::Vector4d index1_dae_exact(double t) {
  const double th = t + 0.25 * t * t;
  return Eigen::Vector4d(std::cos(th), -std::sin(th), std::cos(th), 1.0 + 0.5 * t);
}

inline ReferenceProblem index1_dae() {
  ReferenceProblem r;
  r.name = "index-1 DAE";
  OdeProblem& p = r.problem;
  p.n = 4;
  auto pt = [](double t) {
    const double ze = 1.0 + 0.5 * t;
    return ze * ze * ze + ze;
  };
  p.rhs = [pt](double t, const double* y, double* f) {
    const double z = y[3];
    f[0] = z * y[1];
    f[1] = -z * y[0];
    f[2] = -1.0e4 * (y[2] - y[0]) + z * y[1];
    f[3] = z * z * z + z - pt(t) * (y[0] * y[0] + y[1] * y[1]);
    return true;
  };
  p.jacobian = [pt](double t, const double* y, double* J) {  // column-major 4 x 4
    const double z = y[3];
    const double q = pt(t);
    Eigen::Map<Eigen::Matrix4d> M(J);
    M << 0.0, z, 0.0, y[1],
        -z, 0.0, 0.0, -y[0],
        1.0e4, z, -1.0e4, y[1],
        -2.0 * q * y[0], -2.0 * q * y[1], 0.0, 3.0 * z * z + 1.0;
    return true;
  };
  p.mass = Eigen::Vector4d(1.0, 1.0, 1.0, 0.0).asDiagonal();
  r.t0 = 0.0;
  r.t_end = 3.0;
  r.y0 = index1_dae_exact(0.0);
  r.y_ref = index1_dae_exact(r.t_end);
  r.ref_source = "exact solution (constructed)";
  return r;
}

// ---------------------------------------------------------------------------------------------
// Planar pendulum: point mass m on a massless rod of length L about the origin, gravity g along
// -y; phi is the angle from the downward vertical, x = L sin(phi), y = -L cos(phi).
// Constraint c = (x^2 + y^2 - L^2)/2 = 0, reaction -lambda (x, y); the rod tension is
// T = lambda L = m (g cos(phi) + L phi'^2).
// ---------------------------------------------------------------------------------------------
struct PendulumParameters {
  double m = 1.5;
  double L = 0.8;
  double g = 9.81;
  double phi0 = 1.2;  ///< released at rest from this angle [rad] (about 69 degrees)
};

/// Index-1 DAE, 5 unknowns u = (x, y, vx, vy, lambda), K = diag(1, 1, 1, 1, 0):
///   x' = vx,  y' = vy,  m vx' = -lambda x,  m vy' = -m g - lambda y,
///   0 = vx^2 + vy^2 - g y - lambda (x^2 + y^2) / m
/// (the constraint differentiated twice, x x'' + y y'' + |v|^2 = 0, with the accelerations
/// substituted: the multiplier is eliminated at acceleration level; d/dlambda = -L^2/m != 0).
inline ReferenceProblem pendulum_dae(const PendulumParameters& P = {}) {
  ReferenceProblem r;
  r.name = "pendulum DAE (x,y,v,lambda)";
  OdeProblem& p = r.problem;
  p.n = 5;
  const double m = P.m, g = P.g;
  p.rhs = [m, g](double, const double* u, double* f) {
    const double x = u[0], y = u[1], vx = u[2], vy = u[3], lam = u[4];
    f[0] = vx;
    f[1] = vy;
    f[2] = -lam * x / m;
    f[3] = -g - lam * y / m;
    f[4] = vx * vx + vy * vy - g * y - lam * (x * x + y * y) / m;
    return true;
  };
  p.jacobian = [m, g](double, const double* u, double* J) {  // column-major 5 x 5
    const double x = u[0], y = u[1], vx = u[2], vy = u[3], lam = u[4];
    Eigen::Map<Eigen::Matrix<double, 5, 5>> M(J);
    M.setZero();
    M(0, 2) = 1.0;
    M(1, 3) = 1.0;
    M(2, 0) = -lam / m;  M(2, 4) = -x / m;
    M(3, 1) = -lam / m;  M(3, 4) = -y / m;
    M(4, 0) = -2.0 * lam * x / m;
    M(4, 1) = -g - 2.0 * lam * y / m;
    M(4, 2) = 2.0 * vx;
    M(4, 3) = 2.0 * vy;
    M(4, 4) = -(x * x + y * y) / m;
    return true;
  };
  Eigen::VectorXd k = Eigen::VectorXd::Ones(5);
  k(4) = 0.0;
  p.mass = k.asDiagonal();
  r.t0 = 0.0;
  r.t_end = 5.0;  // about 2.5 periods
  r.y0.resize(5);
  const double x0 = P.L * std::sin(P.phi0), y0 = -P.L * std::cos(P.phi0);
  r.y0 << x0, y0, 0.0, 0.0, P.m * P.g * std::cos(P.phi0) / P.L;  // consistent lambda
  r.ref_source = "exact minimal-coordinate solution (Jacobi elliptic functions)";
  return r;
}

/// The same pendulum in the engine's DAE form y = (q, v, a, R): 7 unknowns
/// u = (x, y, vx, vy, ax, ay, lambda), K = diag(1, 1, 1, 1, 0, 0, 0):
///   x' = vx, y' = vy, vx' = ax, vy' = ay,
///   0 = m ax + lambda x,  0 = m ay + m g + lambda y,  0 = x ax + y ay + vx^2 + vy^2.
/// The algebraic block d(g)/d(ax, ay, lambda) has determinant -m L^2 != 0: index 1.
inline ReferenceProblem pendulum_dae_accel(const PendulumParameters& P = {}) {
  ReferenceProblem r;
  r.name = "pendulum DAE (q,v,a,lambda)";
  OdeProblem& p = r.problem;
  p.n = 7;
  const double m = P.m, g = P.g;
  p.rhs = [m, g](double, const double* u, double* f) {
    const double x = u[0], y = u[1], vx = u[2], vy = u[3], ax = u[4], ay = u[5], lam = u[6];
    f[0] = vx;
    f[1] = vy;
    f[2] = ax;
    f[3] = ay;
    f[4] = -(m * ax + lam * x);
    f[5] = -(m * ay + m * g + lam * y);
    f[6] = x * ax + y * ay + vx * vx + vy * vy;
    return true;
  };
  p.jacobian = [m](double, const double* u, double* J) {  // column-major 7 x 7
    const double x = u[0], y = u[1], vx = u[2], vy = u[3], ax = u[4], ay = u[5], lam = u[6];
    Eigen::Map<Eigen::Matrix<double, 7, 7>> M(J);
    M.setZero();
    M(0, 2) = 1.0;
    M(1, 3) = 1.0;
    M(2, 4) = 1.0;
    M(3, 5) = 1.0;
    M(4, 0) = -lam;  M(4, 4) = -m;  M(4, 6) = -x;
    M(5, 1) = -lam;  M(5, 5) = -m;  M(5, 6) = -y;
    M(6, 0) = ax;  M(6, 1) = ay;  M(6, 2) = 2.0 * vx;  M(6, 3) = 2.0 * vy;
    M(6, 4) = x;   M(6, 5) = y;
    return true;
  };
  Eigen::VectorXd k = Eigen::VectorXd::Zero(7);
  k.head(4).setOnes();
  p.mass = k.asDiagonal();
  r.t0 = 0.0;
  r.t_end = 5.0;
  const double x0 = P.L * std::sin(P.phi0), y0 = -P.L * std::cos(P.phi0);
  const double lam0 = P.m * P.g * std::cos(P.phi0) / P.L;
  r.y0.resize(7);
  r.y0 << x0, y0, 0.0, 0.0, -lam0 * x0 / P.m, -P.g - lam0 * y0 / P.m, lam0;
  r.ref_source = "exact minimal-coordinate solution (Jacobi elliptic functions)";
  return r;
}

/// Minimal-coordinate state of the pendulum.
struct PendulumState {
  double phi = 0.0;
  double phidot = 0.0;
};

/// EXACT solution of phi'' = -(g/L) sin(phi), phi(0) = phi0 in (0, pi), phi'(0) = 0:
///   sin(phi/2) = k sn(K(k) - w t, k),  k = sin(phi0/2),  w = sqrt(g/L),
///   phi' = -2 k w cn(u, k) dn(u, k) / cos(phi/2),  u = K(k) - w t
/// (differentiate the first line; at t = 0, sn(K) = 1, cn(K) = 0). Boost.Math's ellint_1 and
/// jacobi_elliptic evaluate K and sn, cn, dn to a few ulps.
inline PendulumState pendulum_exact(const PendulumParameters& P, double t) {
  const double k = std::sin(0.5 * P.phi0);
  const double w = std::sqrt(P.g / P.L);
  const double K = boost::math::ellint_1(k);
  const double u = K - w * t;
  double cn = 0.0, dn = 0.0;
  const double sn = boost::math::jacobi_elliptic(k, u, &cn, &dn);
  PendulumState s;
  s.phi = 2.0 * std::asin(k * sn);
  s.phidot = -2.0 * k * w * cn * dn / std::cos(0.5 * s.phi);
  return s;
}

/// INDEPENDENT second oracle for the same: classical RK4 on (phi, phi') with n steps and with
/// 2n steps, combined by Richardson extrapolation (16 y_{h/2} - y_h) / 15, which cancels the
/// leading h^4 term of the global error, leaving O(h^5). Shares no code with pendulum_exact.
inline PendulumState pendulum_rk4_richardson(const PendulumParameters& P, double t, long n) {
  const double w2 = P.g / P.L;
  auto f = [w2](const Eigen::Vector2d& s) { return Eigen::Vector2d(s(1), -w2 * std::sin(s(0))); };
  auto rk4 = [&f](Eigen::Vector2d s, double T, long steps) {
    const double h = T / static_cast<double>(steps);
    for (long i = 0; i < steps; ++i) {
      const Eigen::Vector2d k1 = f(s);
      const Eigen::Vector2d k2 = f(s + 0.5 * h * k1);
      const Eigen::Vector2d k3 = f(s + 0.5 * h * k2);
      const Eigen::Vector2d k4 = f(s + h * k3);
      s += (h / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    }
    return s;
  };
  const Eigen::Vector2d s0(P.phi0, 0.0);
  const Eigen::Vector2d coarse = rk4(s0, t, n);
  const Eigen::Vector2d fine = rk4(s0, t, 2 * n);
  const Eigen::Vector2d ex = (16.0 * fine - coarse) / 15.0;
  return PendulumState{ex(0), ex(1)};
}

/// Cartesian position, velocity and multiplier of the pendulum at minimal-coordinate state s.
/// Returns (x, y, vx, vy, lambda) with lambda = T / L = m (g cos(phi) + L phi'^2) / L.
inline Eigen::Matrix<double, 5, 1> pendulum_cartesian(const PendulumParameters& P,
                                                      const PendulumState& s) {
  Eigen::Matrix<double, 5, 1> c;
  const double sp = std::sin(s.phi), cp = std::cos(s.phi);
  c << P.L * sp, -P.L * cp, P.L * cp * s.phidot, P.L * sp * s.phidot,
      P.m * (P.g * cp + P.L * s.phidot * s.phidot) / P.L;
  return c;
}

// ---------------------------------------------------------------------------------------------
// Error measures.
// ---------------------------------------------------------------------------------------------

/// max_i |y_i - ref_i| / |ref_i| (every reference component here is nonzero).
inline double max_relative_error(const Eigen::VectorXd& y, const Eigen::VectorXd& ref) {
  double e = 0.0;
  for (Eigen::Index i = 0; i < ref.size(); ++i)
    e = std::max(e, std::abs(y(i) - ref(i)) / std::abs(ref(i)));
  return e;
}

/// Significant correct digits: -log10 of the max relative error (capped at 16).
inline double correct_digits(const Eigen::VectorXd& y, const Eigen::VectorXd& ref) {
  const double e = max_relative_error(y, ref);
  return e > 0.0 ? std::min(16.0, -std::log10(e)) : 16.0;
}

/// Agreement of two kernels' results, componentwise: |a_i - b_i| / max(|a_i|, |b_i|, floor).
inline double kernel_disagreement(const Eigen::VectorXd& a, const Eigen::VectorXd& b,
                                  double floor = std::numeric_limits<double>::min()) {
  double e = 0.0;
  for (Eigen::Index i = 0; i < a.size(); ++i) {
    const double s = std::max({std::abs(a(i)), std::abs(b(i)), floor});
    e = std::max(e, std::abs(a(i) - b(i)) / s);
  }
  return e;
}

// ---------------------------------------------------------------------------------------------
// Running with a trace of the accepted steps.
// ---------------------------------------------------------------------------------------------

/// The result of one integration plus (t, y) after every accepted step.
struct TracedRun {
  RadauResult result;
  std::vector<double> t;           ///< end time of each accepted step
  std::vector<Eigen::VectorXd> y;  ///< solution after each accepted step
};

/// Integrates rp from rp.t0 to rp.t_end with the given kernel and scalar tolerances, recording
/// every accepted step; `extra` (optional) is called on each step as well.
inline TracedRun run_traced(const ReferenceProblem& rp, Kernel kernel, double rtol, double atol,
                            const std::function<void(const StepInfo&)>& extra = {},
                            RadauOptions options = {}) {
  options.kernel = kernel;
  options.rtol = rtol;
  options.atol = atol;
  TracedRun run;
  run.result = radau_integrate(rp.problem, rp.t0, rp.y0, rp.t_end, options,
                               [&run, &extra](StepInfo& s) {
                                 run.t.push_back(s.t);
                                 run.y.emplace_back(Eigen::Map<const Eigen::VectorXd>(s.y, s.n));
                                 if (extra) extra(s);
                                 return StepAction::proceed;
                               });
  return run;
}

/// The largest relative difference between two traced runs over all accepted steps: step end
/// times, and solutions componentwise scaled by max(|a_i|, |b_i|, floor); +infinity if they
/// took different numbers of steps.
inline double trace_disagreement(const TracedRun& a, const TracedRun& b, double floor) {
  if (a.t.size() != b.t.size()) return std::numeric_limits<double>::infinity();
  double e = kernel_disagreement(a.result.y, b.result.y, floor);
  for (std::size_t k = 0; k < a.t.size(); ++k) {
    e = std::max(e, std::abs(a.t[k] - b.t[k]) / std::max(std::abs(a.t[k]), std::abs(b.t[k])));
    e = std::max(e, kernel_disagreement(a.y[k], b.y[k], floor));
  }
  return e;
}

/// RADAU5's tolerance transformation, which fortran/radau.f documents and both kernels apply:
/// the local error is controlled against rtol' = 0.1 rtol^(2/3) (calibrated so that the global
/// error of dissipative stiff problems lands near rtol).
inline double transformed_rtol(double rtol) { return 0.1 * std::pow(rtol, 2.0 / 3.0); }

}  // namespace pcsim::testproblems
