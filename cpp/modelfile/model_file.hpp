// Model files: a mechanical system described in TOML (shared/design/model-files.md, extensions
// in docs/model-files.md) read, checked and derived symbolically once into an immutable
// ModelDescription, which instantiates pcsim::mech::Model objects for given parameter values
// without compiling anything.
#pragma once

#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "common/eigen_instances.hpp"
#include <toml++/toml.h>

#include "mech/model.hpp"
#include "modelfile/tape.hpp"

namespace pcsim::modelfile {

struct CompiledModel;  // the evaluation tape and what goes with it (expression_model.hpp)

/// One parameter of a model file: `name = 1.0` or `name = { value = 1.0, unit = "kg", ... }`.
struct ParameterSpec {
  std::string name;
  double value = 0.0;   ///< the default (SI)
  std::string unit;     ///< "" if not given
  std::string meaning;  ///< "" if not given
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool min_exclusive = false, max_exclusive = false;
  /// True if v lies in [min, max] (with the exclusive ends excluded) and is finite.
  bool admits(double v) const;
  /// What admits() accepts, in words: "a number > 0", "a number in [0, 1]", "a finite number".
  std::string range_text() const;
};

/// One constraint the model offers.
struct ConstraintSpec {
  std::string name;
  mech::ConstraintKind kind = mech::ConstraintKind::holonomic;
  bool active_by_default = true;  ///< `active = false` in the file: offered, but off by default
  /// Holonomic only: the constraint is Φ(q, t) − Φ(q0, t0) = 0 (the constant fixed at the
  /// initial state passed to instantiate()).
  bool from_initial = false;
  std::string holonomic;                                    ///< Φ as written (holonomic)
  std::vector<std::pair<std::string, std::string>> velocity;  ///< coordinate -> coefficient
  std::string velocity0;                                    ///< g0 as written ("" = 0)
  bool added = false;             ///< added by with_constraints (not in the file)
  // Contact attributes (issue 12; docs/model-files.md "Contact"). Expressions are of the
  // parameters only, evaluated by instantiate().
  bool unilateral = false;        ///< `unilateral = true`: gap_sign·Φ >= 0 (holonomic only)
  int gap_sign = 1;               ///< `gap_sign = -1`: the gap is −Φ
  std::string restitution;        ///< Newton's e_n as written ("" = 0)
  std::string friction;           ///< `friction = "NAME"`: attached to unilateral NAME ("" none)
  std::string mu_static;          ///< μ_s as written (required with friction)
  std::string mu_kinetic;         ///< μ_k as written ("" = μ_s)
  bool rough = false;             ///< `rough = true` with friction: no slip while closed (no μ)
};

/// A spatial body placed by Euler parameters (body form, issue 22): a case may give its initial
/// angular velocity (initial.NAME_w1..w3 in body axes or NAME_wx..wz in ground axes) instead of
/// the rates of e0..e3 (docs/bodies-spatial.md).
struct EulerBody {
  std::string name;
  std::vector<std::string> e;  ///< the coordinates e0, e1, e2, e3
  /// Empty: the body's own Euler parameters (its orientation in ground). Else the name of the
  /// spherical tree joint whose coordinates e are (marker2's frame relative to marker1's): no
  /// rotation-vector or angular-velocity keys in the case.
  std::string joint;
};

/// A derived output column: `name = "expression"` in [model.outputs].
struct OutputSpec {
  std::string name;
  std::string expression;
};

/// A holonomic constraint added from the command line (a variant of the model).
struct ExtraConstraint {
  std::string name;
  std::string holonomic;      ///< Φ(q, t), as in a model file
  bool from_initial = false;  ///< Φ(q, t) − Φ(q0, t0) = 0
  /// Where it came from, for messages: "<origin>: key '<key>': ..." (defaults: "command line",
  /// "constraint.<name>").
  std::string origin = "command line";
  std::string key;
};

/// A model file, parsed, validated and derived symbolically (M, h, Q, constraint rows, outputs,
/// all compiled into one flat evaluation tape). Immutable and thread-safe: instantiate(),
/// period() and the accessors may be called from any number of threads at once.
class ModelDescription {
 public:
  const std::string& name() const { return name_; }
  /// The file it was read from ("" for a table built in memory).
  const std::filesystem::path& source() const { return source_; }
  const std::vector<std::string>& coordinates() const { return coordinates_; }
  int n() const { return static_cast<int>(coordinates_.size()); }
  const std::vector<ParameterSpec>& parameters() const { return parameters_; }
  const std::vector<ConstraintSpec>& constraints() const { return constraints_; }
  const std::vector<OutputSpec>& outputs() const { return outputs_; }
  /// The excitation period as written (`[model] period = "2*pi/omega"`), if any.
  const std::optional<std::string>& period_expression() const { return period_expression_; }
  /// Coordinates declared slow (`[model] slow = ["s"]`), in file order.
  const std::vector<std::string>& slow_coordinates() const { return slow_; }
  /// The spatial bodies placed by Euler parameters (body form), in body order.
  const std::vector<EulerBody>& euler_bodies() const { return euler_bodies_; }

