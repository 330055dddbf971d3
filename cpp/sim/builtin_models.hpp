// The model files compiled into pcsim (models/*.toml, embedded at build time by
// cmake/embed_models.cmake), so that the built-in models run without the models/ directory.
#pragma once

#include <string>
#include <vector>

namespace pcsim::sim {

struct EmbeddedModel {
  const char* file_stem;  ///< e.g. "sieve_1995", "pendulum"
  const char* text;       ///< the model file's text
};

const std::vector<EmbeddedModel>& embedded_models();

/// The text of an embedded model file by stem; throws std::out_of_range if there is none.
const char* embedded_model_text(const std::string& file_stem);

}  // namespace pcsim::sim
