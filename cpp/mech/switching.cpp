// simulate_switching(): unilateral contact and Coulomb friction by switching the active
// constraints at events (see switching.hpp and docs/switching.md).
#include "mech/switching.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <ostream>
#include <sstream>

#include "common/format.hpp"
#include <Eigen/Eigenvalues>

#include "linalg/huang.hpp"
#include "mech/dynamics.hpp"
#include "mech/projection.hpp"
#include "ode/integrate.hpp"

namespace pcsim::mech {

const char* to_string(ContactMode mode) {
  switch (mode) {
    case ContactMode::flight: return "flight";
    case ContactMode::contact: return "contact";
    case ContactMode::stick: return "stick";
    case ContactMode::slip: return "slip";
  }
  return "unknown";
}

const char* to_string(ContactEventKind kind) {
  switch (kind) {
    case ContactEventKind::lift_off: return "lift_off";
    case ContactEventKind::impact: return "impact";
    case ContactEventKind::accumulation: return "accumulation";
    case ContactEventKind::slip: return "slip";
    case ContactEventKind::stick: return "stick";
    case ContactEventKind::reversal: return "reversal";
  }
  return "unknown";
}

std::ostream& operator<<(std::ostream& os, ContactMode mode) { return os << to_string(mode); }
std::ostream& operator<<(std::ostream& os, ContactEventKind kind) { return os << to_string(kind); }

std::vector<std::string> unilateral_constraints(const Model& model,
                                                const std::vector<std::string>& active) {
  std::vector<std::string> out;
  for (const ConstraintInfo& c : model.constraints())
    if (c.contact.unilateral && std::find(active.begin(), active.end(), c.name) != active.end())
      out.push_back(c.name);
  return out;
}

namespace {

std::string num(double v) { return format_significant(v, 9); }

/// One unilateral contact of the run.
struct ContactDef {
  int normal = -1;    ///< constraint index of the unilateral constraint
  int friction = -1;  ///< constraint index of its active friction constraint, or -1
  int sign = 1;       ///< gap = sign Φ, normal force = sign λ
  double e = 0.0, mu_s = 0.0, mu_k = 0.0;
  std::string name;
};

/// The contacts' modes for one segment; sigma is the sliding direction (±1) of slipping ones.
struct Config {
  std::vector<ContactMode> modes;
  std::vector<int> sigma;
  /// Per contact (or empty): its friction row sticks but depends on the other imposed rows
  /// (a block resting on two corners with friction has four rows on three coordinates), so it
  /// is implied, not imposed; its friction force is then carried by the others (reported 0).
  std::vector<char> implied;
};

/// The active set of a configuration: the constraints imposed (case order: bilateral ones,
/// closed normals, sticking friction rows), then the rows of sliding friction constraints
/// (not imposed: their row is the direction of the friction force and their g q̇ + g0 the
/// sliding velocity).
struct Layout {
  ActiveSet set;
  std::vector<int> imposed;       ///< constraint indices of the first s_A rows
  int s_A = 0;
  std::vector<int> normal_pos;    ///< per contact: row of its normal in set, or -1
  std::vector<int> friction_pos;  ///< per contact: row of its friction constraint, or -1
};

/// Reactions at one state for one configuration.
struct Solved {
  Eigen::VectorXd qdd, R, lambda;     ///< lambda: the s_A imposed multipliers
  std::vector<double> lambda_n, lambda_t;  ///< per contact (0 when open / no friction)
};

/// Kinematics of one constraint row at a state.
struct Row {
  Eigen::RowVectorXd g;
  double g0 = 0.0, gamma = 0.0;
  double value(const Eigen::VectorXd& qd) const { return g.dot(qd) + g0; }
};

class Engine {
 public:
  Engine(const Model& model, const SimulationOptions& opt, const SwitchingOptions& sw,
         std::vector<int> active, std::vector<ContactDef> contacts)
      : model_(model),
        opt_(opt),
        sw_(sw),
        active_(std::move(active)),
        contacts_(std::move(contacts)),
        n_(model.n()),
        method_(opt.linear_algebra == RadauOptions::LinearAlgebra::lapack
                    ? ReactionMethod::compatibility
                    : opt.reaction_method),
        dyn_(model, opt.kernel),
        aux_dyn_(model, opt.kernel) {
    for (int i : active_) {
      const ContactInfo& ci = model.constraints()[i].contact;
      if (!ci.unilateral && !ci.is_friction()) bilateral_.push_back(i);
    }
  }

  int nc() const { return static_cast<int>(contacts_.size()); }
  const std::vector<ContactDef>& contacts() const { return contacts_; }

  // ---- configuration -> layout ---------------------------------------------------------------

  Layout layout(const Config& cfg) const {
    Layout L;
    std::vector<int> rows;
    L.normal_pos.assign(nc(), -1);
    L.friction_pos.assign(nc(), -1);
    for (int i : active_) {
      const ContactInfo& ci = model_.constraints()[i].contact;
      int c = -1;
      if (ci.unilateral) {
        c = contact_of_normal(i);
        if (!is_closed(cfg.modes[c])) continue;
        L.normal_pos[c] = static_cast<int>(rows.size());
      } else if (ci.is_friction()) {
        c = contact_of_friction(i);
        if (c < 0 || cfg.modes[c] != ContactMode::stick) continue;
        if (!cfg.implied.empty() && cfg.implied[c]) continue;
        L.friction_pos[c] = static_cast<int>(rows.size());
      }
      rows.push_back(i);
    }
    L.imposed = rows;
    L.s_A = static_cast<int>(rows.size());
    for (int c = 0; c < nc(); ++c) {
      if (cfg.modes[c] == ContactMode::slip) {
        L.friction_pos[c] = static_cast<int>(rows.size());
        rows.push_back(contacts_[c].friction);
      }
    }
    L.set = ActiveSet::of(model_, rows);
    return L;
  }

  // ---- reactions ------------------------------------------------------------------------------

  /// Evaluates and solves for the reactions of configuration cfg (layout L) at (t, q, qd).
  ModelIssue solve(Dynamics& d, const Layout& L, const Config& cfg, double t,
                   const Eigen::VectorXd& q, const Eigen::VectorXd& qd, Solved& out,
                   ReactionMethod method) {
    ModelIssue e = d.evaluate(L.set, t, q, qd);
    if (e != ModelIssue::none) return e;
    const int s_all = L.set.size();
    if (s_all == L.s_A) {
      // No sliding contact: exactly the engine's solve of simulate().
      e = d.solve(method);
      if (e != ModelIssue::none) return e;
      out.qdd = d.qdd;
      out.R = d.R;
      out.lambda = d.lambda;
    } else if (method == ReactionMethod::compatibility) {
      e = solve_dense(d, L, cfg, out);
      if (e != ModelIssue::none) return e;
    } else {
      e = solve_structured(d, L, cfg, out);
      if (e != ModelIssue::none) return e;
    }
    out.lambda_n.assign(nc(), 0.0);
    out.lambda_t.assign(nc(), 0.0);
    for (int c = 0; c < nc(); ++c) {
      if (L.normal_pos[c] < 0) continue;
      out.lambda_n[c] = contacts_[c].sign * out.lambda[L.normal_pos[c]];
      if (cfg.modes[c] == ContactMode::stick && L.friction_pos[c] >= 0)
        out.lambda_t[c] = out.lambda[L.friction_pos[c]];
      if (cfg.modes[c] == ContactMode::slip)
        out.lambda_t[c] = -contacts_[c].mu_k * cfg.sigma[c] * out.lambda_n[c];
    }
    return ModelIssue::none;
  }

  // The structured solve with sliding friction: R = (g_Aᵀ + F) λ, F's column of contact c's
  // normal row = −μ_k σ_c sign_c t_cᵀ (the friction force −μ_k λ_n σ along the sliding row),
  // and the compatibility rows g_A M⁻¹ (g_Aᵀ + F) λ = −(g_A M⁻¹ f + γ_A): a non-symmetric
  // s_A x s_A system (no ideality rows: R's form carries them and the friction law).
  ModelIssue solve_structured(Dynamics& d, const Layout& L, const Config& cfg, Solved& out) {
    const int sA = L.s_A;
    llt_.compute(d.M);
    if (llt_.info() != Eigen::Success) return fail(ModelIssue::singular_mass_matrix, "M is not positive definite");
    const Eigen::MatrixXd gA = d.g.topRows(sA);
    Eigen::MatrixXd B = gA.transpose();  // n x sA: g_Aᵀ + F
    for (int c = 0; c < nc(); ++c) {
      if (cfg.modes[c] != ContactMode::slip) continue;
      B.col(L.normal_pos[c]) += -contacts_[c].mu_k * cfg.sigma[c] * contacts_[c].sign *
                                d.g.row(L.friction_pos[c]).transpose();
    }
    const Eigen::VectorXd a0 = llt_.solve(d.f);
    const Eigen::MatrixXd MinvB = llt_.solve(B);
    const Eigen::MatrixXd S = gA * MinvB;
    const Eigen::VectorXd rhs = -(gA * a0 + d.gamma.head(sA));
    const Eigen::FullPivLU<Eigen::MatrixXd> lu(S);
    if (!lu.isInvertible())
      return fail(ModelIssue::dependent_constraints,
                  "the compatibility system with sliding friction is singular (the friction force "
                  "cancels the normal one: Painleve's paradox, or dependent constraints)");
    out.lambda = lu.solve(rhs);
    out.R = B * out.lambda;
    out.qdd = a0 + MinvB * out.lambda;
    if (!out.R.allFinite() || !out.qdd.allFinite())
      return fail(ModelIssue::non_finite, "the reactions with sliding friction are not finite");
    return ModelIssue::none;
  }

  // The paper's dense system with one ideality row replaced by the friction law per sliding
  // contact: rows G_A R = −G0_A (s_A), Dᵀ R = 0 with D spanning null([g_A; g_slip])
  // (n − s_A − m), and λ_t + μ_k σ λ_n = 0 (m), where the multipliers are the components of R
  // in the rows, λ = (g gᵀ)⁻¹ g R (exact for R in the row space, which the Dᵀ rows enforce).
  ModelIssue solve_dense(Dynamics& d, const Layout& L, const Config& cfg, Solved& out) {
    const int sA = L.s_A, s_all = L.set.size();
    ModelIssue e = d.prepare_compatibility();
    if (e != ModelIssue::none) return e;
    const Eigen::MatrixXd C = (d.g * d.g.transpose()).ldlt().solve(d.g);  // s_all x n
    Eigen::MatrixXd A(n_, n_);
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n_);
    A.topRows(sA) = d.G.topRows(sA);
    rhs.head(sA) = -d.G0.head(sA);
    A.middleRows(sA, n_ - s_all) = d.D.transpose();
    int r = n_ - (s_all - sA);
    for (int c = 0; c < nc(); ++c) {
      if (cfg.modes[c] != ContactMode::slip) continue;
      A.row(r++) = C.row(L.friction_pos[c]) +
                   contacts_[c].mu_k * cfg.sigma[c] * contacts_[c].sign * C.row(L.normal_pos[c]);
    }
    const Eigen::PartialPivLU<Eigen::MatrixXd> lu(A);
    out.R = lu.solve(rhs);
    llt_.compute(d.M);
    out.qdd = llt_.solve(d.f + out.R);
    out.lambda = (C * out.R).head(sA);
    if (!out.R.allFinite() || !out.qdd.allFinite() ||
        (A * out.R - rhs).cwiseAbs().maxCoeff() > 1e-8 * (1.0 + rhs.cwiseAbs().maxCoeff() +
                                                          (A.cwiseAbs() * out.R.cwiseAbs()).maxCoeff()))
      return fail(ModelIssue::dependent_constraints,
                  "the compatibility system [G; D^T; friction] R = [-G0; 0; 0] is singular");
    return ModelIssue::none;
  }

