// The tape-evaluated mech::Model (see expression_model.hpp).
#include "modelfile/expression_model.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

namespace pcsim::modelfile {

void CompiledModel::index_entries() {
  const int n = static_cast<int>(coordinates.size());
  mass_entries.clear();
  const Block& kin = tape.blocks[kinetic_block];
  int r = 0;
  for (int i = 0; i < n; ++i) {
    for (int j = i; j < n; ++j, ++r) {
      if (kin.results[r] != tape.zero_slot) mass_entries.push_back({i, j, kin.results[r]});
    }
  }
  row_entries.assign(constraint_blocks.size(), {});
  for (std::size_t c = 0; c < constraint_blocks.size(); ++c) {
    const Block& b = tape.blocks[constraint_blocks[c].rows];
    for (int k = 0; k < n; ++k) {
      if (b.results[k] != tape.zero_slot) row_entries[c].push_back({0, k, b.results[k]});
    }
  }
}

namespace {

// One scratch array per thread, shared by every ExpressionModel: it holds the constant
// region of the model that used it last (owner), so consecutive calls on one model copy
// nothing; tangents likewise, for one k.
struct Scratch {
  std::uint64_t owner = 0;
  std::vector<double> v;
  std::uint64_t tangent_owner = 0;
  int tangent_k = 0;
  std::vector<double> d;
};

Scratch& scratch() {
  static thread_local Scratch s;
  return s;
}

std::uint64_t next_id() {
  static std::atomic<std::uint64_t> counter{0};
  return ++counter;
}

}  // namespace

ExpressionModel::ExpressionModel(std::shared_ptr<const CompiledModel> compiled,
                                 std::vector<double> constants)
    : compiled_(std::move(compiled)), constants_(std::move(constants)), id_(next_id()) {
  name_ = compiled_->name;
  coordinates_ = compiled_->coordinates;
  constraints_ = compiled_->constraints;
  derived_names_ = compiled_->output_names;
  // Contact attributes for these parameter values (prelude results; 0 when absent, μ_k = μ_s
  // when only μ_s is given). ModelDescription::instantiate checks their ranges.
  for (std::size_t i = 0; i < constraints_.size(); ++i) {
    const auto& slots = compiled_->constraint_blocks[i].contact_slots;
    auto value = [&](int k) {
      return slots[k] >= 0 ? constants_[static_cast<std::size_t>(slots[k])] : 0.0;
    };
    mech::ContactInfo& c = constraints_[i].contact;
    c.restitution = value(0);
    c.mu_static = value(1);
    c.mu_kinetic = slots[2] >= 0 ? value(2) : c.mu_static;
  }
  // The sparse pattern: the results of the tape that are not the literal zero (structural).
  pattern_.mass.reserve(compiled_->mass_entries.size());
  for (const auto& e : compiled_->mass_entries) pattern_.mass.emplace_back(e.i, e.j);
  pattern_.rows.resize(compiled_->row_entries.size());
  for (std::size_t c = 0; c < compiled_->row_entries.size(); ++c)
    for (const auto& e : compiled_->row_entries[c]) pattern_.rows[c].push_back(e.j);
}

double* ExpressionModel::values(double t, const Eigen::VectorXd& q,
                                const Eigen::VectorXd* qd) const {
  const Tape& tape = compiled_->tape;
  Scratch& s = scratch();
  if (s.owner != id_) {
    if (s.v.size() < tape.n_slots) s.v.resize(tape.n_slots);
    std::copy(constants_.begin(), constants_.end(), s.v.begin());
    s.owner = id_;
  }
  double* v = s.v.data();
  const int n = tape.n;
  v[tape.t_slot] = t;
  for (int i = 0; i < n; ++i) v[tape.q_slot + i] = q[i];
  if (qd) {
    for (int i = 0; i < n; ++i) v[tape.qd_slot + i] = (*qd)[i];
  }
  return v;
}

double* ExpressionModel::tangents(const Eigen::MatrixXd& V, int k) const {
  const Tape& tape = compiled_->tape;
  const int n = tape.n;
  Scratch& s = scratch();
  if (s.tangent_owner != id_ || s.tangent_k != k) {
    const std::size_t size = static_cast<std::size_t>(tape.n_slots) * k;
    if (s.d.size() < size) s.d.resize(size);
    std::fill(s.d.begin(), s.d.begin() + size, 0.0);  // constant region and qdd, R: zero
    s.tangent_owner = id_;
    s.tangent_k = k;
  }
  double* d = s.d.data();
  for (int j = 0; j < k; ++j) {
    for (int i = 0; i < n; ++i) {
      d[(tape.q_slot + i) * static_cast<std::size_t>(k) + j] = V(i, j);
      d[(tape.qd_slot + i) * static_cast<std::size_t>(k) + j] = V(n + i, j);
    }
    d[tape.t_slot * static_cast<std::size_t>(k) + j] = V(2 * n, j);
  }
  return d;
}

void ExpressionModel::kinetic_terms(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                    Eigen::MatrixXd& M, Eigen::VectorXd& h) const {
  const CompiledModel& c = *compiled_;
  const Block& b = c.tape.blocks[c.kinetic_block];
  double* v = values(t, q, &qd);
  c.run_block(c.kinetic_block, v);
  M.setZero();
  for (const auto& e : c.mass_entries) M(e.i, e.j) = M(e.j, e.i) = v[e.slot];
  const int n = c.tape.n;
  const std::uint32_t* hr = b.results.data() + n * (n + 1) / 2;
  for (int i = 0; i < n; ++i) h[i] = v[hr[i]];
}

void ExpressionModel::forces(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                             Eigen::VectorXd& Q) const {
  const CompiledModel& c = *compiled_;
  const Block& b = c.tape.blocks[c.forces_block];
  double* v = values(t, q, &qd);
  c.run_block(c.forces_block, v);
  for (int i = 0; i < c.tape.n; ++i) Q[i] = v[b.results[i]];
}

void ExpressionModel::constraint_rows(const std::vector<int>& active, double t,
                                      const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                      Eigen::MatrixXd& g, Eigen::VectorXd& g0,
                                      Eigen::VectorXd& gamma) const {
  const CompiledModel& c = *compiled_;
  const int n = c.tape.n;
  g.setZero();
  if (active.empty()) return;
  double* v = values(t, q, &qd);
  for (std::size_t r = 0; r < active.size(); ++r) {
    const int i = active[r];
    const Block& b = c.tape.blocks[c.constraint_blocks[i].rows];
    c.run_block(c.constraint_blocks[i].rows, v);
    for (const auto& e : c.row_entries[i]) g(static_cast<int>(r), e.j) = v[e.slot];
    g0[static_cast<int>(r)] = v[b.results[n]];
    gamma[static_cast<int>(r)] = v[b.results[n + 1]];
  }
}

void ExpressionModel::kinetic_terms_sparse(double t, const Eigen::VectorXd& q,
                                           const Eigen::VectorXd& qd, double* mass_values,
                                           Eigen::VectorXd& h) const {
  const CompiledModel& c = *compiled_;
  const Block& b = c.tape.blocks[c.kinetic_block];
  double* v = values(t, q, &qd);
  c.run_block(c.kinetic_block, v);
  for (std::size_t k = 0; k < c.mass_entries.size(); ++k) mass_values[k] = v[c.mass_entries[k].slot];
  const int n = c.tape.n;
  const std::uint32_t* hr = b.results.data() + n * (n + 1) / 2;
  for (int i = 0; i < n; ++i) h[i] = v[hr[i]];
}

void ExpressionModel::constraint_rows_sparse(const std::vector<int>& active, double t,
                                             const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                             double* row_values, Eigen::VectorXd& g0,
                                             Eigen::VectorXd& gamma) const {
  const CompiledModel& c = *compiled_;
  const int n = c.tape.n;
  if (active.empty()) return;
  double* v = values(t, q, &qd);
  for (std::size_t r = 0; r < active.size(); ++r) {
    const int i = active[r];
    const Block& b = c.tape.blocks[c.constraint_blocks[i].rows];
    c.run_block(c.constraint_blocks[i].rows, v);
    for (const auto& e : c.row_entries[i]) *row_values++ = v[e.slot];
    g0[static_cast<int>(r)] = v[b.results[n]];
    gamma[static_cast<int>(r)] = v[b.results[n + 1]];
  }
}

double ExpressionModel::position_residual(int i, double t, const Eigen::VectorXd& q) const {
  const CompiledModel& c = *compiled_;
  if (i < 0 || i >= static_cast<int>(c.constraint_blocks.size()) ||
      c.constraint_blocks[i].position < 0) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  const Block& b = c.tape.blocks[c.constraint_blocks[i].position];
  double* v = values(t, q, nullptr);
  c.run_block(c.constraint_blocks[i].position, v);
  return v[b.results[0]];
}

void ExpressionModel::position_residuals(const std::vector<int>& rows, double t,
                                         const Eigen::VectorXd& q, double* out) const {
  const CompiledModel& c = *compiled_;
  if (rows.empty()) return;
  double* v = values(t, q, nullptr);
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const int i = rows[k];
    if (i < 0 || i >= static_cast<int>(c.constraint_blocks.size()) ||
        c.constraint_blocks[i].position < 0) {
      out[k] = std::numeric_limits<double>::quiet_NaN();
      continue;
    }
    c.run_block(c.constraint_blocks[i].position, v);
    out[k] = v[c.tape.blocks[c.constraint_blocks[i].position].results[0]];
  }
}

