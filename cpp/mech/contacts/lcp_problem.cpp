// The contacts' complementarity problems: rows, inertia, assembly, solution, polish.
#include "mech/contacts/lcp_problem.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>
#include "common/eigen_instances.hpp"

namespace pcsim::mech::contacts {

std::string names(const ContactSet& cs, const Problem& p) {
  std::string s;
  for (const Cand& k : p.cands) s += (s.empty() ? "'" : ", '") + cs[k.c].name + "'";
  return s;
}

void rows_of(const ContactSet& cs, Problem& p, double t, const Eigen::VectorXd& q,
             const Eigen::VectorXd& qd, Eigen::MatrixXd& J, Eigen::VectorXd& j0,
             Eigen::VectorXd& jgamma) {
  int nj = 0;
  for (Cand& k : p.cands) {
    k.kn = nj++;
    if (cs[k.c].friction >= 0 && (k.frictional || k.sigma != 0)) {
      k.kt = nj++;
      if (cs[k.c].cone()) k.kt2 = nj++;
    }
  }
  J.resize(nj, cs.n());
  j0.resize(nj);
  jgamma.resize(nj);
  for (const Cand& k : p.cands) {
    const Row rn = cs.normal_row(k.c, t, q, qd);
    J.row(k.kn) = rn.g;
    j0[k.kn] = rn.g0;
    jgamma[k.kn] = rn.gamma;
    if (k.kt >= 0) {
      const Row rt = cs.row(cs[k.c].friction, t, q, qd);
      J.row(k.kt) = rt.g;
      j0[k.kt] = rt.g0;
      jgamma[k.kt] = rt.gamma;
    }
    if (k.kt2 >= 0) {
      const Row rt = cs.row(cs[k.c].friction2, t, q, qd);
      J.row(k.kt2) = rt.g;
      j0[k.kt2] = rt.g0;
      jgamma[k.kt2] = rt.gamma;
    }
  }
}

ModelIssue contact_inertia(Dynamics& d, const ContactSet& cs, double t, const Eigen::VectorXd& q,
                           const Eigen::VectorXd& qd, Eigen::MatrixXd& P, Eigen::VectorXd& aB,
                           std::string& message, const std::vector<int>& extra, Eigen::VectorXd* dv0) {
  const int n = cs.n();
  std::vector<int> brows = cs.bilateral();
  brows.insert(brows.end(), extra.begin(), extra.end());
  const ActiveSet bset = ActiveSet::of(cs.model(), brows);
  Eigen::LLT<Eigen::MatrixXd> llt(n);
  ModelIssue e = d.evaluate(bset, t, q, qd);
  if (e != ModelIssue::none) {
    message = d.message();
    return e;
  }
  e = d.solve(ReactionMethod::compatibility_structured);
  if (e != ModelIssue::none) {
    message = d.message();
    return e;
  }
  aB = d.qdd;
  llt.compute(d.M);
  P = llt.solve(Eigen::MatrixXd::Identity(n, n));
  if (dv0) *dv0 = Eigen::VectorXd::Zero(n);
  if (!brows.empty()) {
    const Eigen::MatrixXd MinvgT = llt.solve(d.g.transpose());
    const Eigen::MatrixXd S = d.g * MinvgT;
    const auto Sf = S.ldlt();
    P -= MinvgT * Sf.solve(MinvgT.transpose());
    if (dv0) *dv0 = -MinvgT * Sf.solve(d.g * qd + d.g0);
  }
  P = 0.5 * (P + P.transpose());
  return ModelIssue::none;
}

namespace {

void assemble(Problem& p) {
  int nz = 0;
  for (Cand& k : p.cands) {
    k.zn = nz;
    nz += k.frictional ? 4 : 1;
  }
  const int nj = static_cast<int>(p.W.rows());
  p.E = Eigen::MatrixXd::Zero(nj, nz);
  for (const Cand& k : p.cands) {
    p.E(k.kn, k.zn) = 1.0;
    if (k.kt2 >= 0) {  // a 2-D cone: (Λn, Λt1, Λt2, ζ), or Λn sliding along dir
      if (k.frictional) {
        p.E(k.kt, k.zn + 1) = 1.0;
        p.E(k.kt2, k.zn + 2) = 1.0;
      } else {
        p.E(k.kt, k.zn) = -k.mu * k.dir[0];
        p.E(k.kt2, k.zn) = -k.mu * k.dir[1];
      }
    } else if (k.frictional) {
      p.E(k.kt, k.zn + 1) = 1.0;
      p.E(k.kt, k.zn + 2) = -1.0;
    } else if (k.sigma != 0) {
      p.E(k.kt, k.zn) = -k.mu * k.sigma;
    }
  }
  const Eigen::MatrixXd WE = p.W * p.E;
  p.A = Eigen::MatrixXd::Zero(nz, nz);
  p.b = Eigen::VectorXd::Zero(nz);
  for (const Cand& k : p.cands) {
    p.A.row(k.zn) = WE.row(k.kn);
    p.b[k.zn] = p.free_normal(k);
    if (!k.frictional || k.kt2 >= 0) continue;  // a cone's other rows: not an LCP's
    p.A.row(k.zn + 1) = WE.row(k.kt);
    p.A(k.zn + 1, k.zn + 3) += 1.0;
    p.b[k.zn + 1] = p.f[k.kt];
    p.A.row(k.zn + 2) = -WE.row(k.kt);
    p.A(k.zn + 2, k.zn + 3) += 1.0;
    p.b[k.zn + 2] = -p.f[k.kt];
    p.A(k.zn + 3, k.zn) = k.mu;
    p.A(k.zn + 3, k.zn + 1) = -1.0;
    p.A(k.zn + 3, k.zn + 2) = -1.0;
  }
}

/// The single-contact problem in closed form: its complementary solutions are the contact's
/// modes (open; closed and sticking; closed and sliding either way), of which the first
/// consistent one is taken. Returns false when none is (then the LCP solver decides).
bool solve_single(const Problem& p, Eigen::VectorXd& z) {
  const Cand& k = p.cands[0];
  const double qn = p.b[k.zn];
  const double scale = 1.0 + std::abs(qn) + (k.frictional ? std::abs(p.f[k.kt]) : 0.0);
  const double tol = 1e-12 * scale;
  z = Eigen::VectorXd::Zero(p.b.size());
  if (!k.frictional) {
    const double a = p.A(k.zn, k.zn);
    if (qn >= 0.0) return true;  // open (or touching without force)
    if (!(a > 0.0)) return false;
    z[k.zn] = -qn / a;
    return true;
  }
  const double Wnn = p.W(k.kn, k.kn), Wnt = p.W(k.kn, k.kt), Wtn = p.W(k.kt, k.kn),
               Wtt = p.W(k.kt, k.kt), bt = p.f[k.kt];
  if (qn >= 0.0) {  // open: no force; ζ takes up the sliding velocity's magnitude
    z[k.zn + 3] = std::abs(bt);
    return true;
  }
  // Stick: both relative values zero.
  const double det = Wnn * Wtt - Wnt * Wtn;
  if (std::abs(det) > 1e-14 * std::abs(Wnn * Wtt)) {
    const double ln = (-qn * Wtt + bt * Wnt) / det;
    const double lt = (-bt * Wnn + qn * Wtn) / det;
    if (ln >= 0.0 && std::abs(lt) <= k.mu * ln + tol) {
      z[k.zn] = ln;
      z[k.zn + 1] = std::max(lt, 0.0);
      z[k.zn + 2] = std::max(-lt, 0.0);
      return true;
    }
  }
  // Slide: Λt = −σ μ Λn, the sliding value after has the sign σ.
  for (int sigma : {+1, -1}) {
    const double a = Wnn - sigma * k.mu * Wnt;
    if (!(a > 0.0)) continue;
    const double ln = -qn / a;
    const double vt_after = bt + (Wtn - sigma * k.mu * Wtt) * ln;
    if (sigma * vt_after >= -tol) {
      z[k.zn] = ln;
      z[k.zn + (sigma > 0 ? 2 : 1)] = k.mu * ln;
      z[k.zn + 3] = std::max(sigma * vt_after, 0.0);
      return true;
    }
  }
  return false;
}

/// The LCP decides which contacts are closed, sticking or sliding; the values then come
/// from the equations of that set, solved exactly (least norm where contacts are redundant):
/// closed normals w_n = 0, sticking tangents v_t = 0, sliding ones Λt = −σ μ Λn, open ones
/// Λ = 0. This removes the regularization's 1e-10 from unique solutions. Kept only if the
/// result is still complementary (to 1e-9 of the problem's scale).
void polish(const Problem& p, Eigen::VectorXd& z) {
  const int nz = static_cast<int>(z.size());
  const double zs = 1.0 + z.cwiseAbs().maxCoeff();
  const double tol = 1e-9 * zs;
  // Unknowns: Λ_J (one per row of J); equations built row by row.
  const int nj = static_cast<int>(p.W.rows());
  std::vector<Eigen::RowVectorXd> rows;
  std::vector<double> rhs;
  auto unit = [nj](int k) {
    Eigen::RowVectorXd r = Eigen::RowVectorXd::Zero(nj);
    r[k] = 1.0;
    return r;
  };
  for (const Cand& k : p.cands) {
    const bool closed = z[k.zn] > tol;
    const double bn = p.free_normal(k);
    if (!closed) {
      rows.push_back(unit(k.kn));
      rhs.push_back(0.0);
      if (k.kt >= 0) {
        rows.push_back(unit(k.kt));
        rhs.push_back(0.0);
      }
      continue;
    }
    if (k.frictional) {
      const double bp = z[k.zn + 1], bm = z[k.zn + 2], zeta = z[k.zn + 3];
      rows.push_back(p.W.row(k.kn));  // w_n = 0: (W Λ)_n = −b_n
      rhs.push_back(-bn);
      if (zeta <= tol) {
        rows.push_back(p.W.row(k.kt));  // sticks: (W Λ)_t = −f_t
        rhs.push_back(-p.f[k.kt]);
      } else {
        const double sigma = bm > bp ? 1.0 : -1.0;  // slides: Λt = −σ μ Λn
        Eigen::RowVectorXd r = unit(k.kt);
        r[k.kn] = sigma * k.mu;
        rows.push_back(r);
        rhs.push_back(0.0);
      }
    } else {
      // Λ_J = E z: the normal row of the variable, and a sliding contact's tangent row
      // −μσ times it; the normal equation on the combined column.
      Eigen::RowVectorXd r = p.W.row(k.kn);
      if (k.sigma != 0) {
        rows.push_back(r);
        rhs.push_back(-bn);
        Eigen::RowVectorXd c = unit(k.kt);
        c[k.kn] = k.mu * k.sigma;
        rows.push_back(c);
        rhs.push_back(0.0);
      } else {
        rows.push_back(r);
        rhs.push_back(-bn);
      }
    }
  }
  const int m = static_cast<int>(rows.size());
  Eigen::MatrixXd A(m, nj);
  Eigen::VectorXd b(m);
  for (int i = 0; i < m; ++i) {
    A.row(i) = rows[i];
    b[i] = rhs[i];
  }
  const Eigen::VectorXd lam = A.completeOrthogonalDecomposition().solve(b);
  if (!lam.allFinite() || (A * lam - b).cwiseAbs().maxCoeff() > 1e-9 * (1.0 + b.cwiseAbs().maxCoeff())) return;
  // Back to the LCP's variables.
  Eigen::VectorXd zp = Eigen::VectorXd::Zero(nz);
  const Eigen::VectorXd vrel = p.f + p.W * lam;
  for (const Cand& k : p.cands) {
    zp[k.zn] = lam[k.kn];
    if (k.frictional) {
      zp[k.zn + 1] = std::max(lam[k.kt], 0.0);
      zp[k.zn + 2] = std::max(-lam[k.kt], 0.0);
      zp[k.zn + 3] = z[k.zn + 3] <= tol ? 0.0 : std::abs(vrel[k.kt]);
    }
  }
  const Eigen::VectorXd w = p.A * zp + p.b;
  for (int i = 0; i < nz; ++i)
    if (zp[i] < -tol || w[i] < -tol * (1.0 + p.b.cwiseAbs().maxCoeff()) / zs) return;
  z = zp;
}

}  // namespace

// ---- problems with a 2-D Coulomb cone --------------------------------------------------------
//
// A contact that may slide in a plane has the local law (u = W Λ + b its relative values: the
// normal value and the tangential velocity after the impulse, or the accelerations):
//   open:   Λ = 0, u_n >= 0;
//   stick:  u_n = 0, u_t = 0, |Λ_t| <= μ Λ_n;
//   slide:  u_n = 0, Λ_t = −μ Λ_n d, u_t = α d with |d| = 1 and α > 0
// (the friction force opposes the sliding that results: the maximal dissipation of Coulomb's
// cone). With the cone circular this is not an LCP. Each contact's law is solved exactly with the
// others' forces fixed, contact after contact, until no force changes (Moreau's nonsmooth
// Gauss-Seidel); one contact alone is solved in one pass.

namespace {

struct Local {
  std::vector<int> rows;  // kn, then kt, kt2 of the candidate
  Eigen::MatrixXd W;      // W restricted to them
  Eigen::VectorXd u0;     // their values with this contact's own forces removed
};

/// The slide of a 2-D cone: the direction d (angle θ) with u_t(θ) = α d, α >= 0, where
/// Λ_n(θ) = −u0_n / (W_nn − μ W_nt·d) and u_t(θ) = u0_t + (W_tn − μ W_tt d) Λ_n. The function
/// F(θ) = d × u_t(θ) is scanned on 720 angles and its sign changes with d·u_t > 0 refined by
/// bisection; of several, the one nearest `guess` is taken. Returns false if there is none.
bool slide_2d(const Local& l, double mu, const Eigen::Vector2d& guess, Eigen::Vector3d& lam,
              double& zeta) {
  const Eigen::Matrix3d W = l.W;
  const Eigen::Vector3d u0 = l.u0;
  struct Eval {
    bool ok = false;
    double F = 0.0, G = 0.0, ln = 0.0;
    Eigen::Vector2d d, ut;
  };
  auto eval = [&](double th) {
    Eval e;
    e.d = Eigen::Vector2d(std::cos(th), std::sin(th));
    const double a = W(0, 0) - mu * (W(0, 1) * e.d[0] + W(0, 2) * e.d[1]);
    if (!(a > 0.0)) return e;
    e.ln = -u0[0] / a;
    if (!(e.ln >= 0.0)) return e;
    const Eigen::Vector2d wtn(W(1, 0), W(2, 0));
    e.ut = u0.tail<2>() + (wtn - mu * W.block<2, 2>(1, 1) * e.d) * e.ln;
    e.F = e.d[0] * e.ut[1] - e.d[1] * e.ut[0];
    e.G = e.d.dot(e.ut);
    e.ok = true;
    return e;
  };
  const int n = 720;
  const double two_pi = 8.0 * std::atan(1.0), step = two_pi / n;
  double best = -1.0, best_th = 0.0;
  Eval prev = eval(0.0);
  for (int i = 1; i <= n; ++i) {
    const double th = i * step;
    const Eval cur = eval(th);
    if (prev.ok && cur.ok && (prev.F == 0.0 || (prev.F < 0.0) != (cur.F < 0.0))) {
      double lo = th - step, hi = th;
      const bool lo_neg = prev.F < 0.0;
      for (int it = 0; it < 100 && hi - lo > 1e-16 * two_pi; ++it) {
        const double mid = 0.5 * (lo + hi);
        const Eval m = eval(mid);
        if (!m.ok) break;
        ((m.F < 0.0) == lo_neg ? lo : hi) = mid;
      }
      const double root = 0.5 * (lo + hi);
      const Eval r = eval(root);
      if (r.ok && r.G >= -1e-12 * (1.0 + r.ut.norm())) {
        const double closeness = guess.norm() > 0.0 ? r.d.dot(guess) / guess.norm() : 1.0;
        if (best < -0.5 || closeness > best) {
          best = closeness;
          best_th = root;
        }
      }
    }
    prev = cur;
  }
  if (best < -0.5) return false;
  const Eval r = eval(best_th);
  lam[0] = r.ln;
  lam[1] = -mu * r.ln * r.d[0];
  lam[2] = -mu * r.ln * r.d[1];
  zeta = std::max(r.G, 0.0);
  return true;
}

/// The exact local solution of one candidate (its forces Λ_r and, for a frictional one, ζ)
/// given the values u0 the others leave. Returns false when it has none.
bool solve_local(const Cand& k, const Local& l, Eigen::VectorXd& lam, double& zeta) {
  const int m = static_cast<int>(l.rows.size());
  lam = Eigen::VectorXd::Zero(m);
  zeta = 0.0;
  const double un = l.u0[0];
  const double tol = 1e-13 * (1.0 + l.u0.cwiseAbs().maxCoeff());
  if (un >= 0.0) {  // open
    if (k.frictional && m > 1) zeta = l.u0.tail(m - 1).norm();
    return true;
  }
  if (m == 1) {
    if (!(l.W(0, 0) > 0.0)) return false;
    lam[0] = -un / l.W(0, 0);
    return true;
  }
  if (!k.frictional) {  // sliding in a known direction: Λ_t = −μ Λ_n d
    Eigen::VectorXd d(m - 1);
    if (m == 2) d[0] = k.sigma;
    else d = k.dir;
    const double a = l.W(0, 0) - k.mu * l.W.row(0).tail(m - 1).dot(d);
    if (!(a > 0.0)) return false;
    lam[0] = -un / a;
    lam.tail(m - 1) = -k.mu * lam[0] * d;
    return true;
  }
  // Stick: u = 0.
  const Eigen::FullPivLU<Eigen::MatrixXd> lu(l.W);
  if (lu.isInvertible()) {
    const Eigen::VectorXd st = lu.solve(-l.u0);
    if (st[0] >= 0.0 && st.tail(m - 1).norm() <= k.mu * st[0] + tol) {
      lam = st;
      return true;
    }
  }
  if (m == 2) {  // a 1-D cone: slide either way
    for (int sigma : {+1, -1}) {
      const double a = l.W(0, 0) - sigma * k.mu * l.W(0, 1);
      if (!(a > 0.0)) continue;
      const double ln = -un / a;
      const double vt = l.u0[1] + (l.W(1, 0) - sigma * k.mu * l.W(1, 1)) * ln;
      if (sigma * vt >= -tol) {
        lam[0] = ln;
        lam[1] = -sigma * k.mu * ln;
        zeta = std::max(sigma * vt, 0.0);
        return true;
      }
    }
    return false;
  }
  // A 2-D cone slides against the force that would have held it.
  Eigen::Vector2d guess = Eigen::Vector2d::Zero();
  if (lu.isInvertible()) guess = -lu.solve(-l.u0).tail<2>();
  if (!(guess.norm() > 0.0)) guess = l.u0.tail<2>();
  Eigen::Vector3d l3;
  if (!slide_2d(l, k.mu, guess, l3, zeta)) return false;
  lam = l3;
  return true;
}

// ---- the fallback: the laws of all contacts at once -----------------------------------------
//
// Gauss-Seidel stalls where contacts wedge the body (three planes squeezing a tetrahedron: up to
// nine rows on six velocities): W is singular, forces Λ0 with W Λ0 = 0 squeeze the body without
// moving it, and sweep after sweep adds such a squeeze, so the forces drift without settling
// (or settle slowly short of a solution). The laws are then solved at once. With per-contact
// ρ = 1/W_nn and the contact's unknowns y (Λn, Λt of a frictional contact; Λn only of a
// frictionless or sliding one, whose tangential force −μ Λn d follows), u = W E y + b, the law of
// each contact holds iff (Alart and Curnier's equations)
//   Φn = Λn − max(0, ξn) = 0,                     ξn = Λn − ρ u_n,
//   Φt = Λt − P_B(r)(ξt) = 0,  r = μ max(0, ξn),  ξt = Λt − ρ u_t,
// P_B(r) the projection on the disk (interval) of radius r: Λn >= 0, u_n >= 0, Λn u_n = 0 from
// the first; from the second |Λt| <= μ Λn, with u_t = 0 inside and u_t = −α Λt, α >= 0, on the
// boundary (the slide against the friction force), Λt = 0 where the contact is open. Φ is
// piecewise smooth, and positively homogeneous of degree one in (y, b), so it is solved for
// b / s with s = max ρ|b| (unknowns of order one) and scaled back. Two methods, in turn:
// - Levenberg-Marquardt steps (HᵀH + ν I) δ = −HᵀΦ, H an element of Φ's generalized Jacobian,
//   ν = |Φ|² (with which the method converges quadratically to a solution set that is not
//   isolated, under a local error bound: Yamashita and Fukushima 2001), with Armijo's
//   backtracking on the merit ½|Φ|²; the step lies in the row space of H, so it adds no
//   squeeze the laws do not need. From Gauss-Seidel's last forces, then from zero. A merit
//   method can stop at a point where |Φ| > 0 is locally least (Coulomb's law is not monotone);
// - so then De Saxcé's fixed point (de_saxce): convex problems on the cones, whose solution
//   exists and is found by a projected gradient method, their results polished by the steps above.
// A result is accepted when |Φ| <= 1e-12 of the unknowns' size. Where the solution is not
// unique (W singular), it is the one these steps reach: any forces satisfying the laws, not a
// least-norm choice among them (the velocities they make, W Λ + b, are what the laws fix).

/// Unknowns of the Newton method and the map E (rows of J x unknowns, Λ_J = E y).
struct Unknowns {
  std::vector<int> at;  // first unknown of each candidate
  std::vector<int> m;   // its count: 1, 2 (a 1-D cone) or 3 (a 2-D cone)
  Eigen::MatrixXd E;
};

Unknowns unknowns_of(const Problem& p) {
  Unknowns un;
  int ny = 0;
  for (const Cand& k : p.cands) {
    un.at.push_back(ny);
    un.m.push_back(k.frictional ? 1 + (k.kt >= 0) + (k.kt2 >= 0) : 1);
    ny += un.m.back();
  }
  un.E = Eigen::MatrixXd::Zero(p.W.rows(), ny);
  for (std::size_t i = 0; i < p.cands.size(); ++i) {
    const Cand& k = p.cands[i];
    const int y = un.at[i];
    un.E(k.kn, y) = 1.0;
    if (k.frictional) {
      if (k.kt >= 0) un.E(k.kt, y + 1) = 1.0;
      if (k.kt2 >= 0) un.E(k.kt2, y + 2) = 1.0;
    } else if (k.kt2 >= 0) {
      un.E(k.kt, y) = -k.mu * k.dir[0];
      un.E(k.kt2, y) = -k.mu * k.dir[1];
    } else if (k.kt >= 0 && k.sigma != 0) {
      un.E(k.kt, y) = -k.mu * k.sigma;
    }
  }
  return un;
}

/// Φ(y) of the Alart-Curnier equations and, if H is given, an element of its generalized
/// Jacobian. G = W E, u = G y + b.
Eigen::VectorXd alart_curnier(const Problem& p, const Unknowns& un, const Eigen::MatrixXd& G,
                              const Eigen::VectorXd& b, const Eigen::VectorXd& rho,
                              const Eigen::VectorXd& y, Eigen::MatrixXd* H) {
  const int ny = static_cast<int>(y.size());
  const Eigen::VectorXd u = G * y + b;
  Eigen::VectorXd phi(ny);
  if (H) *H = Eigen::MatrixXd::Identity(ny, ny);
  for (std::size_t i = 0; i < p.cands.size(); ++i) {
    const Cand& k = p.cands[i];
    const int a = un.at[i], m = un.m[i];
    const double r = rho[static_cast<Eigen::Index>(i)];
    const double xn = y[a] - r * u[k.kn];
    phi[a] = y[a] - std::max(0.0, xn);
    if (H && xn > 0.0) H->row(a) = r * G.row(k.kn);  // Φn = ρ u_n
    if (m == 1) continue;
    const int rows[2] = {k.kt, k.kt2};
    Eigen::VectorXd xt(m - 1);
    for (int j = 0; j < m - 1; ++j) xt[j] = y[a + 1 + j] - r * u[rows[j]];
    const double radius = k.mu * std::max(0.0, xn), nx = xt.norm();
    if (nx <= radius) {  // inside: Φt = ρ u_t
      for (int j = 0; j < m - 1; ++j) {
        phi[a + 1 + j] = r * u[rows[j]];
        if (H) H->row(a + 1 + j) = r * G.row(rows[j]);
      }
      continue;
    }
    const Eigen::VectorXd dir = xt / nx;
    for (int j = 0; j < m - 1; ++j) phi[a + 1 + j] = y[a + 1 + j] - radius * dir[j];
    if (!H) continue;
    // d(r ξ̂) = ξ̂ dr + (r/|ξ|) (I − ξ̂ξ̂ᵀ) dξ, dr = μ dξn (ξn > 0), dξ = dΛt − ρ G_t dy.
    Eigen::MatrixXd dxt(m - 1, ny);
    for (int j = 0; j < m - 1; ++j) {
      dxt.row(j) = -r * G.row(rows[j]);
      dxt(j, a + 1 + j) += 1.0;
    }
    Eigen::RowVectorXd dxn = -r * G.row(k.kn);
    dxn[a] += 1.0;
    const Eigen::MatrixXd proj = Eigen::MatrixXd::Identity(m - 1, m - 1) - dir * dir.transpose();
    Eigen::MatrixXd d = (radius / nx) * proj * dxt;
    if (xn > 0.0) d += k.mu * dir * dxn;
    for (int j = 0; j < m - 1; ++j) {
      H->row(a + 1 + j) = -d.row(j);
      (*H)(a + 1 + j, a + 1 + j) += 1.0;
    }
  }
  return phi;
}

/// The Alart-Curnier equations of a problem, scaled (b / s), with what the methods need.
struct Equations {
  const Problem& p;
  Unknowns un;
  Eigen::MatrixXd G;     // W E
  Eigen::VectorXd rho;   // per candidate, 1/W_nn
  Eigen::VectorXd bs;    // b / s
  double s = 0.0;
  Eigen::VectorXd phi(const Eigen::VectorXd& y, Eigen::MatrixXd* H) const {
    return alart_curnier(p, un, G, bs, rho, y, H);
  }
  bool solved(const Eigen::VectorXd& phi_y, const Eigen::VectorXd& y, double tol) const {
    return phi_y.cwiseAbs().maxCoeff() <= tol * std::max(1.0, y.cwiseAbs().maxCoeff());
  }
};

/// Levenberg-Marquardt steps with ν = |Φ|² and Armijo's backtracking from y (in place) until
/// |Φ| <= 1e-14 of |y| or no step decreases the merit. Returns whether |Φ| <= 1e-12 of |y|.
bool levenberg_marquardt(const Equations& eq, Eigen::VectorXd& y, long& steps) {
  const int ny = static_cast<int>(y.size());
  Eigen::MatrixXd H;
  Eigen::VectorXd phi = eq.phi(y, &H);
  double merit = 0.5 * phi.squaredNorm();
  for (int it = 0; it < 300 && !eq.solved(phi, y, 1e-14); ++it) {
    ++steps;
    const Eigen::VectorXd grad = H.transpose() * phi;
    Eigen::MatrixXd A(2 * ny, ny);
    A << H, std::sqrt(2.0 * merit) * Eigen::MatrixXd::Identity(ny, ny);  // √ν, ν = |Φ|²
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(2 * ny);
    rhs.head(ny) = -phi;
    const Eigen::VectorXd delta = A.completeOrthogonalDecomposition().solve(rhs);
    const double slope = grad.dot(delta);
    if (!delta.allFinite() || !(slope < 0.0)) break;
    double t = 1.0;
    Eigen::VectorXd yt;
    bool moved = false;
    for (int ls = 0; ls < 60 && !moved; ++ls, t *= 0.5) {
      yt = y + t * delta;
      moved = 0.5 * eq.phi(yt, nullptr).squaredNorm() <= merit + 1e-4 * t * slope;
    }
    if (!moved) break;
    y = yt;
    phi = eq.phi(y, &H);
    merit = 0.5 * phi.squaredNorm();
  }
  return y.allFinite() && eq.solved(phi, y, 1e-12);
}

/// The projection on the product of the candidates' cones: |Λt| <= μ Λn of a frictional one,
/// Λn >= 0 of the others.
void project_cones(const Equations& eq, Eigen::VectorXd& y) {
  for (std::size_t i = 0; i < eq.p.cands.size(); ++i) {
    const int a = eq.un.at[i], m = eq.un.m[i];
    const double mu = eq.p.cands[i].mu;
    if (m == 1) {
      y[a] = std::max(y[a], 0.0);
      continue;
    }
    const double n = y[a], t = y.segment(a + 1, m - 1).norm();
    if (t <= mu * n) continue;
    if (mu * t <= -n) {  // in the polar cone: to the apex
      y.segment(a, m).setZero();
      continue;
    }
    const double pn = (n + mu * t) / (1.0 + mu * mu);
    y[a] = pn;
    y.segment(a + 1, m - 1) *= mu * pn / t;
  }
}

/// De Saxcé's fixed point: with s_n = μ |u_t| of each frictional contact fixed, Coulomb's law is
/// the convex problem min ½ yᵀ Wy y + (b + s)ᵀ y over the cones (its optimality conditions are
/// the law with u_n replaced by u_n + μ|u_t|, which is the law itself where s matches), solved
/// by Nesterov's accelerated projected gradient with adaptive restart (O'Donoghue and Candès);
/// s is renewed from the result, 50 times. Only problems whose unknowns are all frictional or
/// frictionless (every impact's): a sliding contact's force −μ Λn d makes the problem no
/// gradient. Its result then starts the Levenberg-Marquardt steps.
bool de_saxce(const Equations& eq, Eigen::VectorXd& y, long& steps) {
  for (const Cand& k : eq.p.cands)
    if (!k.frictional && k.kt >= 0) return false;
  const Eigen::MatrixXd Wy = eq.un.E.transpose() * eq.p.W * eq.un.E;
  const Eigen::VectorXd by = eq.un.E.transpose() * eq.bs;
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(Wy, Eigen::EigenvaluesOnly);
  const double lip = es.eigenvalues().maxCoeff();
  if (!(lip > 0.0)) return false;
  project_cones(eq, y);
  for (int outer = 0; outer < 50; ++outer) {
    const Eigen::VectorXd u = eq.G * y + eq.bs;
    Eigen::VectorXd c = by;
    for (std::size_t i = 0; i < eq.p.cands.size(); ++i) {
      const Cand& k = eq.p.cands[i];
      if (eq.un.m[i] == 1) continue;
      c[eq.un.at[i]] += k.mu * std::hypot(u[k.kt], k.kt2 >= 0 ? u[k.kt2] : 0.0);
    }
    Eigen::VectorXd x = y, z = y;
    double tk = 1.0;
    for (int it = 0; it < 3000; ++it) {
      ++steps;
      Eigen::VectorXd xn = z - (Wy * z + c) / lip;
      project_cones(eq, xn);
      const double tn = 0.5 * (1.0 + std::sqrt(1.0 + 4.0 * tk * tk));
      const Eigen::VectorXd dx = xn - x;
      if ((Wy * xn + c).dot(dx) > 0.0) {  // the objective would rise: restart the momentum
        z = xn;
        tk = 1.0;
      } else {
        z = xn + ((tk - 1.0) / tn) * dx;
        tk = tn;
      }
      x = xn;
      if (dx.cwiseAbs().maxCoeff() <= 1e-16 * std::max(1.0, x.cwiseAbs().maxCoeff())) break;
    }
    y = x;
    if (!y.allFinite()) return false;
  }
  return levenberg_marquardt(eq, y, steps);
}

/// The fallback from each start in turn (Levenberg-Marquardt steps on the Alart-Curnier
/// equations), then De Saxcé's fixed point from the first; Λ_J = E y of the first that
/// converges. Returns false if none does.
/// The equations of problem p with free values b; false if a contact has no normal inertia.
bool equations_of(const Problem& p, const Eigen::VectorXd& b, Equations& eq) {
  eq.G = p.W * eq.un.E;
  eq.rho.resize(static_cast<Eigen::Index>(p.cands.size()));
  eq.s = 0.0;
  for (std::size_t i = 0; i < p.cands.size(); ++i) {
    const Cand& k = p.cands[i];
    const double wnn = p.W(k.kn, k.kn);
    if (!(wnn > 0.0)) return false;
    eq.rho[static_cast<Eigen::Index>(i)] = 1.0 / wnn;
    eq.s = std::max(eq.s, std::abs(b[k.kn]) / wnn);
    if (k.kt >= 0) eq.s = std::max(eq.s, std::abs(b[k.kt]) / wnn);
    if (k.kt2 >= 0) eq.s = std::max(eq.s, std::abs(b[k.kt2]) / wnn);
  }
  if (!(eq.s > 0.0)) return false;
  eq.bs = b / eq.s;
  return true;
}

/// The unknowns y (scaled by 1/s) of forces Λ_J: Λn and, of a frictional contact, its Λt rows.
Eigen::VectorXd unknowns_from(const Equations& eq, const Eigen::VectorXd& Lam) {
  Eigen::VectorXd y(eq.un.E.cols());
  for (std::size_t i = 0; i < eq.p.cands.size(); ++i) {
    const Cand& k = eq.p.cands[i];
    const int a = eq.un.at[i];
    y[a] = Lam[k.kn] / eq.s;
    if (eq.un.m[i] > 1) y[a + 1] = Lam[k.kt] / eq.s;
    if (eq.un.m[i] > 2) y[a + 2] = Lam[k.kt2] / eq.s;
  }
  return y;
}

/// Whether forces Λ_J satisfy every contact's law to `tol` of their size (|Φ| <= tol |y|).
bool laws_hold(const Problem& p, const Eigen::VectorXd& b, const Eigen::VectorXd& Lam, double tol) {
  Equations eq{p, unknowns_of(p), {}, {}, {}, 0.0};
  if (!equations_of(p, b, eq)) return true;  // b = 0 (Λ = 0) or no normal inertia: not judged
  const Eigen::VectorXd y = unknowns_from(eq, Lam);
  return y.allFinite() && eq.solved(eq.phi(y, nullptr), y, tol);
}

/// The fallback from each start in turn (Levenberg-Marquardt steps on the Alart-Curnier
/// equations), then De Saxcé's fixed point from the first; Λ_J = E y of the first that
/// converges. Returns false if none does.
bool newton_cones(const Problem& p, const Eigen::VectorXd& b, const std::vector<Eigen::VectorXd>& starts,
                  Eigen::VectorXd& Lam, long& steps) {
  Equations eq{p, unknowns_of(p), {}, {}, {}, 0.0};
  if (!equations_of(p, b, eq)) return false;
  std::vector<Eigen::VectorXd> ys;
  for (const Eigen::VectorXd& start : starts) {
    Eigen::VectorXd y = unknowns_from(eq, start);
    if (!y.allFinite()) y.setZero();
    ys.push_back(y);
  }
  for (std::size_t r = 0; r <= ys.size(); ++r) {
    Eigen::VectorXd y = ys[r % ys.size()];
    if (r < ys.size() ? levenberg_marquardt(eq, y, steps) : de_saxce(eq, y, steps)) {
      Lam = eq.un.E * (eq.s * y);
      return true;
    }
  }
  return false;
}

/// Moreau's nonsmooth Gauss-Seidel over the candidates, the damped Newton method where it
/// stalls: z in the layout of assemble().
bool solve_cones(const Problem& p, Eigen::VectorXd& z, std::string& why, LcpCounters& counters) {
  const int nj = static_cast<int>(p.W.rows());
  Eigen::VectorXd b(nj);
  for (const Cand& k : p.cands) {
    b[k.kn] = p.free_normal(k);
    if (k.kt >= 0) b[k.kt] = p.f[k.kt];
    if (k.kt2 >= 0) b[k.kt2] = p.f[k.kt2];
  }
  std::vector<Local> loc(p.cands.size());
  for (std::size_t i = 0; i < p.cands.size(); ++i) {
    const Cand& k = p.cands[i];
    Local& l = loc[i];
    l.rows = {k.kn};
    if (k.kt >= 0) l.rows.push_back(k.kt);
    if (k.kt2 >= 0) l.rows.push_back(k.kt2);
    const int m = static_cast<int>(l.rows.size());
    l.W.resize(m, m);
    for (int a = 0; a < m; ++a)
      for (int c = 0; c < m; ++c) l.W(a, c) = p.W(l.rows[a], l.rows[c]);
  }
  Eigen::VectorXd Lam = Eigen::VectorXd::Zero(nj);
  std::vector<double> zeta(p.cands.size(), 0.0);
  const int max_sweeps = 2000;
  bool converged = false;
  // Contacts that pose dependent conditions (a tripod's six friction rows on three) leave W
  // singular: the forces along its null space are not determined and may drift from sweep to
  // sweep while the velocities they make, u = W Λ + b, and so the motion, have settled. Either
  // settles the iteration.
  Eigen::VectorXd u_prev = b;
  const double u_scale = 1.0 + b.cwiseAbs().maxCoeff();
  bool stalled = false;  // a contact without a local solution
  for (int sweep = 0; sweep < max_sweeps && !converged && !stalled; ++sweep) {
    ++counters.cone_sweeps;
    double change = 0.0, size = 0.0;
    for (std::size_t i = 0; i < p.cands.size(); ++i) {
      Local& l = loc[i];
      const int m = static_cast<int>(l.rows.size());
      l.u0.resize(m);
      for (int a = 0; a < m; ++a) {
        double v = b[l.rows[a]] + p.W.row(l.rows[a]).dot(Lam);
        for (int c = 0; c < m; ++c) v -= l.W(a, c) * Lam[l.rows[c]];
        l.u0[a] = v;
      }
      Eigen::VectorXd lam;
      if (!solve_local(p.cands[i], l, lam, zeta[i])) {
        stalled = true;
        break;
      }
      for (int a = 0; a < m; ++a) {
        change = std::max(change, std::abs(lam[a] - Lam[l.rows[a]]));
        size = std::max(size, std::abs(lam[a]));
        Lam[l.rows[a]] = lam[a];
      }
    }
    if (stalled) break;
    const Eigen::VectorXd u = p.W * Lam + b;
    const double u_change = (u - u_prev).cwiseAbs().maxCoeff();
    u_prev = u;
    converged = change <= 1e-14 * size || (p.cands.size() == 1 && sweep == 0) || size == 0.0 ||
                (sweep > 0 && u_change <= 1e-14 * u_scale);
  }
  // Gauss-Seidel can also settle short of a solution (its forces' changes shrinking slowly
  // below 1e-14 without the laws holding): its result is kept only if every contact's law holds
  // to 1e-9 (the Alart-Curnier residual, below), which every result of its converged
  // sweeps meets to rounding.
  if (converged && !laws_hold(p, b, Lam, 1e-9)) converged = false;
  if (!converged) {
    // The laws at once (above), from Gauss-Seidel's last forces, then from none; ζ is then the
    // sliding magnitude |u_t| after (zero, to rounding, where a contact sticks).
    ++counters.cone_fallbacks;
    const std::vector<Eigen::VectorXd> starts{Lam, Eigen::VectorXd::Zero(nj)};
    if (!newton_cones(p, b, starts, Lam, counters.cone_newton_steps)) {
      ++counters.cone_unsolved;
      why = stalled ? "no local solution of Coulomb's law at one contact (the friction force would cancel "
                      "the normal one: Painleve's paradox), nor a solution of all contacts' laws at once"
                    : "the contact forces with 2-D friction cones did not converge in 2000 Gauss-Seidel "
                      "sweeps, nor did a damped Newton method on all contacts' laws at once";
      return false;
    }
    const Eigen::VectorXd u = p.W * Lam + b;
    for (std::size_t i = 0; i < p.cands.size(); ++i) {
      const Cand& k = p.cands[i];
      if (!k.frictional || k.kt < 0) continue;
      zeta[i] = k.kt2 >= 0 ? std::hypot(u[k.kt], u[k.kt2]) : std::abs(u[k.kt]);
    }
  }
  int nz = 0;
  for (const Cand& k : p.cands) nz = std::max(nz, k.zn + (k.frictional ? 4 : 1));
  z = Eigen::VectorXd::Zero(nz);
  for (std::size_t i = 0; i < p.cands.size(); ++i) {
    const Cand& k = p.cands[i];
    z[k.zn] = Lam[k.kn];
    if (!k.frictional) continue;
    if (k.kt2 >= 0) {
      z[k.zn + 1] = Lam[k.kt];
      z[k.zn + 2] = Lam[k.kt2];
    } else {
      z[k.zn + 1] = std::max(Lam[k.kt], 0.0);
      z[k.zn + 2] = std::max(-Lam[k.kt], 0.0);
    }
    z[k.zn + 3] = zeta[i];
  }
  return true;
}

}  // namespace

bool solve_problem(const ContactSet& cs, Problem& p, const LcpSettings& settings, double t,
                   Eigen::VectorXd& z, LcpCounters& counters, std::string& message) {
  assemble(p);
  bool cone = false;
  for (const Cand& k : p.cands) cone = cone || k.kt2 >= 0;
  if (cone) {
    std::string why;
    if (solve_cones(p, z, why, counters)) return true;
    message = std::string(p.impulse ? "the impact" : "the contact modes") + " at t = " + num(t) +
              " (contacts " + names(cs, p) + "): " + why;
    return false;
  }
  const bool single = p.cands.size() == 1 && settings.closed_form_single;
  if (single && solve_single(p, z)) return true;
  // The LCP is linear in b: it is solved for b / max|b| (solutions of order one, so the
  // solver's absolute tolerance is a relative one) and scaled back; b = 0 has z = 0.
  const double scale = p.b.cwiseAbs().maxCoeff();
  if (!(scale > 0.0)) {
    z = Eigen::VectorXd::Zero(p.b.size());
    return true;
  }
  // Several contacts can pose redundant conditions (a block resting on two corners with
  // friction: four rows on three coordinates), and then W = J P Jᵀ is singular and the forces
  // are not unique. Then (only then) W is regularized by 1e-10 of its largest diagonal entry,
  // which selects the solution of least norm (the limit of a very stiff contact, and the
  // distribution the compatibility method's ideality gives bilateral constraints).
  Problem reg = p;
  {
    const Eigen::MatrixXd W_sym = 0.5 * (p.W + p.W.transpose());  // a MatrixXd: eigen_instances.hpp
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(W_sym, Eigen::EigenvaluesOnly);
    const double top = es.eigenvalues().cwiseAbs().maxCoeff();
    if (!(es.eigenvalues().minCoeff() > 1e-9 * top)) {
      reg.W.diagonal().array() += 1e-10 * p.W.diagonal().cwiseAbs().maxCoeff();
      assemble(reg);
    }
  }
  lcp::LcpOptions lo;
  lo.solver = settings.solver;
  ++counters.solves;
  lcp::LcpResult r = lcp::solve_lcp(reg.A, reg.b / scale, lo);
  if (r.status == lcp::LcpStatus::no_solution && lo.solver == lcp::LcpSolver::lemke) {
    // Lemke's method can end on a ray in degenerate problems (contacts at rest, redundant
    // rows: b with exact zeros, W singular); enumeration of the bases then decides.
    lo.solver = lcp::LcpSolver::enumerative;
    r = lcp::solve_lcp(reg.A, reg.b / scale, lo);
  }
  if (r.status != lcp::LcpStatus::solved) {
    message = std::string(p.impulse ? "the impact" : "the contact modes") + " at t = " + num(t) +
              " (contacts " + names(cs, p) + "): " + r.message;
    counters.library_unavailable = r.status == lcp::LcpStatus::library_unavailable;
    return false;
  }
  z = r.z * scale;
  polish(p, z);
  return true;
}

}  // namespace pcsim::mech::contacts
