// The linearization on the constraint manifold's tangent space (see linearize.hpp).
#include "modes/linearize.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Eigenvalues>
#include "common/eigen_instances.hpp"
#include <Eigen/SVD>

#include "common/error.hpp"
#include "common/format.hpp"
#include "mech/dynamics.hpp"
#include "mech/tangent.hpp"

namespace pcsim::modes {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// An orthonormal basis of the null space of X (rows scaled to unit length first), with the
/// rank and the singular values on either side of the cut.
Eigen::MatrixXd null_basis(const Eigen::MatrixXd& X, double tol, int& rank, double& below, double& above) {
  const Eigen::Index cols = X.cols();
  rank = 0;
  below = kNaN;
  above = kNaN;
  if (X.rows() == 0) return Eigen::MatrixXd::Identity(cols, cols);
  Eigen::MatrixXd Xn = X;
  for (Eigen::Index i = 0; i < Xn.rows(); ++i) {
    const double r = Xn.row(i).norm();
    if (r > 0) Xn.row(i) /= r;
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(Xn, Eigen::ComputeFullV);
  const Eigen::VectorXd s = svd.singularValues();
  for (Eigen::Index i = 0; i < s.size(); ++i)
    if (s[i] > tol) ++rank;
  if (rank > 0) below = s[rank - 1];
  if (rank < s.size()) above = s[rank];
  return svd.matrixV().rightCols(cols - rank);
}

}  // namespace

Linearization linearize(const LinearizeInput& in) {
  const mech::Model& model = *in.model;
  const int n = model.n();
  const int s = static_cast<int>(in.active.size());
  Linearization L;
  L.n = n;
  const mech::ActiveSet set = mech::ActiveSet::of(model, in.active);
  mech::RhsTangent rt(model);
  // The mean over the evaluation times of J, M, F = Q − h (+ the extra force), g, γ and C's
  // velocity-form rows' derivative.
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(2 * n, 2 * n), Jt(2 * n, 2 * n);
  Eigen::MatrixXd M = Eigen::MatrixXd::Zero(n, n), Mt(n, n);
  Eigen::VectorXd F = Eigen::VectorXd::Zero(n), ht(n), Qt(n), Qm = Eigen::VectorXd::Zero(n),
                  hm = Eigen::VectorXd::Zero(n);
  Eigen::MatrixXd g = Eigen::MatrixXd::Zero(s, n), gt(s, n), dvq = Eigen::MatrixXd::Zero(s, n), dgt0(s, n);
  Eigen::VectorXd gamma = Eigen::VectorXd::Zero(s), g0t(s), gat(s);
  Eigen::MatrixXd V = Eigen::MatrixXd::Zero(2 * n + 1, n);
  for (int i = 0; i < n; ++i) V(i, i) = 1.0;
  std::vector<Eigen::MatrixXd> dg;
  Eigen::MatrixXd dg0, dgamma;
  const double w = 1.0 / static_cast<double>(in.times.size());
  for (const double t : in.times) {
    if (rt.jacobian(set, t, in.q, in.qd, Jt) != mech::ModelIssue::none)
      throw NumericalError("the linearization does not exist at the reference state: " + rt.message(), t);
    J += w * Jt;
    model.kinetic_terms(t, in.q, in.qd, Mt, ht);
    model.forces(t, in.q, in.qd, Qt);
    M += w * Mt;
    F += w * (Qt - ht);
    Qm = Qm.cwiseMax(Qt.cwiseAbs());  // the largest over the times (an averaged-out forcing counts)
    hm = hm.cwiseMax(ht.cwiseAbs());
    if (s > 0) {
      model.constraint_rows_tangent(in.active, t, in.q, in.qd, V, gt, g0t, gat, dg, dg0, dgamma);
      g += w * gt;
      gamma += w * gat;
      for (int j = 0; j < n; ++j) dvq.col(j) += w * (dg[static_cast<std::size_t>(j)] * in.qd + dg0.col(j));
    }
  }
  if (in.extra_force.size() == n) F += in.extra_force;
  L.J = J;

  // The tangent space of the manifold: null(C).
  std::vector<int> hol;
  for (int k = 0; k < s; ++k)
    if (model.constraints()[static_cast<std::size_t>(in.active[static_cast<std::size_t>(k)])].kind ==
        mech::ConstraintKind::holonomic)
      hol.push_back(k);
  L.holonomic_rows = static_cast<int>(hol.size());
  L.velocity_rows = s;
  Eigen::MatrixXd C = Eigen::MatrixXd::Zero(L.holonomic_rows + s, 2 * n);
  for (std::size_t k = 0; k < hol.size(); ++k) C.row(static_cast<Eigen::Index>(k)).head(n) = g.row(hol[k]);
  C.bottomLeftCorner(s, n) = dvq;
  C.bottomRightCorner(s, n) = g;
  L.B = null_basis(C, in.rank_tol, L.rank, L.rank_gap_below, L.rank_gap_above);
  L.dimension = static_cast<int>(L.B.cols());
  L.A = L.B.transpose() * J * L.B;
  L.invariance = (J * L.B - L.B * L.A).norm() / std::max(J.norm(), 1.0);

  // The rest check: M q̈ = F + gᵀλ, g q̈ = −γ (the mean forces), q̈ and the imbalance M q̈.
  {
    Eigen::MatrixXd K = Eigen::MatrixXd::Zero(n + s, n + s);
    K.topLeftCorner(n, n) = M;
    K.topRightCorner(n, s) = -g.transpose();
    K.bottomLeftCorner(s, n) = g;
    Eigen::VectorXd rhs(n + s);
    rhs.head(n) = F;
    rhs.tail(s) = -gamma;
    const Eigen::VectorXd x = K.completeOrthogonalDecomposition().solve(rhs);
    L.qdd = x.head(n);
    L.imbalance = M * L.qdd;
    const Eigen::VectorXd R = g.transpose() * x.tail(s);
    // The scale: the largest of the force terms that balance (applied, inertial, reactions,
    // holding), so that a balance of large terms is judged relative to them.
    L.force_scale = std::max({Qm.cwiseAbs().maxCoeff(), hm.cwiseAbs().maxCoeff(),
                              R.size() ? R.cwiseAbs().maxCoeff() : 0.0,
                              in.extra_force.size() == n ? in.extra_force.cwiseAbs().maxCoeff() : 0.0});
    L.residual = L.imbalance.cwiseAbs().maxCoeff();
    for (int i = 0; i < n; ++i)
      if (std::abs(L.imbalance[i]) > in.rest_tol * L.force_scale && std::abs(L.imbalance[i]) > 0)
        L.moving.push_back(i);
    double cyc_rate = 1.0;
    for (int c : in.cyclic) cyc_rate = std::max(cyc_rate, std::abs(in.qd[c]));
    for (int i = 0; i < n; ++i)
      if (std::find(in.cyclic.begin(), in.cyclic.end(), i) == in.cyclic.end() &&
          std::abs(in.qd[i]) > 1e-12 * cyc_rate)
        L.moving_velocity.push_back(i);
    // Cyclic coordinates: absent from the equations (∂q̈/∂q_c = 0, the column of J) and from
    // the constraints (C's column).
    const double jt = 1e-12 * std::max(J.norm(), 1.0), ct = 1e-12 * std::max(C.norm(), 1.0);
    for (int c : in.cyclic)
      if (J.col(c).norm() > jt || (C.rows() > 0 && C.col(c).norm() > ct)) L.cyclic_in_equations.push_back(c);
  }

  // The eigen-analysis of A.
  const int m = L.dimension;
  if (m > 0) {
    const Eigen::EigenSolver<Eigen::MatrixXd> es(L.A, true);
    if (es.info() != Eigen::Success)
      throw NumericalError("the eigenvalues of the reduced " + std::to_string(m) + "x" + std::to_string(m) +
                               " linearization did not converge", in.times.front());
    L.eigenvalues = es.eigenvalues();
    const Eigen::MatrixXcd Y = L.B.cast<std::complex<double>>() * es.eigenvectors();
    L.eigenvectors = Y;
    for (int k = 0; k < m; ++k) L.eigenvectors.col(k).normalize();
    L.zero_tol = 1e-7 * std::max(L.A.norm(), 1.0);
    for (int k = 0; k < m; ++k) {
      const std::complex<double> lam = L.eigenvalues[k];
      if (lam.imag() < 0) continue;
      Mode md;
      md.lambda = lam;
      md.pair = lam.imag() > 0;
      Eigen::VectorXcd y = Y.col(k).head(n);
      if (y.norm() < 1e-12 * Y.col(k).norm()) y = Y.col(k).tail(n);
      Eigen::Index imax = 0;
      y.cwiseAbs().maxCoeff(&imax);
      md.shape = y / y[imax];
      std::vector<int> idx(static_cast<std::size_t>(n));
      for (int i = 0; i < n; ++i) idx[static_cast<std::size_t>(i)] = i;
      std::stable_sort(idx.begin(), idx.end(),
                       [&](int a, int b) { return std::abs(md.shape[a]) > std::abs(md.shape[b]); });
      for (int i : idx)
        if (std::abs(md.shape[i]) >= 0.1 && md.dominant.size() < 4) md.dominant.push_back(i);
      md.natural_frequency = std::abs(lam);
      md.damped_frequency = std::abs(lam.imag());
      if (md.natural_frequency <= L.zero_tol) {
        const bool cyc = std::find(in.cyclic.begin(), in.cyclic.end(), static_cast<int>(imax)) != in.cyclic.end();
        md.kind = cyc ? "cyclic" : "rigid-body";
        md.damping_ratio = kNaN;
      } else {
        md.kind = md.pair ? "oscillatory" : "real";
        md.damping_ratio = -lam.real() / md.natural_frequency + 0.0;  // no -0
      }
      L.modes.push_back(std::move(md));
    }
    std::stable_sort(L.modes.begin(), L.modes.end(), [](const Mode& a, const Mode& b) {
      return a.natural_frequency < b.natural_frequency;
    });
    L.stable = true;
    for (int k = 0; k < m; ++k) L.stable = L.stable && L.eigenvalues[k].real() <= L.zero_tol;
  }

  // Undamped: the velocity tangent space (null of every active row), the reduced mass and
  // stiffness with the velocity-dependent terms dropped.
  {
    int r = 0;
    double b1, b2;
    const Eigen::MatrixXd N = null_basis(g, in.rank_tol, r, b1, b2);
    L.Mr = N.transpose() * M * N;
    L.Kr = -N.transpose() * M * J.bottomLeftCorner(n, n) * N;
    if (N.cols() > 0) {
      // The solvers' arguments as MatrixXd: their compute() is then the one compiled once
      // (common/eigen_instances.hpp), not one more instance for an expression type.
      const Eigen::MatrixXd Mr_sym = 0.5 * (L.Mr + L.Mr.transpose());
      const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> me(Mr_sym);
      const Eigen::VectorXd mv = me.eigenvalues();
      if (!(mv.minCoeff() > 1e-12 * std::max(mv.maxCoeff(), 0.0)))
        throw NumericalError("the mass matrix is singular on the tangent space of the constraints (its "
                             "reduced eigenvalues range over " + format_significant(mv.minCoeff(), 3) +
                             " .. " + format_significant(mv.maxCoeff(), 3) +
                             "): a motion the constraints allow carries no inertia",
                             in.times.front());
      const Eigen::MatrixXd MrinvKr = L.Mr.ldlt().solve(L.Kr);
      const Eigen::EigenSolver<Eigen::MatrixXd> ke(MrinvKr, false);
      double big = 0;
      for (Eigen::Index k = 0; k < ke.eigenvalues().size(); ++k) big = std::max(big, std::abs(ke.eigenvalues()[k]));
      // |w^2| below 1e-10 of the largest is a zero (a rigid-body motion), not a tiny instability.
      for (Eigen::Index k = 0; k < ke.eigenvalues().size(); ++k) {
        const double w2 = ke.eigenvalues()[k].real();
        L.omega2.push_back(std::abs(w2) <= 1e-10 * big ? 0.0 : w2);
      }
      std::sort(L.omega2.begin(), L.omega2.end());
    }
  }
  return L;
}

std::string rest_problem(const Linearization& L, const std::vector<std::string>& coords,
                         const std::vector<int>& cyclic) {
  std::string out;
  auto names = [&](const std::vector<int>& idx, const Eigen::VectorXd* v, const std::string& what) {
    std::string s;
    for (int i : idx) {
      s += (s.empty() ? "" : ", ") + coords[static_cast<std::size_t>(i)];
      if (v) s += " (" + what + " " + format_significant((*v)[i], 3) + ")";
    }
    return s;
  };
  const bool steady = !cyclic.empty();
  if (!L.moving_velocity.empty()) {
    out += std::string(steady ? "the coordinates that are not cyclic must rest, but " : "a rest state has q_d = 0, but ") +
           names(L.moving_velocity, nullptr, "") + " move";
  }
  if (!L.moving.empty()) {
    if (!out.empty()) out += "; ";
    out += std::string("the forces do not balance (q_dd != 0): residual ") + format_significant(L.residual, 3) +
           " of the force scale " + format_significant(L.force_scale, 3) + " (accepted: 1e-8 of it); " +
           "accelerating: " + names(L.moving, &L.qdd, "q_dd =");
  }
  if (!L.cyclic_in_equations.empty()) {
    if (!out.empty()) out += "; ";
    out += "the cyclic coordinate(s) " + names(L.cyclic_in_equations, nullptr, "") +
           " appear in the equations of motion or the constraints (their column of the Jacobian is not zero), "
           "so a constant rate of them is not a steady motion";
  }
  return out;
}

}  // namespace pcsim::modes
