// Expressions of model files with GiNaC (see expression.hpp).
#include "modelfile/expression.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <limits>
#include <set>
#include <unordered_map>
#include <sstream>

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
  static const std::set<std::string> reserved = {"t", "pi", "residual_pos", "residual_vel"};
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
namespace {

std::string ginac_text(const ex& e) {
  std::ostringstream os;
  os << e;
  return os.str();
}

// Texts of the functions the model-file language names, by GiNaC's name.
bool language_function(const std::string& name) {
  static const std::set<std::string> known{"sin",  "cos",  "tan",  "asin", "acos", "atan", "atan2", "sinh",
                                           "cosh", "tanh", "exp",  "log",  "abs",  "min",  "max"};
  return known.count(name) != 0;
}

std::string canonical(const ex& e);

// A term's numeric coefficient and the rest: 3*x*y -> (3, x*y), -x -> (-1, x), 2 -> (2, 1).
std::pair<GiNaC::numeric, ex> split_coefficient(const ex& t) {
  if (GiNaC::is_a<GiNaC::numeric>(t)) return {GiNaC::ex_to<GiNaC::numeric>(t), ex(1)};
  if (!GiNaC::is_a<GiNaC::mul>(t)) return {GiNaC::numeric(1), t};
  GiNaC::numeric c = 1;
  GiNaC::exvector rest;
  for (std::size_t i = 0; i < t.nops(); ++i) {
    if (GiNaC::is_a<GiNaC::numeric>(t.op(i))) c *= GiNaC::ex_to<GiNaC::numeric>(t.op(i));
    else rest.push_back(t.op(i));
  }
  return {c, rest.empty() ? ex(1) : ex(GiNaC::mul(rest))};
}

// Negates the sum s (term by term, held as written) if its first term by text, coefficients
// aside, has a negative coefficient; returns whether it did.
bool negate_sum(ex& s) {
  std::string first;
  bool negative = false;
  for (std::size_t i = 0; i < s.nops(); ++i) {
    const auto [c, rest] = split_coefficient(s.op(i));
    const std::string key = canonical(rest);
    if (i == 0 || key < first) {
      first = key;
      negative = c.is_negative();
    }
  }
  if (!negative) return false;
  GiNaC::exvector terms;
  for (std::size_t i = 0; i < s.nops(); ++i) terms.push_back(-s.op(i));
  s = GiNaC::add(terms);
  return true;
}

// A factor or a base: in parentheses unless it is an atom, a function call or a positive integer.
std::string operand(const ex& e) {
  const std::string t = canonical(e);
  if (GiNaC::is_a<GiNaC::symbol>(e) || GiNaC::is_a<GiNaC::function>(e) || GiNaC::is_a<GiNaC::constant>(e)) return t;
  if (GiNaC::is_a<GiNaC::numeric>(e) && GiNaC::ex_to<GiNaC::numeric>(e).is_pos_integer()) return t;
  return "(" + t + ")";
}

std::string canonical(const ex& e) {
  if (GiNaC::is_a<GiNaC::numeric>(e) || GiNaC::is_a<GiNaC::symbol>(e)) return ginac_text(e);
  if (GiNaC::is_a<GiNaC::constant>(e)) return e.is_equal(GiNaC::Pi) ? "pi" : ginac_text(e);
  if (GiNaC::is_a<GiNaC::add>(e)) {
    std::vector<std::string> terms;
    for (std::size_t i = 0; i < e.nops(); ++i) terms.push_back(canonical(e.op(i)));
    std::sort(terms.begin(), terms.end());
    std::string out;
    for (const std::string& t : terms) out += out.empty() || t[0] == '-' ? t : "+" + t;
    return out;
  }
  if (GiNaC::is_a<GiNaC::mul>(e)) {
    GiNaC::numeric c = 1;
    std::vector<std::string> factors;
    for (std::size_t i = 0; i < e.nops(); ++i) {
      if (GiNaC::is_a<GiNaC::numeric>(e.op(i))) {
        c *= GiNaC::ex_to<GiNaC::numeric>(e.op(i));
        continue;
      }
      ex f = e.op(i);
      // A sum factor's sign is GiNaC's choice too (−(A − w) or (w − A), by serial numbers): it
      // is taken so that the sum's first term is positive, the sign moved to the coefficient
      // (for a sum raised to an integer power, (−1)^n).
      if (GiNaC::is_a<GiNaC::add>(f)) {
        if (negate_sum(f)) c = -c;
      } else if (GiNaC::is_a<GiNaC::power>(f) && GiNaC::is_a<GiNaC::add>(f.op(0)) &&
                 GiNaC::is_a<GiNaC::numeric>(f.op(1)) && GiNaC::ex_to<GiNaC::numeric>(f.op(1)).is_integer()) {
        ex base = f.op(0);
        if (negate_sum(base)) {
          if (GiNaC::ex_to<GiNaC::numeric>(f.op(1)).is_odd()) c = -c;
          f = GiNaC::power(base, f.op(1));
        }
      }
      factors.push_back(GiNaC::is_a<GiNaC::add>(f) || GiNaC::is_a<GiNaC::mul>(f) ? "(" + canonical(f) + ")"
                                                                                  : canonical(f));
    }
    std::sort(factors.begin(), factors.end());
    std::string body;
    for (const std::string& f : factors) body += (body.empty() ? "" : "*") + f;
    if (body.empty()) return ginac_text(c);
    if (c.is_equal(1)) return body;
    if (c.is_equal(-1)) return "-" + body;
    return ginac_text(c) + "*" + body;
  }
  if (GiNaC::is_a<GiNaC::power>(e)) {
    const ex& b = e.op(0);
    const ex& x = e.op(1);
    if (x.is_equal(GiNaC::numeric(1, 2))) return "sqrt(" + canonical(b) + ")";
    const std::string base = operand(b);
    if (GiNaC::is_a<GiNaC::numeric>(x) && GiNaC::ex_to<GiNaC::numeric>(x).is_pos_integer()) return base + "^" + canonical(x);
    return base + "^(" + canonical(x) + ")";
  }
  if (GiNaC::is_a<GiNaC::function>(e)) {
    const std::string name = GiNaC::ex_to<GiNaC::function>(e).get_name();
    if (!language_function(name)) return ginac_text(e);
    std::string out = name + "(";
    for (std::size_t i = 0; i < e.nops(); ++i) out += (i ? "," : "") + canonical(e.op(i));
    return out + ")";
  }
  return ginac_text(e);
}

}  // namespace

