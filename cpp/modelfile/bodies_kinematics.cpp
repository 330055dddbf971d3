// Generated kinematic definitions of the body form beyond positions and velocities (issue 22;
// docs/bodies.md, "Generated definitions"): the angular velocity of each body (planar BODY_w;
// spatial BODY_wx, _wy, _wz in ground axes, BODY_w1..w3 in body axes exist already), its angular
// acceleration (BODY_alpha; BODY_alphax.._alphaz, BODY_alpha1..alpha3) and the acceleration of
// each marker (BODY_MARKER_ax, _ay, _az, ground axes).
//
// An acceleration is the total time derivative of the velocity's definition, taken
// symbolically by GiNaC with the chain rule through the definitions it uses:
//     d/dt f = Σ_l ∂f/∂q_l q̇_l + Σ_l ∂f/∂q̇_l q̈_l + ∂f/∂t + Σ_d ∂f/∂d · (d/dt d),
// where each definition d that f uses gets its own derivative as a definition (d_dt), so the
// texts stay as short as the velocities' (a chain of tree joints does not repeat its parents).
// The accelerations use <coordinate>_dd, so the derivation makes them usable in outputs only
// (symbolic.cpp: a definition that uses accelerations, reactions or multipliers is known only
// to [model.outputs]).
//
// They are generated LAZILY: only the names that the outputs, the definitions or the drawing
// use (and that the user has not defined), so a model that uses none loads exactly as before
// and no generated name can clash with a name of an existing model.
#include <map>
#include <mutex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <ginac/ginac.h>

#include "modelfile/bodies.hpp"
#include "modelfile/expression.hpp"

namespace pcsim::modelfile::bodies {

namespace {

// The total time derivative of definitions, as new definitions.
class TimeDerivatives {
 public:
  explicit TimeDerivatives(Expander& x) : x_(x), src_(x.source()) {
    for (const auto& c : src_.coordinates) {
      add(c, Kind::coordinate, c);
      add(c + "_d", Kind::velocity, c);
      add(c + "_dd", Kind::acceleration, c);
    }
    add("t", Kind::time, "");
    for (const auto& p : src_.parameters) add(p.name, Kind::parameter, "");
    for (std::size_t i = 0; i < src_.definitions.size(); ++i) {
      add(src_.definitions[i].first, Kind::definition, "");
      definition_index_[src_.definitions[i].first] = i;
    }
    pi_ = GiNaC::realsymbol("pi");
  }

  bool defined(const std::string& name) const { return definition_index_.count(name) != 0; }

  // Defines `name` as d/dt of the definition `of` ("0" if it vanishes: the user asked for it).
  void define_derivative(const std::string& of, const std::string& name, const std::string& key) {
    if (auto it = done_.find(of); it != done_.end()) {  // derived already, under another name
      define(name, it->second.is_zero() ? std::string("0") : GiNaC::ex_to<GiNaC::symbol>(it->second).get_name(), key);
      return;
    }
    preferred_[of] = name;
    const GiNaC::ex d = derivative_of(of, key);
    if (d.is_zero()) define(name, "0", key);
  }

  // Defines name = text (a new definition the derivatives may use in turn).
  void define(const std::string& name, const Expr& text, const std::string& key) {
    x_.define(name, text, key);
    add(name, Kind::definition, "");
    definition_index_[name] = src_.definitions.size() - 1;
  }

 private:
  enum class Kind { coordinate, velocity, acceleration, time, parameter, definition };
  struct Name {
    Kind kind;
    std::string coordinate;
    GiNaC::ex symbol;
  };

  void add(const std::string& name, Kind kind, const std::string& coordinate) {
    const GiNaC::ex s = GiNaC::realsymbol(name);
    names_[name] = Name{kind, coordinate, s};
    parser_.define(name, s);
  }

