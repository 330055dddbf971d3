// Model files as model sources of the case layer: a modelfile::ModelDescription (parsed,
// derived and compiled once) seen through the ModelSource interface.
#pragma once

#include <memory>
#include <string>

#include "modelfile/model_file.hpp"
#include "sim/model_source.hpp"

namespace pcsim::sim {

/// The source of a model description; `origin` names it in messages ("model file x.toml",
/// "built-in model 'pendulum'"), `text` is what its fingerprint hashes (the file's text).
std::shared_ptr<const ModelSource> make_file_model_source(
    std::shared_ptr<const modelfile::ModelDescription> description, std::string origin,
    const std::string& text);

/// A built-in model from an embedded model file (models/<file_stem>.toml), named `name`.
std::shared_ptr<const ModelSource> make_embedded_model_source(const std::string& name,
                                                              const std::string& file_stem);

/// A model file's parameter as the case layer's parameter spec (default, unit, meaning, range).
ParameterSpec parameter_spec(const modelfile::ParameterSpec& p);

/// The embedded model file's description (shared; built on first use).
std::shared_ptr<const modelfile::ModelDescription> embedded_description(const std::string& file_stem);

}  // namespace pcsim::sim
