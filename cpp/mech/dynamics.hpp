// The per-run workspace of the engine (the "Data" beside the immutable Model): evaluates M, h,
// Q, g, g0, γ at a state for a given active constraint set and solves for the reactions R and
// accelerations q̈ by one of the three formulations, without heap allocation after
// construction (except Huang calls when the constraint rows vary with q or t, or the active set
// changes). The active set is passed per evaluation, as Pinocchio passes its Data per call, so
// a run can add and remove constraints.
#pragma once

#include <algorithm>
#include <string>
#include <vector>

#include "common/eigen_instances.hpp"
#include "common/eigen_instances.hpp"

#include "common/kernel.hpp"
#include "mech/model.hpp"
#include "mech/sparse_compat.hpp"
#include "mech/status.hpp"

namespace pcsim::mech {

/// The active constraints of an evaluation: indices into model.constraints(), in row order.
/// Immutable; each instance has its own identity (id), which lets a workspace keep quantities
/// that depend only on the set (the null-space basis D of constant rows) until the set changes.
class ActiveSet {
 public:
  ActiveSet() : ActiveSet(std::vector<int>{}, true) {}
  /// constant_rows: every row is declared constant (ConstraintInfo::constant_row).
  ActiveSet(std::vector<int> rows, bool constant_rows);
  /// The set of `rows` of `model`, constant_rows taken from the model's declarations.
  static ActiveSet of(const Model& model, std::vector<int> rows);

  const std::vector<int>& rows() const { return rows_; }
  int size() const { return static_cast<int>(rows_.size()); }
  bool constant_rows() const { return constant_rows_; }
  unsigned long id() const { return id_; }

 private:
  std::vector<int> rows_;
  bool constant_rows_ = true;
  unsigned long id_ = 0;
};

/// One sliding contact of a solve with sliding friction (Dynamics::solve_sliding): the rows of
/// the evaluated set that carry its normal and its friction direction, and c = μ_k σ sign (the
/// kinetic friction coefficient, the sliding direction ±1, the gap's sign ±1): the friction
/// force is −c λ_normal along the friction row.
/// A 2-D Coulomb cone slides along both its rows: friction_row2 >= 0, and the force is
/// −c λ_normal (w1 along friction_row + w2 along friction_row2), (w1, w2) the unit sliding
/// direction.
struct SlidingFriction {
  int normal_row = -1;
  int friction_row = -1;
  double coefficient = 0.0;
  int friction_row2 = -1;
  double w1 = 1.0, w2 = 0.0;
};

class Dynamics {
 public:
  /// Baumgarte terms are added to γ when stabilization == baumgarte.
  Dynamics(const Model& model, Kernel kernel, Stabilization stabilization = Stabilization::none,
           double alpha = 0.0, double beta = 0.0);

  /// Evaluates M, h, Q, f = Q − h, g, g0, γ (with Baumgarte terms) at (t, q, qd) for the active
  /// set and checks them for NaN/Inf. Returns the issue (and sets message()) or none. The set
  /// must stay alive until the next evaluate().
  ModelIssue evaluate(const ActiveSet& active, double t, const Eigen::VectorXd& q,
                      const Eigen::VectorXd& qd);

  /// After evaluate(): factorizes M and solves for R and q̈ (members R, qdd).
  ModelIssue solve(ReactionMethod method);

  /// After evaluate() of a set whose first `imposed` rows are imposed and whose other rows are
  /// the friction rows of sliding contacts (not imposed: the direction of the friction force):
  /// R, q̈ and λ with Coulomb's law −c λ_n along each sliding row (issue 12, docs/switching.md).
  /// compatibility_structured: R = (g_Aᵀ + F) λ_A with F's column of a sliding normal
  /// −c g_frictionᵀ, from g_A M⁻¹ (g_Aᵀ + F) λ_A = −(g_A M⁻¹ f + γ_A) (non-symmetric, s_A x s_A).
  /// compatibility: the paper's dense [G; Dᵀ] system with one ideality row per sliding contact
  /// replaced by the friction law λ_t + c λ_n = 0 (λ = (g gᵀ)⁻¹ g R). λ then holds every row of
  /// the set: the imposed multipliers first, then those of the sliding rows (R = gᵀ λ).
  ModelIssue solve_sliding(ReactionMethod method, int imposed,
                           const std::vector<SlidingFriction>& sliding);

