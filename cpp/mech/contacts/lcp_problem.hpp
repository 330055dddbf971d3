// The complementarity problem of the contacts that touch (issue 12): at impulse level for an
// impact (Newton's law with Coulomb friction), at acceleration level for the mode decision. Its
// rows J, the inverse inertia P the contacts see with the bilateral constraints imposed, the
// Delassus matrix W = J P Jᵀ, and its solution: the single contact in closed form, several by
// the LCP solvers of lcp/ (Siconos), the solution then polished on the equations of its modes.
#pragma once

#include <string>
#include <vector>

#include "common/eigen_instances.hpp"

#include "lcp/lcp.hpp"
#include "mech/contacts/contact_set.hpp"

namespace pcsim::mech::contacts {

/// One contact in a complementarity problem. frictional: the planar Coulomb cone with the
/// variables (Λn, β+, β−, ζ), Λt = β+ − β− (Stewart-Trinkle); sliding (acceleration level,
/// |v_t| > 0): the friction force −μ σ Λn along the row, variable Λn only; otherwise Λn only.
///
/// A contact with a 2-D cone (ContactDef::cone) has a second tangent row kt2. frictional: the
/// variables (Λn, Λt1, Λt2, ζ), ζ the sliding magnitude after (|v_t| or |a_t|); sliding: Λn
/// only, the friction force −μ Λn dir. Problems with a 2-D cone are not LCPs: they are solved
/// contact by contact (solve_problem).
struct Cand {
  int c = 0;
  bool frictional = false;
  int sigma = 0;   ///< sliding direction (acceleration level, sliding contacts)
  double e = 0.0;  ///< restitution (impulse level)
  double mu = 0.0;
  int kn = -1, kt = -1;  ///< rows in J
  int kt2 = -1;          ///< a 2-D cone's second tangent row in J, or -1
  Eigen::Vector2d dir = Eigen::Vector2d::Zero();  ///< a sliding 2-D contact's unit direction
  int zn = -1;           ///< first variable
};

/// The LCP w = A z + b of candidates with rows J, Delassus W = J P Jᵀ and free values f (the
/// contact velocities before the impulse, or accelerations without contact forces).
struct Problem {
  std::vector<Cand> cands;
  Eigen::MatrixXd W, E, A;  ///< E: rows of J x variables (Λ_J = E z)
  Eigen::VectorXd f, b;
  bool impulse = false;
  /// Impulse level: the velocities Newton's law refers to, v_n⁺ >= −e v_n⁻ (empty: f). A rough
  /// landing's rough rows are imposed in P, and f is then the velocities after the impulse that
  /// stops them, while v_n⁻ stays the velocity before the impact: the simultaneous rough impact.
  Eigen::VectorXd newton_ref;
  /// The normal row's free value: (1 + e) f_n at impulse level (f_n + e v_n⁻ with newton_ref),
  /// f_n at acceleration level.
  double free_normal(const Cand& k) const {
    if (!impulse) return f[k.kn];
    return f[k.kn] + k.e * (newton_ref.size() ? newton_ref[k.kn] : f[k.kn]);
  }
};

/// How a problem is solved, and what the solves did over a run.
struct LcpSettings {
  /// The single-contact problem in closed form (false: always by the LCP solver).
  bool closed_form_single = true;
  lcp::LcpSolver solver = lcp::LcpSolver::lemke;
};
struct LcpCounters {
  long solves = 0;                   ///< problems solved by the LCP solver
  bool library_unavailable = false;  ///< the last failure was the solver library's absence
  long cone_sweeps = 0;              ///< Gauss-Seidel sweeps over problems with a 2-D cone
  long cone_fallbacks = 0;           ///< of those, problems handed to the fallback (all laws at once)
  long cone_unsolved = 0;            ///< of those, problems it found no solution of
  long cone_newton_steps = 0;        ///< its steps (Levenberg-Marquardt and projected gradient)
};

/// Rows J (normal, then tangent of each candidate) at the state; sets the candidates' kn, kt.
void rows_of(const ContactSet& cs, Problem& p, double t, const Eigen::VectorXd& q,
             const Eigen::VectorXd& qd, Eigen::MatrixXd& J, Eigen::VectorXd& j0,
             Eigen::VectorXd& jgamma);

/// P = M⁻¹ − M⁻¹ g_Bᵀ (g_B M⁻¹ g_Bᵀ)⁻¹ g_B M⁻¹ (the inverse inertia with the bilateral
/// constraints imposed) and a_B, the acceleration with only the bilateral constraints, by `d`.
/// `extra`: constraints imposed with the bilateral ones (the rough rows of the contacts that
/// take part); `dv0`, if given: the velocity change −M⁻¹ g_Bᵀ (g_B M⁻¹ g_Bᵀ)⁻¹ (g_B q̇ + g0_B)
/// of the impulse that brings those rows to rest (a rough landing). On failure `message` says why.
ModelIssue contact_inertia(Dynamics& d, const ContactSet& cs, double t, const Eigen::VectorXd& q,
                           const Eigen::VectorXd& qd, Eigen::MatrixXd& P, Eigen::VectorXd& aB,
                           std::string& message, const std::vector<int>& extra = {},
                           Eigen::VectorXd* dv0 = nullptr);

/// Solves the problem: closed form for one candidate (settings permitting), else the LCP
/// solver; a problem with a 2-D cone by the nonsmooth block Gauss-Seidel method (each contact's
/// exact local solution in turn, the others' forces fixed, until they no longer change), and
/// where that stalls (a wedged body: W singular, the squeeze undetermined) by a damped
/// semismooth Newton method on the Alart-Curnier equations. Returns false with `message` set
/// when no solution is found.
bool solve_problem(const ContactSet& cs, Problem& p, const LcpSettings& settings, double t,
                   Eigen::VectorXd& z, LcpCounters& counters, std::string& message);

/// "'a', 'b'": the candidates' contacts, for messages.
std::string names(const ContactSet& cs, const Problem& p);

}  // namespace pcsim::mech::contacts