std::string canonical_text(const GiNaC::ex& e) { return canonical(e); }

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

// ---- limits before parsing -----------------------------------------------------------------

std::string shortened(const std::string& text) {
  if (text.size() <= 80) return text;
  return text.substr(0, 60) + "... (" + std::to_string(text.size()) + " characters)";
}

void check_expression_size(const ExprText& e) {
  if (e.text.size() > limits::expression_length) {
    fail(e.where, e.key,
         "an expression of at most " + std::to_string(limits::expression_length) +
             " characters, got " + std::to_string(e.text.size()) + " (\"" + shortened(e.text) +
             "\")");
  }
  // Parentheses and runs of signs, as the parser will nest them (a cheap upper bound of its
  // depth that needs no tokens).
  int depth = 0, signs = 0;
  for (std::size_t i = 0; i < e.text.size(); ++i) {
    const char c = e.text[i];
    if (c == '(') ++depth;
    if (c == ')') depth = std::max(0, depth - 1);
    if (c == '-' || c == '+') {
      ++signs;
    } else if (!std::isspace(static_cast<unsigned char>(c))) {
      signs = 0;
    }
    if (depth + signs > limits::nesting) {
      fail(e.where, e.key,
           "an expression nested at most " + std::to_string(limits::nesting) +
               " levels deep (parentheses, calls and signs), got more at column " +
               std::to_string(i + 1) + " of \"" + shortened(e.text) + "\"");
    }
  }
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
    fail(e.where, e.key, "the expression \"" + shortened(e.text) + "\" is not a real number");
  }
  const GiNaC::numeric& n = GiNaC::ex_to<GiNaC::numeric>(number);
  const double v = n.to_double();
  // A nonzero number that would be 0 or subnormal as a double is refused as one that
  // overflows is: 1e-400 and 1e400 alike are out of double's range.
  if (!std::isfinite(v) || (!n.is_zero() && std::fabs(v) < std::numeric_limits<double>::min())) {
    fail(e.where, e.key, "a number in \"" + shortened(e.text) +
                             "\" is out of the range of double (" +
                             (std::isfinite(v) ? "its magnitude is below 2.2e-308" : "above 1.8e308") +
                             ")");
  }
  return v;
}

