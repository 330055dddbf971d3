// Internal: a model file as read from TOML, before any expression is parsed (texts, names,
// where each came from). What the symbolic derivation (symbolic.hpp) starts from.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "common/error.hpp"
#include "modelfile/draw.hpp"
#include "modelfile/model_file.hpp"

namespace pcsim::modelfile::detail {

/// An expression as written, and where: messages read "<where>: key '<key>': ...".
struct ExprText {
  std::string where;  ///< the file (or another origin, e.g. "command line")
  std::string key;    ///< the dotted key, e.g. "model.energy.kinetic"
  std::string text;   ///< the expression ("" = absent)
};

/// Throws the project's one-line input error: "<where>: key '<key>': <what>".
[[noreturn]] inline void fail(const std::string& where, const std::string& key,
                              const std::string& what) {
  throw InputError(where + ": key '" + key + "': " + what);
}

struct SourceConstraint {
  ConstraintSpec spec;
  std::string key;  ///< "model.constraint[NAME]"
  ExprText holonomic;                                   ///< holonomic: Φ
  std::vector<std::pair<int, ExprText>> velocity;       ///< velocity form: coordinate -> g_ik
  ExprText velocity0;                                   ///< velocity form: g0 ("" = 0)
  ExprText restitution, mu_static, mu_kinetic;          ///< contact attributes ("" = absent)
  int friction_of = -1;                                 ///< index of the unilateral constraint
};

struct ModelSource {
  std::string where;   ///< the file, for messages ("<model>" if none)
  std::filesystem::path file;
  std::string prefix;  ///< "model"
  std::string name;
  std::vector<std::string> coordinates;
  std::vector<ParameterSpec> parameters;
  std::vector<std::pair<std::string, ExprText>> definitions;  ///< in file order
  ExprText kinetic, potential, dissipation;
  std::vector<std::pair<int, ExprText>> forces;  ///< coordinate index -> extra Q
  std::vector<SourceConstraint> constraints;
  std::vector<std::pair<std::string, ExprText>> outputs;  ///< in file order
  std::optional<ExprText> period;
  /// [model] velocity_terms: h (the velocity terms of the equations of motion) as derived from
  /// T as written ("as_written", false: the default of an energy-form file) or expanded in the
  /// velocities with like terms combined ("expanded", true: the default with bodies and joints).
  bool expand_velocity_terms = false;
  std::vector<std::string> slow;
  std::vector<EulerBody> euler_bodies;  ///< body form: spatial bodies with Euler parameters
  DrawSpec draw;  ///< [model.draw] (issue 26); empty when the file has none
};

/// Reads a [model] table (names checked, nothing parsed yet). Throws InputError.
ModelSource read_model_source(const toml::table& model, const std::filesystem::path& source,
                              const std::string& prefix);
/// Reads [model.draw] into src.draw (after the rest of the table: it names coordinates,
/// parameters, definitions, outputs and constraints). Throws InputError.
void read_draw_table(const toml::node& node, ModelSource& src);
/// Reads a model file's [model] table. Throws InputError.
ModelSource load_model_source(const std::filesystem::path& file);
/// The same from the file's text (`file` names it in messages).
ModelSource parse_model_source_text(const std::string& text, const std::filesystem::path& file);

}  // namespace pcsim::modelfile::detail