void ExpressionModel::derived(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                              const Eigen::VectorXd& qdd, const Eigen::VectorXd& R,
                              Eigen::VectorXd& out) const {
  static const std::vector<int> none;
  derived_with_multipliers(t, q, qd, qdd, R, none, Eigen::VectorXd(), out);
}

void ExpressionModel::derived_with_multipliers(double t, const Eigen::VectorXd& q,
                                               const Eigen::VectorXd& qd,
                                               const Eigen::VectorXd& qdd,
                                               const Eigen::VectorXd& R,
                                               const std::vector<int>& imposed,
                                               const Eigen::VectorXd& lambda,
                                               Eigen::VectorXd& out) const {
  const CompiledModel& c = *compiled_;
  const Block& b = c.tape.blocks[c.outputs_block];
  if (out.size() != static_cast<Eigen::Index>(b.results.size())) out.resize(b.results.size());
  if (b.results.empty()) return;
  double* v = values(t, q, &qd);
  const Tape& tape = c.tape;
  for (int i = 0; i < tape.n; ++i) {
    v[tape.qdd_slot + i] = qdd.size() == tape.n ? qdd[i] : std::numeric_limits<double>::quiet_NaN();
    v[tape.R_slot + i] = R.size() == tape.n ? R[i] : std::numeric_limits<double>::quiet_NaN();
  }
  if (tape.n_lambda > 0) {
    for (std::uint32_t i = 0; i < tape.n_lambda; ++i)
      v[tape.lambda_slot + i] = std::numeric_limits<double>::quiet_NaN();
    const std::size_t k_max = std::min<std::size_t>(imposed.size(), static_cast<std::size_t>(lambda.size()));
    for (std::size_t k = 0; k < k_max; ++k)
      if (imposed[k] >= 0 && static_cast<std::uint32_t>(imposed[k]) < tape.n_lambda)
        v[tape.lambda_slot + static_cast<std::uint32_t>(imposed[k])] = lambda[static_cast<Eigen::Index>(k)];
  }
  c.run_block(c.outputs_block, v);
  for (std::size_t k = 0; k < b.results.size(); ++k) out[static_cast<int>(k)] = v[b.results[k]];
}

