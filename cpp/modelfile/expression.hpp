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

/// True if `name` may not be declared: a function name, t, pi, or a timeseries column name
/// (residual_pos, residual_vel). GiNaC's own names (I, Pi, Euler, Catalan, D, ...) are not
/// reserved: pcsim's parser reads every other identifier as the user's name.
bool is_reserved_name(const std::string& name);

/// The limits of the model-file format, checked while the file is read, before any symbolic
/// work (each one an InputError naming the file and the key). Reasons in the README's limits
/// table.
namespace limits {
inline constexpr std::size_t expression_length = 100000;  ///< characters of one expression
inline constexpr int nesting = 200;             ///< parentheses, signs and calls, one in another
inline constexpr int tree_depth = 1000;         ///< of an expression with definitions inlined
inline constexpr long exponent = 1000;          ///< |n| of a numeric exponent
inline constexpr long power_bits = 65536;       ///< bits of an exact power of numbers
inline constexpr std::size_t name_length = 128;  ///< characters of a declared name
/// Coordinates and constraints: the engine solves sparse systems from 60 coordinates up, but
/// the model interface still fills M (n x n) and g (s x n) densely per evaluation (72 MB and
/// 48 MB at n = 3000, s = 2000: a chain of 1000 links).
inline constexpr std::size_t coordinates = 3000;
inline constexpr std::size_t parameters = 10000;
inline constexpr std::size_t definitions = 2000;
inline constexpr std::size_t constraints = 3000;
inline constexpr std::size_t outputs = 1000;
}  // namespace limits

/// The text shortened for a message: at most 80 characters, then "..." and the length.
std::string shortened(const std::string& text);

/// Checks an expression's size before it is parsed: its length and the nesting of its
/// parentheses and signs (a text cheap to refuse never reaches GiNaC).
void check_expression_size(const ExprText& e);

/// Refuses an expression in which one of `symbols` appears other than polynomially (inside a
/// function such as abs, min, sqrt or sin, in a denominator, in an exponent, or under a
/// non-integer power): "<what> must be <what_needed>, but <symbol> appears inside ...".
void check_polynomial_in(const GiNaC::ex& e, const std::vector<GiNaC::ex>& symbols,
                         const ExprText& where, const std::string& what);

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

  /// Parses e.text (which must not be empty) with pcsim's own parser (bounded depth, arities
  /// checked, numbers exact and in double's range, exponents bounded). Throws InputError
  /// "<where>: key '<key>': syntax error at column C: ..." or "unknown name 'z' at column C"
  /// or the like.
  GiNaC::ex parse(const ExprText& e) const;

 private:
  GiNaC::symtab table_;
  std::vector<Hint> hints_;
};

/// An expression printed in the model-file language in an order that does not depend on the
/// process: the terms of a sum and the factors of a product sorted by their own texts, π as
/// `pi`. GiNaC's own printing orders them by hash values seeded with the addresses of type
/// names, which move from run to run (address-space randomization): a derived velocity printed
/// `A*omega*cos(t*omega)` once and `A*cos(t*omega)*omega` the next time, so `pcsim expand` and
/// the tapes built from such texts differed between runs. Functions the language does not name
/// (none is expected) are printed by GiNaC.
std::string canonical_text(const GiNaC::ex& e);

/// A double from a GiNaC numeric that is real and finite; throws InputError otherwise.
double to_real(const GiNaC::ex& number, const ExprText& where);

}  // namespace pcsim::modelfile::detail
