// Coordinate projection onto the active constraints: the minimum-norm (Huang) corrections of q
// (Newton on the holonomic Φ) and of q̇ (g q̇ + g0 = 0), used for consistent initial values and
// for drift control after accepted steps.
#pragma once

#include <string>
#include <vector>

#include "common/eigen_instances.hpp"

#include "common/kernel.hpp"
#include "mech/model.hpp"
#include "mech/dynamics.hpp"
#include "mech/simulation.hpp"
#include "mech/sparse_compat.hpp"

namespace pcsim::mech {

struct ProjectionWork {
  Eigen::MatrixXd g;
  Eigen::VectorXd g0, gamma;
  /// The full-rank minimum-norm solves for n >= Dynamics::kSparseMinN (sparse_min_n) instead of
  /// Huang's dense kernel (same solution up to rounding); Huang decides where it declines.
  SparseMinNorm sparse;
  int sparse_min_n = Dynamics::kSparseMinN;
  /// The rows as sparse values (models with sparse structure, n >= sparse_min_n): the Huang
  /// path's Newton and velocity stages then do no s x n work unless the sparse solve declines.
  SparseRows rows_holonomic, rows_active;
};

/// Projects (q, qd) in place. tol: relative Newton tolerance for the position part. On return
/// dq, dv are the 2-norms of the total corrections. Returns the issue (message in *message).
ModelIssue project_state(const Model& model, const std::vector<int>& active, double t,
                         Eigen::VectorXd& q, Eigen::VectorXd& qd, Kernel kernel, double tol,
                         double& dq, double& dv, std::string& message, ProjectionWork& work);

/// Whether the row-scaled g of the active rows at (t, q) has σ_min <= kNearSingular σ_max (or
/// more rows than coordinates): dependent rows, or a state near a singular position, where
/// project_state takes the rank-revealing path (Huang's steps there follow the nearly
/// dependent rows and can throw the velocity off the motion: A02 with N = 4 lost its whole
/// kinetic energy in one projection at a singular position before this test).
inline constexpr double kNearSingular = 1e-4;
bool near_singular(const Model& model, const std::vector<int>& active, double t,
                   const Eigen::VectorXd& q, const Eigen::VectorXd& qd, ProjectionWork& work);

/// The Huang path of project_state (before issue 21 the only one).
ModelIssue project_state_huang(const Model& model, const std::vector<int>& active, double t,
                               Eigen::VectorXd& q, Eigen::VectorXd& qd, Kernel kernel, double tol,
                               double& dq, double& dv, std::string& message, ProjectionWork& work);

/// The rank-revealing projection (issue 21): Gauss–Newton with minimum-norm steps through the
/// truncated SVD of the row-scaled g (truncation 1e-5 σ_max), so dependent rows (everywhere,
/// or at a singular position) neither stop it nor blow its steps up; contradictory rows are
/// named (the row left most violated).
ModelIssue project_state_rank_revealing(const Model& model, const std::vector<int>& active,
                                        double t, Eigen::VectorXd& q, Eigen::VectorXd& qd,
                                        double tol, double& dq, double& dv, std::string& message,
                                        ProjectionWork& work);

/// Whether one imposed constraint row holds at (t, q, qd) to the projection's tolerance already,
/// so that projecting would change the state by rounding only (the drift allowed between
/// projections). The tolerance is relative to the row's OWN terms, never to the size of the
/// largest coordinate (issue 19: a pendulum hung at x = 1e5, or a floor contact far along x,
/// got drift tolerances 1e5 times looser than at the origin):
///   position row i (pos_residual = Φ_i, only if `position`):
///     |Φ_i| <= tol · (1 + Σ_j |g_ij| |q_j| + |g0_i| |t|)
///   velocity row i:  |g_i q̇ + g0_i| <= tol · (1 + Σ_j |g_ij| |q̇_j| + |g0_i|)
/// The sums are the magnitudes of the terms whose cancellation forms the residual (to first
/// order, Φ_i changes by g_ij δq_j for a relative perturbation δq_j = ε q_j of every
/// coordinate, and by ∂Φ_i/∂t t for t's): a residual computed in floating point is uncertain by
/// a few eps times them, so no state can be asked to satisfy the row better. tol is the
/// existing projection_tol (1e-13, about 450 eps): a margin of a few hundred roundings above
/// that floor, so a state the projection has just made consistent is not projected again for
/// its own rounding, yet drift beyond a few hundred roundings of the row is corrected.
/// The 1 is the old rule's absolute floor (1e-13 in the row's own units) and is kept on
/// purpose: it does not grow with any coordinate, and without it rows whose terms vanish at the
/// state (a rolling row s + r φ at s = φ = 0, a gap rate at rest) would be projected after
/// every step for rounding, which changes the sieve's stored references (case_sieve_1995 moved
/// by 1e-5 relative in y's amplitude with the floor removed). With it, models of moderate size
/// (|q| ~ 1) make the same decisions as under the old rule `tol (1 + |q|∞)` (every stored
/// reference and test_sieve_rolling's bit-for-bit check are unchanged).
bool row_within_projection_tol(const Eigen::Ref<const Eigen::RowVectorXd>& g, double g0,
                               bool position, double pos_residual, double t,
                               const Eigen::VectorXd& q, const Eigen::VectorXd& qd, double tol);

/// row_within_projection_tol for every row of a sparse g (s x n) at once: true if all hold.
/// position[r]: row r is holonomic with residual phi[r].
bool rows_within_projection_tol(const SparseMatrixD& g, const Eigen::VectorXd& g0,
                                const std::vector<char>& position, const Eigen::VectorXd& phi,
                                double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                double tol);

/// Resolves constraint names to indices into model.constraints(); returns the issue.
ModelIssue resolve_constraints(const Model& model, const std::vector<std::string>& names,
                               std::vector<int>& active, std::string& message);

}  // namespace pcsim::mech
