// The model registry: model name -> factory building an immutable Model from a parameter map.
// Adding a model is one file tests/mech/models/<name>.cpp defining
//   std::shared_ptr<const Model> create_<name>(const ModelParameters&)
// and one line X(<name>) in the list PCSIM_MECH_MODELS of registry.cpp (an explicit list, so it
// works from a static library, where self-registering static objects would be dropped).
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "mech/model.hpp"

namespace pcsim::mech {

using ModelParameters = std::map<std::string, double>;
using ModelFactory = std::function<std::shared_ptr<const Model>(const ModelParameters&)>;

/// Builds the named model. Unset parameters take the model's documented defaults. Throws
/// pcsim::InputError for an unknown model name, an unknown parameter name or a non-physical
/// value (the message names the model and the key): model creation is an input boundary.
std::shared_ptr<const Model> create_model(const std::string& name,
                                          const ModelParameters& parameters = {});

/// The names of all registered models, sorted.
std::vector<std::string> model_names();

/// The default parameters of a registered model (what create_model uses for unset keys).
ModelParameters default_parameters(const std::string& name);

/// Adds a model at run time (for components built after mech, e.g. the sieve: call this once,
/// explicitly, before create_model). Thread-safe. Replaces an existing entry of the same name.
void register_model(const std::string& name, ModelFactory factory,
                    ModelParameters defaults = {});

/// Reads a parameter map against a table of defaults: rejects unknown keys, fills defaults.
/// For model factories. Throws pcsim::InputError naming the model and the key.
class ParameterReader {
 public:
  ParameterReader(std::string model, ModelParameters defaults, const ModelParameters& given);
  /// The value of key (given or default).
  double get(const std::string& key) const;
  /// The value of key, which must be > 0 (masses, lengths, inertias).
  double positive(const std::string& key) const;

 private:
  std::string model_;
  ModelParameters values_;
};

}  // namespace pcsim::mech
