#include "mech/sparse_compat.hpp"

#include <algorithm>
#include <cmath>

namespace pcsim::mech {

bool SparseCompatibility::gather(const Eigen::MatrixXd& A, bool lower, std::vector<char>& mask,
                                 Sparse& S) {
  const Eigen::Index rows = A.rows(), cols = A.cols();
  bool changed = false;
  if (mask.size() != static_cast<std::size_t>(rows * cols) || S.rows() != rows || S.cols() != cols) {
    mask.assign(static_cast<std::size_t>(rows * cols), 0);
    changed = true;
  }
  const double* a = A.data();
  for (Eigen::Index j = 0; j < cols; ++j) {
    const Eigen::Index i0 = lower ? j : 0;
    const double* col = a + j * rows;
    char* m = mask.data() + j * rows;
    for (Eigen::Index i = i0; i < rows; ++i) {
      if (col[i] != 0.0 && !m[i]) {
        m[i] = 1;
        changed = true;
      }
    }
  }
  if (changed) {
    std::vector<Eigen::Triplet<double, int>> entries;
    for (Eigen::Index j = 0; j < cols; ++j)
      for (Eigen::Index i = lower ? j : 0; i < rows; ++i)
        if (mask[static_cast<std::size_t>(i + j * rows)])
          entries.emplace_back(static_cast<int>(i), static_cast<int>(j), 0.0);
    S.resize(rows, cols);
    S.setFromTriplets(entries.begin(), entries.end());
    S.makeCompressed();
  }
  const int* outer = S.outerIndexPtr();
  const int* inner = S.innerIndexPtr();
  double* v = S.valuePtr();
  for (Eigen::Index j = 0; j < cols; ++j) {
    const double* col = a + j * rows;
    for (int p = outer[j]; p < outer[j + 1]; ++p) v[p] = col[inner[p]];
  }
  return changed;
}

void SparseCompatibility::analyse_mass(const Sparse& M) {
  const int n = static_cast<int>(M.rows());
  // Union-find over the nonzeros of M's lower triangle.
  std::vector<int> parent(n);
  for (int i = 0; i < n; ++i) parent[i] = i;
  auto root = [&](int i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  for (int j = 0; j < n; ++j)
    for (Sparse::InnerIterator it(M, j); it; ++it) {
      const int a = root(static_cast<int>(it.row())), b = root(j);
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
  std::vector<int> block_of(n, -1);
  blocks_.clear();
  local_.assign(n, 0);
  for (int i = 0; i < n; ++i) {
    const int r = root(i);
    if (block_of[r] < 0) {
      block_of[r] = static_cast<int>(blocks_.size());
      blocks_.emplace_back();
    }
    local_[i] = static_cast<int>(blocks_[block_of[r]].size());
    blocks_[block_of[r]].push_back(i);  // ascending
  }
  largest_block_ = 0;
  std::vector<Eigen::Triplet<double, int>> entries;
  for (const auto& b : blocks_) {
    largest_block_ = std::max(largest_block_, static_cast<int>(b.size()));
    for (int j : b)
      for (int i : b) entries.emplace_back(i, j, 0.0);
  }
  Minv_.resize(n, n);
  Minv_.setFromTriplets(entries.begin(), entries.end());
  Minv_.makeCompressed();
  M_outer_.assign(M.outerIndexPtr(), M.outerIndexPtr() + M.cols() + 1);
  M_inner_.assign(M.innerIndexPtr(), M.innerIndexPtr() + M.nonZeros());
  ++analyses_M_;
  plan_valid_ = false;
}

bool SparseCompatibility::invert_blocks(double& dmin, double& dmax) {
  const Sparse& M = *Mp_;
  double* minv = Minv_.valuePtr();
  const int* outer = Minv_.outerIndexPtr();
  for (const auto& b : blocks_) {
    const int k = static_cast<int>(b.size());
    chol_.assign(static_cast<std::size_t>(2 * k * k), 0.0);
    double* a = chol_.data();          // the block, then its factor L (lower, row-major a[i*k+j])
    double* li = chol_.data() + k * k;  // L⁻¹ (lower)
    for (int j = 0; j < k; ++j)  // the lower triangle's entries of the block's columns
      for (Sparse::InnerIterator it(M, b[j]); it; ++it) a[local_[it.row()] * k + j] = it.value();
    for (int j = 0; j < k; ++j) {  // Cholesky, column by column
      double d = a[j * k + j];
      for (int p = 0; p < j; ++p) d -= a[j * k + p] * a[j * k + p];
      if (!(d > 0.0)) return false;
      dmin = std::min(dmin, d);
      dmax = std::max(dmax, d);
      const double ljj = std::sqrt(d);
      a[j * k + j] = ljj;
      for (int i = j + 1; i < k; ++i) {
        double v = a[i * k + j];
        for (int p = 0; p < j; ++p) v -= a[i * k + p] * a[j * k + p];
        a[i * k + j] = v / ljj;
      }
    }
    for (int j = 0; j < k; ++j) {  // L⁻¹ by forward substitution, column j
      li[j * k + j] = 1.0 / a[j * k + j];
      for (int i = j + 1; i < k; ++i) {
        double v = 0.0;
        for (int p = j; p < i; ++p) v -= a[i * k + p] * li[p * k + j];
        li[i * k + j] = v / a[i * k + i];
      }
    }
    for (int j = 0; j < k; ++j) {  // M⁻¹ = L⁻ᵀ L⁻¹, into rows b[0..k) of column b[j]
      double* col = minv + outer[b[j]];
      for (int i = 0; i < k; ++i) {
        double v = 0.0;
        for (int p = std::max(i, j); p < k; ++p) v += li[p * k + i] * li[p * k + j];
        col[i] = v;
      }
    }
  }
  return true;
}

void SparseCompatibility::plan_products(const Sparse& g) {
  const int s = static_cast<int>(g.rows()), n = static_cast<int>(g.cols());
  g_outer_.assign(g.outerIndexPtr(), g.outerIndexPtr() + n + 1);
  g_inner_.assign(g.innerIndexPtr(), g.innerIndexPtr() + g.nonZeros());
  // g by rows: for row i, its (column, value index) pairs, columns ascending.
  std::vector<int> row_start(static_cast<std::size_t>(s) + 1, 0);
  for (int p = 0; p < g.nonZeros(); ++p) ++row_start[g_inner_[p] + 1];
  for (int i = 0; i < s; ++i) row_start[i + 1] += row_start[i];
  std::vector<int> row_col(static_cast<std::size_t>(g.nonZeros())), row_val(row_col.size());
  {
    std::vector<int> fill(row_start.begin(), row_start.end() - 1);
    for (int c = 0; c < n; ++c)
      for (int p = g_outer_[c]; p < g_outer_[c + 1]; ++p) {
        const int r = g_inner_[p];
        row_col[fill[r]] = c;
        row_val[fill[r]++] = p;
      }
  }
  auto find = [](const Sparse& A, int row, int col) {  // value index of A(row, col), or -1
    const int* begin = A.innerIndexPtr() + A.outerIndexPtr()[col];
    const int* end = A.innerIndexPtr() + A.outerIndexPtr()[col + 1];
    const int* it = std::lower_bound(begin, end, row);
    return it != end && *it == row ? static_cast<int>(it - A.innerIndexPtr()) : -1;
  };
  // W = g M⁻¹: W(i, c) = Σ_k g(i, k) M⁻¹(k, c), k over c's block (M⁻¹'s column c).
  W_ = Sparse(g * Minv_);  // the pattern (structural: Minv_'s entries are stored in full blocks)
  W_.makeCompressed();
  w_plan_.clear();
  for (int c = 0; c < n; ++c)
    for (int p = W_.outerIndexPtr()[c]; p < W_.outerIndexPtr()[c + 1]; ++p) {
      const int i = W_.innerIndexPtr()[p];
      for (int m = Minv_.outerIndexPtr()[c]; m < Minv_.outerIndexPtr()[c + 1]; ++m) {
        const int gk = find(g, i, Minv_.innerIndexPtr()[m]);
        if (gk >= 0) w_plan_.insert(w_plan_.end(), {p, gk, m});
      }
    }
  // S = W gᵀ, lower triangle: S(i, j) = Σ_c W(i, c) g(j, c), c over row j of g.
  Sparse full = Sparse(W_ * Sparse(g.transpose()));
  std::vector<Eigen::Triplet<double, int>> lower;
  for (int j = 0; j < full.outerSize(); ++j)
    for (Sparse::InnerIterator it(full, j); it; ++it)
      if (it.row() >= j) lower.emplace_back(static_cast<int>(it.row()), j, 0.0);
  S_.resize(s, s);
  S_.setFromTriplets(lower.begin(), lower.end());
  S_.makeCompressed();
  s_plan_.clear();
  for (int j = 0; j < s; ++j)
    for (int p = S_.outerIndexPtr()[j]; p < S_.outerIndexPtr()[j + 1]; ++p) {
      const int i = S_.innerIndexPtr()[p];
      for (int q = row_start[j]; q < row_start[j + 1]; ++q) {
        const int w = find(W_, i, row_col[q]);
        if (w >= 0) s_plan_.insert(s_plan_.end(), {p, w, row_val[q]});
      }
    }
  ldlt_S_.analyzePattern(S_);
  ++analyses_S_;
  plan_valid_ = true;
}

SparseCompatibility::Outcome SparseCompatibility::solve(
    const Eigen::MatrixXd& M, const Eigen::MatrixXd& g, const Eigen::VectorXd& f,
    const Eigen::VectorXd& gamma, double kSwitch, Eigen::VectorXd& G0, Eigen::VectorXd& lambda,
    Eigen::VectorXd& R, Eigen::VectorXd& qdd) {
  if (gather(M, true, mask_M_, M_)) analyse_mass(M_);
  if (g.rows() > 0) gather(g, false, mask_g_, g_);
  else g_.resize(0, M.cols());
  Mp_ = &M_;
  return solve_filled(g_, f, gamma, kSwitch, G0, lambda, R, qdd);
}

SparseCompatibility::Outcome SparseCompatibility::solve(
    const SparseMatrixD& M_lower, const SparseMatrixD& g, const Eigen::VectorXd& f,
    const Eigen::VectorXd& gamma, double kSwitch, Eigen::VectorXd& G0, Eigen::VectorXd& lambda,
    Eigen::VectorXd& R, Eigen::VectorXd& qdd) {
  const int c = static_cast<int>(M_lower.cols());
  const bool same = static_cast<int>(M_outer_.size()) == c + 1 &&
                    static_cast<int>(M_inner_.size()) == M_lower.nonZeros() &&
                    std::equal(M_outer_.begin(), M_outer_.end(), M_lower.outerIndexPtr()) &&
                    std::equal(M_inner_.begin(), M_inner_.end(), M_lower.innerIndexPtr());
  if (!same) analyse_mass(M_lower);
  Mp_ = &M_lower;
  return solve_filled(g, f, gamma, kSwitch, G0, lambda, R, qdd);
}

SparseCompatibility::Outcome SparseCompatibility::solve_filled(
    const Sparse& gs, const Eigen::VectorXd& f, const Eigen::VectorXd& gamma, double kSwitch,
    Eigen::VectorXd& G0, Eigen::VectorXd& lambda, Eigen::VectorXd& R, Eigen::VectorXd& qdd) {
  min_pivot_ratio_ = 1.0;
  if (largest_block_ > kMaxBlock) return Outcome::not_sparse;
  // M⁻¹ block by block. M must be positive definite with a pivot ratio above 1e-13, the dense
  // kernel's criterion on the squared diagonal of its Cholesky factor (here of the blocks').
  double dmin = INFINITY, dmax = 0.0;
  if (!invert_blocks(dmin, dmax)) return Outcome::singular_mass;
  if (!(dmin > 1e-13 * dmax)) return Outcome::singular_mass;
  a0_.noalias() = Minv_ * f;
  if (gs.rows() == 0) {
    R.setZero();
    qdd = a0_;
    return Outcome::solved;
  }
  G0 = gamma;
  G0.noalias() += gs * a0_;
  // S = g M⁻¹ gᵀ (lower triangle) by the products' plan (g M⁻¹ has g's pattern widened to whole
  // blocks); the plan and S's symbolic analysis are redone only when g's pattern changes.
  const int s = static_cast<int>(gs.rows());
  const bool same = plan_valid_ && static_cast<int>(g_outer_.size()) == gs.cols() + 1 &&
                    static_cast<int>(g_inner_.size()) == gs.nonZeros() &&
                    S_.rows() == s &&
                    std::equal(g_outer_.begin(), g_outer_.end(), gs.outerIndexPtr()) &&
                    std::equal(g_inner_.begin(), g_inner_.end(), gs.innerIndexPtr());
  if (!same) plan_products(gs);
  {
    const double* gv = gs.valuePtr();
    const double* mv = Minv_.valuePtr();
    double* wv = W_.valuePtr();
    std::fill(wv, wv + W_.nonZeros(), 0.0);
    for (std::size_t k = 0; k < w_plan_.size(); k += 3)
      wv[w_plan_[k]] += gv[w_plan_[k + 1]] * mv[w_plan_[k + 2]];
    double* sv = S_.valuePtr();
    std::fill(sv, sv + S_.nonZeros(), 0.0);
    for (std::size_t k = 0; k < s_plan_.size(); k += 3)
      sv[s_plan_[k]] += wv[s_plan_[k + 1]] * gv[s_plan_[k + 2]];
  }
  ldlt_S_.factorize(S_);
  if (ldlt_S_.info() != Eigen::Success) return Outcome::dependent_rows;
  // The hand-over test of the dense kernel, pivot by pivot in the factor's order: D_jj is the
  // squared distance (M⁻¹ metric) of row j from the span of the rows factored before it.
  {
    sdiag_ = ldlt_S_.permutationP() * Eigen::VectorXd(S_.diagonal());
    const Eigen::VectorXd& d = ldlt_S_.vectorD();
    const double dSmax = d.maxCoeff();
    for (int j = 0; j < s; ++j) {
      min_pivot_ratio_ = std::min(min_pivot_ratio_, d[j] / sdiag_[j]);
      if (!(d[j] > 1e-13 * dSmax) || d[j] < kSwitch * sdiag_[j]) return Outcome::dependent_rows;
    }
  }
  lambda = ldlt_S_.solve(-G0);
  R.noalias() = gs.transpose() * lambda;
  qdd = a0_;
  qdd.noalias() += Minv_ * R;
  return Outcome::solved;
}

namespace {
// True if the pattern of A equals the one stored (and stores A's if not).
bool same_pattern(const Eigen::SparseMatrix<double, Eigen::ColMajor, int>& A,
                  std::vector<int>& outer, std::vector<int>& inner) {
  const int c = static_cast<int>(A.cols());
  const bool same = static_cast<int>(outer.size()) == c + 1 &&
                    static_cast<int>(inner.size()) == A.nonZeros() &&
                    std::equal(outer.begin(), outer.end(), A.outerIndexPtr()) &&
                    std::equal(inner.begin(), inner.end(), A.innerIndexPtr());
  if (!same) {
    outer.assign(A.outerIndexPtr(), A.outerIndexPtr() + c + 1);
    inner.assign(A.innerIndexPtr(), A.innerIndexPtr() + A.nonZeros());
  }
  return same;
}
}  // namespace

bool SparseMinNorm::solve(const Eigen::MatrixXd& g, const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  if (g.rows() == 0) {
    x = Eigen::VectorXd::Zero(g.cols());
    return true;
  }
  SparseCompatibility::gather(g, false, mask_, g_);
  return solve(g_, b, x);
}

bool SparseMinNorm::solve(const SparseMatrixD& gs, const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  if (gs.rows() == 0) {
    x = Eigen::VectorXd::Zero(gs.cols());
    return true;
  }
  A_ = gs * Sparse(gs.transpose());
  A_.makeCompressed();
  if (!same_pattern(A_, outer_, inner_)) ldlt_.analyzePattern(A_);
  ldlt_.factorize(A_);
  if (ldlt_.info() != Eigen::Success) return false;
  diag_ = ldlt_.permutationP() * Eigen::VectorXd(A_.diagonal());
  const Eigen::VectorXd& d = ldlt_.vectorD();
  for (Eigen::Index j = 0; j < d.size(); ++j)
    if (!(d[j] > kDependent * diag_[j])) return false;
  const Eigen::VectorXd y = ldlt_.solve(b);
  x.noalias() = gs.transpose() * y;
  return true;
}

}  // namespace pcsim::mech

// ---- the model's sparse values ------------------------------------------------------------------

namespace pcsim::mech {

namespace {
// A compressed matrix with the given (row, col) entries (values zero) and, per entry in the
// given order, its place among the matrix's values.
void build_pattern(int rows, int cols, const std::vector<std::pair<int, int>>& entries,
                   SparseMatrixD& A, std::vector<int>& place) {
  std::vector<Eigen::Triplet<double, int>> t;
  t.reserve(entries.size());
  for (const auto& [i, j] : entries) t.emplace_back(i, j, 0.0);
  A.resize(rows, cols);
  A.setFromTriplets(t.begin(), t.end());
  A.makeCompressed();
  place.resize(entries.size());
  for (std::size_t k = 0; k < entries.size(); ++k) {
    const auto [i, j] = entries[k];
    const int* begin = A.innerIndexPtr() + A.outerIndexPtr()[j];
    const int* end = A.innerIndexPtr() + A.outerIndexPtr()[j + 1];
    place[k] = static_cast<int>(std::lower_bound(begin, end, i) - A.innerIndexPtr());
  }
}
bool finite(const SparseMatrixD& A) {
  const double* v = A.valuePtr();
  for (Eigen::Index k = 0; k < A.nonZeros(); ++k)
    if (!std::isfinite(v[k])) return false;
  return true;
}
}  // namespace

void SparseMass::evaluate(const Model& model, double t, const Eigen::VectorXd& q,
                          const Eigen::VectorXd& qd, Eigen::VectorXd& h) {
  const Model::SparsePattern& p = model.sparse_pattern();
  if (model_ != &model || place_.size() != p.mass.size()) {
    std::vector<std::pair<int, int>> lower;
    lower.reserve(p.mass.size());
    for (const auto& [i, j] : p.mass) lower.emplace_back(std::max(i, j), std::min(i, j));
    build_pattern(model.n(), model.n(), lower, L_, place_);
    values_.resize(p.mass.size());
    model_ = &model;
  }
  model.kinetic_terms_sparse(t, q, qd, values_.data(), h);
  double* v = L_.valuePtr();
  for (std::size_t k = 0; k < values_.size(); ++k) v[place_[k]] = values_[k];
}

bool SparseMass::all_finite() const { return finite(L_); }

void SparseMass::to_dense(Eigen::MatrixXd& M) const {
  M.setZero(L_.rows(), L_.cols());
  for (int j = 0; j < L_.outerSize(); ++j)
    for (SparseMatrixD::InnerIterator it(L_, j); it; ++it)
      M(it.row(), j) = M(j, it.row()) = it.value();
}

void SparseRows::evaluate(const Model& model, const std::vector<int>& active, double t,
                          const Eigen::VectorXd& q, const Eigen::VectorXd& qd, Eigen::VectorXd& g0,
                          Eigen::VectorXd& gamma) {
  if (model_ != &model || active != active_) {
    const Model::SparsePattern& p = model.sparse_pattern();
    std::vector<std::pair<int, int>> entries;
    for (std::size_t r = 0; r < active.size(); ++r)
      for (int k : p.rows[static_cast<std::size_t>(active[r])]) entries.emplace_back(static_cast<int>(r), k);
    build_pattern(static_cast<int>(active.size()), model.n(), entries, g_, place_);
    values_.resize(entries.size());
    model_ = &model;
    active_ = active;
  }
  if (active.empty()) return;
  model.constraint_rows_sparse(active, t, q, qd, values_.data(), g0, gamma);
  double* v = g_.valuePtr();
  for (std::size_t k = 0; k < values_.size(); ++k) v[place_[k]] = values_[k];
}

bool SparseRows::all_finite() const { return finite(g_); }

void SparseRows::to_dense(Eigen::MatrixXd& g) const {
  g.setZero(g_.rows(), g_.cols());
  for (int j = 0; j < g_.outerSize(); ++j)
    for (SparseMatrixD::InnerIterator it(g_, j); it; ++it) g(it.row(), j) = it.value();
}

}  // namespace pcsim::mech