  // ---- contact kinematics ---------------------------------------------------------------------

  Row row(int constraint, double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) const {
    Eigen::MatrixXd g(1, n_);
    Eigen::VectorXd g0(1), gamma(1);
    model_.constraint_rows({constraint}, t, q, qd, g, g0, gamma);
    Row r;
    r.g = g.row(0);
    r.g0 = g0[0];
    r.gamma = gamma[0];
    return r;
  }
  Row normal_row(int c, double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) const {
    Row r = row(contacts_[c].normal, t, q, qd);
    const double s = contacts_[c].sign;
    r.g *= s;
    r.g0 *= s;
    r.gamma *= s;
    return r;
  }
  double gap(int c, double t, const Eigen::VectorXd& q) const {
    return contacts_[c].sign * model_.position_residual(contacts_[c].normal, t, q);
  }
  double vn(int c, double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) const {
    return normal_row(c, t, q, qd).value(qd);
  }
  double vt(int c, double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) const {
    if (contacts_[c].friction < 0) return 0.0;
    return row(contacts_[c].friction, t, q, qd).value(qd);
  }

  // ---- the inertia seen by the contacts ---------------------------------------------------------

  /// P = M⁻¹ − M⁻¹ g_Bᵀ (g_B M⁻¹ g_Bᵀ)⁻¹ g_B M⁻¹ (the inverse inertia with the bilateral
  /// constraints imposed) and a_B, the acceleration with only the bilateral constraints.
  ModelIssue inertia(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                     Eigen::MatrixXd& P, Eigen::VectorXd& aB) {
    const ActiveSet bset = ActiveSet::of(model_, bilateral_);
    ModelIssue e = aux_dyn_.evaluate(bset, t, q, qd);
    if (e != ModelIssue::none) return fail(e, aux_dyn_.message());
    e = aux_dyn_.solve(ReactionMethod::compatibility_structured);
    if (e != ModelIssue::none) return fail(e, aux_dyn_.message());
    aB = aux_dyn_.qdd;
    llt_.compute(aux_dyn_.M);
    P = llt_.solve(Eigen::MatrixXd::Identity(n_, n_));
    if (!bilateral_.empty()) {
      const Eigen::MatrixXd MinvgT = llt_.solve(aux_dyn_.g.transpose());
      const Eigen::MatrixXd S = aux_dyn_.g * MinvgT;
      P -= MinvgT * S.ldlt().solve(MinvgT.transpose());
    }
    P = 0.5 * (P + P.transpose());
    return ModelIssue::none;
  }

  // ---- complementarity problems -------------------------------------------------------------

  /// One contact in a complementarity problem. frictional: the planar Coulomb cone with the
  /// variables (Λn, β+, β−, ζ), Λt = β+ − β− (Stewart-Trinkle); sliding (acceleration level,
  /// |v_t| > 0): the friction force −μ σ Λn along the row, variable Λn only; otherwise Λn only.
  struct Cand {
    int c = 0;
    bool frictional = false;
    int sigma = 0;   ///< sliding direction (acceleration level, sliding contacts)
    double e = 0.0;  ///< restitution (impulse level)
    double mu = 0.0;
    int kn = -1, kt = -1;  ///< rows in J
    int zn = -1;           ///< first variable
  };

  /// The LCP w = A z + b of candidates with rows J, Delassus W = J P Jᵀ and free values f (the
  /// contact velocities before the impulse, or accelerations without contact forces).
  struct Problem {
    std::vector<Cand> cands;
    Eigen::MatrixXd W, E, A;  ///< E: rows of J x variables (Λ_J = E z)
    Eigen::VectorXd f, b;
    bool impulse = false;
  };

