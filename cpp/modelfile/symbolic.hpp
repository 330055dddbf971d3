// Internal: the symbolic half of a model file. derive() parses every expression of a
// ModelSource with GiNaC and differentiates: M = ∂²T/∂q̇², h, Q, the constraint rows g, g0 and
// γ, the outputs; compile_tape() turns the result into the flat tape of expression_model.hpp
// (common subexpressions shared, parameter-only work hoisted into the prelude).
// Callers hold ginac_mutex() (expression.hpp) around both.
#pragma once

#include <memory>
#include <utility>
#include <optional>
#include <vector>

#include <ginac/ginac.h>

#include "modelfile/expression_model.hpp"
#include "modelfile/model_source.hpp"

namespace pcsim::modelfile::detail {

struct SymbolicModel {
  int n = 0;
  // The symbols (GiNaC realsymbols), by index.
  std::vector<GiNaC::ex> q, qd, qdd, R;  ///< coordinates, x_d, x_dd, R_x
  std::vector<GiNaC::ex> lambda;         ///< lambda_<constraint>, one per constraint (outputs)
  GiNaC::ex t;
  std::vector<GiNaC::ex> parameters;     ///< in ModelSource::parameters order
  std::vector<GiNaC::ex> hidden;         ///< Φ_i(q0, t0) of the from_initial constraints
  /// The definitions ([model.define]) in dependency order: a symbol named after each, and its
  /// value (which refers to earlier definitions by their symbols). The expressions below keep
  /// the definitions as symbols: inlining them would let GiNaC rewrite the user's structure
  /// ((a b)^2 becomes a^2 b^2, so d*d/(d*d+1) chained k times becomes powers 2^k) and walk
  /// shared subexpressions once per use.
  std::vector<std::pair<GiNaC::ex, GiNaC::ex>> definitions;

  GiNaC::ex T, V, F;                     ///< definitions inlined
  std::vector<std::vector<GiNaC::ex>> M; ///< n x n, symmetric
  std::vector<GiNaC::ex> h, Q;           ///< n each
  struct Constraint {
    bool holonomic = true;
    GiNaC::ex phi;                       ///< Φ − hidden (holonomic), 0 otherwise
    std::vector<GiNaC::ex> g;            ///< n
    GiNaC::ex g0, gamma;
    int hidden = -1;                     ///< index into hidden, or -1
    bool constant_row = false;           ///< g free of q and t
    /// Contact attributes (issue 12), expressions of the parameters only; absent: none.
    std::optional<GiNaC::ex> restitution, mu_static, mu_kinetic;
  };
  std::vector<Constraint> constraints;
  std::vector<GiNaC::ex> outputs;
  std::optional<GiNaC::ex> period;
};

/// e with every definition symbol replaced by its value, recursively (GiNaC's tree form, for
/// tests and checks that need the expression in the coordinates alone; it may be large).
GiNaC::ex inline_definitions(const SymbolicModel& model, const GiNaC::ex& e);

/// Parses and differentiates; throws InputError naming the file and key on any bad input.
SymbolicModel derive(const ModelSource& source);

/// The tape of a derived model (blocks: kinetic, forces, outputs, then per constraint its
/// rows and its position residual).
std::shared_ptr<CompiledModel> compile_tape(const SymbolicModel& model, const ModelSource& source);

}  // namespace pcsim::modelfile::detail