namespace {

// The functions and their arities.
int arity_of(const std::string& f) {
  if (f == "atan2" || f == "pow" || f == "min" || f == "max") return 2;
  return 1;
}

// An example call for messages: "atan2(y, x)".
std::string example_call(const std::string& f) {
  return arity_of(f) == 2 ? f + "(a, b)" : f + "(x)";
}

std::string numeric_text(const ex& n) {
  std::ostringstream os;
  os << n;
  return shortened(os.str());
}

long bit_length(const GiNaC::numeric& n) {
  return static_cast<long>(GiNaC::abs(n).int_length());
}

// Every node of a parsed expression (a DAG: shared nodes once, no recursion): its leaves are
// known symbols, pi or finite real numbers in double's range; exponents are bounded (GiNaC
// merges x^600*x^600 into x^1200 and (x^100)^100 into x^10000 on its own); the depth is
// bounded, so that GiNaC's recursive algorithms never run out of stack.
// A post-order walk of an expression without recursion: enter(e) on the way down (may throw),
// leave(e, results of its operands) -> R on the way up. Nodes met again (shared subexpressions
// such as inlined definitions) are not walked twice: the memo keeps them alive, so that no
// freed node's address comes back for another one (op() of a product may build its operand
// anew).
template <class R, class Enter, class Leave>
R post_order(const ex& root, Enter enter, Leave leave) {
  std::unordered_map<const GiNaC::basic*, R> memo;
  std::vector<ex> alive;
  struct Frame {
    ex e;
    std::size_t next;
    std::vector<R> results;
  };
  std::vector<Frame> stack;
  stack.push_back({root, 0, {}});
  R last{};
  while (!stack.empty()) {
    Frame& f = stack.back();
    const GiNaC::basic* key = &GiNaC::ex_to<GiNaC::basic>(f.e);
    if (f.next == 0 && f.results.empty()) {
      const auto it = memo.find(key);
      if (it != memo.end()) {
        last = it->second;
        stack.pop_back();
        if (!stack.empty()) stack.back().results.push_back(last);
        continue;
      }
      enter(f.e);
    }
    if (f.next < f.e.nops()) {
      ex child = f.e.op(f.next++);
      stack.push_back({std::move(child), 0, {}});
      continue;
    }
    last = leave(f.e, f.results);
    memo.emplace(key, last);
    alive.push_back(f.e);
    stack.pop_back();
    if (!stack.empty()) stack.back().results.push_back(last);
  }
  return last;
}

// Every node of a parsed expression: its leaves are known symbols, pi or finite real numbers
// in double's range; exponents are bounded (GiNaC merges x^600*x^600 into x^1200 and
// (x^100)^100 into x^10000 on its own); the depth is bounded, so that GiNaC's recursive
// algorithms never run out of stack.
void check_tree(const ex& root, const ExprText& where) {
  auto enter = [&](const ex& e) {
    if (GiNaC::is_a<GiNaC::numeric>(e)) (void)to_real(e, where);
    if (GiNaC::is_a<GiNaC::constant>(e) && !e.is_equal(GiNaC::Pi)) {
      fail(where.where, where.key, "only the constant pi is allowed in \"" + shortened(where.text) + "\"");
    }
    if (GiNaC::is_a<GiNaC::power>(e) && GiNaC::is_a<GiNaC::numeric>(e.op(1)) &&
        GiNaC::abs(GiNaC::ex_to<GiNaC::numeric>(e.op(1))) > limits::exponent) {
      fail(where.where, where.key,
           "exponents of at most " + std::to_string(limits::exponent) + " in magnitude, but \"" +
               shortened(where.text) + "\" makes a power of the exponent " + numeric_text(e.op(1)));
    }
  };
  auto leave = [&](const ex&, const std::vector<int>& children) {
    int d = 0;
    for (int c : children) d = std::max(d, c);
    if (d + 1 > limits::tree_depth) {
      fail(where.where, where.key,
           "an expression at most " + std::to_string(limits::tree_depth) +
               " levels deep with its definitions inlined, but \"" + shortened(where.text) +
               "\" is deeper (nest fewer definitions in one another)");
    }
    return d + 1;
  };
  (void)post_order<int>(root, enter, leave);
}

// A recursive-descent parser over the tokens, its depth bounded by limits::nesting.
//   expression := term (('+' | '-') term)*
//   term       := unary (('*' | '/') unary)*
//   unary      := ('-' | '+') unary | power          (-x^2 is -(x^2), as in GiNaC)
//   power      := primary ('^' exponent)?            (a^b^c is refused: ambiguous)
//   exponent   := ('-' | '+') exponent | primary
//   primary    := number | name | function '(' expression (',' expression)* ')' | '(' expression ')'
class Descent {
 public:
  Descent(const std::vector<Token>& tokens, const ExprText& e, const GiNaC::symtab& table)
      : tk_(tokens), e_(e), table_(table) {}