  void assemble(Problem& p) const {
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
  bool solve_single(const Problem& p, Eigen::VectorXd& z) const {
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

  /// Solves the problem: closed form for one candidate (unless options say always), else
  /// Siconos. Returns false with message_ set when no solution is found.
  bool solve_problem(Problem& p, double t, Eigen::VectorXd& z) {
    assemble(p);
    const bool single = p.cands.size() == 1 && sw_.lcp == SwitchingOptions::Lcp::several_contacts;
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
      const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(0.5 * (p.W + p.W.transpose()),
                                                              Eigen::EigenvaluesOnly);
      const double top = es.eigenvalues().cwiseAbs().maxCoeff();
      if (!(es.eigenvalues().minCoeff() > 1e-9 * top)) {
        reg.W.diagonal().array() += 1e-10 * p.W.diagonal().cwiseAbs().maxCoeff();
        assemble(reg);
      }
    }
    lcp::LcpOptions lo;
    lo.solver = sw_.lcp_solver;
    ++lcp_solves_;
    lcp::LcpResult r = lcp::solve_lcp(reg.A, reg.b / scale, lo);
    if (r.status == lcp::LcpStatus::no_solution && lo.solver == lcp::LcpSolver::lemke) {
      // Lemke's method can end on a ray in degenerate problems (contacts at rest, redundant
      // rows: b with exact zeros, W singular); enumeration of the bases then decides.
      lo.solver = lcp::LcpSolver::enumerative;
      r = lcp::solve_lcp(reg.A, reg.b / scale, lo);
    }
    if (r.status != lcp::LcpStatus::solved) {
      message_ = std::string(p.impulse ? "the impact" : "the contact modes") + " at t = " + num(t) +
                 " (contacts " + names(p) + "): " + r.message;
      lcp_failed_ = r.status == lcp::LcpStatus::library_unavailable;
      return false;
    }
    z = r.z * scale;
    polish(p, z);
    return true;
  }

  /// The LCP decides which contacts are closed, sticking or sliding; the values then come
  /// from the equations of that set, solved exactly (least norm where contacts are redundant):
  /// closed normals w_n = 0, sticking tangents v_t = 0, sliding ones Λt = −σ μ Λn, open ones
  /// Λ = 0. This removes the regularization's 1e-10 from unique solutions. Kept only if the
  /// result is still complementary (to 1e-9 of the problem's scale).
  void polish(const Problem& p, Eigen::VectorXd& z) const {
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

  std::string names(const Problem& p) const {
    std::string s;
    for (const Cand& k : p.cands) s += (s.empty() ? "'" : ", '") + contacts_[k.c].name + "'";
    return s;
  }

  /// Rows J (normal, then tangent of each candidate) at the state.
  void rows_of(Problem& p, double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
               Eigen::MatrixXd& J, Eigen::VectorXd& j0, Eigen::VectorXd& jgamma) const {
    int nj = 0;
    for (Cand& k : p.cands) {
      k.kn = nj++;
      if (contacts_[k.c].friction >= 0 && (k.frictional || k.sigma != 0)) k.kt = nj++;
    }
    J.resize(nj, n_);
    j0.resize(nj);
    jgamma.resize(nj);
    for (const Cand& k : p.cands) {
      const Row rn = normal_row(k.c, t, q, qd);
      J.row(k.kn) = rn.g;
      j0[k.kn] = rn.g0;
      jgamma[k.kn] = rn.gamma;
      if (k.kt >= 0) {
        const Row rt = row(contacts_[k.c].friction, t, q, qd);
        J.row(k.kt) = rt.g;
        j0[k.kt] = rt.g0;
        jgamma[k.kt] = rt.gamma;
      }
    }
  }

  // ---- transitions ----------------------------------------------------------------------------

  // ---- tolerances of one contact (issue 19) ---------------------------------------------------
  //
  // Every tolerance of a contact is relative to the quantity it compares, never to the size of
  // the coordinates: a ball bouncing 50 m along the floor (x = 50, not in the gap) must bounce
  // exactly as at x = 0. The scales come from the contact's own rows:
  //  - the gap's rounding: the representation error of the coordinates (and of t) propagated
  //    through the gap function, kRound eps (sum_j |dg/dq_j| |q_j| + |dg/dt| |t|); a floor
  //    `y - 50 >= 0` with y near 50 has a rounding of 50 eps, a floor y >= 0 at x = 50 none from x;
  //  - the gap's accuracy: the integrator's absolute tolerance propagated through the gradient,
  //    10 atol sum_j |dg/dq_j|, plus the rounding;
  //  - a contact velocity's (gap rate or sliding velocity, g q_d + g0) accuracy: 10 (atol |g|_1
  //    + rtol (|g| . |q_d| + |g0|)) plus its rounding kRound eps (|g| . |q_d| + |g0|): relative to the
  //    terms that make up that velocity, so a fast slide along an incline (x_d, not in the gap
  //    rate) does not widen the normal velocity's tolerance.
  static constexpr double kEps = 2.220446049250313e-16;
  static constexpr double kRound = 100.0;
  /// A rebound whose apex is below kResolve gap roundings is an accumulation (impact()).
  static constexpr double kResolve = 16.0;
  double row_scale(const Row& r, double t, const Eigen::VectorXd& q) const {
    return r.g.cwiseAbs().dot(q.cwiseAbs()) + std::abs(r.g0 * t);
  }
  double gap_round(int c, double t, const Eigen::VectorXd& q) const {
    const Row r = normal_row(c, t, q, Eigen::VectorXd::Zero(n_));
    return kRound * kEps * row_scale(r, t, q);
  }
  double gap_tol(int c, double t, const Eigen::VectorXd& q) const {
    const Row r = normal_row(c, t, q, Eigen::VectorXd::Zero(n_));
    return 10.0 * opt_.atol * r.g.cwiseAbs().sum() + kRound * kEps * row_scale(r, t, q);
  }
  double velocity_tol(const Row& r, const Eigen::VectorXd& qd) const {
    const double terms = r.g.cwiseAbs().dot(qd.cwiseAbs()) + std::abs(r.g0);
    return 10.0 * (opt_.atol * r.g.cwiseAbs().sum() + opt_.rtol * terms) + kRound * kEps * terms;
  }
  double vn_tol(int c, double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) const {
    return velocity_tol(normal_row(c, t, q, qd), qd);
  }
  double vt_tol(int c, double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) const {
    if (contacts_[c].friction < 0) return 0.0;
    return velocity_tol(row(contacts_[c].friction, t, q, qd), qd);
  }
  /// The rounding of a contact velocity (the sliding function's offset).
  double velocity_round(const Row& r, const Eigen::VectorXd& qd) const {
    return kRound * kEps * (r.g.cwiseAbs().dot(qd.cwiseAbs()) + std::abs(r.g0));
  }

  /// Resolves an impact at (t, q, qd) if a touching contact approaches: Newton's law with the
  /// impulses of the compatibility equations at impulse level (Coulomb-bounded tangential
  /// impulses), the accumulation rule, the energy rule, and the events. qd is updated. Returns
  /// false on failure (message_).
  ///
  /// The energy rule (issue 19): an impact never creates kinetic energy. Newton's law with
  /// Coulomb friction can (a corner that must stop sliding while it rebounds: the tangential
  /// impulse works against the coupling of the normal one; Kane's paradox), and so can Newton's
  /// law at several contacts. The plastic impact (e = 0) with Coulomb friction never does: by
  /// complementarity Λ_n v_n⁺ = 0 and Λ_t v_t⁺ = −ζ (β⁺ + β⁻) <= 0, so
  /// ΔT = Λ·v⁺ − ½ Λ·WΛ <= 0. Where Newton's impulse Λ_N would create energy, the impulse taken
  /// is Λ_0 + s (Λ_N − Λ_0) with Λ_0 the plastic one and s in [0, 1) the largest with ΔT <= 0:
  /// it lies in Coulomb's cone (both do, and the cone is convex), no contact approaches after it
  /// (both leave v_n⁺ >= 0), and it loses no more energy than needed (for e = 1 it conserves
  /// the energy exactly). Counted in energy_limited_impacts.
  bool impact(double t, const Eigen::VectorXd& q, Eigen::VectorXd& qd, const Config& before,
              std::vector<ContactEvent>& events, std::vector<char>& hit) {
    Problem p;
    p.impulse = true;
    bool approaching = false;
    std::vector<double> vtol_of(nc(), 0.0);
    for (int c = 0; c < nc(); ++c) {
      if (!(gap(c, t, q) <= gap_tol(c, t, q))) continue;
      Cand k;
      k.c = c;
      k.frictional = contacts_[c].friction >= 0;
      k.mu = contacts_[c].mu_k;
      vtol_of[c] = vn_tol(c, t, q, qd);
      const bool approaches = vn(c, t, q, qd) < -vtol_of[c];
      // Newton's law v_n⁺ >= −e v_n⁻ restores an approach; a touching contact that does not
      // approach (at rest or separating) only may not be driven into the surface by the others'
      // impulses: v_n⁺ >= 0 (with e, a separating one could have been left approaching at −e v_n⁻).
      k.e = approaches ? contacts_[c].e : 0.0;
      p.cands.push_back(k);
      approaching = approaching || approaches;
    }
    if (!approaching) return true;
    Eigen::MatrixXd J, P;
    Eigen::VectorXd j0, jg, aB;
    rows_of(p, t, q, qd, J, j0, jg);
    if (inertia(t, q, qd, P, aB) != ModelIssue::none) return false;
    const Eigen::MatrixXd M = aux_dyn_.M;
    p.W = J * P * J.transpose();
    p.f = J * qd + j0;  // velocities before
    const Eigen::VectorXd v_before = p.f;
    // The change of kinetic energy by the contact impulses Λ, from the velocity change they
    // make (Δq̇ = P Jᵀ Λ): ΔT = q̇⁻ᵀ M Δq̇ + ½ Δq̇ᵀ M Δq̇ + Λ·j0. For scleronomic contacts this is
    // T⁺ − T⁻ (the bilateral constraints' impulses do no work); for a moving surface (j0 ≠ 0)
    // it is the change of the kinetic energy of the motion relative to it, Λ·(v⁻ + v⁺)/2.
    // Computed from Δq̇, not from Λ·WΛ: impulses of redundant contacts can be large and cancel.
    auto energy_change = [&](const Eigen::VectorXd& L, double* round) {
      const Eigen::VectorXd d = P * (J.transpose() * L);
      const Eigen::VectorXd Md = M * d;
      if (round)
        *round = 1e-12 * (qd.cwiseAbs().dot((M.cwiseAbs() * d.cwiseAbs())) +
                          0.5 * d.cwiseAbs().dot(M.cwiseAbs() * d.cwiseAbs()) +
                          L.cwiseAbs().dot(j0.cwiseAbs())) + 1e-300;
      return qd.dot(Md) + 0.5 * d.dot(Md) + L.dot(j0);
    };
    // No touching contact approaches after the impulse (its velocities from Δq̇ as well).
    auto velocities_after = [&](const Eigen::VectorXd& L) -> Eigen::VectorXd {
      return J * (qd + P * (J.transpose() * L)) + j0;
    };
    auto leaves_none_approaching = [&](const Eigen::VectorXd& L) {
      const Eigen::VectorXd v = velocities_after(L);
      for (const Cand& k : p.cands)
        if (!(v[k.kn] >= -vtol_of[k.c])) return false;
      return true;
    };
    const Problem newton = p;  // before assemble(): the plastic problem below starts from it
    Eigen::VectorXd z;
    if (!solve_problem(p, t, z)) return false;
    Eigen::VectorXd Lam = p.E * z;
    // The energy rule.
    bool limited = false;
    double round = 0.0;
    double dT = energy_change(Lam, &round);
    const bool newton_solves = leaves_none_approaching(Lam);
    if (dT > round || !newton_solves) {
      Problem plastic = newton;
      for (Cand& k : plastic.cands) k.e = 0.0;
      Eigen::VectorXd z0;
      if (!solve_problem(plastic, t, z0)) return false;
      const Eigen::VectorXd Lam0 = plastic.E * z0;
      double round0 = 0.0;
      const double dT0 = energy_change(Lam0, &round0);
      if (dT0 > round0 || !leaves_none_approaching(Lam0)) {
        message_ = "the impact at t = " + num(t) + " (contacts " + names(p) + ") has no consistent " +
                   "solution: the impulses found " +
                   (dT0 > round0 ? "would create kinetic energy even without restitution (" + num(dT0) + " J)"
                                 : std::string("leave a contact approaching")) +
                   " (several contacts that pose dependent conditions, with friction?)";
        return false;
      }
      if (newton_solves) {
        double lo = 0.0, hi = 1.0;
        for (int it = 0; it < 60; ++it) {
          const double mid = 0.5 * (lo + hi);
          (energy_change(Lam0 + mid * (Lam - Lam0), nullptr) <= 0.0 ? lo : hi) = mid;
        }
        max_energy_prevented_ = std::max(max_energy_prevented_, dT);
        Lam = Lam0 + lo * (Lam - Lam0);
      } else {
        Lam = Lam0;  // Newton's impulse is no solution (an LCP answer out of tolerance): plastic
      }
      dT = energy_change(Lam, nullptr);
      limited = true;
      ++energy_limited_;
    }
    Eigen::VectorXd v_after = velocities_after(Lam);
    // Accumulation: a contact that leaves the surface after the impact (a rebound, or a corner
    // lifted by an impact elsewhere) and would land again within zeno_time (2 v_n / |a_n|,
    // a_n with every contact open) starts a sequence of impacts that accumulates; so does a
    // rebound whose apex v_n² / (2 |a_n|) stays below kResolve times the gap's rounding (the
    // flight cannot be resolved: at 50 m from the origin the gap y − 50 is known to 50 eps only,
    // and the landing would be decided by rounding, not by the motion). Its limit is taken at
    // once: every touching contact closed, by the impulse of least kinetic energy that brings
    // their normal velocities to zero (Λ_n = −W_nn⁺ v_n⁻, the P-weighted projection; friction is
    // decided at acceleration level right after).
    bool accumulate = false;
    for (const Cand& k : p.cands) {
      if (!(v_after[k.kn] > vtol_of[k.c])) continue;
      const double an = J.row(k.kn).dot(aB) + jg[k.kn];
      if (!(an < 0.0)) continue;
      const double v = v_after[k.kn];
      if (2.0 * v / -an < sw_.zeno_time || v * v / (2.0 * -an) < kResolve * gap_round(k.c, t, q))
        accumulate = true;
    }
    if (accumulate) {
      if (limited) --energy_limited_;  // the closure replaces the limited impulse
      limited = false;
      // First with the sliding velocities of the frictional contacts brought to zero as well
      // (the accumulating impacts end at rest), if the tangential impulses that takes stay in
      // Coulomb's cone (|Λ_t| <= μ_k |Λ_n|); otherwise normals only (a sliding body keeps
      // sliding after its bounces have accumulated).
      for (int with_t = 1; with_t >= 0; --with_t) {
        std::vector<int> rows;
        for (const Cand& k : p.cands) {
          rows.push_back(k.kn);
          if (with_t && k.frictional) rows.push_back(k.kt);
        }
        const int m = static_cast<int>(rows.size());
        Eigen::MatrixXd Wr(m, m);
        Eigen::VectorXd vr(m);
        for (int a = 0; a < m; ++a) {
          vr[a] = v_before[rows[a]];
          for (int b = 0; b < m; ++b) Wr(a, b) = p.W(rows[a], rows[b]);
        }
        const Eigen::VectorXd l = -Wr.completeOrthogonalDecomposition().solve(vr);
        Lam.setZero();
        for (int a = 0; a < m; ++a) Lam[rows[a]] = l[a];
        bool in_cone = true;
        for (const Cand& k : p.cands)
          if (with_t && k.frictional)
            in_cone = in_cone && std::abs(Lam[k.kt]) <= contacts_[k.c].mu_k * std::abs(Lam[k.kn]) * (1 + 1e-9);
        if (in_cone) break;
      }
      v_after = velocities_after(Lam);
      dT = energy_change(Lam, &round);
      // The least-energy closure: ΔT = −½ v⁻·W⁺v⁻ <= 0 by construction; checked all the same.
      if (dT > round) {
        message_ = "the accumulation closure at t = " + num(t) + " (contacts " + names(p) +
                   ") would create kinetic energy (" + num(dT) + " J)";
        return false;
      }
    }
    last_energy_change_ = dT;
    const Eigen::VectorXd dqd = P * (J.transpose() * Lam);
    for (const Cand& k : p.cands) {
      const double ln = Lam[k.kn], lt = k.kt >= 0 ? Lam[k.kt] : 0.0;
      const double vb = v_before[k.kn], va = v_after[k.kn];
      const double vtb = k.kt >= 0 ? v_before[k.kt] : 0.0, vta = k.kt >= 0 ? v_after[k.kt] : 0.0;
      const double lost = -0.5 * (ln * (va + vb) + lt * (vta + vtb));
      if (!(vb < -vtol_of[k.c])) {
        // A closed contact that took part: its share of the loss is booked with the impact,
        // its impulse reported with its own switch (a lift-off), if any.
        if (ln != 0.0 || lt != 0.0) pending_loss_[k.c] += lost;
        impulsed_[k.c] = 1;
        impulse_n_[k.c] = ln;
        impulse_t_[k.c] = lt;
        continue;
      }
      ContactEvent ev;
      ev.t = t;
      ev.kind = accumulate ? ContactEventKind::accumulation : ContactEventKind::impact;
      ev.contact = k.c;
      ev.constraint = contacts_[k.c].name;
      ev.mode_before = before.modes[k.c];
      ev.normal = ln;
      ev.tangential = lt;
      ev.vn_before = vb;
      ev.vn_after = va;
      ev.vt_before = vtb;
      ev.vt_after = vta;
      ev.energy_lost = lost;
      ev.energy_limited = limited;
      hit[k.c] = 1;
      events.push_back(ev);
    }
    qd += dqd;
    return true;
  }

  /// Decides the modes of the touching contacts at (t, q, qd) (after any impact): the
  /// acceleration-level complementarity problem of normal forces and, for contacts at rest
  /// tangentially, the Coulomb cone with μ_s; sliding contacts keep their direction with μ_k.
  bool decide(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Config& before,
              Config& cfg, bool force_lcp) {
    cfg.modes.assign(nc(), ContactMode::flight);
    cfg.sigma.assign(nc(), 0);
    Problem p;
    for (int c = 0; c < nc(); ++c) {
      if (!(gap(c, t, q) <= gap_tol(c, t, q)) || !(vn(c, t, q, qd) <= vn_tol(c, t, q, qd))) continue;
      Cand k;
      k.c = c;
      if (contacts_[c].friction >= 0) {
        const double v = vt(c, t, q, qd);
        if (std::abs(v) <= vt_tol(c, t, q, qd)) {
          k.frictional = true;
          k.mu = contacts_[c].mu_s;
        } else {
          k.sigma = v > 0 ? 1 : -1;
          k.mu = contacts_[c].mu_k;
        }
      }
      p.cands.push_back(k);
    }
    if (p.cands.empty()) return true;
    Eigen::MatrixXd J, P;
    Eigen::VectorXd j0, jg, aB;
    rows_of(p, t, q, qd, J, j0, jg);
    if (inertia(t, q, qd, P, aB) != ModelIssue::none) return false;
    p.W = J * P * J.transpose();
    p.f = J * aB + jg;  // accelerations without contact forces
    const SwitchingOptions::Lcp saved = sw_.lcp;
    if (force_lcp) sw_.lcp = SwitchingOptions::Lcp::always;
    Eigen::VectorXd z;
    const bool ok = solve_problem(p, t, z);
    sw_.lcp = saved;
    if (!ok) return false;
    const Eigen::VectorXd w = p.A * z + p.b;
    const Eigen::VectorXd acc = p.f + p.W * (p.E * z);
    const double scale = 1.0 + p.f.cwiseAbs().maxCoeff() + (p.W * (p.E * z)).cwiseAbs().maxCoeff();
    const double tol = 1e-9 * scale;
    for (const Cand& k : p.cands) {
      const bool separates = z[k.zn] <= tol && w[k.zn] > tol;
      if (separates) continue;
      if (contacts_[k.c].friction < 0) {
        cfg.modes[k.c] = ContactMode::contact;
      } else if (k.frictional) {
        const double zeta = z[k.zn + 3];
        if (zeta <= tol) {
          cfg.modes[k.c] = ContactMode::stick;
        } else {
          cfg.modes[k.c] = ContactMode::slip;
          cfg.sigma[k.c] = acc[k.kt] > 0 ? 1 : -1;
        }
      } else {
        cfg.modes[k.c] = ContactMode::slip;
        cfg.sigma[k.c] = k.sigma;
      }
    }
    (void)before;
    return true;
  }

  /// Marks the sticking friction rows that depend on the other imposed rows at this state as
  /// implied (Huang's rank test, friction rows last). Fails if a normal or bilateral row is
  /// itself redundant (contacts that pose the same condition twice).
  bool mark_implied(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd, Config& cfg) {
    cfg.implied.assign(nc(), 0);
    const Layout L = layout(cfg);
    if (L.imposed.empty()) return true;
    std::vector<int> order;
    for (int i : L.imposed)
      if (!model_.constraints()[i].contact.is_friction()) order.push_back(i);
    const int n_plain = static_cast<int>(order.size());
    for (int i : L.imposed)
      if (model_.constraints()[i].contact.is_friction()) order.push_back(i);
    const int s = static_cast<int>(order.size());
    Eigen::MatrixXd g(s, n_);
    Eigen::VectorXd g0(s), gamma(s);
    model_.constraint_rows(order, t, q, qd, g, g0, gamma);
    HuangOptions ho;
    ho.kernel = opt_.kernel;
    const HuangResult hr = huang_solve(g, Eigen::VectorXd::Zero(s), ho);
    if (hr.info < 0) {
      message_ = "the Huang kernel rejected the contact rows at t = " + num(t);
      return false;
    }
    if (hr.rank == s) return true;
    for (int r = 0; r < s && r < static_cast<int>(hr.row_dependent.size()); ++r) {
      if (!hr.row_dependent[r]) continue;
      if (r < n_plain) {
        message_ = "the constraint '" + model_.constraints()[order[r]].name +
                   "' depends on the other closed contacts at t = " + num(t) +
                   " (redundant unilateral contacts are not supported)";
        return false;
      }
      cfg.implied[contact_of_friction(order[r])] = 1;
    }
    return true;
  }

  /// Checks a configuration at a state: closed contacts push (λ_n > 0), sticking ones inside
  /// the cone, sliding ones accelerate along their direction when they start from rest. At a
  /// rounding-level tie the first offending contact is switched (closed -> open, stick ->
  /// slip) and 1 is returned; 0 when consistent; -1 on failure.
  int check(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd, Config& cfg) {
    const Layout L = layout(cfg);
    Solved s;
    if (solve(aux_dyn_, L, cfg, t, q, qd, s, method_) != ModelIssue::none) {
      message_ = aux_dyn_.message().empty() ? message_ : aux_dyn_.message();
      return -1;
    }
    for (int c = 0; c < nc(); ++c) {
      if (!is_closed(cfg.modes[c])) continue;
      if (!(s.lambda_n[c] > 0.0)) {
        cfg.modes[c] = ContactMode::flight;
        cfg.sigma[c] = 0;
        return 1;
      }
      if (cfg.modes[c] == ContactMode::stick &&
          !(std::abs(s.lambda_t[c]) <= contacts_[c].mu_s * s.lambda_n[c])) {
        cfg.modes[c] = ContactMode::slip;
        cfg.sigma[c] = s.lambda_t[c] > 0 ? -1 : 1;  // it slides against the force that held it
        return 1;
      }
    }
    return 0;
  }

  /// The full transition at an event (or at t0): impact, modes, consistency, projection, and
  /// the events of the mode changes. Returns false on failure (message_).
  bool transition(double t, Eigen::VectorXd& q, Eigen::VectorXd& qd, const Config& before,
                  const Solved* reactions_before, Config& after, std::vector<ContactEvent>& events,
                  bool initial) {
    std::vector<char> hit(nc(), 0);
    impulsed_.assign(nc(), 0);
    impulse_n_.assign(nc(), 0.0);
    impulse_t_.assign(nc(), 0.0);
    const Eigen::VectorXd qd_before = qd;
    std::vector<double> vn_b(nc()), vt_b(nc());
    for (int c = 0; c < nc(); ++c) {
      vn_b[c] = vn(c, t, q, qd);
      vt_b[c] = vt(c, t, q, qd);
    }
    if (!impact(t, q, qd, before, events, hit)) return false;
    bool force_lcp = false;
    for (int attempt = 0;; ++attempt) {
      if (!decide(t, q, qd, before, after, force_lcp)) return false;
      int fixes = 0, r = 0;
      while (true) {
        if (!mark_implied(t, q, qd, after)) return false;
        r = check(t, q, qd, after);
        if (r != 1 || ++fixes >= 2 * nc() + 2) break;
      }
      if (r == 0) break;
      if (r < 0 || attempt > 0 || force_lcp) {
        if (r > 0)
          message_ = "no consistent set of contact modes at t = " + num(t) +
                     " (the contacts switch back and forth at one instant)";
        return false;
      }
      force_lcp = true;  // the closed form's choice did not hold: let the LCP decide
    }
    // A friction row whose contact leaves stick loses its position-level constant for good.
    for (int c = 0; c < nc(); ++c)
      if (!initial && after.modes[c] != ContactMode::stick) anchored_[c] = 0;
    // Consistent state for the new set: the minimum-norm projection onto the imposed rows.
    const Layout L = layout(after);
    double dq = 0.0, dv = 0.0;
    std::string msg;
    if (project(L, t, q, qd, dq, dv, msg) != ModelIssue::none) {
      message_ = "projection onto the new contact set at t = " + num(t) + ": " + msg;
      return false;
    }
    // A contact that flies on after the event starts on the surface, not below it. The state
    // at an event lies on the root's far side (the gap a rounding below zero), and the landing
    // threshold of the next flight is taken from where it starts: without this, every bounce
    // started a rounding deeper than the last (the ball 50 m along the floor went 4.8e-6 m into
    // it in 429,062 bounces). The open contacts touching from below (within gap_tol) are
    // projected onto their surface together with the imposed rows, positions only, and the
    // velocities then onto the imposed rows again. Deeper penetrations are left as they are and
    // reported (penetration_max).
    {
      std::vector<int> rows;
      bool lift = false;
      for (int i : L.imposed)
        if (model_.constraints()[i].kind == ConstraintKind::holonomic && position_level(i)) rows.push_back(i);
      for (int c = 0; c < nc(); ++c) {
        if (is_closed(after.modes[c])) continue;
        const double gc = gap(c, t, q);
        if (gc < 0.0 && gc >= -gap_tol(c, t, q)) {
          rows.push_back(contacts_[c].normal);
          lift = true;
        }
      }
      if (lift) {
        Eigen::VectorXd qd_tmp = qd;
        if (project_state(model_, rows, t, q, qd_tmp, opt_.kernel, opt_.projection_tol, dq, dv, msg, pw_) !=
                ModelIssue::none ||
            project(L, t, q, qd, dq, dv, msg) != ModelIssue::none) {
          message_ = "lifting the rebounding contacts onto their surface at t = " + num(t) + ": " + msg;
          return false;
        }
      }
    }
    for (ContactEvent& ev : events)
      if (ev.t == t && hit[ev.contact]) ev.mode_after = after.modes[ev.contact];
    if (initial) return true;
    // Events of the mode changes that are not impacts.
    for (int c = 0; c < nc(); ++c) {
      const ContactMode mb = before.modes[c], ma = after.modes[c];
      if (hit[c]) {
        for (auto it = events.rbegin(); it != events.rend(); ++it)
          if (it->contact == c && it->t == t) {
            it->energy_lost += pending_loss_[c];
            pending_loss_[c] = 0.0;
            break;
          }
        continue;
      }
      ContactEvent ev;
      ev.t = t;
      ev.contact = c;
      ev.constraint = contacts_[c].name;
      ev.mode_before = mb;
      ev.mode_after = ma;
      ev.vn_before = vn_b[c];
      ev.vt_before = vt_b[c];
      ev.vn_after = vn(c, t, q, qd);
      ev.vt_after = vt(c, t, q, qd);
      if (impulsed_[c]) {  // switched by an impact elsewhere: the impulse it received
        ev.normal = impulse_n_[c];
        ev.tangential = impulse_t_[c];
      } else if (reactions_before && !reactions_before->lambda_n.empty()) {
        ev.normal = reactions_before->lambda_n[c];
        ev.tangential = reactions_before->lambda_t[c];
      }
      if (is_closed(mb) && !is_closed(ma)) {
        ev.kind = ContactEventKind::lift_off;
      } else if (!is_closed(mb) && is_closed(ma)) {
        ev.kind = ContactEventKind::impact;  // touched down without approach velocity
      } else if (mb == ContactMode::stick && ma == ContactMode::slip) {
        ev.kind = ContactEventKind::slip;
      } else if (mb == ContactMode::slip && ma == ContactMode::stick) {
        ev.kind = ContactEventKind::stick;
      } else if (mb == ContactMode::slip && ma == ContactMode::slip && before.sigma[c] != after.sigma[c]) {
        ev.kind = ContactEventKind::reversal;
      } else {
        continue;
      }
      ev.energy_lost = pending_loss_[c];
      pending_loss_[c] = 0.0;
      events.push_back(ev);
    }
    // A closed contact that took part in an impact without a switch of its own: its share of
    // the loss goes to the first impact of the instant.
    for (int c = 0; c < nc(); ++c) {
      if (pending_loss_[c] == 0.0) continue;
      for (ContactEvent& ev : events)
        if (ev.t == t && (ev.kind == ContactEventKind::impact || ev.kind == ContactEventKind::accumulation)) {
          ev.energy_lost += pending_loss_[c];
          break;
        }
      pending_loss_[c] = 0.0;
    }
    (void)qd_before;
    return true;
  }

  ModelIssue fail(ModelIssue e, std::string message) {
    message_ = std::move(message);
    return e;
  }

  /// A holonomic friction constraint (rolling: s + r φ = const) holds its position-level
  /// constant only until its contact first leaves stick: after a slip or a flight the contact
  /// point has moved, and sticking again means v_t = 0 from the new position on. Such an
  /// unanchored friction row is projected at the velocity level only, and its Φ is not a
  /// residual.
  bool position_level(int constraint) const {
    const int c = contact_of_friction(constraint);
    return c < 0 || anchored_[c];
  }

  /// The minimum-norm projection of (q, q̇) onto the imposed rows of L (project_state; with
  /// unanchored friction rows: positions onto the others, then velocities onto all).
  ModelIssue project(const Layout& L, double t, Eigen::VectorXd& q, Eigen::VectorXd& qd,
                     double& dq, double& dv, std::string& msg) {
    dq = dv = 0.0;
    if (L.imposed.empty()) return ModelIssue::none;
    std::vector<int> pos;
    for (int i : L.imposed)
      if (position_level(i)) pos.push_back(i);
    if (pos.size() == L.imposed.size())
      return project_state(model_, L.imposed, t, q, qd, opt_.kernel, opt_.projection_tol, dq, dv,
                           msg, pw_);
    if (!pos.empty()) {
      const ModelIssue e = project_state(model_, pos, t, q, qd, opt_.kernel, opt_.projection_tol,
                                         dq, dv, msg, pw_);
      if (e != ModelIssue::none) return e;
    }
    const int s = static_cast<int>(L.imposed.size());
    pw_.g.resize(s, n_);
    pw_.g0.resize(s);
    pw_.gamma.resize(s);
    model_.constraint_rows(L.imposed, t, q, qd, pw_.g, pw_.g0, pw_.gamma);
    HuangOptions ho;
    ho.kernel = opt_.kernel;
    const HuangResult hr = huang_solve(pw_.g, -(pw_.g * qd + pw_.g0), ho);
    if (hr.info != 0) {
      msg = "the velocity projection onto the contact set failed (Huang info " +
            std::to_string(hr.info) + ")";
      return ModelIssue::inconsistent_constraints;
    }
    qd += hr.x;
    dv += hr.x.norm();
    return ModelIssue::none;
  }

  int contact_of_normal(int constraint) const {
    for (int c = 0; c < nc(); ++c)
      if (contacts_[c].normal == constraint) return c;
    return -1;
  }
  int contact_of_friction(int constraint) const {
    for (int c = 0; c < nc(); ++c)
      if (contacts_[c].friction == constraint) return c;
    return -1;
  }

  const Model& model_;
  const SimulationOptions& opt_;
  SwitchingOptions sw_;
  std::vector<int> active_, bilateral_;
  std::vector<ContactDef> contacts_;
  int n_;
 public:
  ReactionMethod method_;
  Dynamics dyn_, aux_dyn_;
  Eigen::LLT<Eigen::MatrixXd> llt_;
  ProjectionWork pw_;
  std::string message_;
  long lcp_solves_ = 0;
  bool lcp_failed_ = false;
  long energy_limited_ = 0;           ///< impacts whose impulse the energy rule limited
  double max_energy_prevented_ = 0.0; ///< the largest ΔT > 0 Newton's impulse would have made
  double last_energy_change_ = 0.0;   ///< ΔT of the last impact (J, <= rounding)
  std::vector<double> pending_loss_;
  std::vector<char> anchored_;  ///< per contact: its friction row still holds its position constant
  std::vector<char> impulsed_;  ///< per contact: took part in this instant's impact without approaching
  std::vector<double> impulse_n_, impulse_t_;
};

// Builds the contacts of a run from the active constraints; "" or the reason they cannot be
// switched.
std::string contacts_of(const Model& model, const std::vector<int>& active,
                        std::vector<ContactDef>& out) {
  for (int i : active) {
    const ConstraintInfo& ci = model.constraints()[i];
    if (!ci.contact.unilateral) continue;
    if (ci.kind != ConstraintKind::holonomic)
      return "the unilateral constraint '" + ci.name + "' is not holonomic";
    ContactDef d;
    d.normal = i;
    d.sign = ci.contact.gap_sign >= 0 ? 1 : -1;
    d.e = ci.contact.restitution;
    d.name = ci.name;
    out.push_back(d);
  }
  for (int i : active) {
    const ConstraintInfo& ci = model.constraints()[i];
    if (!ci.contact.is_friction()) continue;
    ContactDef* owner = nullptr;
    for (ContactDef& d : out)
      if (d.normal == ci.contact.friction_of) owner = &d;
    if (!owner)
      return "the friction constraint '" + ci.name + "' acts at the unilateral constraint '" +
             model.constraints()[ci.contact.friction_of].name +
             "', which is not active (activate both, or neither)";
    if (owner->friction >= 0)
      return "the unilateral constraint '" + owner->name + "' has two active friction constraints ('" +
             model.constraints()[owner->friction].name + "' and '" + ci.name + "'); activate one";
    owner->friction = i;
    owner->mu_s = ci.contact.mu_static;
    owner->mu_k = ci.contact.mu_kinetic;
  }
  return "";
}

}  // namespace

// ---- the run ------------------------------------------------------------------------------------

namespace {

class Run {
 public:
  Run(const Model& model, const SimulationOptions& opt, const SwitchingOptions& sw, Engine& eng,
      SwitchingResult& res, const SwitchingObserver& observer)
      : model_(model), opt_(opt), sw_(sw), eng_(eng), res_(res), observer_(observer),
        n_(model.n()), sample_dyn_(model, opt.kernel), event_dyn_(model, opt.kernel) {}