  /// The parameter with this name, or nullptr.
  const ParameterSpec* parameter(const std::string& name) const;
  /// Index of the named constraint in constraints(), or -1.
  int constraint_index(const std::string& name) const;
  /// The names of the constraints active by default, in model order.
  std::vector<std::string> default_active_constraints() const;

  /// The excitation period for these parameter values (others take their defaults); NaN if
  /// the model declares none. Throws pcsim::InputError as instantiate() does for bad values.
  double period(const std::map<std::string, double>& parameter_values = {}) const;

  /// A new description with these holonomic constraints added (active by default). Throws
  /// pcsim::InputError naming the origin and key: bad syntax (with the column), unknown names,
  /// a name already used, a constraint that involves no coordinate.
  std::shared_ptr<const ModelDescription> with_constraints(
      const std::vector<ExtraConstraint>& extra) const;

  /// The mechanical model for these parameter values: every parameter is either given or
  /// takes its default; unknown names and values outside a parameter's range throw
  /// pcsim::InputError naming the key (parameters.NAME). q0 and t0 are the initial state
  /// that fixes the constants of from_initial constraints (q0 may be empty when the model has
  /// no such constraint; otherwise it must have n() entries).
  std::shared_ptr<const mech::Model> instantiate(const std::map<std::string, double>& parameters,
                                                 const Eigen::VectorXd& q0 = Eigen::VectorXd(),
                                                 double t0 = 0.0) const;

  /// The compiled tape and its layout (for benchmarks, tests and tools).
  const CompiledModel& compiled() const { return *compiled_; }

  // Internal: built by load_model_file / parse_model_table.
  struct Parts;
  explicit ModelDescription(Parts parts);
  ~ModelDescription();

 private:
  /// Parameter values in parameters() order: defaults overridden by `given`, checked.
  std::vector<double> parameter_values(const std::map<std::string, double>& given) const;

  std::string name_;
  std::filesystem::path source_;
  std::vector<std::string> coordinates_;
  std::vector<ParameterSpec> parameters_;
  std::vector<ConstraintSpec> constraints_;
  std::vector<OutputSpec> outputs_;
  std::optional<std::string> period_expression_;
  std::vector<std::string> slow_;
  std::vector<EulerBody> euler_bodies_;
  std::shared_ptr<const void> source_data_;  // the parsed file (for with_constraints)
  std::shared_ptr<const CompiledModel> compiled_;
};

/// Reads a model file (a TOML file with a [model] table). Throws pcsim::InputError naming the
/// file and the key for unreadable or malformed TOML, unknown keys, wrong types, bad names,
/// expressions that do not parse (with the column), unknown symbols, T not quadratic in the
/// velocities, a constraint that involves no coordinate, and the like.
std::shared_ptr<const ModelDescription> load_model_file(const std::filesystem::path& file);

/// The same from the text of a model file (a built-in model compiled into pcsim, or a file
/// already read); `name` names it in messages.
/// `precompiled`: serialize_compiled() bytes of this text's compiled model (made at build time
/// for the built-in models); when they match the text, the symbolic derivation is skipped.
/// `native`: the blocks of that compiled model as native code (made by the same build); used
/// only with matching `precompiled` bytes and when there is one per block.
std::shared_ptr<const ModelDescription> load_model_text(
    const std::string& text, const std::filesystem::path& name,
    const std::string* precompiled = nullptr, const std::vector<NativeBlock>* native = nullptr);

/// The same for a [model] table already read (e.g. inline in a case file). `source` names the
/// file in messages; `key_prefix` is the dotted key of the table ("model").
std::shared_ptr<const ModelDescription> parse_model_table(const toml::table& model,
                                                          const std::filesystem::path& source,
                                                          const std::string& key_prefix = "model");

}  // namespace pcsim::modelfile
