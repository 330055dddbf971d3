// Expressions of model files with GiNaC (see expression.hpp).
#include "modelfile/expression.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <set>
#include <sstream>
#include <unordered_set>

namespace pcsim::modelfile::detail {

using GiNaC::ex;

std::mutex& ginac_mutex() {
  static std::mutex m;
  return m;
}

const std::vector<std::string>& allowed_functions() {
  static const std::vector<std::string> names = {"sin",  "cos",  "tan",  "asin", "acos", "atan",
                                                 "atan2", "sinh", "cosh", "tanh", "exp",  "log",
                                                 "sqrt", "abs",  "pow",  "min",  "max"};
  return names;
}

bool is_reserved_name(const std::string& name) {
  static const std::set<std::string> reserved = {
      "t", "pi", "I", "Pi", "Euler", "Catalan", "residual_pos", "residual_vel"};
  if (reserved.count(name)) return true;
  const auto& f = allowed_functions();
  return std::find(f.begin(), f.end(), name) != f.end();
}

bool is_identifier(const std::string& name) {
  if (name.empty()) return false;
  const auto c0 = static_cast<unsigned char>(name[0]);
  if (!(std::isalpha(c0) || name[0] == '_')) return false;
  for (char ch : name) {
    const auto c = static_cast<unsigned char>(ch);
    if (!(std::isalnum(c) || ch == '_')) return false;
  }
  return true;
}

// ---- min, max, Heaviside as GiNaC functions --------------------------------------------------

namespace {

bool both_real_numbers(const ex& a, const ex& b) {
  return GiNaC::is_exactly_a<GiNaC::numeric>(a) && GiNaC::is_exactly_a<GiNaC::numeric>(b) &&
         a.info(GiNaC::info_flags::real) && b.info(GiNaC::info_flags::real);
}

ex min_eval(const ex& a, const ex& b) {
  if (both_real_numbers(a, b)) return GiNaC::ex_to<GiNaC::numeric>(a) <= GiNaC::ex_to<GiNaC::numeric>(b) ? a : b;
  if (a.is_equal(b)) return a;
  return GiNaC::function(min_serial(), a, b).hold();
}
ex min_evalf(const ex& a, const ex& b) { return min_eval(a.evalf(), b.evalf()); }
ex min_conjugate(const ex& a, const ex& b) { return min_of(a.conjugate(), b.conjugate()); }
ex min_derivative(const ex& a, const ex& b, unsigned param) {
  return param == 0 ? heaviside(b - a) : heaviside(a - b);
}

ex max_eval(const ex& a, const ex& b) {
  if (both_real_numbers(a, b)) return GiNaC::ex_to<GiNaC::numeric>(a) >= GiNaC::ex_to<GiNaC::numeric>(b) ? a : b;
  if (a.is_equal(b)) return a;
  return GiNaC::function(max_serial(), a, b).hold();
}
ex max_evalf(const ex& a, const ex& b) { return max_eval(a.evalf(), b.evalf()); }
ex max_conjugate(const ex& a, const ex& b) { return max_of(a.conjugate(), b.conjugate()); }
ex max_derivative(const ex& a, const ex& b, unsigned param) {
  return param == 0 ? heaviside(a - b) : heaviside(b - a);
}

ex heaviside_eval(const ex& a) {
  if (GiNaC::is_exactly_a<GiNaC::numeric>(a) && a.info(GiNaC::info_flags::real)) {
    const GiNaC::numeric& v = GiNaC::ex_to<GiNaC::numeric>(a);
    if (v.is_zero()) return GiNaC::numeric(1, 2);
    return v.is_positive() ? ex(1) : ex(0);
  }
  return GiNaC::function(heaviside_serial(), a).hold();
}
ex heaviside_evalf(const ex& a) { return heaviside_eval(a.evalf()); }
ex heaviside_conjugate(const ex& a) { return heaviside(a.conjugate()); }
ex heaviside_derivative(const ex&, unsigned) { return 0; }

// GiNaC's parser tells a registered function (whose serial it finds in the table, encoded as
// an odd "pointer" (serial << 1) | 1) from a reader function (an even pointer it calls). min and
// max are registered functions, so they are entered the first way: a reader function of our own
// could sit at an odd address in an unoptimized build and be taken for a serial.
GiNaC::reader_func encoded_serial(unsigned serial) {
  return reinterpret_cast<GiNaC::reader_func>((static_cast<std::uintptr_t>(serial) << 1) | 1u);
}

// The parser's function table: GiNaC's readers for the allowed functions, plus min and max.
const GiNaC::prototype_table& reader_table() {
  static const GiNaC::prototype_table table = [] {
    GiNaC::prototype_table t;
    const auto& all = GiNaC::get_default_reader();
    for (const auto& [proto, reader] : all) {
      const auto& f = allowed_functions();
      if (std::find(f.begin(), f.end(), proto.first) != f.end()) t[proto] = reader;
    }
    t[{"min", 2}] = encoded_serial(min_serial());
    t[{"max", 2}] = encoded_serial(max_serial());
    return t;
  }();
  return table;
}

}  // namespace

unsigned min_serial() {
  static const unsigned serial = GiNaC::function::register_new(
      GiNaC::function_options("min", 2)
          .eval_func(min_eval)
          .evalf_func(min_evalf)
          .conjugate_func(min_conjugate)
          .derivative_func(min_derivative));
  return serial;
}
unsigned max_serial() {
  static const unsigned serial = GiNaC::function::register_new(
      GiNaC::function_options("max", 2)
          .eval_func(max_eval)
          .evalf_func(max_evalf)
          .conjugate_func(max_conjugate)
          .derivative_func(max_derivative));
  return serial;
}
unsigned heaviside_serial() {
  static const unsigned serial = GiNaC::function::register_new(
      GiNaC::function_options("heaviside", 1)
          .eval_func(heaviside_eval)
          .evalf_func(heaviside_evalf)
          .conjugate_func(heaviside_conjugate)
          .derivative_func(heaviside_derivative));
  return serial;
}
ex min_of(const ex& a, const ex& b) { return GiNaC::function(min_serial(), a, b); }
ex max_of(const ex& a, const ex& b) { return GiNaC::function(max_serial(), a, b); }
ex heaviside(const ex& a) { return GiNaC::function(heaviside_serial(), a); }

// ---- scanning ------------------------------------------------------------------------------

std::vector<Token> scan(const std::string& s) {
  std::vector<Token> out;
  std::size_t i = 0;
  const std::size_t n = s.size();
  auto at = [&](std::size_t k) { return k < n ? static_cast<unsigned char>(s[k]) : 0u; };
  while (i < n) {
    const unsigned c = at(i);
    if (std::isspace(static_cast<int>(c))) {
      ++i;
      continue;
    }
    const std::size_t b = i;
    if (std::isalpha(static_cast<int>(c)) || c == '_') {
      while (i < n && (std::isalnum(static_cast<int>(at(i))) || at(i) == '_')) ++i;
      out.push_back({Token::identifier, b, i, s.substr(b, i - b)});
    } else if (std::isdigit(static_cast<int>(c)) || c == '.') {
      // As GiNaC's lexer: [0-9.]+ then an optional exponent [eE][+-]?[0-9]*.
      while (i < n && (std::isdigit(static_cast<int>(at(i))) || at(i) == '.')) ++i;
      if (at(i) == 'e' || at(i) == 'E') {
        ++i;
        if (at(i) == '+' || at(i) == '-') ++i;
        while (i < n && std::isdigit(static_cast<int>(at(i)))) ++i;
      }
      out.push_back({Token::number, b, i, s.substr(b, i - b)});
    } else {
      ++i;
      out.push_back({Token::symbol, b, i, s.substr(b, 1)});
    }
  }
  return out;
}

namespace {

bool is_call(const std::vector<Token>& tokens, std::size_t k) {
  return k + 1 < tokens.size() && tokens[k + 1].kind == Token::symbol && tokens[k + 1].text == "(";
}

std::string column_text(std::size_t begin) { return "column " + std::to_string(begin + 1); }

// The first line of a GiNaC exception text, without GiNaC's location prefix.
std::string ginac_reason(const std::string& what) {
  std::string s = what.substr(0, what.find('\n'));
  const std::string marker = "column 0: ";
  const auto p = s.find(marker);
  if (p != std::string::npos) s = s.substr(p + marker.size());
  return s;
}

}  // namespace

std::vector<std::string> names_used(const std::string& text) {
  const auto tokens = scan(text);
  std::vector<std::string> names;
  for (std::size_t k = 0; k < tokens.size(); ++k) {
    if (tokens[k].kind == Token::identifier && !is_call(tokens, k) &&
        std::find(names.begin(), names.end(), tokens[k].text) == names.end()) {
      names.push_back(tokens[k].text);
    }
  }
  return names;
}

// ---- parsing -------------------------------------------------------------------------------

ExpressionParser::ExpressionParser() {
  // Register the extra functions before the first parse (their serials are function-local
  // statics; GiNaC's own library is initialized by its headers).
  (void)min_serial();
  (void)max_serial();
  (void)heaviside_serial();
  table_["pi"] = GiNaC::Pi;
}

void ExpressionParser::define(const std::string& name, const ex& value) { table_[name] = value; }

double to_real(const ex& number, const ExprText& e) {
  if (!GiNaC::is_a<GiNaC::numeric>(number) || !number.info(GiNaC::info_flags::real)) {
    fail(e.where, e.key, "the expression \"" + e.text + "\" is not a real number");
  }
  const double v = GiNaC::ex_to<GiNaC::numeric>(number).to_double();
  if (!std::isfinite(v)) {
    fail(e.where, e.key, "a number in \"" + e.text + "\" is out of the range of double");
  }
  return v;
}

namespace {

// Every leaf of a parsed expression is a known symbol, pi or a finite real number. Each node
// is visited once (chained definitions share subexpressions: a walk of the tree would take
// 2^k steps for k definitions that each use the previous one twice).
struct ExHash {
  std::size_t operator()(const ex& e) const { return e.gethash(); }
};
using ExSet = std::unordered_set<ex, ExHash, GiNaC::ex_is_equal>;
void check_leaves(const ex& e, const ExprText& where, ExSet& seen) {
  if (!seen.insert(e).second) return;
  if (GiNaC::is_a<GiNaC::numeric>(e)) {
    (void)to_real(e, where);
    return;
  }
  if (GiNaC::is_a<GiNaC::constant>(e) && !e.is_equal(GiNaC::Pi)) {
    fail(where.where, where.key, std::string("the constant ") + GiNaC::ex_to<GiNaC::basic>(e).class_name() +
                                     " is not allowed in \"" + where.text + "\"");
  }
  for (std::size_t i = 0; i < e.nops(); ++i) check_leaves(e.op(i), where, seen);
}
void check_leaves(const ex& e, const ExprText& where) {
  ExSet seen;
  check_leaves(e, where, seen);
}

// The text with each number token replaced by an exact rational in parentheses: mantissa
// digits over a power of ten ("12.5e-3" -> "(125/10000)").
// Returns "" if a number lies beyond double's range (|exponent| > 400 after the mantissa).
std::string exact_numbers(const std::string& text, const std::vector<Token>& tokens) {
  std::string out;
  std::size_t pos = 0;
  for (const Token& tk : tokens) {
    if (tk.kind != Token::number) continue;
    const std::string& t = tk.text;
    const std::size_t epos = t.find_first_of("eE");
    const std::string mant = t.substr(0, epos);
    const std::string etext = epos == std::string::npos ? "" : t.substr(epos + 1);
    if (etext.size() > 6) return "";
    long exponent = etext.empty() || etext == "+" || etext == "-" ? 0 : std::stol(etext);
    std::string digits;
    const std::size_t dot = mant.find('.');
    for (char ch : mant) {
      if (ch != '.') digits += ch;
    }
    if (dot != std::string::npos) exponent -= static_cast<long>(mant.size() - dot - 1);
    const std::size_t nz = digits.find_first_not_of('0');
    digits = nz == std::string::npos ? "0" : digits.substr(nz);
    if (digits != "0" && (exponent > 400 || exponent < -400 - static_cast<long>(digits.size()))) {
      return "";
    }
    std::string rational;
    if (digits == "0") {
      rational = "0";
    } else if (exponent >= 0) {
      rational = digits + std::string(static_cast<std::size_t>(exponent), '0');
    } else {
      rational = digits + "/1" + std::string(static_cast<std::size_t>(-exponent), '0');
    }
    out += text.substr(pos, tk.begin - pos) + "(" + rational + ")";
    pos = tk.end;
  }
  out += text.substr(pos);
  return out;
}

}  // namespace

ex ExpressionParser::parse(const ExprText& e) const {
  const auto tokens = scan(e.text);
  auto at_column = [&](std::size_t begin, const std::string& what) {
    fail(e.where, e.key, what + " at " + column_text(begin) + " of \"" + e.text + "\"");
  };
  if (tokens.empty()) fail(e.where, e.key, "an expression, got an empty string");
  // Names and calls first, so that every unknown name is reported with its column (GiNaC's
  // strict parser says only that a symbol was not found).
  const auto& functions = allowed_functions();
  for (std::size_t k = 0; k < tokens.size(); ++k) {
    const Token& tk = tokens[k];
    if (tk.kind != Token::identifier) continue;
    const bool known_function =
        std::find(functions.begin(), functions.end(), tk.text) != functions.end();
    if (is_call(tokens, k)) {
      if (!known_function) {
        if (table_.count(tk.text)) at_column(tk.begin, "'" + tk.text + "' is not a function");
        std::string list;
        for (const auto& f : functions) list += (list.empty() ? "" : " ") + f;
        at_column(tk.begin, "unknown function '" + tk.text + "' (functions: " + list + ")");
      }
    } else if (!table_.count(tk.text)) {
      if (known_function) {
        at_column(tk.begin, "the function '" + tk.text + "' needs arguments in parentheses");
      }
      std::string hint;
      for (const Hint& h : hints_) {
        if (h.exact) {
          if (tk.text == h.prefix) {
            hint = " (" + h.text + ")";
            break;
          }
          continue;
        }
        if (tk.text.size() > h.prefix.size() + h.suffix.size() &&
            tk.text.compare(0, h.prefix.size(), h.prefix) == 0 &&
            tk.text.compare(tk.text.size() - h.suffix.size(), h.suffix.size(), h.suffix) == 0) {
          hint = " (" + h.text + ")";
          break;
        }
      }
      at_column(tk.begin, "unknown name '" + tk.text + "'" + hint);
    }
  }
  // Numbers beyond double's range are rejected before GiNaC sees them (CLN would build
  // 1e9999999999 digit by digit).
  const std::string exact = exact_numbers(e.text, tokens);
  if (exact.empty()) {
    fail(e.where, e.key, "a number in \"" + e.text + "\" is out of the range of double");
  }
  std::istringstream in(e.text);
  ex result;
  try {
    GiNaC::parser reader(table_, /*strict=*/true, reader_table());
    result = reader(in);
  } catch (const std::exception& err) {
    // Where the lexer stopped: one character past the token it last read (its look-ahead),
    // or the end of the text. The offending token is the last one ending before that.
    // At the end of the text the look-ahead failed (eof set) and the last token is the one.
    const bool at_eof = in.eof();
    in.clear();
    const std::streamoff pos_raw = in.tellg();
    const std::size_t len = e.text.size();
    const std::size_t pos = pos_raw < 0 ? len : static_cast<std::size_t>(pos_raw);
    const Token* last = nullptr;
    for (const Token& tk : tokens) {
      if (at_eof || tk.end < pos) last = &tk;
    }
    const std::string what = err.what();
    std::string reason = ginac_reason(what);
    if (what.find("power should have exactly 2 operands") != std::string::npos) {
      // GiNaC cannot parse a^b^c; say so at the second '^'.
      std::size_t col = len;
      int seen = 0;
      for (const Token& tk : tokens) {
        if (tk.text == "^" && ++seen == 2) {
          col = tk.begin;
          break;
        }
      }
      at_column(col, "syntax error: a^b^c needs parentheses, (a^b)^c or a^(b^c),");
    }
    if (what.find("Illegal number syntax") != std::string::npos) {
      const Token* number = nullptr;
      for (const Token& tk : tokens) {
        if (tk.kind == Token::number && (at_eof || tk.end < pos)) number = &tk;
      }
      at_column(number ? number->begin : 0,
                "syntax error: bad number '" + (number ? number->text : std::string()) + "'");
    }
    if (reason.compare(0, 13, "expected EOF,") == 0) {
      reason = "expected an operator or the end of the expression," + reason.substr(13);
    }
    if (reason.find("got: EOF") != std::string::npos) {
      reason.replace(reason.find("got: EOF"), 8, "got the end of the expression");
      at_column(len, "syntax error: " + reason);
    }
    at_column(last ? last->begin : 0, "syntax error: " + reason);
  }
  // Parse again with every number written as an exact rational ("0.1" as 1/10): GiNaC would
  // keep "0.1" as a 17-digit float, and float coefficients combined in GiNaC's (address-
  // dependent) term order could round differently from run to run; exact ones cannot.
  if (exact != e.text) {
    std::istringstream in2(exact);
    GiNaC::parser reader(table_, /*strict=*/true, reader_table());
    result = reader(in2);
  }
  check_leaves(result, e);
  return result;
}

}  // namespace pcsim::modelfile::detail

// LeakSanitizer (Debug builds run with detect_leaks=1): CLN, GiNaC's number library, allocates
// a few bytes when it initializes and never frees them, which LeakSanitizer reports at the exit
// of every program that links it. Suppress leaks allocated inside CLN and GiNaC only; pcsim holds
// no owning raw pointers to their objects, so leaks of its own are still reported. (The hook is
// read by the sanitizer runtime; without sanitizers nothing calls it.)
// Siconos numerics 4.4 (the LCP plugin, issue 12) never frees the 32-byte enumeration state its
// enumerative LCP solver allocates in enum_init on each call; suppressed by that function's name.
extern "C" const char* __lsan_default_suppressions() {
  return "leak:libcln.so\nleak:libginac.so\nleak:enum_init\n";
}
// ... and quietly: the table of suppressions used that LeakSanitizer otherwise prints at exit
// would be mixed into every program's stderr (the CLI tests count its lines).
extern "C" const char* __lsan_default_options() { return "print_suppressions=0"; }