  // The segment's configuration (set before each integration). The event functions start on
  // their positive side by construction of the modes, often exactly at zero (a gap or a sliding
  // velocity that has just opened). The kernels take the sign of a function that is exactly
  // zero at the start from the end of the first step, which would hide a root inside that
  // step (a flight or a slip shorter than the step). Each function therefore carries a tiny
  // positive offset (the rounding of its own gap or sliding velocity, Engine::gap_round, 1e-12 of the forces), so its
  // sign is known from the start; roots are located that far on the other side of zero.
  // `grazing`: the previous event of a flying contact changed nothing (its gap returned to
  // zero without approach velocity and the contact still separates: it grazes the surface at
  // the integration's accuracy); its next landing is then taken only below -gap_tol, so the
  // run progresses instead of switching at every rounding-level dip.
  void configure(const Config& cfg, double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                 bool grazing = false) {
    cfg_ = cfg;
    layout_ = eng_.layout(cfg);
    gap_offset_.assign(eng_.nc(), 0.0);
    eps_gap_.assign(eng_.nc(), 0.0);
    eps_vel_.assign(eng_.nc(), 0.0);
    for (int c = 0; c < eng_.nc(); ++c) {
      // Rounding-size offsets of this contact's own gap and sliding velocity (Engine::gap_round).
      eps_gap_[c] = eng_.gap_round(c, t, q);
      if (eng_.contacts()[c].friction >= 0)
        eps_vel_[c] = eng_.velocity_round(eng_.row(eng_.contacts()[c].friction, t, q, qd), qd);
      if (!is_closed(cfg.modes[c]))
        gap_offset_[c] = std::min(eng_.gap(c, t, q), 0.0) - (grazing ? eng_.gap_tol(c, t, q) : 0.0);
    }
    modes_ = cfg.modes;
    eps_force_ = 0.0;
    bool closed = false;
    for (ContactMode m : cfg.modes) closed = closed || is_closed(m);
    if (closed && eng_.solve(event_dyn_, layout_, cfg_, t, q, qd, ev_solved_, eng_.method_) == ModelIssue::none) {
      double f = 0.0;
      for (int c = 0; c < eng_.nc(); ++c)
        f = std::max(f, std::abs(ev_solved_.lambda_n[c]) + std::abs(ev_solved_.lambda_t[c]));
      eps_force_ = 1e-12 * f;
    }
  }