  /// After evaluate() and solve(compatibility) (which factorizes M and forms G, G0, D):
  /// the DAE residuals for given a and R: res_dyn = M a − f − R (n),
  /// res_con = [G R + G0; Dᵀ R] (n).
  void dae_residuals(const Eigen::VectorXd& a, const Eigen::VectorXd& Rv,
                     Eigen::Ref<Eigen::VectorXd> res_dyn, Eigen::Ref<Eigen::VectorXd> res_con) const;

  /// Factorizes M and forms G = g M⁻¹, G0 = g M⁻¹ f + γ and D (Huang) without solving for R.
  ModelIssue prepare_compatibility();

  /// max |Φ_i(q, t)| over the active holonomic constraints of the last evaluate() (0 if none).
  double position_residual(double t, const Eigen::VectorXd& q) const;
  /// max |g q̇ + g0| from the last evaluate().
  double velocity_residual(const Eigen::VectorXd& qd) const;

  const std::string& message() const { return message_; }
  int n() const { return n_; }
  int s() const { return s_; }
  const Model& model() const { return *model_; }

  // Results of the last evaluate() / solve(), readable by the caller (g, G: s x n; D: n x (n-s)).
  // lambda (s): the reaction split by constraint, R = gᵀ λ, so constraint r's own generalized
  // reaction is λ_r g_rᵀ (the sieve's contact force without a holding constraint's share).
  Eigen::MatrixXd M, g, D, G, A;
  Eigen::VectorXd h, Q, f, g0, gamma, G0, R, qdd, lambda;

  /// The numerical rank of the active rows used by the last solve() (s when the full-rank
  /// structured or dense solve applied; from the rank-revealing solve otherwise) and whether the
  /// rank-revealing solve was taken (issue 21). When rank < s the multipliers λ are the
  /// minimum-norm split of R (statically indeterminate: null space of dimension s − rank), R and
  /// q̈ are unique.
  int rank = 0;
  bool rank_revealing = false;
  /// s − rank of the last solve (0 with full rank): the dimension of the null space of gᵀ, i.e.
  /// of the splits λ of R that are not determined (statically indeterminate when > 0). λ is
  /// then the minimum-norm split (of the row-scaled rows) and R = gᵀ λ still holds (R is
  /// unique; docs/redundant.md). Per-joint outputs built from λ must say so when nullity > 0.
  int nullity = 0;
  bool indeterminate() const { return nullity > 0; }

