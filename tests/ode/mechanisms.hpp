// The Test Set's index-3 multibody benchmarks for Radau IIA, written from the published
// equations (Hairer & Wanner, Solving ODEs II, VII.7 "Andrews' squeezer", (7.11); Mazzia &
// Magherini, Test Set for IVP Solvers, problems ANDREWS and CAR AXIS), with the published
// reference solutions at t_end and the Test Set protocol (rtol = atol = h0, scd at t_end).
// Jacobians are exact, by forward-mode automatic differentiation of the same right-hand side
// (Eigen's AutoDiffScalar). Shared by tests/ode/test_radau_mechanisms.cpp and
// bench/bench_radau_mechanisms.cpp.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "common/eigen_instances.hpp"
#include <unsupported/Eigen/AutoDiff>

#include "ode/radau.hpp"

namespace pcsim::testproblems {

/// An index-3 benchmark: the problem (with index counts), y0, t_end, the reference y(t_end).
struct MechanismProblem {
  std::string name;
  OdeProblem problem;
  double t_end = 0.0;
  Eigen::VectorXd y0;
  Eigen::VectorXd y_ref;
  int scd_components = 0;  ///< scd over y[0 .. scd_components) (the positions)
};

/// Significant correct digits as the Test Set defines them: -log10 of the largest relative
/// error over the compared components (absolute error where the reference is 0).
inline double scd(const Eigen::VectorXd& y, const Eigen::VectorXd& ref, int m) {
  double e = 0.0;
  for (int i = 0; i < m; ++i) {
    const double d = std::abs(y[i] - ref[i]);
    e = std::max(e, ref[i] != 0.0 ? d / std::abs(ref[i]) : d);
  }
  return e > 0.0 ? -std::log10(e) : 16.0;
}

namespace detail {

// Fills J (column-major n x n) with df/dy of the template rhs F at (t, y).
template <int N, class F>
void ad_jacobian(const F& f, double t, const double* y, double* J) {
  using AD = Eigen::AutoDiffScalar<Eigen::Matrix<double, N, 1>>;
  AD ya[N], fa[N];
  for (int i = 0; i < N; ++i) ya[i] = AD(y[i], N, i);
  f(t, ya, fa);
  for (int i = 0; i < N; ++i)
    for (int j = 0; j < N; ++j) J[i + N * j] = fa[i].derivatives()[j];
}

// ---- Andrews' squeezer: 7 bodies, y = (q[7], v[7], w[7], lambda[6]).
struct Andrews {
  static constexpr double m1 = .04325, m2 = .00365, m3 = .02373, m4 = .00706, m5 = .07050,
                          m6 = .00706, m7 = .05498;
  static constexpr double i1 = 2.194e-6, i2 = 4.410e-7, i3 = 5.255e-6, i4 = 5.667e-7,
                          i5 = 1.169e-5, i6 = 5.667e-7, i7 = 1.912e-5;
  static constexpr double xa = -.06934, ya = -.00227, xb = -.03635, yb = .03273, xc = .014,
                          yc = .072;
  static constexpr double d = 28e-3, da = 115e-4, e = 2e-2, ea = 1421e-5, rr = 7e-3,
                          ra = 92e-5, ss = 35e-3, sa = 1874e-5, sb = 1043e-5, sc = 18e-3,
                          sd = 2e-2, ta = 2308e-5, tb = 916e-5, u = 4e-2, ua = 1228e-5,
                          ub = 449e-5, zf = 2e-2, zt = 4e-2, fa = 1421e-5;
  static constexpr double mom = 33e-3, c0 = 4530.0, l0 = 7785e-5;