  bool rhs(double t, const double* y, double* out) {
    q_ = Eigen::Map<const Eigen::VectorXd>(y, n_);
    qd_ = Eigen::Map<const Eigen::VectorXd>(y + n_, n_);
    if (eng_.solve(eng_.dyn_, layout_, cfg_, t, q_, qd_, rhs_solved_, eng_.method_) != ModelIssue::none) {
      last_failure_ = eng_.dyn_.message().empty() ? eng_.message_ : eng_.dyn_.message();
      model_failed_ = true;
      return false;
    }
    Eigen::Map<Eigen::VectorXd>(out, n_) = qd_;
    Eigen::Map<Eigen::VectorXd>(out + n_, n_) = rhs_solved_.qdd;
    return true;
  }

  // Event functions of the segment, in the order of `kinds_`.
  struct EventFn {
    int c;
    /// surfaced: a flight that started inside the surface (gap below −its rounding) came out
    /// of it; its landing threshold, taken from the start, is then reset to the surface.
    enum Kind { lift_off, cone_plus, cone_minus, sliding, gap, surfaced } kind;
  };
  std::vector<EventFn> event_functions() const {
    std::vector<EventFn> ev;
    for (int c = 0; c < eng_.nc(); ++c) {
      switch (cfg_.modes[c]) {
        case ContactMode::flight:
          ev.push_back({c, EventFn::gap});
          if (gap_offset_[c] < -2.0 * eps_gap_[c]) ev.push_back({c, EventFn::surfaced});
          break;
        case ContactMode::contact: ev.push_back({c, EventFn::lift_off}); break;
        case ContactMode::stick:
          ev.push_back({c, EventFn::lift_off});
          ev.push_back({c, EventFn::cone_plus});
          ev.push_back({c, EventFn::cone_minus});
          break;
        case ContactMode::slip:
          ev.push_back({c, EventFn::lift_off});
          ev.push_back({c, EventFn::sliding});
          break;
      }
    }
    return ev;
  }

  bool events(double t, const double* y, double* g) {
    q_e_ = Eigen::Map<const Eigen::VectorXd>(y, n_);
    qd_e_ = Eigen::Map<const Eigen::VectorXd>(y + n_, n_);
    bool solved = false;
    for (std::size_t i = 0; i < fns_.size(); ++i) {
      const EventFn& f = fns_[i];
      if (f.kind == EventFn::surfaced) {
        g[i] = -eng_.gap(f.c, t, q_e_) - eps_gap_[f.c];  // falls through 0 as the gap rises above −rounding
        continue;
      }
      if (f.kind == EventFn::gap) {
        g[i] = eng_.gap(f.c, t, q_e_) - gap_offset_[f.c] + eps_gap_[f.c];
        continue;
      }
      if (f.kind == EventFn::sliding) {
        g[i] = cfg_.sigma[f.c] * eng_.vt(f.c, t, q_e_, qd_e_) + eps_vel_[f.c];
        continue;
      }
      if (!solved) {
        if (eng_.solve(event_dyn_, layout_, cfg_, t, q_e_, qd_e_, ev_solved_, eng_.method_) != ModelIssue::none)
          return false;
        solved = true;
      }
      const double ln = ev_solved_.lambda_n[f.c], lt = ev_solved_.lambda_t[f.c];
      const double mu = eng_.contacts()[f.c].mu_s;
      g[i] = eps_force_ + (f.kind == EventFn::lift_off ? ln : f.kind == EventFn::cone_plus ? mu * ln - lt : mu * ln + lt);
    }
    return true;
  }

