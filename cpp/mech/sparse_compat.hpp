// The structured compatibility solve on sparse matrices (issue 23): R = gᵀ λ with
// (g M⁻¹ gᵀ) λ = −(γ + g M⁻¹ f), for large models whose M is block-diagonal (absolute
// coordinates: one small block per body) and whose g is sparse (each row touches a few
// coordinates). M⁻¹ is formed block by block (a dense Cholesky per block, so M⁻¹ has M's
// pattern), S = g M⁻¹ gᵀ (banded for a chain) by sparse products planned once per pattern, and S is factored by
// Eigen's SimplicialLDLT with the AMD fill-reducing ordering: its symbolic analysis is done
// when the pattern first appears (again only if a new nonzero shows up: the pattern kept is
// the union of those seen), the numeric factorization per evaluation. Dynamics uses it for
// n >= Dynamics::sparse_min_n (below, its dense kernel is faster); a singular M, a (nearly)
// dependent row, or an M whose largest block has more than kMaxBlock coordinates (relative
// coordinates: M⁻¹ is dense, nothing to gain) hands back to Dynamics' dense paths.
#pragma once

#include <vector>

#include "common/eigen_instances.hpp"
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include "mech/model.hpp"

namespace pcsim::mech {

using SparseMatrixD = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

/// M of a model with sparse structure (Model::has_sparse_structure) as a compressed sparse
/// matrix: its lower triangle (n x n, column-major), the pattern built once from
/// Model::sparse_pattern(), the values copied in per evaluation (O(entries), no dense work).
class SparseMass {
 public:
  /// M's values and h at the state (Model::kinetic_terms_sparse); h sized n.
  void evaluate(const Model& model, double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                Eigen::VectorXd& h);
  const SparseMatrixD& lower() const { return L_; }
  bool all_finite() const;
  /// The dense symmetric M (n x n, resized if needed): for the dense paths (rare hand-overs).
  void to_dense(Eigen::MatrixXd& M) const;

 private:
  const Model* model_ = nullptr;
  SparseMatrixD L_;
  std::vector<int> place_;  // value k of the model's order -> its place in L_'s values
  std::vector<double> values_;
};

/// The rows g (s x n) of an active set of a model with sparse structure, compressed (column-
/// major), pattern built from Model::sparse_pattern() when the active set changes, values
/// copied in per evaluation.
class SparseRows {
 public:
  /// g's values, g0 and γ (sized s) at the state (Model::constraint_rows_sparse).
  void evaluate(const Model& model, const std::vector<int>& active, double t,
                const Eigen::VectorXd& q, const Eigen::VectorXd& qd, Eigen::VectorXd& g0,
                Eigen::VectorXd& gamma);
  const SparseMatrixD& matrix() const { return g_; }
  bool all_finite() const;
  /// The dense g (s x n, resized if needed).
  void to_dense(Eigen::MatrixXd& g) const;

 private:
  const Model* model_ = nullptr;
  std::vector<int> active_;
  SparseMatrixD g_;
  std::vector<int> place_;
  std::vector<double> values_;
};

class SparseCompatibility {
 public:
  enum class Outcome {
    solved,          ///< λ, R, q̈ and G0 set
    singular_mass,   ///< M not positive definite (pivot ratio below 1e-13): nothing set
    dependent_rows,  ///< a row within the hand-over angle of the others: G0 set only
    not_sparse,      ///< M has a block larger than kMaxBlock: use the dense solve
  };
  static constexpr int kMaxBlock = 48;
  /// M (n x n, symmetric, only its lower triangle read), g (s x n), f = Q − h, γ (s); kSwitch:
  /// the hand-over threshold on the pivots of S (D_jj < kSwitch S_jj, in the factor's order).
  Outcome solve(const Eigen::MatrixXd& M, const Eigen::MatrixXd& g, const Eigen::VectorXd& f,
                const Eigen::VectorXd& gamma, double kSwitch, Eigen::VectorXd& G0,
                Eigen::VectorXd& lambda, Eigen::VectorXd& R, Eigen::VectorXd& qdd);
  /// The same from a model's sparse values (SparseMass, SparseRows): no dense matrix is read.
  Outcome solve(const SparseMatrixD& M_lower, const SparseMatrixD& g, const Eigen::VectorXd& f,
                const Eigen::VectorXd& gamma, double kSwitch, Eigen::VectorXd& G0,
                Eigen::VectorXd& lambda, Eigen::VectorXd& R, Eigen::VectorXd& qdd);
  /// After a solve that reached the factorization of S: the smallest D_jj / S_jj (sin² of the
  /// angle between a row and the span of the rows before it, M⁻¹ metric; 1 when s = 0).
  double min_pivot_ratio() const { return min_pivot_ratio_; }
  /// How many symbolic analyses were done (of M, of S): a fixed pattern gives one each.
  int analyses_M() const { return analyses_M_; }
  int analyses_S() const { return analyses_S_; }

