// Helpers of the modes tests: a 2-DOF spring-mass-damper chain as a case text (wall - k1,c1 -
// m1 - k2,c2 - m2 - k3,c3 - wall, optionally forced F cos(omega t) on m1), its M, C, K, and
// the roots of its characteristic polynomial det(lambda^2 M + lambda C + K) = 0 by the
// companion matrix of the quartic (independent of pcsim's first-order form).
#pragma once

#include <complex>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "common/eigen_instances.hpp"
#include <Eigen/Eigenvalues>
#include "common/eigen_instances.hpp"

#include "common/format.hpp"

namespace pcsim::modes::testing {

struct Chain {
  double m1 = 1, m2 = 2, k1 = 100, k2 = 50, k3 = 0, c1 = 0, c2 = 0, c3 = 0, F = 0, omega = 0;
};

/// The chain's model file (inline [model]) as a case: at rest at x = 0.
inline std::string chain_case(const Chain& c) {
  auto n = [](double v) { return format_number(v); };
  std::ostringstream os;
  os << "[model]\nname = \"chain\"\ncoordinates = [\"x1\", \"x2\"]\n";
  if (c.omega > 0) os << "period = \"2*pi/omega\"\n";
  os << "\n[model.parameters]\n";
  os << "m1 = " << n(c.m1) << "\nm2 = " << n(c.m2) << "\nk1 = " << n(c.k1) << "\nk2 = " << n(c.k2)
     << "\nk3 = " << n(c.k3) << "\nc1 = " << n(c.c1) << "\nc2 = " << n(c.c2) << "\nc3 = " << n(c.c3)
     << "\nF = " << n(c.F) << "\n";
  if (c.omega > 0) os << "omega = " << n(c.omega) << "\n";
  os << "\n[model.energy]\nkinetic = \"0.5*m1*x1_d^2 + 0.5*m2*x2_d^2\"\n"
     << "potential = \"0.5*k1*x1^2 + 0.5*k2*(x2 - x1)^2 + 0.5*k3*x2^2\"\n"
     << "dissipation = \"0.5*c1*x1_d^2 + 0.5*c2*(x2_d - x1_d)^2 + 0.5*c3*x2_d^2\"\n";
  if (c.omega > 0) os << "\n[model.forces]\nx1 = \"F*cos(omega*t)\"\n";
  return os.str();
}

inline void write(const std::filesystem::path& p, const std::string& text) {
  std::ofstream out(p);
  out << text;
}

/// The roots of det(lambda^2 M + lambda C + K) for the chain: the quartic's coefficients in
/// closed form, its roots as the eigenvalues of the companion matrix.
inline std::vector<std::complex<double>> chain_roots(const Chain& c) {
  const double k11 = c.k1 + c.k2, k22 = c.k2 + c.k3, k12 = -c.k2;
  const double c11 = c.c1 + c.c2, c22 = c.c2 + c.c3, c12 = -c.c2;
  // (m1 l^2 + c11 l + k11)(m2 l^2 + c22 l + k22) - (c12 l + k12)^2
  const double a4 = c.m1 * c.m2, a3 = c.m1 * c22 + c11 * c.m2,
               a2 = c.m1 * k22 + c11 * c22 + k11 * c.m2 - c12 * c12, a1 = c11 * k22 + k11 * c22 - 2 * c12 * k12,
               a0 = k11 * k22 - k12 * k12;
  Eigen::Matrix4d comp = Eigen::Matrix4d::Zero();
  comp(0, 0) = -a3 / a4;
  comp(0, 1) = -a2 / a4;
  comp(0, 2) = -a1 / a4;
  comp(0, 3) = -a0 / a4;
  comp(1, 0) = comp(2, 1) = comp(3, 2) = 1.0;
  const Eigen::Vector4cd r = Eigen::EigenSolver<Eigen::MatrixXd>(Eigen::MatrixXd(comp)).eigenvalues();
  return {r[0], r[1], r[2], r[3]};
}

/// The largest distance from each of `got` to its nearest in `want` and back (0: equal sets).
inline double set_distance(const std::vector<std::complex<double>>& got, const std::vector<std::complex<double>>& want) {
  double worst = 0;
  for (int pass = 0; pass < 2; ++pass) {
    const auto& a = pass ? want : got;
    const auto& b = pass ? got : want;
    for (const auto& x : a) {
      double best = 1e300;
      for (const auto& y : b) best = std::min(best, std::abs(x - y));
      worst = std::max(worst, best);
    }
  }
  return worst;
}

}  // namespace pcsim::modes::testing