  /// The shortest predicted flight of the contacts that have just opened (gap within the
  /// tolerance, moving apart): 2 v_n / |a_n| with a_n from the segment's accelerations; +inf if
  /// none is pulled back.
  double shortest_flight(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) {
    double tau = std::numeric_limits<double>::infinity();
    bool solved = false;
    for (int c = 0; c < eng_.nc(); ++c) {
      if (is_closed(cfg_.modes[c]) || !(eng_.gap(c, t, q) <= eng_.gap_tol(c, t, q))) continue;
      const double v = eng_.vn(c, t, q, qd);
      if (!solved) {
        if (eng_.solve(event_dyn_, layout_, cfg_, t, q, qd, ev_solved_, eng_.method_) != ModelIssue::none)
          return tau;
        solved = true;
      }
      const Row r = eng_.normal_row(c, t, q, qd);
      const double a = r.g.dot(ev_solved_.qdd) + r.gamma;
      if (a < 0.0 && v > 0.0) tau = std::min(tau, 2.0 * v / -a);
      else if (a < 0.0) tau = std::min(tau, std::sqrt(2.0 * eng_.gap_tol(c, t, q) / -a));
    }
    return tau;
  }

  // ---- samples for the observer ----------------------------------------------------------------

  void fill_sample(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd, Sample& out) {
    out.t = t;
    out.q = q;
    out.qd = qd;
    if (eng_.solve(sample_dyn_, layout_, cfg_, t, q, qd, sample_solved_, eng_.method_) == ModelIssue::none) {
      out.qdd = sample_solved_.qdd;
      out.R = sample_solved_.R;
      out.lambda = sample_solved_.lambda;
    } else {
      out.qdd = Eigen::VectorXd::Constant(n_, std::nan(""));
      out.R = out.qdd;
      out.lambda = Eigen::VectorXd::Constant(layout_.s_A, std::nan(""));
    }
    model_.derived(t, q, qd, out.qdd, out.R, out.derived);
    out.residual_pos = 0.0;
    for (int i : layout_.imposed)
      if (model_.constraints()[i].kind == ConstraintKind::holonomic && eng_.position_level(i))
        out.residual_pos = std::max(out.residual_pos, std::abs(model_.position_residual(i, t, q)));
    out.residual_vel = layout_.s_A > 0
                           ? (sample_dyn_.g.topRows(layout_.s_A) * qd + sample_dyn_.g0.head(layout_.s_A))
                                 .cwiseAbs()
                                 .maxCoeff()
                           : 0.0;
  }

  static const Sample& view_at(const void* self, double s) {
    return const_cast<Run*>(static_cast<const Run*>(self))->sample_in_step(s);
  }

  const Sample& sample_in_step(double s) {
    if (step_ == nullptr || s >= step_end_ || step_end_ == step_->t_prev) s = current_t_;
    if (cache_valid_ && cache_.t == s) return cache_;
    if (s == current_t_) {
      fill_sample(current_t_, current_q_, current_qd_, cache_);
    } else {
      dense_.resize(2 * n_);
      step_->dense(std::max(s, step_->t_prev), dense_.data());
      dq_ = dense_.head(n_);
      dqd_ = dense_.tail(n_);
      fill_sample(s, dq_, dqd_, cache_);
    }
    cache_valid_ = true;
    return cache_;
  }

  bool observe(const StepInfo* step, double t_prev, double t, const Eigen::VectorXd& q,
               const Eigen::VectorXd& qd) {
    step_ = step;
    step_end_ = t;
    current_t_ = t;
    current_q_ = q;
    current_qd_ = qd;
    cache_valid_ = false;
    if (!observer_) return true;
    StepView view;
    view.t_prev = t_prev;
    view.t = t;
    view.impl_ = this;
    view.impl_at_ = &Run::view_at;
    try {
      return observer_(view, modes_);
    } catch (const std::exception& ex) {
      observer_error_ = std::string("the step observer threw: ") + ex.what();
    } catch (...) {
      observer_error_ = "the step observer threw an unknown exception";
    }
    return false;
  }

  // ---- statistics over a step ------------------------------------------------------------------

  void dense_at(const StepInfo& step, double s, Eigen::VectorXd& q, Eigen::VectorXd& qd) {
    dense_.resize(2 * n_);
    step.dense(s, dense_.data());
    q = dense_.head(n_);
    qd = dense_.tail(n_);
  }

  void account(const StepInfo& step, double a, double b) {
    if (!(b > a)) return;
    const double w0 = sw_.window_start;
    const double wa = std::max(a, w0), wlen = std::max(0.0, b - wa);
    for (int c = 0; c < eng_.nc(); ++c) {
      ContactStats& st = res_.contacts[c];
      const ContactMode m = cfg_.modes[c];
      if (is_closed(m)) {
        st.run.closed_time += b - a;
        st.window.closed_time += wlen;
      }
      if (m == ContactMode::slip) {
        st.run.slip_time += b - a;
        st.window.slip_time += wlen;
        // ∫ |v_t| and ∫ μ_k λ_n |v_t| by 3-point Gauss-Legendre on the dense output (|v_t| =
        // σ v_t is smooth within a sliding segment).
        auto integrate = [&](double lo, double hi, double& dist, double& energy) {
          if (!(hi > lo)) return;
          const double cm = 0.5 * (lo + hi), hw = 0.5 * (hi - lo), r = std::sqrt(0.6);
          const double xs[3] = {cm - hw * r, cm, cm + hw * r}, ws[3] = {5.0 / 9, 8.0 / 9, 5.0 / 9};
          for (int k = 0; k < 3; ++k) {
            dense_at(step, xs[k], sq_, sqd_);
            const double v = std::abs(eng_.vt(c, xs[k], sq_, sqd_));
            double ln = 0.0;
            if (eng_.solve(sample_dyn_, layout_, cfg_, xs[k], sq_, sqd_, sample_solved_, eng_.method_) ==
                ModelIssue::none)
              ln = sample_solved_.lambda_n[c];
            dist += hw * ws[k] * v;
            energy += hw * ws[k] * eng_.contacts()[c].mu_k * ln * v;
          }
        };
        integrate(a, b, st.run.slip_distance, st.run.energy_friction);
        integrate(wa, b, st.window.slip_distance, st.window.energy_friction);
      }
      if (m == ContactMode::flight) {
        // The flight's highest gap: the step end, and an apex inside the step where the gap
        // rate falls through 0 (bisection on the dense output).
        dense_at(step, b, sq_, sqd_);
        double top = eng_.gap(c, b, sq_);
        dense_at(step, a, sq_, sqd_);
        top = std::max(top, eng_.gap(c, a, sq_));  // a flight that starts high (at t0)
        double va = eng_.vn(c, a, sq_, sqd_);
        dense_at(step, b, sq_, sqd_);
        double vb = eng_.vn(c, b, sq_, sqd_);
        if (va > 0.0 && vb <= 0.0) {
          double lo = a, hi = b;
          for (int it = 0; it < 60 && hi - lo > 1e-14 * (1.0 + std::abs(hi)); ++it) {
            const double mid = 0.5 * (lo + hi);
            dense_at(step, mid, sq_, sqd_);
            if (eng_.vn(c, mid, sq_, sqd_) > 0.0) lo = mid; else hi = mid;
          }
          dense_at(step, 0.5 * (lo + hi), sq_, sqd_);
          top = std::max(top, eng_.gap(c, 0.5 * (lo + hi), sq_));
        }
        if (!st.flights.empty()) st.flights.back().max_gap = std::max(st.flights.back().max_gap, top);
        st.run.max_flight_height = std::max(st.run.max_flight_height, top);
        if (b > w0) st.window.max_flight_height = std::max(st.window.max_flight_height, top);
      }
    }
  }

  // ---- the step callback -----------------------------------------------------------------------

  StepAction on_step(StepInfo& step) {
    Eigen::Map<Eigen::VectorXd> y(step.y, 2 * n_);
    Eigen::VectorXd q = y.head(n_), qd = y.tail(n_);
    // A gap that dips below zero and comes back within one step is not a sign change of the
    // event function: look for it on the dense output, and end the step there.
    double t_end = step.t;
    bool late = false;
    for (int c = 0; c < eng_.nc() && !late; ++c) {
      if (is_closed(cfg_.modes[c])) continue;
      constexpr int K = 8;
      double prev_t = step.t_prev;  // the last sample with a positive gap
      for (int k = 1; k <= K; ++k) {
        const double s = step.t_prev + (step.t - step.t_prev) * k / K;
        dense_at(step, s, sq_, sqd_);
        // Below the accuracy of the positions (a dip within it is not resolved anyway).
        track_penetration(s, sq_, c);  // this open contact's gap inside the step
        const double g = eng_.gap(c, s, sq_) - gap_offset_[c];
        if (g > 0.0) prev_t = s;
        if (g < -eng_.gap_tol(c, s, sq_)) {
          double lo = prev_t, hi = s;
          for (int it = 0; it < 80 && hi - lo > 1e-15 * (1.0 + std::abs(hi)); ++it) {
            const double mid = 0.5 * (lo + hi);
            dense_at(step, mid, sq_, sqd_);
            if (eng_.gap(c, mid, sq_) - gap_offset_[c] < 0.0) hi = mid; else lo = mid;
          }
          t_end = hi;
          late = true;
          break;
        }
      }
    }
    // The same for the forces and sliding velocities of closed contacts (a normal force that
    // turns negative and back, or a cone left and re-entered, within one long step: the
    // explicit pair takes steps of a third of the sieve's excitation period while it sticks).
    // They are sampled at a few points inside the step; the first sign change is located by
    // bisection on the dense output.
    bool any_closed_fn = false;
    for (const EventFn& f : fns_) any_closed_fn = any_closed_fn || (f.kind != EventFn::gap && f.kind != EventFn::surfaced);
    if (any_closed_fn) {
      constexpr int K = 4;
      gs_.resize(fns_.size());
      ys_.resize(2 * n_);
      auto negative = [&](double s) {
        step.dense(s, ys_.data());
        if (!events(s, ys_.data(), gs_.data())) return false;
        for (std::size_t i = 0; i < fns_.size(); ++i)
          if (fns_[i].kind != EventFn::gap && fns_[i].kind != EventFn::surfaced && gs_[i] < 0.0) return true;
        return false;
      };
      double prev_t = step.t_prev;
      const double stop = late ? t_end : step.t;
      for (int k = 1; k < K; ++k) {
        const double s = step.t_prev + (stop - step.t_prev) * k / K;
        if (!negative(s)) {
          prev_t = s;
          continue;
        }
        double lo = prev_t, hi = s;
        for (int it = 0; it < 80 && hi - lo > 1e-15 * (1.0 + std::abs(hi)); ++it) {
          const double mid = 0.5 * (lo + hi);
          (negative(mid) ? hi : lo) = mid;
        }
        t_end = hi;
        late = true;
        break;
      }
    }
    if (late) {
      dense_at(step, t_end, q, qd);
      late_state_q_ = q;
      late_state_qd_ = qd;
      late_t_ = t_end;
      late_found_ = true;
      ++res_.late_roots;
    }
    bool modified = false;
    if (!late && !layout_.imposed.empty() && !consistent_enough(step.t, q, qd)) {
      double dq = 0.0, dv = 0.0;
      std::string msg;
      const ModelIssue e = eng_.project(layout_, step.t, q, qd, dq, dv, msg);
      if (e != ModelIssue::none) {
        projection_issue_ = e;
        projection_message_ = msg;
        return StepAction::stop;
      }
      if (dq > 0.0 || dv > 0.0) {
        y.head(n_) = q;
        y.tail(n_) = qd;
        modified = true;
      }
    }
    track_residuals(t_end, q, qd);
    account(step, step.t_prev, t_end);
    if (!observe(&step, step.t_prev, t_end, q, qd)) {
      stopped_ = true;
      return StepAction::stop;
    }
    if (late) return StepAction::stop;
    return modified ? StepAction::state_modified : StepAction::proceed;
  }

