// A mech::Model evaluated from a compiled model file: the tape (tape.hpp) with the constant
// region filled for one parameter set. Values and forward-mode tangents (directional
// derivatives with respect to q, q̇, t) of M, h, Q and the constraint rows, without GiNaC,
// without heap allocation per call (each thread keeps one scratch array).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "common/eigen_instances.hpp"

#include "mech/model.hpp"
#include "modelfile/tape.hpp"

namespace pcsim::modelfile {

/// The tape of a model file and what its blocks mean. Built once per ModelDescription.
struct CompiledModel {
  std::string name;
  std::vector<std::string> coordinates;
  std::vector<mech::ConstraintInfo> constraints;  ///< in model order (constant_row derived)
  std::vector<std::string> output_names;
  Tape tape;

  /// kinetic: results = M's upper triangle (row by row, j >= i), then h (n).
  /// forces: Q (n). outputs: one per output name.
  int kinetic_block = -1, forces_block = -1, outputs_block = -1;
  struct ConstraintBlocks {
    int rows = -1;      ///< results: g row (n), g0, gamma
    int position = -1;  ///< results: Φ (holonomic only; -1 for velocity form)
    int hidden = -1;    ///< the hidden constant Φ(q0, t0) of a from_initial constraint, or -1
    /// Constant-region slots of the contact attributes (restitution, μ_s, μ_k), or -1.
    std::int64_t contact_slots[3] = {-1, -1, -1};
  };
  std::vector<ConstraintBlocks> constraint_blocks;
  std::int64_t period_slot = -1;  ///< constant-region slot of the period, or -1

  /// Non-zero entries of results, precomputed from the blocks (slot == tape.zero_slot skipped).
  struct Entry {
    int i, j;
    std::uint32_t slot;
  };
  std::vector<Entry> mass_entries;                ///< (i, j) with i <= j
  std::vector<std::vector<Entry>> row_entries;    ///< per constraint: (0, k) of g's row
  void index_entries();                           ///< fills the two lists from the blocks

  /// The blocks compiled to native code at build time (built-in models only; empty: the tape
  /// is interpreted). One per tape block, in order.
  std::vector<NativeBlock> native;
  /// Runs block `index` on the slots v: natively when the model has native code, else from
  /// the tape. The same operations either way.
  void run_block(int index, double* v) const {
    if (!native.empty()) native[static_cast<std::size_t>(index)](v);
    else run(tape.blocks[static_cast<std::size_t>(index)].code, v);
  }
};

/// One instantiation: the compiled model with its constant region (literals, parameters,
/// hidden constants, prelude results). Thread-safe (const, per-thread scratch).
class ExpressionModel final : public mech::Model {
 public:
  /// constants: the constant region, tape.n_constant values (see ModelDescription::instantiate).
  ExpressionModel(std::shared_ptr<const CompiledModel> compiled, std::vector<double> constants);

  void kinetic_terms(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                     Eigen::MatrixXd& M, Eigen::VectorXd& h) const override;
  void forces(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
              Eigen::VectorXd& Q) const override;
  void constraint_rows(const std::vector<int>& active, double t, const Eigen::VectorXd& q,
                       const Eigen::VectorXd& qd, Eigen::MatrixXd& g, Eigen::VectorXd& g0,
                       Eigen::VectorXd& gamma) const override;
  double position_residual(int i, double t, const Eigen::VectorXd& q) const override;
  void position_residuals(const std::vector<int>& rows, double t, const Eigen::VectorXd& q,
                          double* out) const override;
  void derived(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
               const Eigen::VectorXd& qdd, const Eigen::VectorXd& R,
               Eigen::VectorXd& out) const override;
  void derived_with_multipliers(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                const Eigen::VectorXd& qdd, const Eigen::VectorXd& R,
                                const std::vector<int>& imposed, const Eigen::VectorXd& lambda,
                                Eigen::VectorXd& out) const override;

  // ---- sparse structure: the tape's entries (CompiledModel::mass_entries, row_entries) ------
  bool has_sparse_structure() const override { return true; }
  const SparsePattern& sparse_pattern() const override { return pattern_; }
  void kinetic_terms_sparse(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                            double* mass_values, Eigen::VectorXd& h) const override;
  void constraint_rows_sparse(const std::vector<int>& active, double t, const Eigen::VectorXd& q,
                              const Eigen::VectorXd& qd, double* row_values, Eigen::VectorXd& g0,
                              Eigen::VectorXd& gamma) const override;

  // ---- forward mode: k directions at once ---------------------------------------------------
  // V is (2n + 1) x k: each column a direction (δq, δq̇, δt). The outputs are the values (as
  // above) and their directional derivatives, e.g. dM[j] = Σ_l (∂M/∂q_l δq_l + ∂M/∂q̇_l δq̇_l)
  // + ∂M/∂t δt for column j. Output containers are resized if needed (allocation only then).

  bool has_tangents() const override { return true; }
  void kinetic_terms_tangent(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                             const Eigen::MatrixXd& V, Eigen::MatrixXd& M, Eigen::VectorXd& h,
                             std::vector<Eigen::MatrixXd>& dM, Eigen::MatrixXd& dh) const override;
  void forces_tangent(double t, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                      const Eigen::MatrixXd& V, Eigen::VectorXd& Q,
                      Eigen::MatrixXd& dQ) const override;
  /// dg[j] is s x n, dg0 and dgamma are s x k.
  void constraint_rows_tangent(const std::vector<int>& active, double t, const Eigen::VectorXd& q,
                               const Eigen::VectorXd& qd, const Eigen::MatrixXd& V,
                               Eigen::MatrixXd& g, Eigen::VectorXd& g0, Eigen::VectorXd& gamma,
                               std::vector<Eigen::MatrixXd>& dg, Eigen::MatrixXd& dg0,
                               Eigen::MatrixXd& dgamma) const override;

  const CompiledModel& compiled() const { return *compiled_; }
  /// The constant region (parameters, hidden constants, prelude results).
  const std::vector<double>& constants() const { return constants_; }

 private:
  double* values(double t, const Eigen::VectorXd& q, const Eigen::VectorXd* qd) const;
  double* tangents(const Eigen::MatrixXd& V, int k) const;

  std::shared_ptr<const CompiledModel> compiled_;
  std::vector<double> constants_;
  SparsePattern pattern_;  ///< from the compiled model's entries
  std::uint64_t id_;  ///< unique per instance: marks whose constants a thread's scratch holds
};

}  // namespace pcsim::modelfile