  /// The rank-revealing reaction solve (issue 21), for any rank of g: with M = L Lᵀ, the
  /// row-scaled B = S_r g L⁻ᵀ (S_r = diag(1/|g_r|)) and b = −S_r G0, its SVD B = Σ σ_i v_i u_iᵀ
  /// gives y = Σ u_i φ_i (v_iᵀ b)/σ_i with the filter φ_i = σ_i⁴/(σ_i⁴ + μ⁴),
  /// μ = kFilter σ_max, and R = L y, q̈ = M⁻¹ f + L⁻ᵀ y, λ = S_r Σ v_i φ_i (v_iᵀ b)/σ_i².
  /// Proof of uniqueness (docs/redundant.md): q̈ − M⁻¹f = M⁻¹ gᵀ λ and g q̈ = −γ give
  /// (g M⁻¹ gᵀ) λ = −G0; if λ and λ' both solve it, δ = λ − λ' has δᵀ g M⁻¹ gᵀ δ = |L⁻¹ gᵀ δ|² = 0,
  /// so gᵀ δ = 0 and R = gᵀ λ = gᵀ λ'. rank counts σ_i > kRankTol σ_max.
  ModelIssue solve_rank_revealing();
  /// Relative filter μ/σ_max = 1e-6, filter φ = σ⁴/(σ⁴ + μ⁴). Across a singular position (σ → 0
  /// linearly in time, as in A02) the exact component of R along the vanishing direction is
  /// (u·b)/σ, a 0/0 that rounding and drift turn into spikes; filtered it is (u·b) σ³/(σ⁴ + μ⁴):
  /// bounded by about |u·b|/μ and a smooth function of the state, which the step-size control
  /// resolves with steps of about μ/|σ̇| instead of collapsing (a filter of 1e-10 gave steps of
  /// 1e-14 s at rtol 1e-10 in A02, N = 4, and 1e-7 a crank angle off by 4e-4 rad). Its price:
  /// a direction with σ < σ_max/100 (only there is the filter used) is enforced to (μ/σ)⁴
  /// relative, 1e-16 at the hand-over.
  static constexpr double kFilter = 1e-6;
  /// Relative singular value below which a row counts as dependent (reported rank): about
  /// sqrt(eps); rows that are exactly dependent give σ ≈ eps σ_max, far below.
  static constexpr double kRankTol = 1.5e-8;
  /// The consistency test of the directions the filter drops (σ_i < μ): the compatibility
  /// residual left along them, relative to the terms of the right-hand side (|a0| + max |γ_r|/
  /// |g_r| + σ_max |y|), must stay below 1e-2, else the solve fails with
  /// inconsistent_constraints naming the rows (a run stops with exit 3). Consistent data leave
  /// at most 1e-6 (μ/σ_max); a state off the constraints by rtol ≤ 1e-4 moves it by about rtol.
  static constexpr double kConsistency = 1e-2;
  /// The structured (Cholesky) solve hands over to the rank-revealing one where a row is
  /// within an angle of 1e-2 of the span of the rows before it (in the M⁻¹ metric: its pivot
  /// U_jj² < kSwitch S_jj, independent of the row's scale), or where the old test (smallest
  /// pivot < 1e-13 of the largest) fires. There σ ≳ 1e-2 σ_max, so the filter changes R by at
  /// most (μ/σ)⁴ = 1e-16 relative along that direction: q̈ is continuous to that, and the
  /// formulations agree to 1e-10 (test_reactions) on either side.
  static constexpr double kSwitch = 1e-4;
  /// The structured solve (compatibility_structured) runs on sparse matrices (SparseCompatibility,
  /// Eigen's SimplicialLDLT with AMD) from this many coordinates up; below, its dense kernel is
  /// faster (crossover measured with bench_modelfile_chain: see the README). Tests set it to 0 to
  /// compare the two paths on small models.
  static constexpr int kSparseMinN = 60;
  const SparseCompatibility& sparse_solver() const { return sparse_; }
  /// After evaluate(): the rows (indices into the active set) that a column-pivoted QR of the
  /// row-scaled gᵀ leaves outside its first `numerical_rank` pivots: the dependent rows named in
  /// messages and rank reports.
  std::vector<int> dependent_row_indices(int numerical_rank) const;
  /// After a solve() that took the full-rank structured path (rank_revealing false): the
  /// smallest sin² of the angle between a row and the span of the rows before it, in the M⁻¹
  /// metric (the Cholesky pivots U_jj²/S_jj of g M⁻¹ gᵀ; 1 when s = 0). The run's rank watch
  /// (issue 21) looks closer at a step whose evaluations came near a singular position.
  double min_pivot_ratio() const {
    if (used_sparse) return sparse_.min_pivot_ratio();
    double m = 1.0;
    for (int i = 0; i < s_; ++i) m = std::min(m, 1.0 / (sdiag_[i] * inv_s_[i] * inv_s_[i]));
    return m;
  }
  /// After evaluate(): the smallest singular value of g with its rows scaled to unit length (0
  /// when s > n): how close the state is to a singular position.
  double smallest_singular_value() const;

 private:
  ModelIssue fail(ModelIssue issue, std::string message);
  ModelIssue evaluate_sparse_checks(const ActiveSet& active, double t, const Eigen::VectorXd& q,
                                    const Eigen::VectorXd& qd);
  ModelIssue evaluate_finish(const ActiveSet& active, double t, const Eigen::VectorXd& q,
                             const Eigen::VectorXd& qd);
  ModelIssue factorize_mass();
  ModelIssue null_basis();
  /// The names of the active constraints whose rows of g take part in a linear dependency
  /// ("'a', 'b'"), and the message that says so with the time and what the user can do.
  std::string dependent_rows() const;
  std::string dependency_message() const;
  ModelIssue solve_compatibility();
  ModelIssue solve_compatibility_structured();
  template <int N, int NS> bool structured_kernel();
  bool solve_sparse_structured(ModelIssue& issue);
  bool singular_s_ = false;
  ModelIssue solve_kkt();
  ModelIssue solve_udwadia_kalaba();
  ModelIssue solve_sliding_structured(int imposed, const std::vector<SlidingFriction>& sliding);
  ModelIssue solve_sliding_dense(int imposed, const std::vector<SlidingFriction>& sliding);
  void resize_for(int s);