  ex run() {
    ex r = expression();
    if (k_ < tk_.size()) {
      error(tk_[k_].begin, "syntax error: expected an operator or the end of the expression, got '" +
                               shortened(tk_[k_].text) + "'");
    }
    return r;
  }

 private:
  const std::vector<Token>& tk_;
  const ExprText& e_;
  const GiNaC::symtab& table_;
  std::size_t k_ = 0;
  int depth_ = 0;

  [[noreturn]] void error(std::size_t begin, const std::string& what) const {
    fail(e_.where, e_.key,
         what + " at column " + std::to_string(begin + 1) + " of \"" + shortened(e_.text) + "\"");
  }
  bool peek(const char* s) const {
    return k_ < tk_.size() && tk_[k_].kind == Token::symbol && tk_[k_].text == s;
  }
  std::size_t here() const { return k_ < tk_.size() ? tk_[k_].begin : e_.text.size(); }
  std::string got() const {
    return k_ < tk_.size() ? "'" + shortened(tk_[k_].text) + "'" : std::string("the end of the expression");
  }

  struct Level {
    Descent& d;
    Level(Descent& parser, std::size_t begin) : d(parser) {
      if (++d.depth_ > limits::nesting) {
        d.error(begin, "an expression nested at most " + std::to_string(limits::nesting) +
                           " levels deep (parentheses, calls and signs), got more");
      }
    }
    ~Level() { --d.depth_; }
  };

  // GiNaC evaluates as it builds (1/0, log(0), tan(pi/2) throw): its reason at the column.
  template <class F>
  ex build(std::size_t begin, F&& f) const {
    try {
      return f();
    } catch (const InputError&) {
      throw;
    } catch (const std::exception& err) {
      std::string what = err.what();
      what = what.substr(0, what.find('\n'));
      error(begin, "cannot evaluate this part (" + what + ")");
    }
  }

