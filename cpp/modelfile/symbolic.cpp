// Symbolic derivation of a model file and its compilation into a tape (see symbolic.hpp).
#include "modelfile/symbolic.hpp"

#include <array>

#include <cmath>
#include <cstring>
#include <algorithm>
#include <functional>
#include <map>
#include <stdexcept>
#include <tuple>
#include <unordered_map>
#include <unordered_set>

#include "modelfile/expression.hpp"

namespace pcsim::modelfile::detail {

using GiNaC::ex;

namespace {

// ---- derivation ---------------------------------------------------------------------------

std::string symbol_name(const ex& s) { return GiNaC::ex_to<GiNaC::symbol>(s).get_name(); }

struct ExHash {
  std::size_t operator()(const ex& e) const { return e.gethash(); }
};

// The derivation budget: symbolic operations (one per node differentiated, plus the products
// a product's derivative forms) that derive() may spend on one model file. Chained
// definitions share their subexpressions (a DAG), which the derivation below visits once per
// node: 30 chained definitions cost a few hundred operations, the paper's sieve about
// 2,500. The budget refuses, before minutes pass, a model file whose derivatives would be
// enormous (see the README's limits table).
constexpr std::size_t kDerivationBudget = 2'000'000;

struct BudgetExceeded {};

// The deepest nesting of expressions through chained definitions (each definition adds the
// depth of its own expression). The derivation and the tape builder recurse once per level;
// this bound keeps them inside the stack of any thread, also under the sanitizers (a Debug
// build with AddressSanitizer overflowed at about 2000 levels, and ran 1400).
constexpr int kMaxDefinitionDepth = 1000;

unsigned group_serial_init();
unsigned group_serial() {
  static const unsigned serial = group_serial_init();
  return serial;
}

// group(s): s itself, kept apart. GiNaC distributes a number over a sum it multiplies
// (4*(x - a) becomes 4x - 4a, and then melts into the sum around it: 4x - 4a + y), which
// turns the exact difference x - a of the user's expression into a cancellation. The
// derivation wraps a sum that would be so multiplied (the power rule's n (x - a)^(n-1) with
// n = 2, a product rule's remaining factor); the tape evaluates group(s) as s.
ex group_eval(const ex& a) {
  if (!GiNaC::is_a<GiNaC::add>(a)) return a;
  return GiNaC::function(group_serial(), a).hold();
}
ex group_evalf(const ex& a) { return a.evalf(); }
ex group_conjugate(const ex& a) { return GiNaC::function(group_serial(), a.conjugate()); }
ex group_derivative(const ex&, unsigned) { return 1; }
unsigned group_serial_init() {
  return GiNaC::function::register_new(GiNaC::function_options("pcsim_group", 1)
                                           .eval_func(group_eval)
                                           .evalf_func(group_evalf)
                                           .conjugate_func(group_conjugate)
                                           .derivative_func(group_derivative));
}
bool is_group(const ex& e) {
  return GiNaC::is_a<GiNaC::function>(e) &&
         GiNaC::ex_to<GiNaC::function>(e).get_serial() == group_serial();
}
ex unwrap(const ex& e) { return is_group(e) ? e.op(0) : e; }

// The product of factors, a sum among them grouped when it would be the only non-numeric
// factor (GiNaC would distribute the number over it).
ex product_of(GiNaC::exvector factors) {
  int symbolic = 0;
  std::size_t last = 0;
  for (std::size_t i = 0; i < factors.size(); ++i) {
    if (!GiNaC::is_a<GiNaC::numeric>(factors[i])) {
      ++symbolic;
      last = i;
    }
  }
  if (symbolic == 1 && GiNaC::is_a<GiNaC::add>(factors[last])) {
    factors[last] = GiNaC::function(group_serial(), factors[last]);
  }
  return GiNaC::dynallocate<GiNaC::mul>(std::move(factors));
}

// Differentiation and symbol queries that visit each node of an expression DAG once.
// GiNaC's own diff() and has() walk the expression as a tree: a definition used twice by
// the next one (d_k = sin(d_{k-1}) + cos(d_{k-1})) doubles the walk per level, 2^30 visits
// for 30 chained definitions. Here every node's derivative is memoized (per symbol), so the
// derivatives share their subexpressions as the expressions do. The results are the same
// expressions GiNaC's diff() gives (the same rules, GiNaC's own for functions), unexpanded.
class Calculus {
 public:
  // A definition: the symbol `name` stands for `value` (in symbols(), diff() and inlined()).
  void define(const ex& symbol, const ex& value) { defs_[symbol_name(symbol)] = value; }

  // ∂e/∂s, s a symbol.
  ex diff(const ex& e, const ex& s) {
    auto& memo = memo_[symbol_name(s)];
    return d(e, s, memo);
  }

  // The names of the symbols in e that are not definitions, through the definitions: the
  // union of its operands' (each node's set found once).
  const std::unordered_set<std::string>& symbols(const ex& e) {
    auto it = symbols_memo_.find(e);
    if (it != symbols_memo_.end()) return it->second;
    std::unordered_set<std::string> names;
    if (GiNaC::is_a<GiNaC::symbol>(e)) {
      auto def = defs_.find(symbol_name(e));
      if (def == defs_.end()) names.insert(symbol_name(e));
      else names = symbols(def->second);
    } else {
      for (std::size_t i = 0; i < e.nops(); ++i) {
        const auto& inner = symbols(e.op(i));
        names.insert(inner.begin(), inner.end());
      }
    }
    return symbols_memo_.emplace(e, std::move(names)).first->second;
  }

  bool has(const ex& e, const ex& s) { return symbols(e).count(symbol_name(s)) != 0; }

  // e with the definitions substituted (memoized; GiNaC evaluates the result as a tree).
  ex inlined(const ex& e) {
    if (GiNaC::is_a<GiNaC::symbol>(e)) {
      auto def = defs_.find(symbol_name(e));
      if (def == defs_.end()) return e;
      return inlined(def->second);
    }
    if (e.nops() == 0) return e;
    if (is_group(e)) return inlined(e.op(0));
    auto it = inline_memo_.find(e);
    if (it != inline_memo_.end()) return it->second;
    struct Map : GiNaC::map_function {
      Calculus* self;
      explicit Map(Calculus* c) : self(c) {}
      ex operator()(const ex& x) override { return self->inlined(x); }
    } map(this);
    const ex out = e.map(map);
    inline_memo_.emplace(e, out);
    return out;
  }

  std::size_t spent() const { return spent_; }

  // The index of each symbol of `symbols` by name, cached per vector for the life of this
  // Calculus (one derive(): the symbol vectors of its SymbolicModel are filled before any
  // query and do not move; a vector of another size is indexed afresh).
  const std::unordered_map<std::string, int>& index_of(const std::vector<ex>& symbols) {
    auto& idx = index_cache_[static_cast<const void*>(&symbols)];
    if (idx.size() != symbols.size()) {
      idx.clear();
      for (std::size_t i = 0; i < symbols.size(); ++i)
        idx.emplace(symbol_name(symbols[i]), static_cast<int>(i));
    }
    return idx;
  }

 private:
  using Memo = std::unordered_map<ex, ex, ExHash, GiNaC::ex_is_equal>;

  void spend(std::size_t k) {
    spent_ += k;
    if (spent_ > kDerivationBudget) throw BudgetExceeded{};
  }

  ex d(const ex& e, const ex& s, Memo& memo) {
    if (GiNaC::is_a<GiNaC::numeric>(e) || GiNaC::is_a<GiNaC::constant>(e)) return 0;
    auto it = memo.find(e);
    if (it != memo.end()) return it->second;
    if (GiNaC::is_a<GiNaC::symbol>(e)) {
      if (e.is_equal(s)) return 1;
      auto def = defs_.find(symbol_name(e));
      if (def == defs_.end()) return 0;
      const ex out = d(def->second, s, memo);  // the chain rule through a definition
      memo.emplace(e, out);
      return out;
    }
    if (!has(e, s)) {  // constant in s: no work, nothing spent
      memo.emplace(e, 0);
      return 0;
    }
    spend(1);
    ex out;
    if (GiNaC::is_a<GiNaC::add>(e)) {
      GiNaC::exvector terms;
      for (std::size_t i = 0; i < e.nops(); ++i) {
        const ex t = d(e.op(i), s, memo);
        if (!t.is_zero()) terms.push_back(t);
      }
      out = terms.empty() ? ex(0) : ex(GiNaC::dynallocate<GiNaC::add>(std::move(terms)));
    } else if (GiNaC::is_a<GiNaC::mul>(e)) {
      // Σ_i (Π_{j≠i} f_j) ∂f_i
      const std::size_t k = e.nops();
      GiNaC::exvector terms;
      for (std::size_t i = 0; i < k; ++i) {
        const ex di = d(e.op(i), s, memo);
        if (di.is_zero()) continue;
        spend(k);
        GiNaC::exvector factors;
        for (std::size_t j = 0; j < k; ++j) factors.push_back(j == i ? di : e.op(j));
        terms.push_back(product_of(std::move(factors)));
      }
      out = terms.empty() ? ex(0) : ex(GiNaC::dynallocate<GiNaC::add>(std::move(terms)));
    } else if (GiNaC::is_a<GiNaC::power>(e)) {
      const ex& b = e.op(0);
      const ex& k = e.op(1);
      const ex db = d(b, s, memo);
      if (GiNaC::is_a<GiNaC::numeric>(k)) {
        // k b^(k-1) ∂b: (x - x0)^n stays n (x - x0)^(n-1) (GiNaC's rule)
        out = db.is_zero() ? ex(0) : product_of({GiNaC::pow(b, k - 1), k, db});
      } else {
        const ex dk = d(k, s, memo);
        // b^k (∂k log b + k ∂b / b)
        out = e * (dk * GiNaC::log(b) + k * db * GiNaC::pow(b, -1));
      }
    } else if (GiNaC::is_a<GiNaC::function>(e)) {
      // Σ_i ∂f/∂a_i (a) ∂a_i: GiNaC's partial derivative of f at symbols, at the arguments.
      const GiNaC::function& f = GiNaC::ex_to<GiNaC::function>(e);
      GiNaC::exvector terms;
      for (std::size_t i = 0; i < e.nops(); ++i) {
        const ex da = d(e.op(i), s, memo);
        if (da.is_zero()) continue;
        GiNaC::exmap at;
        for (std::size_t j = 0; j < e.nops(); ++j) at[argument(j)] = e.op(j);
        terms.push_back(
            product_of({partial(f.get_serial(), e.nops(), i).subs(at, GiNaC::subs_options::no_pattern), da}));
      }
      out = terms.empty() ? ex(0) : ex(GiNaC::dynallocate<GiNaC::add>(std::move(terms)));
    } else {
      out = e.diff(GiNaC::ex_to<GiNaC::symbol>(s));  // no other kind occurs in a model file
    }
    memo.emplace(e, out);
    return out;
  }

