// The sieve case: loading, validating and overriding a case file (TOML), and writing one back.
// The keys are the contract of shared/design/architecture.md section 4.
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <toml++/toml.h>

namespace pcsim::sieve {

/// A validated case: the TOML table after defaults and overrides, plus where it came from.
/// Immutable once loaded; copy it to vary a design.
struct Case {
  std::string name;               ///< the case name (file stem unless the file sets one)
  std::filesystem::path source;   ///< the file it was loaded from ("" when built in memory)
  toml::table table;              ///< every key, with documented defaults filled in
};

/// One override in `--set KEY=VALUE` form: a dotted key and the value as text
/// ("300", "true", "\"cpp\"" or "cpp" for strings).
using Override = std::pair<std::string, std::string>;

/// Splits "KEY=VALUE" into an Override; throws pcsim::InputError if there is no '='.
Override parse_override(const std::string& text);

/// Loads, fills defaults, applies the overrides in order, and validates. Throws
/// pcsim::InputError naming the file, the key and what was expected, for: unreadable or
/// malformed TOML, unknown keys, wrong types, non-physical values (negative mass or inertia,
/// r <= 0, rtol <= 0, t_end <= 0, ...), an unknown kernel or form.
Case load_case(const std::filesystem::path& file, const std::vector<Override>& overrides = {});

/// Applies one override to a loaded case with the same validation as load_case.
void set_value(Case& c, const Override& o);

/// True if `dotted_key` names a numeric (integer or floating) key of the sieve case format.
bool is_numeric_key(const std::string& dotted_key);

/// The case as TOML text that load_case reads back to an equal case (for "a ready-to-run
/// case file", e.g. the optimizer's best design).
std::string to_toml(const Case& c);

}  // namespace pcsim::sieve