  ex expression() {
    ex r = term();
    while (peek("+") || peek("-")) {
      const bool minus = tk_[k_].text == "-";
      const std::size_t at = tk_[k_++].begin;
      const ex rhs = term();
      r = build(at, [&] { return minus ? ex(r - rhs) : ex(r + rhs); });
    }
    return r;
  }

  ex term() {
    ex r = unary();
    while (peek("*") || peek("/")) {
      const bool divide = tk_[k_].text == "/";
      const std::size_t at = tk_[k_++].begin;
      const ex rhs = unary();
      // Refused here, not by GiNaC: it throws from inside the power it allocated for 1/0, and
      // that object is never freed.
      if (divide && rhs.is_zero()) error(at, "cannot evaluate this part (a division by zero)");
      r = build(at, [&] { return divide ? ex(r / rhs) : ex(r * rhs); });
    }
    return r;
  }

  ex unary() {
    if (peek("-") || peek("+")) {
      const bool minus = tk_[k_].text == "-";
      const Level level(*this, tk_[k_].begin);
      ++k_;
      const ex r = unary();
      return minus ? ex(-r) : r;
    }
    return power_expr();
  }

  ex exponent() {
    if (peek("-") || peek("+")) {
      const bool minus = tk_[k_].text == "-";
      const Level level(*this, tk_[k_].begin);
      ++k_;
      const ex r = exponent();
      return minus ? ex(-r) : r;
    }
    return primary();
  }

  ex power_expr() {
    const ex base = primary();
    if (!peek("^")) return base;
    const std::size_t at = tk_[k_++].begin;
    const ex exp = exponent();
    if (peek("^")) {
      error(tk_[k_].begin, "syntax error: a^b^c needs parentheses, (a^b)^c or a^(b^c),");
    }
    return raise(base, exp, at);
  }

 public:
  // base^exp, refused before GiNaC computes an exact power that is huge (10^(10^10) is 1.6 GB
  // of digits) or a symbolic one of an exponent beyond limits::exponent.
  ex raise(const ex& base, const ex& exp, std::size_t at) const {
    if (GiNaC::is_a<GiNaC::numeric>(exp)) {
      const GiNaC::numeric& n = GiNaC::ex_to<GiNaC::numeric>(exp);
      if (!n.is_real()) error(at, "a real exponent");
      if (GiNaC::abs(n) > limits::exponent) {
        error(at, "an exponent of at most " + std::to_string(limits::exponent) +
                      " in magnitude (an exact power beyond it is no model's need and costs "
                      "unbounded time and memory), got " + numeric_text(exp));
      }
      // GiNaC distributes the power over a product and merges exponents: ((40*y)^2)^2 is
      // 2560000*y^4, so 42 nested squares would compute 40^(2^42). Check what it would make.
      const long nn_total = static_cast<long>(std::ceil(GiNaC::abs(n).to_double()));
      std::vector<ex> factors;
      if (GiNaC::is_a<GiNaC::mul>(base)) {
        for (std::size_t i = 0; i < base.nops(); ++i) factors.push_back(base.op(i));
      } else {
        factors.push_back(base);
      }
      long coefficient_bits = 0;
      for (const ex& f : factors) {
        if (GiNaC::is_a<GiNaC::power>(f) && GiNaC::is_a<GiNaC::numeric>(f.op(1))) {
          const GiNaC::numeric merged = GiNaC::abs(GiNaC::ex_to<GiNaC::numeric>(f.op(1)) * n);
          if (merged > limits::exponent) {
            error(at, "an exponent of at most " + std::to_string(limits::exponent) +
                          " in magnitude, but this power makes one of " + numeric_text(merged));
          }
        }
        if (GiNaC::is_a<GiNaC::numeric>(f) && !GiNaC::is_a<GiNaC::numeric>(base)) {
          const GiNaC::numeric& c = GiNaC::ex_to<GiNaC::numeric>(f);
          if (c.is_rational()) coefficient_bits += bit_length(c.numer()) + bit_length(c.denom());
        }
      }
      if (coefficient_bits * nn_total > limits::power_bits) {
        error(at, "an exact power of numbers of at most " + std::to_string(limits::power_bits) +
                      " bits (a coefficient of this power would have about " +
                      std::to_string(coefficient_bits * nn_total) + ")");
      }
      if (GiNaC::is_a<GiNaC::numeric>(base)) {
        const GiNaC::numeric& b = GiNaC::ex_to<GiNaC::numeric>(base);
        if (b.is_rational() && !b.is_zero()) {
          // |log2 b^n| >= |n| (|bits(num) - bits(den)| - 1): beyond double's range?
          const long nn = static_cast<long>(std::ceil(GiNaC::abs(n).to_double()));
          const long num = bit_length(b.numer()), den = bit_length(b.denom());
          const long magnitude = std::labs(num - den) - 1;
          if (magnitude > 0 && magnitude * nn > 1100) {
            error(at, "a power of numbers out of the range of double (magnitudes 2.2e-308 to "
                      "1.8e308)");
          }
          if ((num + den) * nn > limits::power_bits) {
            error(at, "an exact power of numbers of at most " +
                          std::to_string(limits::power_bits) + " bits (write the number as a "
                          "decimal), got about " + std::to_string((num + den) * nn));
          }
        }
      }
    }
    // 0^0 and 0^(-n) are refused here: GiNaC throws from inside the power it allocated, and
    // that object is never freed.
    if (base.is_zero() && GiNaC::is_a<GiNaC::numeric>(exp) &&
        !(GiNaC::ex_to<GiNaC::numeric>(exp).real() > 0)) {
      error(at, "cannot evaluate this part (0 to a power that is not positive)");
    }
    return build(at, [&] { return ex(GiNaC::pow(base, exp)); });
  }