  // d/dt of the definition `name` as an expression: 0, or the symbol of its derivative's
  // definition (defined here on first use).
  GiNaC::ex derivative_of(const std::string& name, const std::string& key) {
    if (auto it = done_.find(name); it != done_.end()) return it->second;
    if (!busy_.insert(name).second)
      x_.fail(key, "definitions that do not use one another in a cycle (the time derivative of '" +
                       name + "' uses itself)");
    // A copy: defining the derivatives below grows src_.definitions.
    const detail::ExprText text = src_.definitions[definition_index_.at(name)].second;
    const GiNaC::ex value = parser_.parse(text);
    const GiNaC::ex d = total_derivative(value, text.key);
    busy_.erase(name);
    GiNaC::ex result = 0;
    if (!d.is_zero()) {
      std::string out;
      if (auto p = preferred_.find(name); p != preferred_.end()) {
        out = p->second;
      } else {
        out = name + "_dt";
        while (names_.count(out)) out += "_";
      }
      define(out, print(d, text), key);
      result = names_.at(out).symbol;
    }
    done_[name] = result;
    return result;
  }

  GiNaC::ex total_derivative(const GiNaC::ex& e, const std::string& key) {
    std::set<std::string> used;
    for (auto it = e.preorder_begin(); it != e.preorder_end(); ++it)
      if (GiNaC::is_a<GiNaC::symbol>(*it)) used.insert(GiNaC::ex_to<GiNaC::symbol>(*it).get_name());
    GiNaC::ex sum = 0;
    for (const std::string& n : used) {
      const auto it = names_.find(n);
      if (it == names_.end()) continue;
      const Name& nm = it->second;
      const GiNaC::symbol& s = GiNaC::ex_to<GiNaC::symbol>(nm.symbol);
      switch (nm.kind) {
        case Kind::coordinate:
          sum += e.diff(s) * names_.at(nm.coordinate + "_d").symbol;
          break;
        case Kind::velocity:
          sum += e.diff(s) * names_.at(nm.coordinate + "_dd").symbol;
          break;
        case Kind::acceleration:
          x_.fail(key, "an expression without accelerations (its time derivative would need the "
                       "third derivative of '" + nm.coordinate + "')");
        case Kind::time:
          sum += e.diff(s);
          break;
        case Kind::parameter:
          break;
        case Kind::definition: {
          const GiNaC::ex d = derivative_of(n, key);
          if (!d.is_zero()) sum += e.diff(s) * d;
          break;
        }
      }
    }
    return sum;
  }

  // The derivative in the model-file language (GiNaC prints π as Pi), checked by reading it
  // back: a function whose derivative the language cannot write (min, max: a step) is refused.
  std::string print(const GiNaC::ex& d, const detail::ExprText& of) {
    const std::string text = detail::canonical_text(d.subs(GiNaC::Pi == pi_));
    try {
      (void)parser_.parse(detail::ExprText{of.where, of.key, text});
    } catch (const InputError&) {
      x_.fail(of.key, "an expression whose time derivative the model-file language can write "
                      "(the acceleration derived from \"" + detail::shortened(of.text) +
                      "\" is \"" + detail::shortened(text) + "\")");
    }
    return text;
  }