  // The symbol standing for argument i of a function in partial().
  static const ex& argument(std::size_t i) {
    static std::vector<ex> args;
    while (args.size() <= i) args.push_back(GiNaC::realsymbol("pcsim_arg" + std::to_string(args.size())));
    return args[i];
  }

  // ∂f/∂a_i of the function with this serial at the argument symbols.
  const ex& partial(unsigned serial, std::size_t nargs, std::size_t i) {
    const auto key = std::make_tuple(serial, nargs, i);
    auto it = partials_.find(key);
    if (it != partials_.end()) return it->second;
    GiNaC::exvector args;
    for (std::size_t j = 0; j < nargs; ++j) args.push_back(argument(j));
    const ex f = GiNaC::function(serial, args);
    return partials_.emplace(key, f.diff(GiNaC::ex_to<GiNaC::symbol>(argument(i)))).first->second;
  }

  std::unordered_map<std::string, ex> defs_;
  std::map<std::string, Memo> memo_;
  Memo inline_memo_;
  std::unordered_map<ex, std::unordered_set<std::string>, ExHash, GiNaC::ex_is_equal> symbols_memo_;
  std::map<std::tuple<unsigned, std::size_t, std::size_t>, ex> partials_;
  std::size_t spent_ = 0;
  std::map<const void*, std::unordered_map<std::string, int>> index_cache_;
};

// The index of each symbol of `symbols` by name (Calculus::index_of).
const std::unordered_map<std::string, int>& index_of(Calculus& calc, const std::vector<ex>& symbols) {
  return calc.index_of(symbols);
}

// The indices (ascending) of the symbols of `symbols` that e depends on: found from e's own
// symbols, so the cost follows the size of e, not the number of coordinates.
std::vector<int> used_indices(Calculus& calc, const ex& e, const std::vector<ex>& symbols) {
  const auto& idx = index_of(calc, symbols);
  std::vector<int> out;
  for (const std::string& name : calc.symbols(e)) {
    auto it = idx.find(name);
    if (it != idx.end()) out.push_back(it->second);
  }
  std::sort(out.begin(), out.end());
  return out;
}

// The first symbol of `symbols` that e depends on, or -1.
int first_used(Calculus& calc, const ex& e, const std::vector<ex>& symbols) {
  const auto& idx = index_of(calc, symbols);
  int first = -1;
  for (const std::string& name : calc.symbols(e)) {
    auto it = idx.find(name);
    if (it != idx.end() && (first < 0 || it->second < first)) first = it->second;
  }
  return first;
}

// ∂e/∂v_k for every symbol v_k of `vars` that e depends on (the others are 0), as (k, ∂e/∂v_k)
// in ascending k: the same expressions as calc.diff(e, v_k). A sum (an energy: a term per body)
// is differentiated term by term, each term only by the symbols it contains, so the work is
// proportional to the size of e, not to its size times the number of symbols.
std::vector<std::pair<int, ex>> gradient(Calculus& calc, const ex& e, const std::vector<ex>& vars) {
  std::vector<std::pair<int, ex>> out;
  if (GiNaC::is_a<GiNaC::add>(e) && !is_group(e)) {
    std::map<int, GiNaC::exvector> terms;  // k -> the nonzero ∂term/∂v_k, in term order
    for (std::size_t i = 0; i < e.nops(); ++i) {
      const ex term = e.op(i);
      for (int k : used_indices(calc, term, vars)) {
        const ex dt = calc.diff(term, vars[k]);
        if (!dt.is_zero()) terms[k].push_back(dt);
      }
    }
    for (auto& [k, list] : terms) out.emplace_back(k, ex(GiNaC::dynallocate<GiNaC::add>(std::move(list))));
    return out;
  }
  for (int k : used_indices(calc, e, vars)) out.emplace_back(k, calc.diff(e, vars[k]));
  return out;
}

// Definitions in an order where each comes after the ones it uses; a cycle is an error.
std::vector<std::size_t> definition_order(const ModelSource& src) {
  std::map<std::string, std::size_t> index;
  for (std::size_t i = 0; i < src.definitions.size(); ++i) index[src.definitions[i].first] = i;
  std::vector<int> state(src.definitions.size(), 0);  // 0 new, 1 on the path, 2 done
  std::vector<std::size_t> order, path;
  std::function<void(std::size_t)> visit = [&](std::size_t i) {
    if (state[i] == 2) return;
    if (state[i] == 1) {
      std::string cycle;
      bool on = false;
      for (std::size_t p : path) {
        if (p == i) on = true;
        if (on) cycle += src.definitions[p].first + " -> ";
      }
      cycle += src.definitions[i].first;
      const ExprText& e = src.definitions[i].second;
      fail(e.where, e.key, "the definitions refer to each other in a cycle: " + cycle);
    }
    state[i] = 1;
    path.push_back(i);
    for (const std::string& name : names_used(src.definitions[i].second.text)) {
      auto it = index.find(name);
      if (it != index.end()) visit(it->second);
    }
    path.pop_back();
    state[i] = 2;
    order.push_back(i);
  };
  for (std::size_t i = 0; i < src.definitions.size(); ++i) visit(i);
  return order;
}

// γ of a row w = g q̇ + g0 (q̇ held fixed): Σ_l ∂w/∂q_l q̇_l + ∂w/∂t.
ex along_motion(Calculus& calc, const ex& w, const SymbolicModel& m) {
  ex out = calc.diff(w, m.t);
  for (int l : used_indices(calc, w, m.q)) out += calc.diff(w, m.q[l]) * m.qd[l];
  return out;
}

}  // namespace

// The largest h_j (distinct expression nodes) that velocity_terms = "expanded" expands.
constexpr std::size_t kMaxExpandedVelocityTerms = 300;

// h_j expanded in the velocities only: every subexpression that mentions no velocity (through
// the definitions) stands in as one opaque symbol, the rest is expanded and the stand-ins put
// back. Multiplication is distributed over sums of velocity terms only, and like terms combine
// only where their velocity-free coefficients are the same expression: c − c cancels and c + c
// doubles exactly, while a difference of coordinates such as (x − 1000) stays as written (no
// cancellation is introduced). The terms of along_motion(p_j) and ∂T/∂q_j that cancel (the
// sieve's −m2 θ̇ (ẋ cos θ − ẏ sin θ) − m2 θ̇ (ẏ sin θ − ẋ cos θ)) so vanish before the tape.
class VelocityExpansion {
 public:
  VelocityExpansion(Calculus& calc, const std::vector<ex>& qd) : calc_(calc) {
    for (const ex& v : qd) velocities_.insert(symbol_name(v));
  }
  ex operator()(const ex& e) {
    GiNaC::exmap back;
    const ex atomized = atomize(e);
    for (const auto& [original, stand_in] : atoms_) back[stand_in] = original;
    const ex out = atomized.expand().subs(back, GiNaC::subs_options::no_pattern);
    atoms_.clear();
    return out;
  }
  // The number of distinct nodes of e (a tape's size before its own sharing).
  static std::size_t size(const ex& e) {
    std::unordered_set<ex, ExHash, GiNaC::ex_is_equal> seen;
    std::vector<ex> stack{e};
    while (!stack.empty()) {
      const ex x = stack.back();
      stack.pop_back();
      if (!seen.insert(x).second) continue;
      for (std::size_t i = 0; i < x.nops(); ++i) stack.push_back(x.op(i));
    }
    return seen.size();
  }

