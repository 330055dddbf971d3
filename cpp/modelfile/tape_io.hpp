// A compiled model (its tape and layout) as bytes, so that the symbolic derivation of a model
// file can be done once, at build time, for the built-in models (pcsim's start-up then skips
// GiNaC: ~10 ms for the sieve). The bytes carry a format tag and a hash of the model file's
// text; a blob that does not match the text is ignored and the model derived as usual.
#pragma once

#include <memory>
#include <optional>
#include <string>

namespace pcsim::modelfile {

struct CompiledModel;

/// 64-bit FNV-1a of a text.
unsigned long long text_hash(const std::string& text);

/// The compiled model as bytes, tagged with text_hash(text) of the model file it came from.
std::string serialize_compiled(const CompiledModel& compiled, const std::string& text);

/// The compiled model from serialize_compiled's bytes, or nullptr if they are not of this
/// format or not made from `text`.
std::shared_ptr<CompiledModel> deserialize_compiled(const std::string& bytes,
                                                    const std::string& text);

}  // namespace pcsim::modelfile
