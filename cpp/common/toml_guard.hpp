// A guard for TOML text from users (case files, model files): refuses nesting deeper than any
// pcsim file needs before the recursive TOML parser sees the text (a header of tens of
// thousands of dotted parts would otherwise overflow the parser's stack).
#pragma once

#include <filesystem>
#include <string>

namespace pcsim {

/// The deepest nesting a pcsim TOML file may have (dotted key parts, nested arrays or inline
/// tables): case files need 3, model files 4; deeper text is refused.
inline constexpr int kMaxNesting = 16;

/// Throws pcsim::InputError (naming the file, the line and the key) if the TOML text nests
/// deeper than kMaxNesting.
void check_toml_nesting(const std::string& text, const std::filesystem::path& file);

}  // namespace pcsim