  // As simulate() decides: a state that satisfies the imposed constraints to the projection's
  // tolerance already is left alone (the projection would change it by rounding only, and the
  // explicit pair keeps its last evaluation); the pre-issue-14 path projects after every step.
  bool consistent_enough(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) {
    if (opt_.linear_algebra == RadauOptions::LinearAlgebra::lapack) return false;
    // Row by row, each to its own scale (row_within_projection_tol, shared with simulate()).
    for (int i : layout_.imposed) {
      const Row r = eng_.row(i, t, q, qd);
      const bool position =
          model_.constraints()[i].kind == ConstraintKind::holonomic && eng_.position_level(i);
      const double phi = position ? model_.position_residual(i, t, q) : 0.0;
      if (!row_within_projection_tol(r.g, r.g0, position, phi, t, q, qd, opt_.projection_tol))
        return false;
    }
    return true;
  }

  /// The deepest penetration of every contact (any mode), into the run's and window's totals
  /// and into the position residual: a unilateral constraint's violation is a constraint
  /// residual like any other (issue 19: "max constraint residual 0" was printed for a ball
  /// 4.8e-6 m inside the floor).
  void track_penetration(double t, const Eigen::VectorXd& q, int only = -1) {
    for (int c = 0; c < eng_.nc(); ++c) {
      if (only >= 0 && c != only) continue;
      const double pen = -eng_.gap(c, t, q);
      if (!(pen > 0.0)) continue;
      ContactStats& st = res_.contacts[c];
      if (pen > st.run.penetration_max) {
        st.run.penetration_max = pen;
        st.run.penetration_time = t;
      }
      if (t >= sw_.window_start && pen > st.window.penetration_max) {
        st.window.penetration_max = pen;
        st.window.penetration_time = t;
      }
      res_.residual_pos_max = std::max(res_.residual_pos_max, pen);
    }
  }

  void track_residuals(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd) {
    track_penetration(t, q);
    for (int i : layout_.imposed) {
      const Row r = eng_.row(i, t, q, qd);
      res_.residual_vel_max = std::max(res_.residual_vel_max, std::abs(r.value(qd)));
      if (model_.constraints()[i].kind == ConstraintKind::holonomic && eng_.position_level(i))
        res_.residual_pos_max =
            std::max(res_.residual_pos_max, std::abs(model_.position_residual(i, t, q)));
    }
  }

