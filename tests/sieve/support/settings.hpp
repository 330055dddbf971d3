// The typed view of a validated sieve case for the sieve's C++ model forms (model.hpp; tests and
// benchmarks only): parameters, initial state, constraints, solver and output settings as plain
// numbers.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "common/kernel.hpp"
#include "mech/simulation.hpp"
#include "sim/case.hpp"
#include <toml++/toml.h>

namespace pcsim::sieve {

/// Coordinate names in model order q = (x, y, theta, s, u, phi) (sieve-model.md section 1).
inline const std::array<const char*, 6> kCoordinateNames = {"x", "y", "theta", "s", "u", "phi"};

/// Physical parameters (SI units), sieve-model.md section 5.
struct SieveParameters {
  double m0 = 1.27, m1 = 400.0, m2 = 0.5;
  double J0 = 0.127e-3, J1 = 200.0, J2 = 0.25e-4;
  double r = 0.1, e = 0.01;
  double cx = 5e4, cy = 5e4, ctheta = 5e4;
  double bx = 1e5, by = 1e5, btheta = 1e4;
  double omega = 280.0, g = 9.81;
  double x0 = 0.10, y0 = 0.20, xc = 0.0, yc = 0.0, xb = 0.0, yb = 0.0;
  double a = 0.50, b = -0.20, u0 = 0.15, f = 0.3;
};

using Form = mech::Form;  ///< ode: y = (q, q̇); dae: y = (q, v, a, R) as in the paper
using mech::to_string;

/// Which constraints are imposed (sieve-model.md section 4).
struct SieveConstraints {
  bool contact = true;      ///< (3.1) u = u0
  bool rolling = true;      ///< (3.2) s + r phi = s(0) + r phi(0) (erratum 7)
  /// (3.2) with the paper's printed sign, s - r phi = s(0) - r phi(0): reproduces results
  /// computed before erratum 7; not physical rolling (the contact point slides at 2 s').
  bool rolling_as_printed = false;
  bool lock_theta = false;  ///< theta = 0 (the desk without incline vibration)
};

struct SolverSettings {
  Kernel kernel = Kernel::fortran;
  Form form = Form::ode;
  double rtol = 1e-6, atol = 1e-8, t_end = 10.0, h0 = 0.0;
};

struct OutputSettings {
  double dt = 1e-3;         ///< time-series sampling interval
  int summary_periods = 5;  ///< the summary window: this many excitation periods at the end
};

/// Everything a run needs, as numbers.
struct SieveSettings {
  SieveParameters p;
  SieveConstraints constraints;
  std::array<double, 6> q0{};   ///< initial coordinates (x, y, theta, s, u, phi)
  std::array<double, 6> qd0{};  ///< initial velocities
  SolverSettings solver;
  OutputSettings output;
};

/// Reads the typed settings out of a validated sieve case table (sim::load_case has checked
/// every key).
SieveSettings settings_from_table(const toml::table& t);
inline SieveSettings settings_from_case(const sim::Case& c) { return settings_from_table(c.table); }

}  // namespace pcsim::sieve
