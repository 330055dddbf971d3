// The model files compiled into pcsim (models/*.toml, embedded at build time by
// cmake/embed_models.cmake), so that the built-in models run without the models/ directory.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "modelfile/tape.hpp"

namespace pcsim::sim {

struct EmbeddedModel {
  const char* file_stem;  ///< e.g. "sieve_1995", "pendulum"
  const char* text;       ///< the model file's text
};

const std::vector<EmbeddedModel>& embedded_models();

/// The text of an embedded model file by stem; throws std::out_of_range if there is none.
const char* embedded_model_text(const std::string& file_stem);

/// The compiled models of the embedded files, derived at build time
/// (tools/precompile_models.cpp; modelfile::serialize_compiled bytes), by file stem.
const std::map<std::string, std::string>& embedded_model_tapes();

/// Their tape blocks as native functions (the same operations), by file stem.
const std::map<std::string, std::vector<modelfile::NativeBlock>>& embedded_model_natives();

}  // namespace pcsim::sim