 private:
  ex number(const Token& t) const {
    const std::string& s = t.text;
    const std::size_t epos = s.find_first_of("eE");
    const std::string mant = s.substr(0, epos);
    const std::string etext = epos == std::string::npos ? "" : s.substr(epos + 1);
    const std::size_t dot = mant.find('.');
    const bool mant_ok = mant.find_first_of("0123456789") != std::string::npos &&
                         (dot == std::string::npos || mant.find('.', dot + 1) == std::string::npos);
    const std::string edigits = !etext.empty() && (etext[0] == '+' || etext[0] == '-') ? etext.substr(1) : etext;
    const bool exp_ok = epos == std::string::npos || !edigits.empty();
    if (!mant_ok || !exp_ok) error(t.begin, "syntax error: bad number '" + shortened(s) + "'");
    std::string digits;
    for (char ch : mant) {
      if (ch != '.') digits += ch;
    }
    const std::size_t nz = digits.find_first_not_of('0');
    if (nz == std::string::npos) return ex(0);
    digits = digits.substr(nz);
    const auto out_of_range = [&] {
      error(t.begin, "a number in '" + shortened(s) +
                         "' is out of the range of double (magnitudes 2.2e-308 to 1.8e308)");
    };
    if (edigits.size() > 6) out_of_range();
    long exponent = edigits.empty() ? 0 : std::stol(edigits);
    if (!etext.empty() && etext[0] == '-') exponent = -exponent;
    if (dot != std::string::npos) exponent -= static_cast<long>(mant.size() - dot - 1);
    // The value is digits * 10^exponent, of magnitude 10^(exponent + digits - 1).
    const long magnitude = exponent + static_cast<long>(digits.size()) - 1;
    if (magnitude > 308 || magnitude < -308) out_of_range();
    if (digits.size() > 1000) {
      error(t.begin, "a number of at most 1000 digits, got " + std::to_string(digits.size()));
    }
    const GiNaC::numeric mantissa(digits.c_str());
    const GiNaC::numeric scale = GiNaC::numeric(10).power(GiNaC::numeric(std::labs(exponent)));
    const GiNaC::numeric value = exponent >= 0 ? mantissa * scale : mantissa / scale;
    // At the edges (1.9e308, 1e-308 ~ subnormal) to_real decides exactly.
    (void)to_real(value, ExprText{e_.where, e_.key, s});
    return value;
  }

