// The case layer's key table: every common case key (the top-level name, initial.from, [solver],
// [output], [contact]) declared once, with its type, default, range, unit and meaning. The
// schema check (sim/case.cpp), the typed Setup, --set and the README's case-key table all read
// it; the model's own keys (parameters, coordinates, constraints) come from the model, and a
// client's extra keys from the client.
#pragma once

#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace pcsim::sim {

/// What one case key must hold.
struct KeySpec {
  enum class Type { number, integer, boolean, string };
  std::string section;  ///< "" for the top level, e.g. "parameters", "constraints.added"
  std::string name;
  Type type = Type::number;
  std::string meaning;  ///< meaning (and unit), as messages quote it
  std::string unit;     ///< the unit alone ("s"; "" for none or a model's unit in `meaning`)
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool min_exclusive = false, max_exclusive = false;
  std::vector<std::string> choices;  ///< allowed strings (empty: any)
  /// The default (none: the key stays absent unless the case sets it).
  std::optional<double> number_default;  ///< number and integer keys
  std::optional<bool> bool_default;
  std::optional<std::string> string_default;
  /// True: a case without the key gets the default written into its table (and to_toml writes
  /// it). False: the table stays without the key and the typed Setup uses the default.
  bool fill_default = true;
  /// The default in words where it depends on the model (e.g. "5 with an excitation period"),
  /// for the README; "" where the default above says it all.
  std::string default_text;

  std::string dotted() const { return section.empty() ? name : section + "." + name; }
};

/// The common keys of every case, in the schema's order (name, initial.from, [solver],
/// [output], [contact]).
const std::vector<KeySpec>& common_keys();

/// The common key `dotted` ("solver.rtol"); throws std::logic_error if there is none.
const KeySpec& common_key(const std::string& dotted);

}  // namespace pcsim::sim
