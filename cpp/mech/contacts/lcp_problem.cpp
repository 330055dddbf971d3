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
    if (cs[k.c].friction >= 0 && (k.frictional || k.sigma != 0)) k.kt = nj++;
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
    if (k.frictional) {
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
    p.b[k.zn] = (p.impulse ? 1.0 + k.e : 1.0) * p.f[k.kn];
    if (!k.frictional) continue;
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
    const double bn = (p.impulse ? 1.0 + k.e : 1.0) * p.f[k.kn];
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

bool solve_problem(const ContactSet& cs, Problem& p, const LcpSettings& settings, double t,
                   Eigen::VectorXd& z, LcpCounters& counters, std::string& message) {
  assemble(p);
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
