// Helpers of the steady-state tests: linear model files written from matrices, and the exact
// frequency response and Floquet multipliers of a linear system computed from them directly.
#pragma once

#include <complex>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "common/eigen_instances.hpp"
#include <Eigen/Eigenvalues>
#include "common/eigen_instances.hpp"

#include "common/format.hpp"

namespace pcsim::steady::testing {

/// A linear forced system M q̈ + C q̇ + K q = Fc cos(omega t) + Fs sin(omega t) as a model
/// file: T = ½ q̇ᵀ M q̇, the rest as generalized forces (K and C need not be symmetric), with the
/// given holonomic constraints (name, expression) and period 2 pi/omega.
inline std::string linear_model_text(const std::vector<std::string>& names, const Eigen::MatrixXd& M,
                                     const Eigen::MatrixXd& C, const Eigen::MatrixXd& K,
                                     const Eigen::VectorXd& Fc, const Eigen::VectorXd& Fs,
                                     double omega,
                                     const std::vector<std::pair<std::string, std::string>>& constraints = {}) {
  const int n = static_cast<int>(names.size());
  auto num = [](double v) { return "(" + format_number(v) + ")"; };
  std::ostringstream os;
  os << "[model]\nname = \"linear\"\ncoordinates = [";
  for (int i = 0; i < n; ++i) os << (i ? ", " : "") << '"' << names[i] << '"';
  os << "]\nperiod = \"2*pi/omega\"\n\n[model.parameters]\nomega = " << format_number(omega)
     << "\n\n[model.energy]\nkinetic = \"0.5*(";
  bool first = true;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      if (M(i, j) == 0) continue;
      os << (first ? "" : " + ") << num(M(i, j)) << "*" << names[i] << "_d*" << names[j] << "_d";
      first = false;
    }
  os << ")\"\n\n[model.forces]\n";
  for (int i = 0; i < n; ++i) {
    os << names[i] << " = \"" << num(Fc[i]) << "*cos(omega*t) + " << num(Fs[i]) << "*sin(omega*t)";
    for (int j = 0; j < n; ++j) {
      if (K(i, j) != 0) os << " - " << num(K(i, j)) << "*" << names[j];
      if (C(i, j) != 0) os << " - " << num(C(i, j)) << "*" << names[j] << "_d";
    }
    os << "\"\n";
  }
  for (const auto& [name, expr] : constraints)
    os << "\n[[model.constraint]]\nname = \"" << name << "\"\nholonomic = \"" << expr << "\"\n";
  return os.str();
}

/// The complex amplitudes Q = (K − ω² M + i ω C)⁻¹ (Fc − i Fs): q(t) = Re(Q e^{iωt}).
inline Eigen::VectorXcd transfer(const Eigen::MatrixXd& M, const Eigen::MatrixXd& C,
                                 const Eigen::MatrixXd& K, const Eigen::VectorXd& Fc,
                                 const Eigen::VectorXd& Fs, double omega) {
  const std::complex<double> i(0, 1);
  const Eigen::MatrixXcd H = K.cast<std::complex<double>>() - omega * omega * M.cast<std::complex<double>>() +
                             i * omega * C.cast<std::complex<double>>();
  const Eigen::VectorXcd F = Fc.cast<std::complex<double>>() - i * Fs.cast<std::complex<double>>();
  return H.fullPivLu().solve(F);
}

/// exp(λ T) for the eigenvalues λ of the first-order system y' = [[0, I], [−M⁻¹K, −M⁻¹C]] y.
inline Eigen::VectorXcd exact_multipliers(const Eigen::MatrixXd& M, const Eigen::MatrixXd& C,
                                          const Eigen::MatrixXd& K, double T) {
  const int n = static_cast<int>(M.rows());
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  A.topRightCorner(n, n).setIdentity();
  A.bottomLeftCorner(n, n) = -M.lu().solve(K);
  A.bottomRightCorner(n, n) = -M.lu().solve(C);
  const Eigen::VectorXcd lambda = Eigen::EigenSolver<Eigen::MatrixXd>(A).eigenvalues();
  return (lambda * T).array().exp().matrix();
}

/// The largest distance from a multiplier of `got` to the nearest of `want` (both sets equal
/// size), matching greedily: 0 when the sets coincide.
inline double set_distance(const std::vector<std::complex<double>>& got, Eigen::VectorXcd want) {
  double worst = 0;
  std::vector<bool> used(want.size(), false);
  for (const auto& g : got) {
    int best = -1;
    double d = 1e300;
    for (int j = 0; j < want.size(); ++j)
      if (!used[j] && std::abs(g - want[j]) < d) d = std::abs(g - want[j]), best = j;
    if (best >= 0) used[best] = true;
    worst = std::max(worst, d);
  }
  return worst;
}

}  // namespace pcsim::steady::testing
