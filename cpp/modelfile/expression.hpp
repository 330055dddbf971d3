// Internal: expressions of model files with GiNaC: the allowed functions (GiNaC's, plus min,
// max and a Heaviside step for their derivatives), the reserved names, a token scanner for
// error columns and name dependencies, and the strict parser that turns a text into a GiNaC
// expression or a one-line InputError naming the file, the key and the column.
// GiNaC is not thread-safe: every use of it in pcsim holds ginac_mutex().
#pragma once

#include <map>
#include <mutex>
#include <string>
#include <vector>

#include <ginac/ginac.h>

#include "modelfile/model_source.hpp"

namespace pcsim::modelfile::detail {

/// Serializes every use of GiNaC in the process (its reference counts and tables are not
/// thread-safe).
std::mutex& ginac_mutex();

/// The functions an expression may call, as the contract lists them.
const std::vector<std::string>& allowed_functions();

/// True if `name` may not be declared: a function name, t, pi, GiNaC's literals (I, Pi,
/// Euler, Catalan), or a timeseries column name (residual_pos, residual_vel).
bool is_reserved_name(const std::string& name);

/// True for letters, digits and '_', not starting with a digit, not empty.
bool is_identifier(const std::string& name);

/// min, max and the Heaviside step as GiNaC functions (derivatives: d min(a,b)/da =
/// step(b − a), d step/dx = 0).
GiNaC::ex min_of(const GiNaC::ex& a, const GiNaC::ex& b);
GiNaC::ex max_of(const GiNaC::ex& a, const GiNaC::ex& b);
GiNaC::ex heaviside(const GiNaC::ex& a);
unsigned min_serial();
unsigned max_serial();
unsigned heaviside_serial();

/// A token of an expression text: [begin, end) in bytes.
struct Token {
  enum Kind { identifier, number, symbol } kind;
  std::size_t begin, end;
  std::string text;
};
/// Scans the text the way GiNaC's lexer does (identifiers, numbers, single characters).
std::vector<Token> scan(const std::string& text);
/// The distinct identifiers of a text that are not followed by '(' (i.e. names, not calls).
std::vector<std::string> names_used(const std::string& text);

/// A parser for one set of names (the symbol table: name -> symbol or inlined definition).
class ExpressionParser {
 public:
  ExpressionParser();
  /// Adds or replaces a name.
  void define(const std::string& name, const GiNaC::ex& value);
  bool knows(const std::string& name) const { return table_.count(name) != 0; }
  const GiNaC::symtab& table() const { return table_; }
  /// A hint appended to "unknown name 'X'" messages when X matches (e.g. reactions outside
  /// [model.outputs]). Checked in order; the first prefix/suffix match wins.
  struct Hint {
    std::string prefix, suffix, text;
    bool exact = false;  ///< the name equals prefix (suffix unused)
  };
  void add_hint(Hint hint) { hints_.push_back(std::move(hint)); }

  /// Parses e.text (which must not be empty). Throws InputError "<where>: key '<key>':
  /// syntax error at column C: ..." or "unknown name 'z' at column C" or the like.
  GiNaC::ex parse(const ExprText& e) const;

 private:
  GiNaC::symtab table_;
  std::vector<Hint> hints_;
};

/// A double from a GiNaC numeric that is real and finite; throws InputError otherwise.
double to_real(const GiNaC::ex& number, const ExprText& where);

}  // namespace pcsim::modelfile::detail