  template <class T>
  void operator()(double, const T* y, T* f) const {
    using std::cos;
    using std::sin;
    using std::sqrt;
    const T* q = y;
    const T* v = y + 7;
    const T* w = y + 14;
    const T* lam = y + 21;
    const T sibe = sin(q[0]), sith = sin(q[1]), siga = sin(q[2]), siph = sin(q[3]),
            side = sin(q[4]), siom = sin(q[5]), siep = sin(q[6]);
    const T cobe = cos(q[0]), coth = cos(q[1]), coga = cos(q[2]), coph = cos(q[3]),
            code = cos(q[4]), coom = cos(q[5]), coep = cos(q[6]);
    const T sibeth = sin(q[0] + q[1]), cobeth = cos(q[0] + q[1]);
    const T siphde = sin(q[3] + q[4]), cophde = cos(q[3] + q[4]);
    const T siomep = sin(q[5] + q[6]), coomep = cos(q[5] + q[6]);
    const double eea = e - ea, zfa = zf - fa;
    // mass matrix M(q), symmetric, block diagonal (2, 1, 2, 2)
    T M[7][7];
    for (auto& row : M)
      for (auto& x : row) x = T(0.0);
    M[0][0] = m1 * ra * ra + m2 * (rr * rr - 2 * da * rr * coth + da * da) + i1 + i2;
    M[1][0] = M[0][1] = m2 * (da * da - da * rr * coth) + i2;
    M[1][1] = T(m2 * da * da + i2);
    M[2][2] = T(m3 * (sa * sa + sb * sb) + i3);
    M[3][3] = T(m4 * eea * eea + i4);
    M[4][3] = M[3][4] = m4 * (eea * eea + zt * eea * siph) + i4;
    M[4][4] = m4 * (zt * zt + 2 * zt * eea * siph + eea * eea) + m5 * (ta * ta + tb * tb) + i4 + i5;
    M[5][5] = T(m6 * zfa * zfa + i6);
    M[6][5] = M[5][6] = m6 * (zfa * zfa - u * zfa * siom) + i6;
    M[6][6] = m6 * (zfa * zfa - 2 * u * zfa * siom + u * u) + m7 * (ua * ua + ub * ub) + i6 + i7;
    // applied forces: driving torque, spring, and the velocity terms
    const T xd = sd * coga + sc * siga + xb, yd = sd * siga - sc * coga + yb;
    const T lang = sqrt((xd - xc) * (xd - xc) + (yd - yc) * (yd - yc));
    const T force = -c0 * (lang - l0) / lang;
    const T fx = force * (xd - xc), fy = force * (yd - yc);
    T ff[7];
    ff[0] = mom - m2 * da * rr * v[1] * (v[1] + 2 * v[0]) * sith;
    ff[1] = m2 * da * rr * v[0] * v[0] * sith;
    ff[2] = fx * (sc * coga - sd * siga) + fy * (sd * coga + sc * siga);
    ff[3] = m4 * zt * eea * v[4] * v[4] * coph;
    ff[4] = -m4 * zt * eea * v[3] * (v[3] + 2 * v[4]) * coph;
    ff[5] = -m6 * u * zfa * v[6] * v[6] * coom;
    ff[6] = m6 * u * zfa * v[5] * (v[5] + 2 * v[6]) * coom;
    // constraint Jacobian G = dg/dq (6 x 7)
    T G[6][7];
    for (auto& row : G)
      for (auto& x : row) x = T(0.0);
    G[0][0] = -rr * sibe + d * sibeth;  G[0][1] = d * sibeth;  G[0][2] = -ss * coga;
    G[1][0] = rr * cobe - d * cobeth;   G[1][1] = -d * cobeth; G[1][2] = -ss * siga;
    G[2][0] = -rr * sibe + d * sibeth;  G[2][1] = d * sibeth;
    G[2][3] = -e * cophde;              G[2][4] = -e * cophde + zt * side;
    G[3][0] = rr * cobe - d * cobeth;   G[3][1] = -d * cobeth;
    G[3][3] = -e * siphde;              G[3][4] = -e * siphde - zt * code;
    G[4][0] = -rr * sibe + d * sibeth;  G[4][1] = d * sibeth;
    G[4][5] = zf * siomep;              G[4][6] = zf * siomep - u * coep;
    G[5][0] = rr * cobe - d * cobeth;   G[5][1] = -d * cobeth;
    G[5][5] = -zf * coomep;             G[5][6] = -zf * coomep - u * siep;
    // y = (q, v, w, lambda): q' = v, v' = w, 0 = M w - ff + G^T lambda, 0 = g(q)
    for (int i = 0; i < 7; ++i) {
      f[i] = v[i];
      f[7 + i] = w[i];
      T s = -ff[i];
      for (int j = 0; j < 7; ++j) s += M[i][j] * w[j];
      for (int k = 0; k < 6; ++k) s += G[k][i] * lam[k];
      f[14 + i] = s;
    }
    f[21] = rr * cobe - d * cobeth - ss * siga - xb;
    f[22] = rr * sibe - d * sibeth + ss * coga - yb;
    f[23] = rr * cobe - d * cobeth - e * siphde - zt * code - xa;
    f[24] = rr * sibe - d * sibeth + e * cophde - zt * side - ya;
    f[25] = rr * cobe - d * cobeth - zf * coomep - u * siep - xa;
    f[26] = rr * sibe - d * sibeth - zf * siomep + u * coep - ya;
  }
};

// ---- Car axis: y = (xl, yl, xr, yr, xl', yl', xr', yr', lambda1, lambda2).
struct CarAxis {
  static constexpr double eps = 1e-2, M = 10.0, L = 1.0, L0 = 0.5, r = 0.1, w = 10.0, g = 1.0;
  template <class T>
  void operator()(double t, const T* y, T* f) const {
    using std::sqrt;
    const double yb = r * std::sin(w * t);
    const double xb = std::sqrt(L * L - yb * yb);
    const T &xl = y[0], &yl = y[1], &xr = y[2], &yr = y[3], &lam1 = y[8], &lam2 = y[9];
    const T Ll = sqrt(xl * xl + yl * yl);
    const T Lr = sqrt((xr - xb) * (xr - xb) + (yr - yb) * (yr - yb));
    for (int i = 0; i < 4; ++i) f[i] = y[i + 4];
    const double k = M * eps * eps / 2.0;
    f[4] = (L0 - Ll) * xl / Ll + lam1 * xb + 2.0 * lam2 * (xl - xr);
    f[5] = (L0 - Ll) * yl / Ll + lam1 * yb + 2.0 * lam2 * (yl - yr) - k * g;
    f[6] = (L0 - Lr) * (xr - xb) / Lr - 2.0 * lam2 * (xl - xr);
    f[7] = (L0 - Lr) * (yr - yb) / Lr - 2.0 * lam2 * (yl - yr) - k * g;
    f[8] = xb * xl + yb * yl;
    f[9] = (xl - xr) * (xl - xr) + (yl - yr) * (yl - yr) - L * L;
  }
};

}  // namespace detail

/// Andrews' squeezer, t in [0, 0.03], 27 unknowns, index counts (7, 7, 13). Reference at
/// t = 0.03: the Test Set's (PSIDE on a Cray C90 at rtol = atol = 1e-14). With
/// second_order = true the structure q' = v, v' = w is declared: M1 = 14, M2 = 7.
inline MechanismProblem andrews(bool second_order = false) {
  MechanismProblem m;
  m.name = second_order ? "andrews (M1=14,M2=7)" : "andrews";
  OdeProblem& p = m.problem;
  p.n = 27;
  p.rhs = [](double t, const double* y, double* f) {
    detail::Andrews()(t, y, f);
    return true;
  };
  p.jacobian = [](double t, const double* y, double* J) {
    detail::ad_jacobian<27>(detail::Andrews(), t, y, J);
    return true;
  };
  Eigen::VectorXd k = Eigen::VectorXd::Zero(27);
  k.head(14).setOnes();
  p.mass = k.asDiagonal();
  p.index2_count = 7;
  p.index3_count = 13;
  if (second_order) {
    p.second_order_count = 14;
    p.second_order_stride = 7;
  }
  m.t_end = 0.03;
  m.y0 = Eigen::VectorXd::Zero(27);
  m.y0.head(7) << -0.0617138900142764496358948458001, 0.0, 0.455279819163070380255912382449,
      0.222668390165885884674473185609, 0.487364979543842550225598953530,
      -0.222668390165885884674473185609, 1.23054744454982119249735015568;
  m.y0[14] = 14222.4439199541138705911625887;
  m.y0[15] = -10666.8329399655854029433719415;
  m.y0[21] = 98.5668703962410896057654982170;
  m.y0[22] = -6.12268834425566265503114393122;
  m.y_ref.resize(27);
  m.y_ref << 0.1581077119629904e+2, -0.1575637105984298e+2, 0.4082224013073101e-1,
      -0.5347301163226948e+0, 0.5244099658805304e+0, 0.5347301163226948e+0,
      0.1048080741042263e+1, 0.1139920302151208e+4, -0.1424379294994111e+4,
      0.1103291221937134e+2, 0.1929337464421385e+2, 0.5735699284790808e+0,
      -0.1929337464421385e+2, 0.3231791658026955e+0, -0.2463176316945196e+5,
      0.5185037701610329e+5, 0.3241025686413781e+6, 0.5667493645176213e+6,
      0.1674362929479361e+5, -0.5667493645176222e+6, 0.9826520791458422e+4,
      0.1991753333731910e+3, -0.2975531228015052e+2, 0.2306654119098399e+2,
      0.3145271365475927e+2, 0.2264249232082739e+2, 0.1161740700019673e+2;
  m.scd_components = 7;
  return m;
}

/// The car axis, t in [0, 3], 10 unknowns, index counts (4, 4, 2), K = diag(1 x 4, k x 4, 0, 0)
/// with k = M eps^2 / 2. Reference at t = 3: the Test Set's. With second_order = true:
/// M1 = 4, M2 = 4 (x' = v).
inline MechanismProblem car_axis(bool second_order = false) {
  MechanismProblem m;
  m.name = second_order ? "car axis (M1=4,M2=4)" : "car axis";
  OdeProblem& p = m.problem;
  p.n = 10;
  p.rhs = [](double t, const double* y, double* f) {
    detail::CarAxis()(t, y, f);
    return true;
  };
  p.jacobian = [](double t, const double* y, double* J) {
    detail::ad_jacobian<10>(detail::CarAxis(), t, y, J);
    return true;
  };
  const double k = detail::CarAxis::M * detail::CarAxis::eps * detail::CarAxis::eps / 2.0;
  Eigen::VectorXd kd(10);
  kd << 1, 1, 1, 1, k, k, k, k, 0, 0;
  p.mass = kd.asDiagonal();
  p.index2_count = 4;
  p.index3_count = 2;
  if (second_order) {
    p.second_order_count = 4;
    p.second_order_stride = 4;
  }
  m.t_end = 3.0;
  const double L = detail::CarAxis::L, L0 = detail::CarAxis::L0;
  m.y0.resize(10);
  m.y0 << 0.0, L0, L, L0, -L0 / L, 0.0, -L0 / L, 0.0, 0.0, 0.0;
  m.y_ref.resize(10);
  m.y_ref << 0.4934557842755629e-001, 0.4969894602303324e+000, 0.1041742524885400e+001,
      0.3739110272652214e+000, -0.7705836840321485e-001, 0.7446866596327776e-002,
      0.1755681574942899e-001, 0.7703410437794031e+000, -0.4736886750784630e-002,
      -0.1104680411345730e-002;
  m.scd_components = 10;
  return m;
}

}  // namespace pcsim::testproblems