  Expander& x_;
  detail::ModelSource& src_;
  detail::ExpressionParser parser_;
  std::map<std::string, Name> names_;
  std::map<std::string, std::size_t> definition_index_;
  std::map<std::string, std::string> preferred_;
  std::map<std::string, GiNaC::ex> done_;
  std::set<std::string> busy_;
  GiNaC::ex pi_;
};

// The names used by every string of a TOML node (the drawing), with the key of the first use.
void names_in(const toml::node& n, const std::string& key, std::map<std::string, std::string>& out) {
  if (auto s = n.as_string()) {
    for (const auto& name : detail::names_used(s->get())) out.emplace(name, key);
  } else if (auto t = n.as_table()) {
    for (auto&& [k, v] : *t) names_in(v, key + "." + std::string(k.str()), out);
  } else if (auto a = n.as_array()) {
    std::size_t i = 0;
    for (const auto& v : *a) names_in(v, key + "[" + std::to_string(++i) + "]", out);
  }
}

}  // namespace

void define_requested_kinematics(Expander& x, const toml::table& model) {
  detail::ModelSource& src = x.source();
  // What the outputs, the definitions and the drawing use.
  std::set<std::string> used;
  for (const auto& [name, text] : src.outputs)
    for (const auto& n : detail::names_used(text.text)) used.insert(n);
  for (const auto& [name, text] : src.definitions)
    for (const auto& n : detail::names_used(text.text)) used.insert(n);
  std::map<std::string, std::string> drawn;
  const std::string draw_key = (src.prefix.empty() ? std::string() : src.prefix + ".") + "draw";
  if (const toml::node* d = model.get("draw")) names_in(*d, draw_key, drawn);
  for (const auto& [n, k] : drawn) used.insert(n);
  if (used.empty()) return;

  std::set<std::string> defined;
  for (const auto& [name, text] : src.definitions) defined.insert(name);
  for (const auto& c : src.coordinates) defined.insert(c);
  auto wanted = [&](const std::string& n) { return used.count(n) && !defined.count(n); };

  // The accelerations first listed, checked against the drawing (which cannot use them).
  struct Derived {
    std::string name, of, key;
  };
  std::vector<Derived> derived;
  std::vector<std::pair<std::string, std::pair<Expr, std::string>>> plain;  // velocity-level
  const char* ax[3] = {"x", "y", "z"};
  for (const Body& b : x.bodies()) {
    if (b.ground) continue;
    const bool planar = x.kind(b).planar();
    if (planar && b.kind != "particle") {
      const std::string w = b.name + "_w", alpha = b.name + "_alpha";
      if (wanted(alpha)) derived.push_back({alpha, w, b.key});
      if ((wanted(w) || wanted(alpha)) && !defined.count(w))
        plain.push_back({w, {angular_velocity_text(b.pose)[2], b.key}});
    } else if (!planar) {
      for (int i = 0; i < 3; ++i) {
        const std::string wg = b.name + "_w" + ax[i], ag = b.name + "_alpha" + ax[i];
        const std::string wb = b.name + "_w" + std::to_string(i + 1), ab = b.name + "_alpha" + std::to_string(i + 1);
        if (wanted(ag)) derived.push_back({ag, wg, b.key});
        if (wanted(ab)) derived.push_back({ab, wb, b.key});
        if ((wanted(wg) || wanted(ag)) && !defined.count(wg)) {
          // ω = A ω' (ground = rotation · body axes), in the named entries and rates.
          std::vector<Expr> terms;
          for (int k = 0; k < 3; ++k) terms.push_back(mul(b.pose.A.m[i][k], b.name + "_w" + std::to_string(k + 1)));
          plain.push_back({wg, {sum(terms), b.key}});
        }
      }
    }
    for (const Marker& m : b.markers) {
      if (m.name == "origin") continue;
      for (int i = 0; i < (planar ? 2 : 3); ++i) {
        const std::string a = b.name + "_" + m.name + "_a" + ax[i];
        if (wanted(a)) derived.push_back({a, b.name + "_" + m.name + "_v" + ax[i], m.key});
      }
    }
  }
  for (const Derived& d : derived)
    if (auto it = drawn.find(d.name); it != drawn.end())
      x.fail(it->second, "an expression of positions and velocities ('" + d.name +
                             "' is an acceleration: [" + (src.prefix.empty() ? std::string("outputs") : src.prefix + ".outputs") +
                             "] may use it, a drawing may not)");
  if (derived.empty() && plain.empty()) return;

  std::lock_guard<std::mutex> lock(detail::ginac_mutex());
  for (const auto& [name, value] : plain) x.define(name, value.first, value.second);
  TimeDerivatives dt(x);
  for (const Derived& d : derived) dt.define_derivative(d.of, d.name, d.key);
}

}  // namespace pcsim::modelfile::bodies