  const Model& model_;
  const SimulationOptions& opt_;
  const SwitchingOptions& sw_;
  Engine& eng_;
  SwitchingResult& res_;
  const SwitchingObserver& observer_;
  int n_;
  Config cfg_;
  Layout layout_;
  std::vector<EventFn> fns_;
  std::vector<double> gap_offset_, gs_, ys_;
  std::vector<double> eps_gap_, eps_vel_;  ///< per contact (Engine::gap_round, velocity_round)
  double eps_force_ = 0.0;
  std::vector<ContactMode> modes_;
  Dynamics sample_dyn_, event_dyn_;
  Solved rhs_solved_, ev_solved_, sample_solved_;
  Eigen::VectorXd q_, qd_, q_e_, qd_e_, dense_, dq_, dqd_, sq_, sqd_;
  ProjectionWork pw_;
  const StepInfo* step_ = nullptr;
  double step_end_ = 0.0, current_t_ = 0.0;
  Eigen::VectorXd current_q_, current_qd_;
  Sample cache_;
  bool cache_valid_ = false;
  bool model_failed_ = false, stopped_ = false;
  std::string last_failure_, observer_error_, projection_message_;
  ModelIssue projection_issue_ = ModelIssue::none;
  bool late_found_ = false;
  double late_t_ = 0.0;
  Eigen::VectorXd late_state_q_, late_state_qd_;
};

void add_stats(SwitchingResult& res, const OdeResult& rr) {
  res.stats.f_evals += rr.f_evals;
  res.stats.steps += rr.steps;
  res.stats.accepted += rr.accepted;
  res.stats.rejected += rr.rejected;
  res.stats.jacobians += rr.radau_stats.jacobians;
  res.stats.lu_decompositions += rr.radau_stats.lu_decompositions;
  res.stats.linear_solves += rr.radau_stats.linear_solves;
  res.used_explicit = res.used_explicit || rr.used_explicit;
  res.used_radau = res.used_radau || rr.used_radau;
  if (std::isnan(res.switch_time) && !std::isnan(rr.switch_time)) res.switch_time = rr.switch_time;
}

void count_event(SwitchingResult& res, const ContactEvent& ev, double w0) {
  ContactStats& st = res.contacts[ev.contact];
  for (ContactStats::Totals* tot : {&st.run, &st.window}) {
    if (tot == &st.window && !(ev.t >= w0)) continue;
    switch (ev.kind) {
      case ContactEventKind::lift_off: ++tot->lift_offs; break;
      case ContactEventKind::impact:
      case ContactEventKind::accumulation:
        ++tot->impacts;
        tot->max_impact_velocity = std::max(tot->max_impact_velocity, -ev.vn_before);
        break;
      case ContactEventKind::slip: ++tot->slips; break;
      case ContactEventKind::stick: ++tot->sticks; break;
      case ContactEventKind::reversal: ++tot->reversals; break;
    }
    tot->energy_impacts += ev.energy_lost;
    if (ev.mode_after == ContactMode::flight && ev.mode_before != ContactMode::flight) ++tot->flights;
    if (ev.mode_after == ContactMode::flight && ev.mode_before == ContactMode::flight) ++tot->flights;  // a rebound
  }
}

}  // namespace

SwitchingResult simulate_switching(const Model& model, const Eigen::VectorXd& q0,
                                   const Eigen::VectorXd& qd0, const SimulationOptions& options,
                                   const SwitchingOptions& switching,
                                   const SwitchingObserver& observer) {
  SwitchingResult res;
  res.t = options.t0;
  res.q_end = q0;
  res.qd_end = qd0;
  auto refuse = [&](SimulationStatus st, ModelIssue issue, const std::string& msg) {
    res.status = st;
    res.issue = issue;
    res.message = "model '" + model.name() + "': " + msg;
    return res;
  };
  if (options.form != Form::ode)
    return refuse(SimulationStatus::invalid_model, ModelIssue::none,
                  "switching contacts needs the ODE form (solver.form = \"ode\")");
  // The constraint names; then the model and the bilateral constraints as simulate() checks
  // them (the contacts are checked in the set the initial modes impose: all of them together
  // may well exceed the coordinates, as a block's two corners with friction do).
  CheckResult check;
  {
    std::string msg;
    check.issue = resolve_constraints(model, options.active_constraints, check.active, msg);
    if (check.issue != ModelIssue::none)
      return refuse(SimulationStatus::invalid_model, check.issue, msg);
    std::vector<std::string> bilateral;
    for (int i : check.active)
      if (!model.constraints()[i].contact.unilateral && !model.constraints()[i].contact.is_friction())
        bilateral.push_back(model.constraints()[i].name);
    const CheckResult cb = check_model(model, bilateral, options.t0, q0, qd0, options.kernel);
    if (cb.issue != ModelIssue::none) return refuse(SimulationStatus::invalid_model, cb.issue, cb.message);
  }
  std::vector<ContactDef> defs;
  if (const std::string why = contacts_of(model, check.active, defs); !why.empty())
    return refuse(SimulationStatus::invalid_model, ModelIssue::unknown_constraint, why);
  Engine eng(model, options, switching, check.active, defs);
  eng.pending_loss_.assign(eng.nc(), 0.0);
  eng.anchored_.assign(eng.nc(), 1);
  const int n = model.n();
  for (const ContactDef& d : defs) {
    ContactStats st;
    st.name = d.name;
    st.friction = d.friction >= 0 ? model.constraints()[d.friction].name : "";
    res.contacts.push_back(st);
  }
  const double w0 = std::max(options.t0, switching.window_start);
  res.window_length = std::max(0.0, options.t_end - w0);

  // The initial modes: every touching contact as at an event (an approaching one is an impact
  // at t0), the others in flight; then the state projected onto the resulting set.
  Eigen::VectorXd q = q0, qd = qd0;
  Config cfg;
  cfg.modes.assign(eng.nc(), ContactMode::flight);
  cfg.sigma.assign(eng.nc(), 0);
  {
    // Bilateral constraints first (the contacts are decided on a consistent state).
    std::vector<int> bil;
    for (int i : check.active)
      if (!model.constraints()[i].contact.unilateral && !model.constraints()[i].contact.is_friction())
        bil.push_back(i);
    ProjectionWork pw;
    std::string msg;
    double dq = 0, dv = 0;
    if (!bil.empty() && project_state(model, bil, options.t0, q, qd, options.kernel,
                                      options.projection_tol, dq, dv, msg, pw) != ModelIssue::none)
      return refuse(SimulationStatus::inconsistent_start, ModelIssue::inconsistent_constraints,
                    "consistent initial values: " + msg);
    // Contacts declared active start closed when they touch (within the tolerance): project them.
    Config start = cfg;
    std::vector<ContactEvent> none;
    Config decided;
    if (!eng.transition(options.t0, q, qd, start, nullptr, decided, none, true))
      return refuse(SimulationStatus::inconsistent_start, ModelIssue::inconsistent_constraints,
                    "the initial contact modes: " + eng.message_);
    for (const ContactEvent& ev : none) {
      res.events.push_back(ev);
      count_event(res, ev, w0);
    }
    cfg = decided;
    res.initial_modes = cfg.modes;
    std::vector<std::string> imposed;
    for (int i : eng.layout(cfg).imposed) imposed.push_back(model.constraints()[i].name);
    const CheckResult ci = check_model(model, imposed, options.t0, q, qd, options.kernel);
    if (ci.issue != ModelIssue::none)
      return refuse(SimulationStatus::invalid_model, ci.issue, "with the initial contact modes: " + ci.message);
    res.initial_correction_pos = (q - q0).norm();
    res.initial_correction_vel = (qd - qd0).norm();
  }

  Run run(model, options, switching, eng, res, observer);
  run.configure(cfg, options.t0, q, qd);
  for (int c = 0; c < eng.nc(); ++c)
    if (!is_closed(cfg.modes[c])) res.contacts[c].flights.push_back({options.t0, options.t_end, eng.gap(c, options.t0, q)});
  run.track_residuals(options.t0, q, qd);
  if (!run.observe(nullptr, options.t0, options.t0, q, qd)) {
    res.status = run.observer_error_.empty() ? SimulationStatus::stopped_by_observer
                                             : SimulationStatus::observer_error;
    res.message = run.observer_error_;
    res.q_end = q;
    res.qd_end = qd;
    return res;
  }

  double t = options.t0;
  double h_next = options.h0;
  double last_event_time = -std::numeric_limits<double>::infinity();
  int events_at_instant = 0;
  long total_events = static_cast<long>(res.events.size());
  Eigen::VectorXd y(2 * n);
  while (true) {
    ++res.segments;
    run.fns_ = run.event_functions();
    OdeProblem problem;
    problem.n = 2 * n;
    problem.rhs = [&run](double tt, const double* yy, double* f) { return run.rhs(tt, yy, f); };
    if (options.linear_algebra != RadauOptions::LinearAlgebra::lapack) {
      problem.second_order_count = n;
      problem.second_order_stride = n;
    }
    OdeOptions oo;
    oo.kernel = options.kernel;
    oo.rtol = options.rtol;
    oo.atol = options.atol;
    oo.h0 = h_next;
    // A contact that has just left the surface starts its gap function at zero, which the
    // kernels judge by its sign after the first step: that step must end inside the flight, or
    // a flight shorter than one step (the free parabola is integrated exactly, so steps grow
    // fast) would be missed. The first step is kept below a quarter of the predicted flight,
    // 2 v_n / |a_n| with the acceleration of the new set.
    {
      const double tau = run.shortest_flight(t, q, qd);
      if (std::isfinite(tau)) oo.h0 = (oo.h0 > 0.0 ? std::min(oo.h0, 0.25 * tau) : 0.25 * tau);
    }
    oo.hmax = options.hmax;
    bool open_or_sliding = false;
    for (ContactMode m : cfg.modes) open_or_sliding = open_or_sliding || m == ContactMode::flight || m == ContactMode::slip;
    if (open_or_sliding && switching.flight_hmax > 0.0)
      oo.hmax = oo.hmax > 0.0 ? std::min(oo.hmax, switching.flight_hmax) : switching.flight_hmax;
    oo.max_steps = std::max(1L, options.max_steps - res.stats.steps);
    oo.radau.linear_algebra = options.linear_algebra;
    oo.events.count = static_cast<int>(run.fns_.size());
    oo.events.direction.assign(run.fns_.size(), -1);
    oo.events.g = [&run](double tt, const double* yy, double* g) { return run.events(tt, yy, g); };
    y.head(n) = q;
    y.tail(n) = qd;
    run.late_found_ = false;
    const OdeResult rr = ode_integrate(problem, t, y, options.t_end, oo, options.method,
                                       [&run](StepInfo& s) { return run.on_step(s); });
    add_stats(res, rr);
    res.integrator_status = rr.status;
    if (rr.h_last > 0.0) h_next = std::abs(rr.h_last);
    if (run.projection_issue_ != ModelIssue::none) {
      res.status = SimulationStatus::projection_failed;
      res.issue = run.projection_issue_;
      res.t = rr.t;
      res.message = "drift projection failed at t = " + num(rr.t) + ": " + run.projection_message_;
      break;
    }
    if (!run.observer_error_.empty()) {
      res.status = SimulationStatus::observer_error;
      res.message = run.observer_error_;
      res.t = run.current_t_;
      q = run.current_q_;
      qd = run.current_qd_;
      break;
    }
    if (run.stopped_) {
      res.status = SimulationStatus::stopped_by_observer;
      res.t = run.current_t_;
      q = run.current_q_;
      qd = run.current_qd_;
      break;
    }
    const bool late = run.late_found_;
    if (!late && rr.status == OdeStatus::success) {
      res.status = SimulationStatus::success;
      res.t = rr.t;
      q = rr.y.head(n);
      qd = rr.y.tail(n);
      break;
    }
    if (!late && rr.status != OdeStatus::root_found) {
      res.status = run.model_failed_ ? SimulationStatus::model_failed : SimulationStatus::integration_failed;
      res.t = rr.t;
      res.message = rr.message + (run.model_failed_ ? "; the model could not be evaluated: " + run.last_failure_ : "");
      q = rr.y.size() == 2 * n ? Eigen::VectorXd(rr.y.head(n)) : q;
      qd = rr.y.size() == 2 * n ? Eigen::VectorXd(rr.y.tail(n)) : qd;
      break;
    }
    // An event: the state at the root (on its far side), the reactions there with the old set.
    if (late) {
      t = run.late_t_;
      q = run.late_state_q_;
      qd = run.late_state_qd_;
    } else {
      t = rr.t;
      q = rr.y.head(n);
      qd = rr.y.tail(n);
    }
    run.track_penetration(t, q);  // the event's state, before any contact is lifted onto its surface
    Solved before;
    eng.solve(eng.aux_dyn_, run.layout_, cfg, t, q, qd, before, eng.method_);
    Config next;
    std::vector<ContactEvent> evs;
    if (!eng.transition(t, q, qd, cfg, &before, next, evs, false)) {
      res.status = SimulationStatus::model_failed;
      res.t = t;
      res.message = "switching failed at t = " + num(t) + ": " + eng.message_;
      if (eng.lcp_failed_) res.issue = ModelIssue::kernel_failure;
      break;
    }
    for (const ContactEvent& ev : evs) {
      res.events.push_back(ev);
      count_event(res, ev, w0);
      ContactStats& st = res.contacts[ev.contact];
      if (is_closed(ev.mode_before) && !is_closed(ev.mode_after)) st.flights.push_back({t, options.t_end, 0.0});
      if (!is_closed(ev.mode_before) && is_closed(ev.mode_after) && !st.flights.empty()) st.flights.back().end = t;
      if (!is_closed(ev.mode_before) && !is_closed(ev.mode_after) && !st.flights.empty()) {
        st.flights.back().end = t;  // a bounce: one flight ends, the next begins
        st.flights.push_back({t, options.t_end, 0.0});
      }
    }
    total_events += static_cast<long>(evs.size());
    events_at_instant = (t - last_event_time <= 1e-12 * (1.0 + std::abs(t))) ? events_at_instant + 1 : 0;
    last_event_time = t;
    if (events_at_instant > switching.max_events_at_one_instant || total_events > switching.max_events) {
      res.status = SimulationStatus::model_failed;
      res.t = t;
      res.message = "switching does not settle at t = " + num(t) + ": " +
                    (total_events > switching.max_events
                         ? counted(total_events, "event") + ", more than contact.max_events = " +
                               counted(switching.max_events, "event")
                         : counted(events_at_instant, "switch", "switches") + " at one instant");
      break;
    }
    bool surfaced = false;  // a flight came out of the surface: not a grazing landing
    for (std::size_t i = 0; !late && i < rr.roots.size() && i < run.fns_.size(); ++i)
      surfaced = surfaced || (rr.roots[i] != 0 && run.fns_[i].kind == Run::EventFn::surfaced);
    const bool nothing_changed = !surfaced && evs.empty() && next.modes == cfg.modes && next.sigma == cfg.sigma;
    cfg = next;
    run.configure(cfg, t, q, qd, nothing_changed);
    if (t >= options.t_end) {
      res.status = SimulationStatus::success;
      res.t = t;
      break;
    }
  }
  res.q_end = q;
  res.qd_end = qd;
  res.lcp_solves = eng.lcp_solves_;
  res.energy_limited_impacts = eng.energy_limited_;
  res.energy_prevented_max = eng.max_energy_prevented_;
  for (ContactStats& st : res.contacts)
    if (!st.flights.empty() && st.flights.back().end > res.t) st.flights.back().end = res.t;
  // The time in flight from the flights recorded (their starts and ends are the events), kept
  // apart from closed_time (summed over the steps with the segment's modes): the report's "in
  // flight" is this one, and the two must agree (test_switching_contacts_far_from_origin).
  for (int c = 0; c < eng.nc(); ++c) {
    ContactStats& st = res.contacts[c];
    for (const ContactStats::Flight& f : st.flights) {
      st.run.flight_time += std::max(0.0, f.end - f.start);
      st.window.flight_time += std::max(0.0, f.end - std::max(f.start, w0));
    }
    st.gap_end = eng.gap(c, res.t, q);
    st.gap_tol_end = eng.gap_tol(c, res.t, q);
  }
  run.track_penetration(res.t, q);
  return res;
}

// ---- resolve_impact (tests of the impact law) -----------------------------------------------------

ImpactOutcome resolve_impact(const Model& model, const std::vector<std::string>& active, double t,
                             const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                             const SimulationOptions& options, const SwitchingOptions& switching) {
  ImpactOutcome out;
  std::vector<int> idx;
  std::string msg;
  if (resolve_constraints(model, active, idx, msg) != ModelIssue::none) {
    out.message = msg;
    return out;
  }
  std::vector<ContactDef> defs;
  if (const std::string why = contacts_of(model, idx, defs); !why.empty()) {
    out.message = why;
    return out;
  }
  Engine eng(model, options, switching, idx, defs);
  eng.anchored_.assign(eng.nc(), 1);
  eng.pending_loss_.assign(eng.nc(), 0.0);
  eng.impulsed_.assign(eng.nc(), 0);
  eng.impulse_n_.assign(eng.nc(), 0.0);
  eng.impulse_t_.assign(eng.nc(), 0.0);
  Config before;
  before.modes.assign(eng.nc(), ContactMode::flight);
  before.sigma.assign(eng.nc(), 0);
  std::vector<char> hit(eng.nc(), 0);
  out.qd_after = qd;
  if (!eng.impact(t, q, out.qd_after, before, out.events, hit)) {
    out.message = eng.message_;
    return out;
  }
  out.ok = true;
  out.energy_change = out.events.empty() ? 0.0 : eng.last_energy_change_;
  out.energy_limited = eng.energy_limited_;
  return out;
}

// ---- switching_reactions (tests of the two formulations) ------------------------------------------

ReactionResult switching_reactions(const Model& model, const std::vector<std::string>& active,
                                   const std::vector<ContactMode>& modes,
                                   const std::vector<int>& slip_sign, double t,
                                   const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                   ReactionMethod method, Kernel kernel) {
  ReactionResult out;
  std::vector<int> idx;
  std::string msg;
  if (const ModelIssue e = resolve_constraints(model, active, idx, msg); e != ModelIssue::none) {
    out.issue = e;
    out.message = msg;
    return out;
  }
  std::vector<ContactDef> defs;
  if (const std::string why = contacts_of(model, idx, defs); !why.empty()) {
    out.issue = ModelIssue::unknown_constraint;
    out.message = why;
    return out;
  }
  if (modes.size() != defs.size() || slip_sign.size() != defs.size()) {
    out.issue = ModelIssue::unknown_constraint;
    out.message = "switching_reactions: one mode and one slip sign per unilateral constraint";
    return out;
  }
  SimulationOptions opt;
  opt.kernel = kernel;
  SwitchingOptions sw;
  Engine eng(model, opt, sw, idx, defs);
  eng.anchored_.assign(eng.nc(), 1);
  eng.pending_loss_.assign(eng.nc(), 0.0);
  Config cfg;
  cfg.modes = modes;
  cfg.sigma = slip_sign;
  const Layout L = eng.layout(cfg);
  Solved s;
  Dynamics d(model, kernel);
  const ModelIssue e = eng.solve(d, L, cfg, t, q, qd, s, method);
  if (e != ModelIssue::none) {
    out.issue = e;
    out.message = d.message().empty() ? eng.message_ : d.message();
    return out;
  }
  out.R = s.R;
  out.qdd = s.qdd;
  out.lambda = s.lambda;
  return out;
}

}  // namespace pcsim::mech