  ex call(const Token& name) {
    const std::size_t name_begin = name.begin;
    const Level level(*this, name_begin);
    ++k_;  // '('
    std::vector<ex> args;
    if (!peek(")")) {
      args.push_back(expression());
      while (peek(",")) {
        ++k_;
        args.push_back(expression());
      }
    }
    if (!peek(")")) {
      error(here(), "syntax error: expected ',' or ')' in the call of '" + name.text + "', got " + got());
    }
    ++k_;
    const int n = arity_of(name.text);
    if (static_cast<int>(args.size()) != n) {
      error(name_begin, "the function '" + name.text + "' takes " + std::to_string(n) +
                            (n == 1 ? " argument" : " arguments") + ", as in " +
                            example_call(name.text) + ", got " + std::to_string(args.size()));
    }
    const std::string& f = name.text;
    if (f == "pow") return raise(args[0], args[1], name_begin);
    return build(name_begin, [&]() -> ex {
      const ex& a = args[0];
      if (f == "sin") return GiNaC::sin(a);
      if (f == "cos") return GiNaC::cos(a);
      if (f == "tan") return GiNaC::tan(a);
      if (f == "asin") return GiNaC::asin(a);
      if (f == "acos") return GiNaC::acos(a);
      if (f == "atan") return GiNaC::atan(a);
      if (f == "atan2") return GiNaC::atan2(a, args[1]);
      if (f == "sinh") return GiNaC::sinh(a);
      if (f == "cosh") return GiNaC::cosh(a);
      if (f == "tanh") return GiNaC::tanh(a);
      if (f == "exp") return GiNaC::exp(a);
      if (f == "log") return GiNaC::log(a);
      if (f == "sqrt") return GiNaC::sqrt(a);
      if (f == "abs") return GiNaC::abs(a);
      if (f == "min") return min_of(a, args[1]);
      if (f == "max") return max_of(a, args[1]);
      throw std::logic_error("no builder for the function '" + f + "'");
    });
  }

  ex primary() {
    if (k_ >= tk_.size()) error(here(), "syntax error: expected an operand, got the end of the expression");
    const Token& t = tk_[k_];
    if (t.kind == Token::number) {
      ++k_;
      return number(t);
    }
    if (t.kind == Token::identifier) {
      if (k_ + 1 < tk_.size() && tk_[k_ + 1].kind == Token::symbol && tk_[k_ + 1].text == "(") {
        ++k_;
        return call(t);
      }
      ++k_;
      const auto it = table_.find(t.text);
      if (it == table_.end()) error(t.begin, "unknown name '" + shortened(t.text) + "'");
      return it->second;
    }
    if (t.text == "(") {
      const Level level(*this, t.begin);
      ++k_;
      const ex r = expression();
      if (!peek(")")) error(here(), "syntax error: expected ')', got " + got());
      ++k_;
      return r;
    }
    error(t.begin, "syntax error: expected an operand (a number, a name, a call or '('), got '" +
                       t.text + "'");
  }
};

}  // namespace