 private:
  bool has_velocity(const ex& e) {
    for (const std::string& name : calc_.symbols(e))
      if (velocities_.count(name)) return true;
    return false;
  }
  ex atomize(const ex& e) {
    if (GiNaC::is_a<GiNaC::numeric>(e) || GiNaC::is_a<GiNaC::symbol>(e)) return e;
    if (!has_velocity(e)) return stand_in(e);
    if (is_group(e)) return atomize(e.op(0));
    if (GiNaC::is_a<GiNaC::add>(e) || GiNaC::is_a<GiNaC::mul>(e)) {
      GiNaC::exvector ops;
      for (std::size_t i = 0; i < e.nops(); ++i) ops.push_back(atomize(e.op(i)));
      if (GiNaC::is_a<GiNaC::add>(e)) return GiNaC::dynallocate<GiNaC::add>(std::move(ops));
      return GiNaC::dynallocate<GiNaC::mul>(std::move(ops));
    }
    if (GiNaC::is_a<GiNaC::power>(e) && GiNaC::is_a<GiNaC::numeric>(e.op(1)) &&
        GiNaC::ex_to<GiNaC::numeric>(e.op(1)).is_pos_integer())
      return GiNaC::pow(atomize(e.op(0)), e.op(1));
    return stand_in(e);  // a function of the velocities: kept whole
  }
  ex stand_in(const ex& e) {
    auto it = atoms_.find(e);
    if (it != atoms_.end()) return it->second;
    const ex s = GiNaC::symbol("pcsim_atom_" + std::to_string(serial_++));
    atoms_.emplace(e, s);
    return s;
  }
  Calculus& calc_;
  std::unordered_set<std::string> velocities_;
  std::unordered_map<ex, ex, ExHash, GiNaC::ex_is_equal> atoms_;
  std::size_t serial_ = 0;
};

// The largest structural degree of T in the velocities that the derivation expands to decide
// whether T is quadratic (cancellations such as (x_d + 1)^3 - x_d^3 - 3*x_d^2 are found up to it).
constexpr long kExpandableDegree = 8;

// T uses the velocities only in sums, products and natural powers (detail::check_polynomial_in),
// also where they reach T through definitions, which stay symbols: every definition that T uses,
// directly or through other definitions, is checked the same way, the definitions that use a
// velocity counting as velocities. (A definition's value is the text its user wrote, so this
// walks each one once.)
static void check_kinetic_structure(Calculus& calc, const SymbolicModel& m, const ExprText& kinetic) {
  std::unordered_map<std::string, ex> value_of;
  std::vector<ex> velocities = m.qd;
  for (const auto& [symbol, value] : m.definitions) {
    value_of.emplace(symbol_name(symbol), value);
    if (first_used(calc, value, m.qd) >= 0) velocities.push_back(symbol);
  }
  detail::check_polynomial_in(m.T, velocities, kinetic, "the kinetic energy T");
  std::unordered_set<std::string> seen;
  std::vector<ex> work{m.T};
  while (!work.empty()) {
    const ex e = work.back();
    work.pop_back();
    for (auto it = e.preorder_begin(); it != e.preorder_end(); ++it) {
      if (!GiNaC::is_a<GiNaC::symbol>(*it)) continue;
      const std::string name = symbol_name(*it);
      const auto def = value_of.find(name);
      if (def == value_of.end() || !seen.insert(name).second) continue;
      if (first_used(calc, def->second, m.qd) >= 0) {
        detail::check_polynomial_in(def->second, velocities, kinetic,
                                    "the kinetic energy T (through the definition '" + name + "')");
      }
      work.push_back(def->second);
    }
  }
  // An upper bound of T's degree in the velocities from its structure: sums take the largest
  // degree, products the sum, natural powers n times the base's, definitions their value's
  // (velocities appear in nothing else: checked above). The degree test of the derivation below
  // expands; a polynomial of a high degree (a quadratic form to the 435th power) would take
  // minutes to expand, so a bound above kExpandableDegree is refused as it stands.
  std::unordered_map<std::string, long> definition_degree;
  std::function<long(const ex&)> degree = [&](const ex& e) -> long {
    if (GiNaC::is_a<GiNaC::symbol>(e)) {
      const std::string name = symbol_name(e);
      for (const ex& v : m.qd)
        if (e.is_equal(v)) return 1;
      const auto def = value_of.find(name);
      if (def == value_of.end()) return 0;
      const auto known = definition_degree.find(name);
      if (known != definition_degree.end()) return known->second;
      const long d = degree(def->second);
      definition_degree.emplace(name, d);
      return d;
    }
    if (GiNaC::is_a<GiNaC::add>(e) || GiNaC::is_a<GiNaC::mul>(e)) {
      long d = 0;
      for (std::size_t i = 0; i < e.nops(); ++i) {
        const long di = degree(e.op(i));
        d = GiNaC::is_a<GiNaC::add>(e) ? std::max(d, di) : std::min(d + di, 1L << 40);
      }
      return d;
    }
    if (GiNaC::is_a<GiNaC::power>(e)) {
      const long base = degree(e.op(0));
      if (base == 0 || !GiNaC::is_a<GiNaC::numeric>(e.op(1))) return 0;
      return std::min(base * GiNaC::ex_to<GiNaC::numeric>(e.op(1)).to_long(), 1L << 40);
    }
    return 0;
  };
  const long bound = degree(m.T);
  if (bound > kExpandableDegree) {
    fail(kinetic.where, kinetic.key,
         "the kinetic energy T must be quadratic in the velocities, but as written it is a "
         "polynomial of degree up to " + std::to_string(bound) + " in them (pcsim looks for "
         "cancellations only up to degree " + std::to_string(kExpandableDegree) + ")");
  }
}

SymbolicModel derive(const ModelSource& src) {
  SymbolicModel m;
  Calculus calc;
  const int n = static_cast<int>(src.coordinates.size());
  m.n = n;
  ExpressionParser base;
  for (const std::string& c : src.coordinates) {
    m.q.push_back(GiNaC::realsymbol(c));
    m.qd.push_back(GiNaC::realsymbol(c + "_d"));
    m.qdd.push_back(GiNaC::realsymbol(c + "_dd"));
    m.R.push_back(GiNaC::realsymbol("R_" + c));
    base.define(c, m.q.back());
    base.define(c + "_d", m.qd.back());
  }
  m.t = GiNaC::realsymbol("t");
  base.define("t", m.t);
  for (const ParameterSpec& p : src.parameters) {
    m.parameters.push_back(GiNaC::realsymbol(p.name));
    base.define(p.name, m.parameters.back());
  }
  // Outputs may also use the reactions and the accelerations, and so may definitions that
  // only outputs use.
  ExpressionParser out = base;
  for (int i = 0; i < n; ++i) {
    out.define("R_" + src.coordinates[i], m.R[i]);
    out.define(src.coordinates[i] + "_dd", m.qdd[i]);
  }
  // The multiplier of each constraint (issue 22): R = gᵀ λ; NaN while the constraint is off.
  for (const auto& c : src.constraints) {
    m.lambda.push_back(GiNaC::realsymbol("lambda_" + c.spec.name));
    out.define("lambda_" + c.spec.name, m.lambda.back());
  }
  base.add_hint({"lambda_", "", "the multipliers lambda_<constraint> may be used only in [" +
                                    (src.prefix.empty() ? std::string("outputs") : src.prefix + ".outputs") + "]"});
  const std::string outputs_key = src.prefix.empty() ? "outputs" : src.prefix + ".outputs";
  std::string coordinate_list;
  for (const auto& c : src.coordinates) coordinate_list += (coordinate_list.empty() ? "" : ", ") + c;
  out.add_hint({"R_", "", "R_<coordinate> is the reaction of a coordinate; the coordinates are " +
                              coordinate_list});
  out.add_hint({"", "_dd", "<coordinate>_dd is the acceleration of a coordinate; the coordinates "
                           "are " + coordinate_list});
  base.add_hint({"R_", "", "the reactions R_<coordinate> may be used only in [" + outputs_key + "]"});
  base.add_hint({"", "_dd", "the accelerations <coordinate>_dd may be used only in [" +
                                outputs_key + "]"});
  // Nesting depth of each definition's value, through the definitions it uses (the
  // derivation and the tape builder recurse that deep).
  std::unordered_map<std::string, int> definition_depth;
  std::function<int(const ex&)> depth_of = [&](const ex& e) -> int {
    if (GiNaC::is_a<GiNaC::symbol>(e)) {
      auto it = definition_depth.find(symbol_name(e));
      return it == definition_depth.end() ? 1 : it->second;
    }
    int d = 0;
    for (std::size_t i = 0; i < e.nops(); ++i) d = std::max(d, depth_of(e.op(i)));
    return d + 1;
  };
  for (std::size_t i : definition_order(src)) {
    const auto& [name, text] = src.definitions[i];
    const ex value = out.parse(text);
    const int depth = depth_of(value);
    if (depth > kMaxDefinitionDepth) {
      fail(text.where, text.key,
           "the definitions nest " + std::to_string(depth) + " levels deep here (through the "
           "definitions this one uses), more than the limit of " +
               std::to_string(kMaxDefinitionDepth) + " (the derivation recurses that deep)");
    }
    definition_depth[name] = depth;
    // The definition stays a symbol (evaluated once on the tape, as written).
    const ex symbol = GiNaC::realsymbol(name);
    m.definitions.emplace_back(symbol, value);
    calc.define(symbol, value);
    out.define(name, symbol);
    if (first_used(calc, value, m.R) >= 0 || first_used(calc, value, m.qdd) >= 0 ||
        first_used(calc, value, m.lambda) >= 0) {
      base.add_hint({name, "", "the definition '" + name + "' uses reactions or accelerations, "
                               "so only [" + outputs_key + "] may use it", true});
    } else {
      base.define(name, symbol);
    }
  }

  auto no_velocities = [&](const ex& e, const ExprText& text, const std::string& what) {
    const int k = first_used(calc, e, m.qd);
    if (k >= 0) {
      fail(text.where, text.key, what + " may not depend on the velocities (it uses " +
                                     symbol_name(m.qd[k]) + ")");
    }
  };

  // Energies and forces.
  m.T = base.parse(src.kinetic);
  check_kinetic_structure(calc, m, src.kinetic);
  m.V = src.potential.text.empty() ? ex(0) : base.parse(src.potential);
  no_velocities(m.V, src.potential, "the potential energy V(q, t)");
  m.F = src.dissipation.text.empty() ? ex(0) : base.parse(src.dissipation);
  std::vector<ex> applied(n, ex(0));
  for (const auto& [i, text] : src.forces) applied[i] = base.parse(text);

  // M, h: p_j = ∂T/∂q̇_j, M_jk = ∂p_j/∂q̇_k, h_j = Σ_k ∂p_j/∂q_k q̇_k + ∂p_j/∂t − ∂T/∂q_j.
  m.M.assign(n, std::vector<ex>(n, ex(0)));
  m.h.assign(n, ex(0));
  m.Q.assign(n, ex(0));
  // The derivatives keep the user's structure (no expansion): the tape evaluates them so.
  // A derivation past the budget is an input error of the expression being derived.
  auto within_budget = [&](const ExprText& where, const std::function<void()>& work) {
    try {
      work();
    } catch (const BudgetExceeded&) {
      fail(where.where, where.key,
           "deriving the model needs more than the derivation budget of " +
               std::to_string(kDerivationBudget) + " symbolic operations (the derivatives of \"" +
               where.text + "\" grow too large; use fewer or simpler chained definitions)");
    }
  };
  std::unordered_map<std::string, int> velocity_index;
  for (int l = 0; l < n; ++l) velocity_index[symbol_name(m.qd[l])] = l;
  // Term by term and only over the symbols each term contains (gradient()): the work grows
  // with the size of T, V and F, not with n times it.
  std::vector<ex> p(n, ex(0)), dTq(n, ex(0)), dV(n, ex(0)), dF(n, ex(0));
  within_budget(src.kinetic, [&] {
    for (auto& [j, pj] : gradient(calc, m.T, m.qd)) p[j] = pj;
    for (auto& [j, d] : gradient(calc, m.T, m.q)) dTq[j] = d;
  });
  within_budget(src.potential, [&] {
    for (auto& [j, d] : gradient(calc, m.V, m.q)) dV[j] = d;
  });
  within_budget(src.dissipation, [&] {
    for (auto& [j, d] : gradient(calc, m.F, m.qd)) dF[j] = d;
  });
  for (int j = 0; j < n; ++j) within_budget(src.kinetic, [&] {
    // M_jk (k >= j) for the velocities p_j mentions (the others are 0).
    for (int k : used_indices(calc, p[j], m.qd)) {
      if (k < j) continue;
      const ex Mjk = calc.diff(p[j], m.qd[k]);
      // The velocities Mjk mentions, in index order (few or none: not a scan of all n).
      std::vector<int> mentioned;
      for (const std::string& name : calc.symbols(Mjk)) {
        auto v = velocity_index.find(name);
        if (v != velocity_index.end()) mentioned.push_back(v->second);
      }
      std::sort(mentioned.begin(), mentioned.end());
      for (int l : mentioned) {
        if (!calc.inlined(calc.diff(Mjk, m.qd[l])).expand().is_zero()) {
          fail(src.kinetic.where, src.kinetic.key,
               "the kinetic energy T must be quadratic in the velocities (M = d2T/dqd2 "
               "independent of them), but d2T/(d" + symbol_name(m.qd[j]) + " d" +
                   symbol_name(m.qd[k]) + ") depends on " + symbol_name(m.qd[l]));
        }
      }
      m.M[j][k] = m.M[k][j] = Mjk;
    }
    m.h[j] = along_motion(calc, p[j], m) - dTq[j];
    // Kept only where it is smaller, and tried only on rows of moderate size: the expansion of
    // a long chain's products of sums (relative coordinates) would grow, not shrink.
    if (src.expand_velocity_terms && !m.h[j].is_zero()) {
      const std::size_t written = VelocityExpansion::size(m.h[j]);
      if (written <= kMaxExpandedVelocityTerms) {
        VelocityExpansion expand_velocities(calc, m.qd);
        const ex e = expand_velocities(m.h[j]);
        if (10 * VelocityExpansion::size(e) < 8 * written) m.h[j] = e;
      }
    }
  });
  for (int j = 0; j < n; ++j) m.Q[j] = -dV[j] - dF[j] + applied[j];

  // Constraints: rows g, g0 and γ = d/dt(g q̇ + g0) − g q̈.
  for (const SourceConstraint& sc : src.constraints) {
    SymbolicModel::Constraint c;
    ex w;
    if (sc.spec.kind == mech::ConstraintKind::holonomic) {
      const ex phi = base.parse(sc.holonomic);
      no_velocities(phi, sc.holonomic, "a holonomic constraint Phi(q, t)");
      if (first_used(calc, phi, m.q) < 0) {
        fail(sc.holonomic.where, sc.holonomic.key,
             "the constraint '" + sc.spec.name + "' involves no coordinate (\"" +
                 sc.holonomic.text + "\")");
      }
      c.holonomic = true;
      c.phi = phi;
      if (sc.spec.from_initial) {
        c.hidden = static_cast<int>(m.hidden.size());
        m.hidden.push_back(GiNaC::realsymbol("Phi0_" + sc.spec.name));
        c.phi = phi - m.hidden.back();
      }
      within_budget(sc.holonomic, [&] {
        c.g.assign(n, ex(0));
        for (int k : used_indices(calc, phi, m.q)) c.g[k] = calc.diff(phi, m.q[k]);
        c.g0 = calc.diff(phi, m.t);
      });
    } else {
      c.holonomic = false;
      c.phi = 0;
      c.g.assign(n, ex(0));
      bool any = false;
      for (const auto& [k, text] : sc.velocity) {
        c.g[k] = base.parse(text);
        no_velocities(c.g[k], text, "a velocity-form coefficient g(q, t)");
        any = any || !c.g[k].is_zero();
      }
      c.g0 = sc.velocity0.text.empty() ? ex(0) : base.parse(sc.velocity0);
      no_velocities(c.g0, sc.velocity0, "the velocity-form term g0(q, t)");
      if (!any) {
        fail(src.where, sc.key + ".velocity",
             "the constraint '" + sc.spec.name + "' involves no coordinate (every coefficient "
             "is zero)");
      }
    }
    w = c.g0;
    for (int k = 0; k < n; ++k)
      if (!c.g[k].is_zero()) w += c.g[k] * m.qd[k];
    within_budget(sc.holonomic.text.empty() ? ExprText{src.where, sc.key, ""} : sc.holonomic,
                  [&] { c.gamma = along_motion(calc, w, m); });
    c.constant_row = true;
    for (int k = 0; k < n; ++k) {
      if (c.g[k].is_zero()) continue;
      c.constant_row = c.constant_row && first_used(calc, c.g[k], m.q) < 0 && !calc.has(c.g[k], m.t);
    }
    // Contact attributes: numbers of the parameters only (evaluated once per instantiate()).
    auto parameter_only = [&](const ExprText& e, const char* what) -> std::optional<ex> {
      if (e.text.empty()) return std::nullopt;
      const ex v = base.parse(e);
      if (first_used(calc, v, m.q) >= 0 || first_used(calc, v, m.qd) >= 0 || calc.has(v, m.t))
        fail(e.where, e.key, std::string(what) + " must be an expression of the parameters only (\"" +
                                 e.text + "\")");
      return v;
    };
    c.restitution = parameter_only(sc.restitution, "the restitution coefficient");
    c.mu_static = parameter_only(sc.mu_static, "the static friction coefficient");
    c.mu_kinetic = parameter_only(sc.mu_kinetic, "the kinetic friction coefficient");
    m.constraints.push_back(std::move(c));
  }

  for (const auto& [name, text] : src.outputs) m.outputs.push_back(out.parse(text));

  if (src.period) {
    const ex period = base.parse(*src.period);
    if (first_used(calc, period, m.q) >= 0 || first_used(calc, period, m.qd) >= 0 ||
        calc.has(period, m.t)) {
      fail(src.period->where, src.period->key,
           "the period must be an expression of the parameters only (\"" + src.period->text +
               "\")");
    }
    m.period = period;
  }
  return m;
}

ex inline_definitions(const SymbolicModel& model, const ex& e) {
  Calculus calc;
  for (const auto& [symbol, value] : model.definitions) calc.define(symbol, value);
  return calc.inlined(e);
}

// ---- compilation into a tape ---------------------------------------------------------------

namespace {

struct NodeKey {
  Op op;
  std::uint32_t a, b;
  bool operator==(const NodeKey& o) const { return op == o.op && a == o.a && b == o.b; }
};
struct NodeKeyHash {
  std::size_t operator()(const NodeKey& k) const {
    std::size_t h = static_cast<std::size_t>(k.op);
    h = h * 1000003u ^ k.a;
    h = h * 1000003u ^ k.b;
    return h;
  }
};

class TapeBuilder {
 public:
  enum class Kind { instr, literal, parameter, hidden, input };
  struct Node {
    Kind kind;
    Op op = Op::add;
    std::uint32_t a = 0, b = 0;
    double value = 0.0;     // literal
    std::uint32_t index = 0;  // parameter, hidden or input index
    bool state = false;
  };
  std::vector<Node> nodes;