// ---- forward mode --------------------------------------------------------------------------

void ExpressionModel::kinetic_terms_tangent(double t, const Eigen::VectorXd& q,
                                            const Eigen::VectorXd& qd, const Eigen::MatrixXd& V,
                                            Eigen::MatrixXd& M, Eigen::VectorXd& h,
                                            std::vector<Eigen::MatrixXd>& dM,
                                            Eigen::MatrixXd& dh) const {
  const CompiledModel& c = *compiled_;
  const int n = c.tape.n, k = static_cast<int>(V.cols());
  const Block& b = c.tape.blocks[c.kinetic_block];
  double* v = values(t, q, &qd);
  double* d = tangents(V, k);
  run_tangent(b.code, v, d, k);
  M.resize(n, n);
  h.resize(n);
  M.setZero();
  if (static_cast<int>(dM.size()) != k) dM.resize(k);
  for (auto& m : dM) {
    m.resize(n, n);
    m.setZero();
  }
  dh.resize(n, k);
  for (const auto& e : c.mass_entries) {
    M(e.i, e.j) = M(e.j, e.i) = v[e.slot];
    for (int j = 0; j < k; ++j) dM[j](e.i, e.j) = dM[j](e.j, e.i) = d[e.slot * static_cast<std::size_t>(k) + j];
  }
  const std::uint32_t* hr = b.results.data() + n * (n + 1) / 2;
  for (int i = 0; i < n; ++i) {
    h[i] = v[hr[i]];
    for (int j = 0; j < k; ++j) dh(i, j) = d[hr[i] * static_cast<std::size_t>(k) + j];
  }
}