  const Model* model_;
  const ActiveSet* active_ = nullptr;
  Kernel kernel_;
  Stabilization stabilization_;
  double alpha_, beta_;
  int n_, s_ = -1;
  unsigned long D_for_ = 0;  ///< id of the active set D was computed for (0: none)
  double t_ = 0.0;
  std::string message_;

  Eigen::LLT<Eigen::MatrixXd> llt_, llt_s_;
  Eigen::MatrixXd S_;       // g M⁻¹ gᵀ (s x s), then its Cholesky factor
  Eigen::MatrixXd L_;       // the Cholesky factor of M (structured solve)
  Eigen::VectorXd inv_, inv_s_;  // 1 / diagonal of the factors of M and of S
  Eigen::VectorXd sdiag_;        // the diagonal of S before its factorization
  void lambda_from_R();     // λ from R = gᵀ λ (the dense methods)
  Eigen::PartialPivLU<Eigen::MatrixXd> lu_;
  Eigen::MatrixXd MinvgT_;  // M⁻¹ gᵀ (n x s)
  Eigen::VectorXd a0_, rhs_, tmp_;
  SparseCompatibility sparse_;

 public:
  // Last in the class: the members before keep their offsets (the small models' kernels).
  int sparse_min_n = kSparseMinN;  ///< the sparse path from this many coordinates (see above)
  bool used_sparse = false;        ///< true if the last structured solve ran on the sparse path
  /// Sparse evaluation (issue 23), off by default: when set, evaluate() of a model with sparse
  /// structure (Model::has_sparse_structure) with n >= sparse_min_n takes M and g as sparse
  /// values only, and the public dense M and g are NOT filled by it: the structured solve runs
  /// on the sparse values; every other method, the hand-overs (dependent rows, singular M) and
  /// the members that read g (dependent_row_indices, smallest_singular_value) fill them first,
  /// once per evaluation. A caller that reads M or g itself after evaluate() calls densify().
  /// Runs (mech::simulate) set it for their own workspaces.
  bool sparse_evaluation = false;
  /// Fills the dense M and g from the sparse values of the last evaluate() (no-op when they
  /// are current).
  void densify();
  /// True if the last evaluate() took the sparse values (M and g dense only after densify()).
  bool sparse_evaluated() const { return sparse_eval_; }
  /// The sparse M (lower triangle) and g of the last sparse evaluate().
  const SparseMass& sparse_mass() const { return mass_sp_; }
  const SparseRows& sparse_rows() const { return rows_sp_; }

 private:
  SparseMass mass_sp_;
  SparseRows rows_sp_;
  bool sparse_eval_ = false;
  bool dense_stale_ = false;  // M and g not yet filled from the sparse values
  mutable std::vector<int> hol_;     // position_residual's scratch
  mutable std::vector<double> phi_;