  explicit TapeBuilder(const SymbolicModel& m) {
    for (const auto& [symbol, value] : m.definitions) definitions_[symbol_name(symbol)] = value;
    zero = literal(0.0);
    one = literal(1.0);
    // Inputs in slot order: t, q, qd, qdd, R.
    std::uint32_t index = 0;
    auto input = [&](const ex& s) {
      Node node{Kind::input};
      node.index = index++;
      node.state = true;
      memo[s] = add_node(node);
    };
    input(m.t);
    for (const auto* v : {&m.q, &m.qd, &m.qdd, &m.R, &m.lambda}) {
      for (const ex& s : *v) input(s);
    }
    for (std::size_t i = 0; i < m.parameters.size(); ++i) {
      Node node{Kind::parameter};
      node.index = static_cast<std::uint32_t>(i);
      memo[m.parameters[i]] = add_node(node);
    }
    for (std::size_t i = 0; i < m.hidden.size(); ++i) {
      Node node{Kind::hidden};
      node.index = static_cast<std::uint32_t>(i);
      memo[m.hidden[i]] = add_node(node);
    }
  }

  std::uint32_t zero = 0, one = 0;

  std::uint32_t literal(double v) {
    std::uint64_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    if (v == 0.0) bits = 0;  // -0.0 and 0.0 are one literal
    auto it = literals_.find(bits);
    if (it != literals_.end()) return it->second;
    Node node{Kind::literal};
    node.value = v == 0.0 ? 0.0 : v;
    const std::uint32_t id = add_node(node);
    literals_[bits] = id;
    return id;
  }