void ExpressionModel::forces_tangent(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                     const Eigen::MatrixXd& V, Eigen::VectorXd& Q,
                                     Eigen::MatrixXd& dQ) const {
  const CompiledModel& c = *compiled_;
  const int n = c.tape.n, k = static_cast<int>(V.cols());
  const Block& b = c.tape.blocks[c.forces_block];
  double* v = values(t, q, &qd);
  double* d = tangents(V, k);
  run_tangent(b.code, v, d, k);
  Q.resize(n);
  dQ.resize(n, k);
  for (int i = 0; i < n; ++i) {
    Q[i] = v[b.results[i]];
    for (int j = 0; j < k; ++j) dQ(i, j) = d[b.results[i] * static_cast<std::size_t>(k) + j];
  }
}

void ExpressionModel::constraint_rows_tangent(const std::vector<int>& active, double t,
                                              const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                              const Eigen::MatrixXd& V, Eigen::MatrixXd& g,
                                              Eigen::VectorXd& g0, Eigen::VectorXd& gamma,
                                              std::vector<Eigen::MatrixXd>& dg,
                                              Eigen::MatrixXd& dg0, Eigen::MatrixXd& dgamma) const {
  const CompiledModel& c = *compiled_;
  const int n = c.tape.n, k = static_cast<int>(V.cols());
  const int s = static_cast<int>(active.size());
  g.resize(s, n);
  g.setZero();
  g0.resize(s);
  gamma.resize(s);
  if (static_cast<int>(dg.size()) != k) dg.resize(k);
  for (auto& m : dg) {
    m.resize(s, n);
    m.setZero();
  }
  dg0.resize(s, k);
  dgamma.resize(s, k);
  if (s == 0) return;
  double* v = values(t, q, &qd);
  double* d = tangents(V, k);
  auto D = [&](std::uint32_t slot, int j) { return d[slot * static_cast<std::size_t>(k) + j]; };
  for (int r = 0; r < s; ++r) {
    const int i = active[r];
    const Block& b = c.tape.blocks[c.constraint_blocks[i].rows];
    run_tangent(b.code, v, d, k);
    for (const auto& e : c.row_entries[i]) {
      g(r, e.j) = v[e.slot];
      for (int j = 0; j < k; ++j) dg[j](r, e.j) = D(e.slot, j);
    }
    g0[r] = v[b.results[n]];
    gamma[r] = v[b.results[n + 1]];
    for (int j = 0; j < k; ++j) {
      dg0(r, j) = D(b.results[n], j);
      dgamma(r, j) = D(b.results[n + 1], j);
    }
  }
}

}  // namespace pcsim::modelfile