 public:
  /// The vanishing limit (issue 21, docs/redundant.md "Inside a crossing's window"). Across a
  /// singular position the singular values σ_k of the directions k that vanish there go through
  /// 0 linearly in time, and the exact share z_k = c_k/σ_k of the reaction along them (the force
  /// that keeps the chain rigid, O(10 N) in A02) has a finite limit that the state alone does not
  /// give (0/0; the filter sets it to 0 inside σ < μ, which lost O(1e-5) J per crossing at tight
  /// tolerances). With the limit on, a solve whose non-persistent singular values fall below
  /// kLimitOuter ν (ν = kLimitWidth σ_max) takes z from the acceleration constraint
  /// differentiated once more along the motion, projected on the vanishing left singular
  /// vectors: V_Kᵀ S (ġ q̈ + γ̇) = 0 with q̈ = q̈⊥ + L⁻ᵀ U_K z (the terms V_Kᵀ S g (...) it drops
  /// are V_Kᵀ B (...) = Σ_K (...) = O(σ)): z is the share at the crossing instant, to first order
  /// in the time to it. ġ and γ̇ by central differences of the constraint rows along (1, q̇, q̈⊥)
  /// and along q̇ + ε L⁻ᵀ u_k (2 + 2m row evaluations, m = number of vanishing directions). The
  /// share taken is z below kLimitInner ν and a C¹ blend to the filtered c_k/σ_k up to
  /// kLimitOuter ν. The `persistent` smallest singular values (the rows dependent at the start:
  /// Bricard, a third crank) are never vanishing directions. Off by default: only a run
  /// (mech::simulate) turns it on, so a solve at a given state is a function of that state only.
  /// switch_ratio: the structured solve's pivot ratio below which the rank-revealing solve takes
  /// over (at most kLimitSwitch; a run passes a tenth of its start's where that is lower: the
  /// smallest pivot ratio of a regular chain of N links is ~0.66/N, far from any singular
  /// position, and must not send every solve to the dense SVD).
  void set_vanishing_limit(bool on, int persistent_nullity, double switch_ratio = kLimitSwitch) {
    limit_on_ = on;
    persistent_nullity_ = std::max(0, persistent_nullity);
    limit_switch_ = std::min(kLimitSwitch, switch_ratio);
  }
  bool vanishing_limit_on() const { return limit_on_; }
  /// ν/σ_max. The limit's own error is first order in the distance to the crossing (the share
  /// at the crossing instant: 1.3e-3 .. 2.3e-3 of R per radian of crank angle in A02 N = 4), the
  /// exact share's grows as the drift over σ; measured on A02 N = 4, 10 s (crank angle error
  /// against the one-degree-of-freedom model at rtol 1e-8 / 1e-10 / 1e-12): ν = 1e-4 σ_max
  /// 1.2e-5 / 9.9e-6 / 4.1e-6 rad, 1e-5 3.7e-8 / 5.2e-7 / 1.3e-8, 1e-6 1.5e-7 / 4.6e-7 / 9.7e-8
  /// (without the limit: 1.1e-7 / 9.6e-5 / 2.5e-4).
  static constexpr double kLimitWidth = 1e-5;
  static constexpr double kLimitInner = 10.0;
  static constexpr double kLimitOuter = 30.0;
  /// With the limit on, a structured solve whose smallest Cholesky pivot ratio (sin² of a row's
  /// angle to the span of the rows before it) is below this hands over to the rank-revealing
  /// solve, so that no state with σ_min < kLimitOuter ν = 3e-4 σ_max takes the structured path
  /// (σ_min of the row-scaled B is at most |b_j| sin θ_j, not bounded below by it): sin θ < 0.1.
  static constexpr double kLimitSwitch = 1e-2;
  /// Solves that used the limit (z blended in with a positive weight) since construction.
  long limit_solves = 0;
  /// Of those, the ones whose limit system was singular (no transversal crossing: the filter
  /// was kept).
  long limit_fallbacks = 0;

 private:
  bool limit_on_ = false;
  int persistent_nullity_ = 0;
  double limit_switch_ = kLimitSwitch;
  Eigen::VectorXd lq_, lqd_;                 // the state of the last evaluate() (limit on)
  Eigen::MatrixXd lgp_, lgm_;                // the rows at the probes
  Eigen::VectorXd lg0_, lgamp_, lgamm_, lv_;
  /// Replaces the shares ycoef of the vanishing directions by the limit (see above). In the
  /// limit basis the share is returned in `extra` (n values, added to y by the caller; sized 0
  /// otherwise) and those directions' ycoef are set to 0.
  void add_vanishing_limit(const Eigen::MatrixXd& U, const Eigen::MatrixXd& V,
                           const Eigen::VectorXd& sv, const Eigen::VectorXd& scale,
                           Eigen::VectorXd& ycoef, Eigen::VectorXd& lcoef, Eigen::VectorXd& extra);
};

/// "coordinate 'x'" style names for messages.
std::string coordinate_list(const Model& model, const Eigen::VectorXd& v, double threshold);

}  // namespace pcsim::mech