  std::uint32_t op(Op o, std::uint32_t a, std::uint32_t b = 0) {
    // Fold operations on literals (GiNaC folds most numbers; this catches our own).
    const bool binary = takes_b(o);
    if (nodes[a].kind == Kind::literal && (!binary || nodes[b].kind == Kind::literal)) {
      double v[3] = {nodes[a].value, binary ? nodes[b].value : 0.0, 0.0};
      const Instr in{o, 2, 0, binary ? 1u : b};
      run(&in, 1, v);
      if (std::isfinite(v[2])) return literal(v[2]);
    }
    // -(-x) is x; -(x - y) is y - x (rounding is symmetric): the sign the primitive form of a
    // sum takes out often comes back.
    if (o == Op::neg && nodes[a].kind == Kind::instr) {
      if (nodes[a].op == Op::neg) return nodes[a].a;
      if (nodes[a].op == Op::sub) return op(Op::sub, nodes[a].b, nodes[a].a);
    }
    // Rewrites that IEEE arithmetic makes exact, so the tape's results keep every bit: x + (-y)
    // is x - y, x - (-y) is x + y, (-x)(-y) is x y; and a + b, a b are commutative, so one
    // operand order finds the copy of a sum or product that another definition formed in the
    // other order (the sieve written as bodies forms some twice).
    if (binary && nodes[b].kind == Kind::instr && nodes[b].op == Op::neg) {
      if (o == Op::add) return op(Op::sub, a, nodes[b].a);
      if (o == Op::sub) return op(Op::add, a, nodes[b].a);
    }
    if (o == Op::add && nodes[a].kind == Kind::instr && nodes[a].op == Op::neg)
      return op(Op::sub, b, nodes[a].a);
    if (o == Op::mul && nodes[a].kind == Kind::instr && nodes[a].op == Op::neg &&
        nodes[b].kind == Kind::instr && nodes[b].op == Op::neg)
      return op(Op::mul, nodes[a].a, nodes[b].a);
    if ((o == Op::add || o == Op::mul) &&
        (nodes[a].state != nodes[b].state ? nodes[a].state : a > b))  // constants first (finish)
      std::swap(a, b);
    const NodeKey key{o, a, binary || o == Op::powi ? b : 0};
    auto it = dedupe_.find(key);
    if (it != dedupe_.end()) return it->second;
    Node node{Kind::instr};
    node.op = o;
    node.a = a;
    node.b = key.b;
    node.state = nodes[a].state || (binary && nodes[b].state);
    const std::uint32_t id = add_node(node);
    dedupe_[key] = id;
    return id;
  }

  static bool takes_b(Op o) {
    switch (o) {
      case Op::add: case Op::sub: case Op::mul: case Op::div: case Op::pow: case Op::atan2:
      case Op::min: case Op::max:
        return true;
      default:
        return false;
    }
  }

  // A hash of e's structure made of names and numbers only. GiNaC orders the terms of sums and
  // the factors of products by hashes seeded with symbol serial numbers (which depend on how
  // many symbols the process made before) and type-name addresses (which change with address
  // space randomization), so its order differs from process to process (the expressions
  // themselves, as sets of operands, do not). The tape takes the operands of every sum and
  // product in the order of this hash instead: the same file gives the same tape, and
  // bit-identical results, in every process and on every load. The expressions are compiled
  // as the user wrote them and as differentiation made them, never expanded: expanding
  // (x - 1000)^3 into x^3 - 3000 x^2 + ... would cancel catastrophically.
  static std::uint64_t mix(std::uint64_t h, std::uint64_t v) {
    return (h ^ (v + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2))) * 0xff51afd7ed558ccdull;
  }
  static std::uint64_t number_hash(const GiNaC::numeric& n) {
    const double v = n.to_double();
    std::uint64_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    return mix(1, bits);
  }

  // shash is also blind to where GiNaC put a number or a sign: a sum hashes as its primitive
  // form (see primitive()) and its factor c, a product as its number (including the factors
  // of its sums) and its primitive factors. So -(a - b)*c and (b - a)*c hash alike (and
  // compile alike).
  std::uint64_t shash(const ex& e) {
    auto it = shash_memo_.find(e);
    if (it != shash_memo_.end()) return it->second;
    std::uint64_t h = 0;
    if (GiNaC::is_a<GiNaC::numeric>(e)) {
      h = number_hash(GiNaC::ex_to<GiNaC::numeric>(e));
    } else if (GiNaC::is_a<GiNaC::symbol>(e)) {
      h = mix(2, std::hash<std::string>()(symbol_name(e)));
    } else if (GiNaC::is_a<GiNaC::constant>(e)) {
      h = mix(3, e.is_equal(GiNaC::Pi) ? 1u : 2u);  // only pi is allowed
    } else if (is_group(e)) {
      h = shash(e.op(0));
    } else if (GiNaC::is_a<GiNaC::add>(e)) {
      const auto& [c, s] = primitive(e);
      h = mix(sum_hash(s), number_hash(c));
    } else if (GiNaC::is_a<GiNaC::mul>(e) || is_integer_power(e)) {
      GiNaC::numeric c = 1;
      std::vector<std::uint64_t> factors;
      auto factor = [&](const ex& f) {
        if (GiNaC::is_a<GiNaC::numeric>(f)) {
          c *= GiNaC::ex_to<GiNaC::numeric>(f);
        } else {
          factors.push_back(factor_key(f, &c));
        }
      };
      if (GiNaC::is_a<GiNaC::mul>(e)) {
        for (std::size_t i = 0; i < e.nops(); ++i) factor(e.op(i));
      } else {
        factor(e);
      }
      // A number times one grouped sum, k*pcsim_group(S), hashes as the sum k*S itself does
      // (the add and group branches): GiNaC keeps -pcsim_group(S) as a product but folds the
      // sign into the sum where nothing is held, so the same term reaches the tape in either
      // form from load to load.
      int others = 0;
      ex lone;
      if (GiNaC::is_a<GiNaC::mul>(e)) {
        for (std::size_t i = 0; i < e.nops(); ++i) {
          if (GiNaC::is_a<GiNaC::numeric>(e.op(i))) continue;
          ++others;
          lone = e.op(i);
        }
      }
      if (others == 1 && GiNaC::is_a<GiNaC::add>(unwrap(lone))) {
        GiNaC::numeric k = 1;
        for (std::size_t i = 0; i < e.nops(); ++i) {
          if (GiNaC::is_a<GiNaC::numeric>(e.op(i))) k *= GiNaC::ex_to<GiNaC::numeric>(e.op(i));
        }
        const auto& [cb, sp] = primitive(unwrap(lone));
        h = mix(sum_hash(sp), number_hash(k * cb));
      } else {
        std::sort(factors.begin(), factors.end());
        h = 6;
        for (std::uint64_t f : factors) h = mix(h, f);
        h = mix(h, number_hash(c));
      }
    } else {
      std::vector<std::uint64_t> children;
      for (std::size_t i = 0; i < e.nops(); ++i) children.push_back(shash(e.op(i)));
      std::uint64_t tag = 4;
      if (GiNaC::is_a<GiNaC::power>(e)) {
        tag = 7;
      } else if (GiNaC::is_a<GiNaC::function>(e)) {
        tag = mix(8, std::hash<std::string>()(GiNaC::ex_to<GiNaC::function>(e).get_name()));
      }
      h = tag;
      for (std::uint64_t ch : children) h = mix(h, ch);
    }
    shash_memo_.emplace(e, h);
    return h;
  }

  static bool is_integer_power(const ex& e) {
    if (!GiNaC::is_a<GiNaC::power>(e) || !GiNaC::is_a<GiNaC::numeric>(e.op(1))) return false;
    const GiNaC::numeric& k = GiNaC::ex_to<GiNaC::numeric>(e.op(1));
    return k.is_integer() && GiNaC::abs(k) < 1000;
  }

  // The hash of a non-numeric factor of a product without its number: a sum or an integer
  // power of a sum as its primitive form (the number, c^k, multiplies *c if c is given).
  std::uint64_t factor_key(const ex& f, GiNaC::numeric* c) {
    ex base = f;
    GiNaC::numeric k = 1;
    if (is_integer_power(f)) {
      base = f.op(0);
      k = GiNaC::ex_to<GiNaC::numeric>(f.op(1));
    }
    std::uint64_t b;
    base = unwrap(base);
    if (GiNaC::is_a<GiNaC::add>(base)) {
      const auto& [cb, s] = primitive(base);
      if (c) *c *= cb.power(k);
      b = sum_hash(s);
    } else {
      b = shash(base);
    }
    return mix(mix(7, b), number_hash(k));
  }

  // The hash of a sum from its terms (in any order).
  std::uint64_t sum_hash(const ex& s) {
    std::vector<std::uint64_t> terms;
    for (std::size_t i = 0; i < s.nops(); ++i) terms.push_back(shash(s.op(i)));
    std::sort(terms.begin(), terms.end());
    std::uint64_t h = 5;
    for (std::uint64_t t : terms) h = mix(h, t);
    return h;
  }

