// Problems with exact or published solutions for the explicit Runge-Kutta tests and benchmark:
// the nonlinear problem of Hairer, Norsett & Wanner with its exact solution, the Arenstorf
// orbit (periodic, published period and initial values), a falling body, and forced damped
// oscillators with the sieve's eigenvalues (closed-form solution). Shared by
// tests/ode/test_*.cpp and bench/bench_explicit.cpp.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "common/eigen_instances.hpp"

#include "ode/explicit_rk.hpp"

namespace pcsim::explicit_problems {

// ---------------------------------------------------------------------------------------------
// Hairer, Norsett & Wanner, Solving ODEs I (section II.10, the test problem for the order of
// DOPRI methods): y1' = 2t y2^(1/5) y4, y2' = 10t exp(5(y3 - 1)) y4, y3' = 2t y4,
// y4' = -2t log(y1), y(0) = (1, 1, 1, 1), with the exact solution
//   y1 = exp(sin t^2), y2 = exp(5 sin t^2), y3 = sin t^2 + 1, y4 = cos t^2.
// Nonlinear and non-autonomous, so it exercises every order condition, not only the linear ones.
// ---------------------------------------------------------------------------------------------
inline OdeProblem hnw_exact_problem() {
  OdeProblem p;
  p.n = 4;
  p.rhs = [](double t, const double* y, double* f) {
    if (!(y[0] > 0.0) || !(y[1] > 0.0)) return false;  // outside the domain of log and ^(1/5)
    f[0] = 2.0 * t * std::pow(y[1], 0.2) * y[3];
    f[1] = 10.0 * t * std::exp(5.0 * (y[2] - 1.0)) * y[3];
    f[2] = 2.0 * t * y[3];
    f[3] = -2.0 * t * std::log(y[0]);
    return true;
  };
  return p;
}
inline Eigen::VectorXd hnw_exact_solution(double t) {
  const double s = std::sin(t * t);
  Eigen::VectorXd y(4);
  y << std::exp(s), std::exp(5.0 * s), s + 1.0, std::cos(t * t);
  return y;
}

// ---------------------------------------------------------------------------------------------
// The Arenstorf orbit (restricted three-body problem, Hairer, Norsett & Wanner I, II.0, eq.
// (0.1)): mu = 0.012277471, y(0) = (0.994, 0, 0, -2.00158510637908252240537862224); the
// solution is periodic with period T = 17.0652165601579625588917206249, so y(T) = y(0) is the
// published reference.
// ---------------------------------------------------------------------------------------------
constexpr double kArenstorfMu = 0.012277471;
constexpr double kArenstorfPeriod = 17.0652165601579625588917206249;
inline OdeProblem arenstorf_problem() {
  OdeProblem p;
  p.n = 4;
  p.rhs = [](double, const double* y, double* f) {
    const double mu = kArenstorfMu, mu1 = 1.0 - mu;
    const double d1 = std::pow((y[0] + mu) * (y[0] + mu) + y[1] * y[1], 1.5);
    const double d2 = std::pow((y[0] - mu1) * (y[0] - mu1) + y[1] * y[1], 1.5);
    f[0] = y[2];
    f[1] = y[3];
    f[2] = y[0] + 2.0 * y[3] - mu1 * (y[0] + mu) / d1 - mu * (y[0] - mu1) / d2;
    f[3] = y[1] - 2.0 * y[2] - mu1 * y[1] / d1 - mu * y[1] / d2;
    return true;
  };
  return p;
}
inline Eigen::VectorXd arenstorf_y0() {
  Eigen::VectorXd y(4);
  y << 0.994, 0.0, 0.0, -2.00158510637908252240537862224;
  return y;
}

// ---------------------------------------------------------------------------------------------
// A body falling from height H: (x, v)' = (v, -g); x(t) = H - g t^2 / 2 reaches 0 at
// t* = sqrt(2 H / g). The solution is a polynomial of degree 2, which the method and its dense
// output reproduce to rounding, so the event time is limited only by the location tolerance.
// ---------------------------------------------------------------------------------------------
inline OdeProblem falling_body(double g) {
  OdeProblem p;
  p.n = 2;
  p.rhs = [g](double, const double* y, double* f) {
    f[0] = y[1];
    f[1] = -g;
    return true;
  };
  return p;
}

// ---------------------------------------------------------------------------------------------
// Four forced, damped oscillators x_j'' + 2 s_j x_j' + (s_j^2 + w_j^2) x_j = F cos(W t), whose
// eigenvalues -s_j +- i w_j have the real parts of the sieve's linearized desk (-249, -44, -5.5,
// -0.5 1/s; issue 14), forced at the sieve's excitation frequency W = 280 rad/s. Not stiff at
// engineering tolerances (the real parts are moderate against the forcing frequency), and it
// has a closed-form solution: y = (x_1, v_1, ..., x_4, v_4).
// ---------------------------------------------------------------------------------------------
struct Oscillators {
  double s[4] = {249.0, 44.0, 5.5, 0.5};
  double w[4] = {300.0, 120.0, 60.0, 20.0};
  double force = 100.0;
  double omega = 280.0;
};
inline OdeProblem oscillators_problem(const Oscillators& o = {}) {
  OdeProblem p;
  p.n = 8;
  p.rhs = [o](double t, const double* y, double* f) {
    const double c = o.force * std::cos(o.omega * t);
    for (int j = 0; j < 4; ++j) {
      f[2 * j] = y[2 * j + 1];
      f[2 * j + 1] = c - 2.0 * o.s[j] * y[2 * j + 1] - (o.s[j] * o.s[j] + o.w[j] * o.w[j]) * y[2 * j];
    }
    return true;
  };
  return p;
}
/// Closed form from x(0) = v(0) = 0: the steady state a cos(W t) + b sin(W t) plus the decaying
/// homogeneous solution exp(-s t)(c cos(w t) + d sin(w t)) that matches the initial values.
inline Eigen::VectorXd oscillators_solution(double t, const Oscillators& o = {}) {
  Eigen::VectorXd y(8);
  for (int j = 0; j < 4; ++j) {
    const double k = o.s[j] * o.s[j] + o.w[j] * o.w[j];
    const double re = k - o.omega * o.omega, im = 2.0 * o.s[j] * o.omega;
    const double den = re * re + im * im;
    const double a = o.force * re / den, b = o.force * im / den;  // x_p = a cos + b sin
    const double c = -a;                                           // x(0) = 0
    const double d = (-b * o.omega + o.s[j] * c) / o.w[j];         // v(0) = 0
    const double e = std::exp(-o.s[j] * t), cw = std::cos(o.w[j] * t), sw = std::sin(o.w[j] * t);
    const double cW = std::cos(o.omega * t), sW = std::sin(o.omega * t);
    y[2 * j] = a * cW + b * sW + e * (c * cw + d * sw);
    y[2 * j + 1] = o.omega * (-a * sW + b * cW) +
                   e * ((-o.s[j] * c + o.w[j] * d) * cw + (-o.s[j] * d - o.w[j] * c) * sw);
  }
  return y;
}

/// Largest componentwise error relative to max(|ref|, floor).
inline double scaled_error(const Eigen::VectorXd& y, const Eigen::VectorXd& ref, double floor) {
  double e = 0.0;
  for (Eigen::Index i = 0; i < y.size(); ++i)
    e = std::max(e, std::abs(y[i] - ref[i]) / std::max(std::abs(ref[i]), floor));
  return e;
}

/// Every accepted step of a run: (t, y) after the callback, for comparing kernels.
struct Trace {
  std::vector<double> t;
  std::vector<Eigen::VectorXd> y;
};
inline StepCallback recorder(Trace& tr) {
  return [&tr](StepInfo& s) {
    tr.t.push_back(s.t);
    tr.y.emplace_back(Eigen::Map<const Eigen::VectorXd>(s.y, s.n));
    return StepAction::proceed;
  };
}

}  // namespace pcsim::explicit_problems