 private:
  using Sparse = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
  using LDLT = Eigen::SimplicialLDLT<Sparse, Eigen::Lower, Eigen::AMDOrdering<int>>;
  // The blocks of M (connected components of its pattern) and M⁻¹'s pattern (full blocks).
  void analyse_mass(const Sparse& M);
  const Sparse* Mp_ = nullptr;  // the M of the current solve (M_ or the caller's)
  // Copies the values of the dense A (its lower triangle if lower) into the sparse pattern S,
  // widening the pattern first if A has a nonzero outside it; true if the pattern changed.
  static bool gather(const Eigen::MatrixXd& A, bool lower, std::vector<char>& mask, Sparse& S);
  // The solve on M_ (lower triangle, pattern analysed) and g.
  Outcome solve_filled(const Sparse& g, const Eigen::VectorXd& f, const Eigen::VectorXd& gamma,
                       double kSwitch, Eigen::VectorXd& G0, Eigen::VectorXd& lambda,
                       Eigen::VectorXd& R, Eigen::VectorXd& qdd);
  friend class SparseMinNorm;

  // The numeric plan of S = g M⁻¹ gᵀ (lower triangle), built when the pattern of g or of M
  // changes: W = g M⁻¹ entry by entry (W's pattern is g's widened to whole blocks), then S from
  // W and g; each product is a list of (target, left, right) value indices, so an evaluation
  // allocates nothing and touches each product term once.
  void plan_products(const Sparse& g);
  bool plan_valid_ = false;
  std::vector<int> g_outer_, g_inner_;  // the pattern of g the plan is for
  std::vector<int> w_plan_, s_plan_;    // triples (target, left, right)
  Sparse W_;
  // M's blocks inverted in place by a small Cholesky (no allocation); false if a pivot is not
  // positive. dmin/dmax: the range of the squared diagonal of the factor (the pivots).
  bool invert_blocks(double& dmin, double& dmax);
  std::vector<double> chol_;

  std::vector<char> mask_M_, mask_g_;
  Sparse M_, g_, S_, Minv_;
  LDLT ldlt_S_;
  std::vector<std::vector<int>> blocks_;
  int largest_block_ = 0;
  std::vector<int> M_outer_, M_inner_;  // the pattern of M analyse_mass was done for
  std::vector<int> local_;              // coordinate -> its index within its block
  double min_pivot_ratio_ = 1.0;
  int analyses_M_ = 0, analyses_S_ = 0;
  Eigen::VectorXd a0_, sdiag_;
};

/// The minimum-norm solution x = gᵀ (g gᵀ)⁻¹ b of g x = b for a sparse g of full row rank (the
/// drift projection's correction, as Huang's method gives it, up to rounding): g gᵀ by a sparse
/// product, factored by SimplicialLDLT with AMD (symbolic analysis once per pattern). Returns
/// false, x untouched, where a pivot of g gᵀ is below kDependent of its diagonal entry (a row
/// within about 1e-5 rad of the span of the others): the caller's Huang path decides there.
class SparseMinNorm {
 public:
  static constexpr double kDependent = 1e-10;
  bool solve(const Eigen::MatrixXd& g, const Eigen::VectorXd& b, Eigen::VectorXd& x);
  /// The same for a compressed g (SparseRows::matrix()).
  bool solve(const SparseMatrixD& g, const Eigen::VectorXd& b, Eigen::VectorXd& x);

 private:
  using Sparse = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;
  std::vector<char> mask_;
  Sparse g_, A_;
  Eigen::SimplicialLDLT<Sparse, Eigen::Lower, Eigen::AMDOrdering<int>> ldlt_;
  std::vector<int> outer_, inner_;
  Eigen::VectorXd diag_;
};

}  // namespace pcsim::mech
