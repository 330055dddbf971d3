// What a case's `model` names, as the case and run layers see it: coordinates, parameters with
// defaults and ranges, the constraints on offer, the outputs, the excitation period, and how to
// build the engine's Model for one run. Implemented by the built-in models (the C++ model
// registry, the sieve) and by model files; the case layer reads nothing else of a model.
#pragma once

#include <cmath>
#include <filesystem>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "common/eigen_instances.hpp"
#include <toml++/toml.h>

#include "mech/model.hpp"

namespace pcsim::sim {

using ParameterValues = std::map<std::string, double>;

/// One model parameter: its default value and what a case may set it to.
struct ParameterSpec {
  std::string name;
  double value = 0.0;                 ///< the default
  std::string unit;                   ///< e.g. "kg" (may be empty)
  std::string meaning;                ///< for messages, e.g. "desk mass"
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool min_exclusive = false;         ///< value > min (true) or >= min (false)
  bool max_exclusive = false;
};

/// One constraint the model offers; a case switches it on or off by name.
struct ConstraintOffer {
  std::string name;
  mech::ConstraintKind kind = mech::ConstraintKind::holonomic;
  bool active_by_default = true;
  std::string meaning;
  bool unilateral = false;   ///< a unilateral contact (issue 12: switched by contact.switching)
  std::string friction_of;   ///< a friction constraint: the unilateral constraint it acts at
  bool rough = false;        ///< with friction_of: a rough row (held while that contact is closed)
};

/// A holonomic constraint added by a case ([constraints.added] NAME = "expression").
struct AddedConstraint {
  std::string name;
  std::string holonomic;  ///< Φ(q, t), an expression of the coordinates, t and parameters
};

/// A spatial body placed by Euler parameters (a body-form model file): a case may give its
/// initial angular velocity by the keys initial.NAME_w1..w3 (body axes) or NAME_wx..wz (ground
/// axes) instead of the rates of its Euler parameters e (docs/bodies-spatial.md).
struct EulerBody {
  std::string name;
  std::vector<std::string> e;  ///< the coordinates e0, e1, e2, e3
  /// Empty: the body's own Euler parameters (its orientation in ground). Else the name of the
  /// spherical tree joint whose coordinates e are (marker2's frame relative to marker1's): no
  /// rotation-vector or angular-velocity keys in the case.
  std::string joint;
};

class ModelSource {
 public:
  virtual ~ModelSource() = default;

  /// The model's name (summary.json "model").
  virtual const std::string& name() const = 0;
  /// Where it comes from, for messages: "built-in model 'pendulum'", "model file m.toml".
  virtual std::string origin() const = 0;
  virtual const std::vector<std::string>& coordinates() const = 0;
  virtual const std::vector<ParameterSpec>& parameters() const = 0;
  virtual const std::vector<ConstraintOffer>& constraints() const = 0;
  /// The names of the derived output columns (timeseries.csv after the reactions).
  virtual const std::vector<std::string>& outputs() const = 0;
  /// Text that changes whenever the model's definition changes (a model file: a hash of its
  /// text): sweeps key their journal with it, so rows of an edited model are not reused.
  virtual std::string fingerprint() const { return origin(); }
  /// The excitation period for these parameter values; NaN if the model declares none.
  virtual double period(const ParameterValues& parameters) const = 0;
  /// The model's slow coordinates ([model] slow): held at their value by `pcsim steady` and by
  /// the static equilibrium (docs/steady.md). Default: none.
  virtual std::vector<std::string> slow_coordinates() const { return {}; }
  /// The spatial bodies placed by Euler parameters (initial angular-velocity keys). Default: none.
  virtual std::vector<EulerBody> euler_bodies() const { return {}; }
  /// The model as a model file's text ([model] table; "" if it has none): a run writes it to
  /// model.toml beside its results, so `pcsim animate` draws the model the run ran.
  virtual std::string definition_text() const { return ""; }

  /// The same model with holonomic constraints added; throws pcsim::InputError (naming `where`
  /// and the constraint) if this model cannot take them or an expression is bad.
  virtual std::shared_ptr<const ModelSource> with_added_constraints(
      const std::vector<AddedConstraint>& added, const std::string& where) const;

  /// The engine's Model for one run. `case_table` is the validated case (for model-specific
  /// keys), `variant` an internal choice of equivalent descriptions ("" = the default).
  /// Throws pcsim::InputError for parameter values the model cannot take.
  virtual std::shared_ptr<const mech::Model> instantiate(const ParameterValues& parameters,
                                                         const Eigen::VectorXd& q0, double t0,
                                                         const toml::table& case_table,
                                                         const std::string& variant) const = 0;

  /// Index of a coordinate by name, or -1.
  int coordinate_index(const std::string& coordinate) const;
};

/// A factory of a built-in model source (called once, on first use).
using SourceFactory = std::function<std::shared_ptr<const ModelSource>()>;

/// Registers a built-in model under `name` (`model = "name"` in a case). Thread-safe.
void register_builtin(const std::string& name, SourceFactory factory);

/// The built-in model `name`, or null. Thread-safe; each source is built once and shared.
std::shared_ptr<const ModelSource> find_builtin(const std::string& name);

/// The names of the built-in models, sorted.
std::vector<std::string> builtin_names();

/// Makes the built-in model `name` the model of a case without a `model` key (an application
/// registers itself so; the sieve does, architecture.md section 4). Thread-safe.
void set_default_builtin(const std::string& name);

/// The built-in model of a case without a `model` key, or null when no application set one.
std::shared_ptr<const ModelSource> default_builtin();

/// Loads a model file (`model = "path.toml"`, the path already resolved) or an inline [model]
/// table of a case file. Throws pcsim::InputError naming the file, the key and what is wrong.
std::shared_ptr<const ModelSource> load_model_file(const std::filesystem::path& file);
std::shared_ptr<const ModelSource> load_inline_model(const toml::table& model,
                                                     const std::filesystem::path& case_file);

}  // namespace pcsim::sim