  // The operands of a sum or product in the order of shash.
  std::vector<ex> sorted_operands(const ex& e) {
    std::vector<std::pair<std::uint64_t, ex>> ops;
    for (std::size_t i = 0; i < e.nops(); ++i) ops.push_back({shash(e.op(i)), e.op(i)});
    std::stable_sort(ops.begin(), ops.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<ex> out;
    for (auto& p : ops) out.push_back(p.second);
    return out;
  }

  // e with every grouped sum that is a plain term of a sum (pcsim_group(S) or -pcsim_group(S))
  // melted into that sum. A group only keeps a number from being distributed over its sum (see
  // group_eval); as a term with coefficient ±1 it protects nothing, but whether the derivation
  // leaves one there depends on GiNaC's internal order, which changes from load to load (the
  // same force reached the tape as a + b + c once and as c + group(a + b) the next time).
  // Melted, every load gives the same sums, and so the same tape.
  ex melt_groups(const ex& e) {
    auto it = melt_memo_.find(e);
    if (it != melt_memo_.end()) return it->second;
    ex out;
    if (GiNaC::is_a<GiNaC::add>(e)) {
      GiNaC::exvector terms;
      bool changed = false;
      for (std::size_t i = 0; i < e.nops(); ++i) {
        const ex t = melt_groups(e.op(i));
        int sign = 0;
        ex inner;
        if (is_group(t)) {
          sign = 1;
          inner = t.op(0);
        } else if (GiNaC::is_a<GiNaC::mul>(t) && t.nops() == 2) {
          for (int j = 0; j < 2; ++j) {
            const ex& a = t.op(j);
            const ex& b = t.op(1 - j);
            if (GiNaC::is_a<GiNaC::numeric>(a) && a.is_equal(-1) && is_group(b)) {
              sign = -1;
              inner = b.op(0);
            }
          }
        }
        if (sign != 0 && GiNaC::is_a<GiNaC::add>(inner)) {
          for (std::size_t k = 0; k < inner.nops(); ++k) {
            terms.push_back(sign > 0 ? inner.op(k) : ex(-inner.op(k)));
          }
          changed = true;
        } else {
          if (!t.is_equal(e.op(i))) changed = true;
          terms.push_back(t);
        }
      }
      out = changed ? ex(GiNaC::dynallocate<GiNaC::add>(std::move(terms))) : e;
    } else if (e.nops() > 0 && !GiNaC::is_a<GiNaC::numeric>(e) && !GiNaC::is_a<GiNaC::symbol>(e)) {
      out = e.map(melter_);
    } else {
      out = e;
    }
    melt_memo_.emplace(e, out);
    return out;
  }

  std::uint32_t compile(const ex& e) {
    auto it = memo.find(e);
    if (it != memo.end()) return it->second;
    const std::uint32_t id = compile_new(e);
    memo.emplace(e, id);
    return id;
  }

 private:
  struct Melter : GiNaC::map_function {
    TapeBuilder* b;
    explicit Melter(TapeBuilder* tb) : b(tb) {}
    ex operator()(const ex& e) override { return b->melt_groups(e); }
  };
  Melter melter_{this};
  std::unordered_map<ex, ex, ExHash, GiNaC::ex_is_equal> melt_memo_;

  std::unordered_map<ex, std::uint32_t, ExHash, GiNaC::ex_is_equal> memo;
  std::unordered_map<std::string, ex> definitions_;
  std::unordered_map<NodeKey, std::uint32_t, NodeKeyHash> dedupe_;
  std::unordered_map<ex, std::uint64_t, ExHash, GiNaC::ex_is_equal> shash_memo_;
  std::unordered_map<ex, std::pair<GiNaC::numeric, ex>, ExHash, GiNaC::ex_is_equal> primitive_memo_;
  std::unordered_map<std::uint64_t, std::uint32_t> literals_;

  std::uint32_t add_node(const Node& node) {
    nodes.push_back(node);
    return static_cast<std::uint32_t>(nodes.size() - 1);
  }

  static double number(const ex& e) {
    const GiNaC::numeric& v = GiNaC::ex_to<GiNaC::numeric>(e);
    if (!v.is_real()) throw std::runtime_error("a complex number");
    return v.to_double();
  }

  // base^k for an integer k >= 1.
  std::uint32_t int_power(std::uint32_t base, long k) {
    switch (k) {
      case 1: return base;
      case 2: return op(Op::sqr, base);
      case 3: return op(Op::mul, op(Op::sqr, base), base);
      case 4: return op(Op::sqr, op(Op::sqr, base));
      default: return op(Op::powi, base, static_cast<std::uint32_t>(static_cast<std::int32_t>(k)));
    }
  }

  // base^exponent with the exponent a GiNaC expression.
  std::uint32_t power(const ex& base_ex, const ex& exponent) {
    const std::uint32_t base = compile(base_ex);
    if (GiNaC::is_a<GiNaC::numeric>(exponent)) {
      const GiNaC::numeric& k = GiNaC::ex_to<GiNaC::numeric>(exponent);
      if (k.is_integer() && GiNaC::abs(k) < 1000) {
        const long ki = k.to_long();
        if (ki == 0) return one;
        if (ki > 0) return int_power(base, ki);
        return op(Op::recip, int_power(base, -ki));
      }
      if (k.is_equal(GiNaC::numeric(1, 2))) return op(Op::sqrt, base);
      if (k.is_equal(GiNaC::numeric(-1, 2))) return op(Op::recip, op(Op::sqrt, base));
      return op(Op::pow, base, literal(number(exponent)));
    }
    return op(Op::pow, base, compile(exponent));
  }

  // A sum as c * s with c a rational number and s primitive: its coefficients integers without
  // a common factor (when they are rational), its sign fixed by shash (s or -s, whichever
  // hashes lower). Two reasons: GiNaC distributes a number over a sum (3*(x - 1000) becomes
  // 3*x - 3000, which loses the digits of x - 1000; here it is 3*(x - 1000) again, exactly),
  // and where the number and the sign of a product land depends on the order in which GiNaC
  // formed it (-(a - b)*c or (b - a)*c), which differs between processes; the primitive form
  // is the same in all.
  const std::pair<GiNaC::numeric, ex>& primitive(const ex& e) {
    auto it = primitive_memo_.find(e);
    if (it != primitive_memo_.end()) return it->second;
    GiNaC::numeric c = rational_content(e);
    ex s = c.is_equal(1) ? e : e / c;
    if (!GiNaC::is_a<GiNaC::add>(s)) {
      c = 1;
      s = e;
    }
    const ex negated = -s;
    if (GiNaC::is_a<GiNaC::add>(negated) && sum_hash(negated) < sum_hash(s)) {
      c = -c;
      s = negated;
    }
    return primitive_memo_.emplace(e, std::make_pair(c, s)).first->second;
  }

  // The largest positive rational c such that every coefficient of the sum e is an integer
  // multiple of c (gcd of the numerators over lcm of the denominators), or 1 if a coefficient
  // is not rational.
  static GiNaC::numeric rational_content(const ex& e) {
    GiNaC::numeric g = 0, l = 1;
    for (std::size_t i = 0; i < e.nops(); ++i) {
      const ex t = e.op(i);
      GiNaC::numeric c = 1;
      if (GiNaC::is_a<GiNaC::numeric>(t)) {
        c = GiNaC::ex_to<GiNaC::numeric>(t);
      } else if (GiNaC::is_a<GiNaC::mul>(t)) {
        for (std::size_t j = 0; j < t.nops(); ++j) {
          if (GiNaC::is_a<GiNaC::numeric>(t.op(j))) c *= GiNaC::ex_to<GiNaC::numeric>(t.op(j));
        }
      }
      if (!c.is_rational() || c.is_zero()) return 1;
      g = GiNaC::gcd(g, c.numer());
      l = GiNaC::lcm(l, c.denom());
    }
    if (g.is_zero()) return 1;
    const double v = (g / l).to_double();
    if (!(v >= 1e-300 && v <= 1e300)) return 1;  // a factor that is not a normal double
    return g / l;
  }

  std::uint32_t compile_new(const ex& e) {
    if (GiNaC::is_a<GiNaC::numeric>(e)) return literal(number(e));
    if (GiNaC::is_a<GiNaC::constant>(e)) {
      if (e.is_equal(GiNaC::Pi)) return literal(M_PI);
      throw std::runtime_error(std::string("the constant ") + GiNaC::ex_to<GiNaC::basic>(e).class_name());
    }
    if (GiNaC::is_a<GiNaC::symbol>(e)) {
      auto def = definitions_.find(symbol_name(e));
      if (def != definitions_.end()) return compile(def->second);  // once per definition
      throw std::runtime_error("the unknown symbol " + symbol_name(e));
    }
    if (GiNaC::is_a<GiNaC::add>(e)) {
      const auto& [c, primitive_sum] = primitive(e);
      if (!c.is_equal(1)) {
        const std::uint32_t inner = compile(primitive_sum);
        const double m = std::abs(c.to_double());
        return finish(Signed{c.is_negative(), m == 1.0 ? inner : op(Op::mul, literal(m), inner)});
      }
      std::vector<Monomial> terms;
      for (const ex& op : sorted_operands(e)) terms.push_back(monomial(op));
      return finish(sum(std::move(terms)));
    }
    if (GiNaC::is_a<GiNaC::mul>(e)) return finish(sum({monomial(e)}));
    if (is_integer_power(e)) return finish(sum({monomial(e)}));  // as in a product
    if (GiNaC::is_a<GiNaC::power>(e)) return power(e.op(0), e.op(1));
    if (GiNaC::is_a<GiNaC::function>(e)) {
      const GiNaC::function& f = GiNaC::ex_to<GiNaC::function>(e);
      const std::string name = f.get_name();
      const unsigned serial = f.get_serial();
      auto arg = [&](std::size_t i) { return compile(e.op(i)); };
      if (serial == group_serial()) return arg(0);
      if (serial == min_serial()) return op(Op::min, arg(0), arg(1));
      if (serial == max_serial()) return op(Op::max, arg(0), arg(1));
      if (serial == heaviside_serial()) return op(Op::step, arg(0));
      static const std::map<std::string, Op> unary = {
          {"sin", Op::sin},   {"cos", Op::cos},   {"tan", Op::tan},   {"asin", Op::asin},
          {"acos", Op::acos}, {"atan", Op::atan}, {"sinh", Op::sinh}, {"cosh", Op::cosh},
          {"tanh", Op::tanh}, {"exp", Op::exp},   {"log", Op::log},   {"abs", Op::abs}};
      auto u = unary.find(name);
      if (u != unary.end() && e.nops() == 1) return op(u->second, arg(0));
      if (name == "atan2" && e.nops() == 2) return op(Op::atan2, arg(0), arg(1));
      // Every expression is real: conjugate and real part are the identity.
      if ((name == "conjugate" || name == "real_part") && e.nops() == 1) return arg(0);
      if (name == "imag_part" && e.nops() == 1) return zero;
      throw std::runtime_error("the function " + name);
    }
    throw std::runtime_error(std::string("a ") + GiNaC::ex_to<GiNaC::basic>(e).class_name() + " object");
  }

  // A term of a sum: sign * K * Π base^exponent, K the parameter-only factors (one constant,
  // computed in the prelude) and the bases state-dependent nodes (negative exponents divide).
  struct Monomial {
    bool negative = false;
    std::uint32_t K = 0;
    bool have_K = false;
    std::map<std::uint32_t, int> state;  // base node -> exponent (by node id: deterministic)
  };
  // A node with a sign still to apply (so sums use sub instead of neg + add).
  struct Signed {
    bool negative;
    std::uint32_t node;
  };

  Monomial monomial(const ex& e) {
    Monomial m;
    GiNaC::numeric c = 1;  // exact: the same number whatever the order of the factors
    std::vector<std::uint32_t> knum, kden;
    // A sum's number and sign (primitive()) join the term's number: the same term however
    // GiNaC placed them.
    auto base_of = [&](const ex& grouped, const GiNaC::numeric& k) -> std::uint32_t {
      const ex b = unwrap(grouped);
      if (!GiNaC::is_a<GiNaC::add>(b)) return compile(b);
      const auto& [cb, s] = primitive(b);
      const GiNaC::numeric ck = cb.power(k);
      const double v = ck.to_double();
      if (!(std::abs(v) >= 1e-300 && std::abs(v) <= 1e300)) return compile(b);
      c *= ck;
      return compile(s);
    };
    auto factor = [&](const ex& f) {
      if (GiNaC::is_a<GiNaC::numeric>(f)) {
        (void)number(f);  // a real number
        c *= GiNaC::ex_to<GiNaC::numeric>(f);
        return;
      }
      if (GiNaC::is_a<GiNaC::power>(f) && GiNaC::is_a<GiNaC::numeric>(f.op(1))) {
        const GiNaC::numeric& k = GiNaC::ex_to<GiNaC::numeric>(f.op(1));
        if (k.is_integer() && GiNaC::abs(k) < 1000) {
          const std::uint32_t base = base_of(f.op(0), k);
          const int ki = static_cast<int>(k.to_long());
          if (nodes[base].state) {
            m.state[base] += ki;
          } else {
            (ki > 0 ? knum : kden).push_back(int_power(base, std::abs(ki)));
          }
          return;
        }
        if (k.is_negative()) {  // x^(-1/2) and the like: a denominator
          const std::uint32_t d = power(f.op(0), -f.op(1));
          if (nodes[d].state) {
            m.state[d] -= 1;
          } else {
            kden.push_back(d);
          }
          return;
        }
      }
      const std::uint32_t x = base_of(f, 1);
      if (nodes[x].state) {
        m.state[x] += 1;
      } else {
        knum.push_back(x);
      }
    };
    if (GiNaC::is_a<GiNaC::mul>(e)) {
      std::vector<std::pair<std::uint64_t, ex>> factors;
      for (std::size_t i = 0; i < e.nops(); ++i) {
        const ex f = e.op(i);
        factors.push_back({GiNaC::is_a<GiNaC::numeric>(f) ? 0 : factor_key(f, nullptr), f});
      }
      std::stable_sort(factors.begin(), factors.end(),
                       [](const auto& a, const auto& b) { return a.first < b.first; });
      for (const auto& f : factors) factor(f.second);
    } else {
      factor(e);
    }
    for (auto it = m.state.begin(); it != m.state.end();) {
      it = it->second == 0 ? m.state.erase(it) : std::next(it);
    }
    m.negative = c.is_negative();
    const double magnitude = std::abs(c.to_double());
    std::uint32_t K = 0;
    bool have = quotient(knum, kden, K);
    if (magnitude != 1.0) {
      K = have ? op(Op::mul, literal(magnitude), K) : literal(magnitude);
      have = true;
    }
    if (!have && m.state.empty()) {
      K = one;
      have = true;
    }
    m.K = K;
    m.have_K = have;
    return m;
  }

  std::uint32_t product(const std::vector<std::uint32_t>& f) {
    std::uint32_t p = f[0];
    for (std::size_t i = 1; i < f.size(); ++i) p = op(Op::mul, p, f[i]);
    return p;
  }
  bool quotient(const std::vector<std::uint32_t>& num, const std::vector<std::uint32_t>& den,
                std::uint32_t& out) {
    if (num.empty() && den.empty()) return false;
    if (den.empty()) {
      out = product(num);
    } else {
      out = num.empty() ? op(Op::recip, product(den)) : op(Op::div, product(num), product(den));
    }
    return true;
  }

  // One monomial as a node: K * (Π positive powers) / (Π negative powers).
  Signed single(const Monomial& m) {
    std::vector<std::uint32_t> num, den;
    for (const auto& [base, k] : m.state) (k > 0 ? num : den).push_back(int_power(base, std::abs(k)));
    std::uint32_t S = 0;
    const bool have_S = quotient(num, den, S);
    if (m.have_K && have_S) return {m.negative, op(Op::mul, m.K, S)};
    return {m.negative, have_S ? S : m.K};
  }

  Signed add_signed(Signed a, Signed b) {
    if (a.negative == b.negative) return {a.negative, op(Op::add, a.node, b.node)};
    return a.negative ? Signed{false, op(Op::sub, b.node, a.node)}
                      : Signed{false, op(Op::sub, a.node, b.node)};
  }

  // A sum of monomials, factored greedily (multivariate Horner): the state base that occurs
  // in most terms is taken out, b * (Σ those terms / b) + Σ the others, recursively; terms
  // without state factors add up to one prelude constant. Expanded expressions (whose form
  // does not depend on GiNaC's internal order) get back most of their factored form this way.
  Signed sum(std::vector<Monomial> terms) {
    if (terms.empty()) return {false, zero};
    std::map<std::uint32_t, int> count;
    for (const Monomial& m : terms) {
      for (const auto& [base, k] : m.state) {
        if (k > 0) ++count[base];
      }
    }
    std::uint32_t best = 0;
    int best_count = 1;
    for (const auto& [base, n] : count) {
      if (n > best_count) {
        best = base;
        best_count = n;
      }
    }
    if (best_count >= 2) {
      std::vector<Monomial> with, rest;
      for (Monomial& m : terms) {
        auto it = m.state.find(best);
        if (it != m.state.end() && it->second > 0) {
          if (--it->second == 0) m.state.erase(it);
          if (!m.have_K && m.state.empty()) {
            m.K = one;
            m.have_K = true;
          }
          with.push_back(std::move(m));
        } else {
          rest.push_back(std::move(m));
        }
      }
      const Signed inner = sum(std::move(with));
      const Signed factored{inner.negative, op(Op::mul, best, inner.node)};
      if (rest.empty()) return factored;
      return add_signed(factored, sum(std::move(rest)));
    }
    // No shared factor: constant terms first (they fold into one prelude constant), then the
    // state terms, positive ones first.
    std::vector<Signed> parts;
    for (const Monomial& m : terms) parts.push_back(single(m));
    std::stable_sort(parts.begin(), parts.end(), [this](const Signed& a, const Signed& b) {
      const int ra = nodes[a.node].state ? (a.negative ? 2 : 1) : 0;
      const int rb = nodes[b.node].state ? (b.negative ? 2 : 1) : 0;
      return ra < rb;
    });
    Signed acc = parts[0];
    for (std::size_t i = 1; i < parts.size(); ++i) acc = add_signed(acc, parts[i]);
    return acc;
  }

  // Applies the sign; −(K * S) with a constant K becomes (−K) * S (the negation in the prelude).
  std::uint32_t finish(Signed s) {
    if (!s.negative) return s.node;
    const Node& n = nodes[s.node];
    if (n.kind == Kind::instr && n.op == Op::mul && !nodes[n.a].state) {
      return op(Op::mul, op(Op::neg, n.a), n.b);
    }
    return op(Op::neg, s.node);
  }
};

}  // namespace

std::shared_ptr<CompiledModel> compile_tape(const SymbolicModel& m, const ModelSource& src) {
  auto out = std::make_shared<CompiledModel>();
  CompiledModel& c = *out;
  const int n = m.n;
  c.name = src.name;
  c.coordinates = src.coordinates;
  for (const auto& [name, text] : src.outputs) c.output_names.push_back(name);
  for (std::size_t i = 0; i < src.constraints.size(); ++i) {
    const SourceConstraint& sc = src.constraints[i];
    mech::ConstraintInfo info{sc.spec.name, sc.spec.kind, m.constraints[i].constant_row};
    info.contact.unilateral = sc.spec.unilateral;
    info.contact.gap_sign = sc.spec.gap_sign;
    info.contact.friction_of = sc.friction_of;
    info.contact.rough = sc.spec.rough;
    c.constraints.push_back(info);
  }

  TapeBuilder b(m);
  auto compile = [&](const ex& e, const ExprText& where) {
    try {
      return b.compile(b.melt_groups(e));
    } catch (const std::runtime_error& err) {
      fail(where.where, where.key, std::string("cannot evaluate ") + err.what() +
                                       " (from \"" + where.text + "\")");
    }
  };
  // Result node lists, one per block.
  std::vector<std::vector<std::uint32_t>> blocks;
  {
    std::vector<std::uint32_t> kin;
    for (int i = 0; i < n; ++i) {
      for (int j = i; j < n; ++j) kin.push_back(compile(m.M[i][j], src.kinetic));
    }
    for (int i = 0; i < n; ++i) kin.push_back(compile(m.h[i], src.kinetic));
    c.kinetic_block = static_cast<int>(blocks.size());
    blocks.push_back(std::move(kin));
  }
  {
    std::vector<std::uint32_t> forces;
    const ExprText& where = src.potential.text.empty() ? src.kinetic : src.potential;
    for (int i = 0; i < n; ++i) forces.push_back(compile(m.Q[i], where));
    c.forces_block = static_cast<int>(blocks.size());
    blocks.push_back(std::move(forces));
  }
  {
    std::vector<std::uint32_t> outs;
    for (std::size_t i = 0; i < m.outputs.size(); ++i) {
      outs.push_back(compile(m.outputs[i], src.outputs[i].second));
    }
    c.outputs_block = static_cast<int>(blocks.size());
    blocks.push_back(std::move(outs));
  }
  for (std::size_t i = 0; i < m.constraints.size(); ++i) {
    const auto& mc = m.constraints[i];
    const SourceConstraint& sc = src.constraints[i];
    const ExprText where = mc.holonomic ? sc.holonomic : ExprText{src.where, sc.key, ""};
    CompiledModel::ConstraintBlocks cb;
    std::vector<std::uint32_t> rows;
    for (int k = 0; k < n; ++k) rows.push_back(compile(mc.g[k], where));
    rows.push_back(compile(mc.g0, where));
    rows.push_back(compile(mc.gamma, where));
    cb.rows = static_cast<int>(blocks.size());
    blocks.push_back(std::move(rows));
    if (mc.holonomic) {
      cb.position = static_cast<int>(blocks.size());
      blocks.push_back({compile(mc.phi, where)});
    }
    cb.hidden = mc.hidden;
    c.constraint_blocks.push_back(cb);
  }
  std::int64_t period_node = -1;
  if (m.period) period_node = compile(*m.period, *src.period);
  // Contact attributes: parameter-only nodes (prelude), read by ExpressionModel's constructor.
  std::vector<std::array<std::int64_t, 3>> contact_nodes(m.constraints.size(), {-1, -1, -1});
  for (std::size_t i = 0; i < m.constraints.size(); ++i) {
    const auto& mc = m.constraints[i];
    const SourceConstraint& sc = src.constraints[i];
    if (mc.restitution) contact_nodes[i][0] = compile(*mc.restitution, sc.restitution);
    if (mc.mu_static) contact_nodes[i][1] = compile(*mc.mu_static, sc.mu_static);
    if (mc.mu_kinetic) contact_nodes[i][2] = compile(*mc.mu_kinetic, sc.mu_kinetic);
  }

  // Which nodes are needed: a reverse sweep per block (operands have smaller ids).
  const std::size_t N = b.nodes.size();
  std::vector<char> used_any(N, 0);
  std::vector<std::vector<char>> used(blocks.size());
  auto mark = [&](std::vector<char>& flags, const std::vector<std::uint32_t>& roots) {
    flags.assign(N, 0);
    for (std::uint32_t r : roots) flags[r] = 1;
    for (std::size_t id = N; id-- > 0;) {
      if (!flags[id]) continue;
      used_any[id] = 1;
      const auto& node = b.nodes[id];
      if (node.kind != TapeBuilder::Kind::instr) continue;
      flags[node.a] = 1;
      if (TapeBuilder::takes_b(node.op)) flags[node.b] = 1;
    }
  };
  for (std::size_t k = 0; k < blocks.size(); ++k) mark(used[k], blocks[k]);
  if (period_node >= 0) {
    std::vector<char> flags;
    mark(flags, {static_cast<std::uint32_t>(period_node)});
  }
  for (const auto& nodes : contact_nodes)
    for (std::int64_t node : nodes)
      if (node >= 0) {
        std::vector<char> flags;
        mark(flags, {static_cast<std::uint32_t>(node)});
      }

  // Slots: the constant region (literals, parameters, hidden, prelude), then the state region
  // (inputs t, q, qd, qdd, R, then the state temporaries).
  Tape& tape = c.tape;
  tape.n = n;
  std::vector<std::uint32_t> slot(N, 0);
  std::uint32_t next = 0;
  tape.parameter_slots.assign(m.parameters.size(), 0);
  tape.hidden_slots.assign(m.hidden.size(), 0);
  for (std::size_t id = 0; id < N; ++id) {
    const auto& node = b.nodes[id];
    switch (node.kind) {
      case TapeBuilder::Kind::literal:
        slot[id] = next++;
        tape.literals.push_back({slot[id], node.value});
        break;
      case TapeBuilder::Kind::parameter:
        slot[id] = next++;
        tape.parameter_slots[node.index] = slot[id];
        break;
      case TapeBuilder::Kind::hidden:
        slot[id] = next++;
        tape.hidden_slots[node.index] = slot[id];
        break;
      default: break;
    }
  }
  for (std::size_t id = 0; id < N; ++id) {
    const auto& node = b.nodes[id];
    if (node.kind == TapeBuilder::Kind::instr && !node.state && used_any[id]) slot[id] = next++;
  }
  tape.n_constant = next;
  tape.zero_slot = slot[b.zero];
  for (std::size_t id = 0; id < N; ++id) {
    const auto& node = b.nodes[id];
    if (node.kind == TapeBuilder::Kind::input) slot[id] = next + node.index;
  }
  tape.t_slot = next;
  tape.q_slot = next + 1;
  tape.qd_slot = tape.q_slot + n;
  tape.qdd_slot = tape.qd_slot + n;
  tape.R_slot = tape.qdd_slot + n;
  tape.lambda_slot = tape.R_slot + n;
  tape.n_lambda = static_cast<std::uint32_t>(m.lambda.size());
  next += 1 + 4 * n + tape.n_lambda;
  for (std::size_t id = 0; id < N; ++id) {
    const auto& node = b.nodes[id];
    if (node.kind == TapeBuilder::Kind::instr && node.state && used_any[id]) slot[id] = next++;
  }
  tape.n_slots = next;

  auto instr = [&](std::size_t id) {
    const auto& node = b.nodes[id];
    Instr in{node.op, slot[id], slot[node.a], 0};
    in.b = TapeBuilder::takes_b(node.op) ? slot[node.b] : node.b;
    return in;
  };
  for (std::size_t id = 0; id < N; ++id) {
    const auto& node = b.nodes[id];
    if (node.kind == TapeBuilder::Kind::instr && !node.state && used_any[id]) {
      tape.prelude.push_back(instr(id));
    }
  }
  // sin(x) and cos(x) of one x in one block: one sincos instruction, at the first of the two.
  std::unordered_map<std::uint32_t, std::uint32_t> sin_of, cos_of;  // operand node -> node
  for (std::size_t id = 0; id < N; ++id) {
    const auto& node = b.nodes[id];
    if (node.kind != TapeBuilder::Kind::instr || !node.state) continue;
    if (node.op == Op::sin) sin_of[node.a] = static_cast<std::uint32_t>(id);
    if (node.op == Op::cos) cos_of[node.a] = static_cast<std::uint32_t>(id);
  }
  for (std::size_t k = 0; k < blocks.size(); ++k) {
    Block block;
    std::vector<char> skip(N, 0);
    for (std::size_t id = 0; id < N; ++id) {
      const auto& node = b.nodes[id];
      if (!used[k][id] || node.kind != TapeBuilder::Kind::instr || !node.state || skip[id]) continue;
      if (node.op == Op::sin || node.op == Op::cos) {
        const auto& partner_map = node.op == Op::sin ? cos_of : sin_of;
        auto p = partner_map.find(node.a);
        if (p != partner_map.end() && used[k][p->second]) {
          const std::uint32_t s_id = node.op == Op::sin ? static_cast<std::uint32_t>(id) : p->second;
          const std::uint32_t c_id = node.op == Op::cos ? static_cast<std::uint32_t>(id) : p->second;
          block.code.push_back(Instr{Op::sincos, slot[s_id], slot[node.a], slot[c_id]});
          skip[p->second] = 1;
          continue;
        }
      }
      block.code.push_back(instr(id));
    }
    for (std::uint32_t r : blocks[k]) block.results.push_back(slot[r]);
    fuse_multiply_add(block.code, block.results);
    tape.blocks.push_back(std::move(block));
  }
  if (period_node >= 0) c.period_slot = slot[period_node];
  for (std::size_t i = 0; i < contact_nodes.size(); ++i)
    for (int k = 0; k < 3; ++k)
      if (contact_nodes[i][k] >= 0)
        c.constraint_blocks[i].contact_slots[k] = slot[contact_nodes[i][k]];
  c.index_entries();
  return out;
}

}  // namespace pcsim::modelfile::detail