ex ExpressionParser::parse(const ExprText& e) const {
  check_expression_size(e);
  const auto tokens = scan(e.text);
  auto at_column = [&](std::size_t begin, const std::string& what) {
    fail(e.where, e.key, what + " at " + column_text(begin) + " of \"" + shortened(e.text) + "\"");
  };
  if (tokens.empty()) fail(e.where, e.key, "an expression, got an empty string");
  // Names and calls first, so that every unknown name is reported with its column in the
  // order of the text (before a syntax error further on).
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
        at_column(tk.begin, "unknown function '" + shortened(tk.text) + "' (functions: " + list + ")");
      }
    } else if (!table_.count(tk.text)) {
      if (known_function) {
        at_column(tk.begin, "the function '" + tk.text + "' needs arguments in parentheses, as in " +
                                example_call(tk.text));
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
      at_column(tk.begin, "unknown name '" + shortened(tk.text) + "'" + hint);
    }
  }
  // Every number is read as an exact rational ("0.1" as 1/10): a float coefficient combined
  // in GiNaC's (address-dependent) term order could round differently from run to run.
  const ex result = Descent(tokens, e, table_).run();
  check_tree(result, e);
  return result;
}

// ---- polynomial use of symbols ---------------------------------------------------------------

void check_polynomial_in(const ex& root, const std::vector<ex>& symbols, const ExprText& where,
                         const std::string& what) {
  constexpr std::size_t none = static_cast<std::size_t>(-1);
  auto refuse = [&](std::size_t s, const ex& part, const std::string& how) {
    std::ostringstream os;
    os << part;
    fail(where.where, where.key,
         what + " must be quadratic in the velocities (a polynomial in them of degree <= 2), "
                "but " + GiNaC::ex_to<GiNaC::symbol>(symbols[s]).get_name() + " appears " + how +
             " " + shortened(os.str()));
  };
  // For each node: a velocity it uses (or none). Velocities may be used only in sums,
  // products and powers of natural exponents.
  auto leave = [&](const ex& e, const std::vector<std::size_t>& child) -> std::size_t {
    if (GiNaC::is_a<GiNaC::symbol>(e)) {
      for (std::size_t s = 0; s < symbols.size(); ++s) {
        if (e.is_equal(symbols[s])) return s;
      }
      return none;
    }
    std::size_t found = none;
    for (std::size_t c : child) {
      if (found == none) found = c;
    }
    if (found == none || GiNaC::is_a<GiNaC::add>(e) || GiNaC::is_a<GiNaC::mul>(e)) return found;
    if (GiNaC::is_a<GiNaC::power>(e)) {
      const ex& x = e.op(1);
      if (child.size() == 2 && child[1] != none) refuse(child[1], e, "in the exponent of");
      if (!x.info(GiNaC::info_flags::nonnegint)) {
        refuse(found, e, x.info(GiNaC::info_flags::negint) ? "in the denominator of"
                                                            : "under the non-integer power");
      }
      return found;
    }
    refuse(found, e, GiNaC::is_a<GiNaC::function>(e) ? "inside the function" : "inside");
    return found;  // not reached
  };
  (void)post_order<std::size_t>(root, [](const ex&) {}, leave);
}

}  // namespace pcsim::modelfile::detail

// LeakSanitizer (Debug builds run with detect_leaks=1): CLN, GiNaC's number library, allocates
// a few bytes when it initializes and never frees them, which LeakSanitizer reports at the exit
// of every program that links it. Suppress leaks allocated inside CLN and GiNaC only; pcsim holds
// no owning raw pointers to their objects, so leaks of its own are still reported. (The hook is
// read by the sanitizer runtime; without sanitizers nothing calls it.)
// Siconos numerics 4.4 (the LCP plugin, issue 12) never frees the 32-byte enumeration state its
// enumerative LCP solver allocates in enum_init on each call. All three are suppressed by library
// name, which LeakSanitizer matches without symbolizing the stack: CI runs the sanitized suite
// with symbolize=0 (reading the debug information of every loaded library at each exit cost
// 0.2 s per process) and re-runs a failed test symbolized.
extern "C" const char* __lsan_default_suppressions() {
  return "leak:libcln.so\nleak:libginac.so\nleak:libsiconos_numerics.so\n";
}
// ... and quietly: the table of suppressions used that LeakSanitizer otherwise prints at exit
// would be mixed into every program's stderr (the CLI tests count its lines).
extern "C" const char* __lsan_default_options() { return "print_suppressions=0"; }
