// Reading model files (TOML) and the ModelDescription (see model_file.hpp).
#include "modelfile/model_file.hpp"
#include "common/toml_guard.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <fstream>
#include <sstream>

#include "common/error.hpp"
#include "common/format.hpp"
#include "modelfile/bodies.hpp"
#include "modelfile/expression.hpp"
#include "modelfile/expression_model.hpp"
#include "modelfile/symbolic.hpp"
#include "modelfile/tape_io.hpp"

namespace pcsim::modelfile {

using detail::ExprText;
using detail::fail;
using detail::ModelSource;
using detail::SourceConstraint;

// ---- ParameterSpec ---------------------------------------------------------------------------

bool ParameterSpec::admits(double v) const {
  if (!std::isfinite(v)) return false;
  if (min_exclusive ? !(v > min) : !(v >= min)) return false;
  if (max_exclusive ? !(v < max) : !(v <= max)) return false;
  return true;
}

namespace {

std::string number_text(double v) {
  return format_number(v);  // the project's one formatter: shortest round trip
}

}  // namespace

std::string ParameterSpec::range_text() const {
  const bool has_min = std::isfinite(min), has_max = std::isfinite(max);
  if (!has_min && !has_max) return "a finite number";
  if (has_min && !has_max) {
    return std::string("a number ") + (min_exclusive ? "> " : ">= ") + number_text(min);
  }
  if (!has_min) return std::string("a number ") + (max_exclusive ? "< " : "<= ") + number_text(max);
  return std::string("a number in ") + (min_exclusive ? "(" : "[") + number_text(min) + ", " +
         number_text(max) + (max_exclusive ? ")" : "]");
}

// ---- reading the TOML table ------------------------------------------------------------------

namespace {

// The entries of a table in file order (toml++ keeps tables sorted by key; the source
// positions give the order of the file; tables built in memory keep key order).
std::vector<std::pair<std::string, const toml::node*>> in_file_order(const toml::table& t) {
  std::vector<std::pair<std::string, const toml::node*>> out;
  std::vector<std::pair<std::pair<toml::source_index, toml::source_index>, std::size_t>> pos;
  for (auto&& [k, v] : t) {
    pos.push_back({{k.source().begin.line, k.source().begin.column}, out.size()});
    out.push_back({std::string(k.str()), &v});
  }
  std::stable_sort(pos.begin(), pos.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<std::pair<std::string, const toml::node*>> sorted;
  for (const auto& p : pos) sorted.push_back(out[p.second]);
  return sorted;
}

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
  return s;
}

class Reader {
 public:
  Reader(std::string where, std::string prefix) : where_(std::move(where)), prefix_(std::move(prefix)) {}

  std::string key(const std::string& k) const { return prefix_.empty() ? k : prefix_ + "." + k; }
  const std::string& where() const { return where_; }

  void only(const toml::table& t, const std::string& table_key,
            const std::vector<std::string>& allowed) const {
    for (auto&& [k, v] : t) {
      const std::string name(k.str());
      if (std::find(allowed.begin(), allowed.end(), name) == allowed.end()) {
        fail(where_, table_key + "." + name, "unknown key (expected one of: " + join(allowed) + ")");
      }
    }
  }

  const toml::table& table(const toml::node& node, const std::string& k) const {
    if (!node.is_table()) fail(where_, k, "a table");
    return *node.as_table();
  }

  double number(const toml::node& node, const std::string& k) const {
    double v;
    if (auto i = node.as_integer()) {
      v = static_cast<double>(i->get());
    } else if (auto f = node.as_floating_point()) {
      v = f->get();
    } else {
      fail(where_, k, "a number");
    }
    if (!std::isfinite(v)) fail(where_, k, "a finite number, got " + number_text(v));
    return v;
  }

  bool boolean(const toml::node& node, const std::string& k) const {
    if (auto b = node.as_boolean()) return b->get();
    fail(where_, k, "a boolean (true or false)");
  }

  std::string string(const toml::node& node, const std::string& k, const std::string& what) const {
    if (auto s = node.as_string()) return s->get();
    fail(where_, k, what);
  }

  /// An expression: a string, or a number (a constant expression).
  ExprText expression(const toml::node& node, const std::string& k) const {
    ExprText e{where_, k, ""};
    if (auto s = node.as_string()) {
      e.text = s->get();
      if (e.text.find_first_not_of(" \t\r\n") == std::string::npos) {
        fail(where_, k, "an expression, got an empty string");
      }
      detail::check_expression_size(e);
    } else if (node.is_number()) {
      e.text = number_text(number(node, k));
    } else {
      fail(where_, k, "an expression (a string such as \"0.5*m*x_d^2\") or a number");
    }
    return e;
  }

  /// A declared name: an identifier that is not reserved.
  void name(const std::string& n, const std::string& k) const {
    if (n.size() > detail::limits::name_length) {
      fail(where_, detail::shortened(k), "a name of at most " + std::to_string(detail::limits::name_length) +
                          " characters, got " + std::to_string(n.size()) + " ('" +
                          detail::shortened(n) + "')");
    }
    if (!detail::is_identifier(n)) {
      fail(where_, k, "a name of letters, digits and '_' not starting with a digit, got '" +
                          detail::shortened(n) + "'");
    }
    if (detail::is_reserved_name(n)) {
      fail(where_, k, "'" + n + "' is reserved (a function name, t, pi, residual_pos or "
                      "residual_vel); choose another name");
    }
  }

  /// At most `limit` entries of a list or table (checked before any is read).
  void count(std::size_t n, std::size_t limit, const std::string& k, const std::string& what) const {
    if (n > limit) {
      fail(where_, k, "at most " + std::to_string(limit) + " " + what + ", got " +
                          std::to_string(n));
    }
  }

 private:
  std::string where_, prefix_;
};

ParameterSpec read_parameter(const Reader& r, const std::string& name, const toml::node& node,
                             const std::string& k) {
  ParameterSpec p;
  p.name = name;
  if (!node.is_table()) {
    if (!node.is_number()) {
      fail(r.where(), k, "a number (the default value, SI) or a table { value = ..., unit = ... }");
    }
    p.value = r.number(node, k);
    return p;
  }
  const toml::table& t = *node.as_table();
  r.only(t, k, {"value", "unit", "meaning", "min", "max", "min_exclusive", "max_exclusive",
                "positive"});
  const toml::node* value = t.get("value");
  if (!value) fail(r.where(), k + ".value", "the parameter's value (a number); it has none");
  p.value = r.number(*value, k + ".value");
  if (auto n = t.get("unit")) p.unit = r.string(*n, k + ".unit", "a string (the unit)");
  if (auto n = t.get("meaning")) p.meaning = r.string(*n, k + ".meaning", "a string");
  if (auto n = t.get("min")) p.min = r.number(*n, k + ".min");
  if (auto n = t.get("max")) p.max = r.number(*n, k + ".max");
  if (auto n = t.get("min_exclusive")) p.min_exclusive = r.boolean(*n, k + ".min_exclusive");
  if (auto n = t.get("max_exclusive")) p.max_exclusive = r.boolean(*n, k + ".max_exclusive");
  if (auto n = t.get("positive"); n && r.boolean(*n, k + ".positive")) {
    if (t.get("min")) fail(r.where(), k + ".positive", "either positive or min, not both");
    p.min = 0.0;
    p.min_exclusive = true;
  }
  if (p.min > p.max) fail(r.where(), k + ".min", "min <= max");
  if (!p.admits(p.value)) {
    fail(r.where(), k + ".value", p.range_text() + " (its own range), got " + number_text(p.value));
  }
  return p;
}

int coordinate_index(const ModelSource& src, const std::string& name) {
  for (std::size_t i = 0; i < src.coordinates.size(); ++i) {
    if (src.coordinates[i] == name) return static_cast<int>(i);
  }
  return -1;
}

// Every declared name is unique, also against the generated names x_d, x_dd and R_x.
void check_unique_names(const ModelSource& src) {
  std::map<std::string, std::string> seen;  // name -> what it is
  auto declare = [&](const std::string& name, const std::string& what, const std::string& where,
                     const std::string& key) {
    auto it = seen.find(name);
    if (it != seen.end()) {
      fail(where, key, "the name '" + name + "' is already used (" + it->second + ")");
    }
    seen[name] = what;
  };
  const std::string ckey = src.prefix.empty() ? "coordinates" : src.prefix + ".coordinates";
  for (const auto& c : src.coordinates) {
    declare(c, "coordinate", src.where, ckey);
  }
  for (const auto& c : src.coordinates) {
    declare(c + "_d", "the velocity of coordinate '" + c + "'", src.where, ckey);
    declare(c + "_dd", "the acceleration of coordinate '" + c + "'", src.where, ckey);
    declare("R_" + c, "the reaction of coordinate '" + c + "'", src.where, ckey);
  }
  const std::string pre = src.prefix.empty() ? "" : src.prefix + ".";
  for (const auto& p : src.parameters) declare(p.name, "a parameter", src.where, pre + "parameters." + p.name);
  for (const auto& [name, e] : src.definitions) declare(name, "a definition", e.where, e.key);
  for (const auto& c : src.constraints) {
    declare(c.spec.name, "a constraint", c.spec.added ? c.holonomic.where : src.where,
            c.spec.added ? c.holonomic.key : c.key + ".name");
    declare("lambda_" + c.spec.name, "the multiplier of constraint '" + c.spec.name + "'",
            c.spec.added ? c.holonomic.where : src.where,
            c.spec.added ? c.holonomic.key : c.key + ".name");
  }
  for (const auto& [name, e] : src.outputs) declare(name, "an output", e.where, e.key);
}

// The contact attributes of one constraint (issue 12), checked where they are read.
void read_contact_attributes(const Reader& r, const toml::table& t, SourceConstraint& sc) {
  const std::string& k = sc.key;
  sc.restitution = ExprText{r.where(), k + ".restitution", ""};
  sc.mu_static = ExprText{r.where(), k + ".mu_static", ""};
  sc.mu_kinetic = ExprText{r.where(), k + ".mu_kinetic", ""};
  if (auto u = t.get("unilateral")) sc.spec.unilateral = r.boolean(*u, k + ".unilateral");
  if (auto gs = t.get("gap_sign")) {
    const double v = r.number(*gs, k + ".gap_sign");
    if (v != 1.0 && v != -1.0)
      fail(r.where(), k + ".gap_sign", "1 (the gap is Phi) or -1 (the gap is -Phi), got " +
                                           number_text(v));
    if (!sc.spec.unilateral)
      fail(r.where(), k + ".gap_sign", "gap_sign only with unilateral = true");
    sc.spec.gap_sign = static_cast<int>(v);
  }
  if (auto e = t.get("restitution")) {
    if (!sc.spec.unilateral)
      fail(r.where(), k + ".restitution",
           "restitution only with unilateral = true (Newton's coefficient of the contact)");
    sc.restitution = r.expression(*e, k + ".restitution");
    sc.spec.restitution = sc.restitution.text;
  }
  if (sc.spec.unilateral && sc.spec.kind != mech::ConstraintKind::holonomic)
    fail(r.where(), k + ".unilateral",
         "a unilateral constraint is holonomic (its gap is Phi(q, t)); a velocity-form row "
         "has no gap");
  if (auto f = t.get("friction")) {
    sc.spec.friction = r.string(*f, k + ".friction",
                                "the name of the unilateral constraint this friction acts at");
    if (sc.spec.unilateral)
      fail(r.where(), k + ".friction",
           "a constraint is either unilateral (a normal contact) or a friction constraint "
           "attached to one, not both");
    if (auto ro = t.get("rough")) sc.spec.rough = r.boolean(*ro, k + ".rough");
    if (sc.spec.rough) {
      // Perfectly rough: no Coulomb coefficients; held while the contact is closed.
      for (const char* key : {"mu_static", "mu_kinetic"})
        if (t.get(key))
          fail(r.where(), k + "." + key,
               std::string(key) + " or rough = true, not both (a rough row never slips: it has no "
                                  "friction coefficient)");
      if (sc.spec.kind != mech::ConstraintKind::velocity)
        fail(r.where(), k + ".rough",
             "a rough row in velocity form (velocity = {...}): a holonomic one would keep its "
             "constant from before a flight");
      return;
    }
    const toml::node* ms = t.get("mu_static");
    if (!ms)
      fail(r.where(), k + ".mu_static",
           "Coulomb's static coefficient (an expression of the parameters) for the friction "
           "constraint '" + sc.spec.name + "'");
    sc.mu_static = r.expression(*ms, k + ".mu_static");
    sc.spec.mu_static = sc.mu_static.text;
    if (auto mk = t.get("mu_kinetic")) {
      sc.mu_kinetic = r.expression(*mk, k + ".mu_kinetic");
      sc.spec.mu_kinetic = sc.mu_kinetic.text;
    }
  } else {
    if (t.get("rough"))
      fail(r.where(), k + ".rough",
           "rough = true only with friction = \"NAME\" (the unilateral constraint it holds at)");
    for (const char* key : {"mu_static", "mu_kinetic"})
      if (t.get(key))
        fail(r.where(), k + "." + key,
             std::string(key) + " only with friction = \"NAME\" (the unilateral constraint the "
                                "friction acts at)");
  }
}

// Resolves each friction constraint's unilateral constraint by name (any order in the file).
void link_friction_constraints(ModelSource& src) {
  for (SourceConstraint& sc : src.constraints) {
    if (sc.spec.friction.empty()) continue;
    int found = -1;
    for (std::size_t i = 0; i < src.constraints.size(); ++i)
      if (src.constraints[i].spec.name == sc.spec.friction) found = static_cast<int>(i);
    std::string unilateral;
    for (const SourceConstraint& c : src.constraints)
      if (c.spec.unilateral) unilateral += (unilateral.empty() ? "" : ", ") + c.spec.name;
    if (found < 0 || !src.constraints[static_cast<std::size_t>(found)].spec.unilateral)
      fail(src.where, sc.key + ".friction",
           "the name of a unilateral constraint of the model (" +
               (unilateral.empty() ? std::string("it declares none: unilateral = true")
                                   : "declared: " + unilateral) +
               "), got '" + sc.spec.friction + "'");
    sc.friction_of = found;
  }
}

}  // namespace

ModelSource detail::read_model_source(const toml::table& model,
                                      const std::filesystem::path& source,
                                      const std::string& prefix) {
  ModelSource src;
  src.file = source;
  src.where = source.empty() ? std::string("<model>") : source.string();
  src.prefix = prefix;
  const Reader r(src.where, prefix);
  std::vector<std::string> allowed{"name", "coordinates", "parameters", "define", "energy", "forces",
                                   "constraint", "outputs", "period", "slow", "draw", "velocity_terms"};
  for (const auto& k : bodies::body_form_keys()) allowed.push_back(k);
  r.only(model, prefix, allowed);
  const bool body_form = bodies::has_body_form(model);
  if (!body_form && model.get("reactions"))
    fail(src.where, r.key("reactions"), "reactions only in a model with bodies and joints ([" + r.key("body") + ".NAME])");

  if (auto n = model.get("name")) {
    src.name = r.string(*n, r.key("name"), "a string (the model name)");
    if (src.name.empty()) fail(src.where, r.key("name"), "a non-empty string");
  } else {
    src.name = source.empty() ? std::string("model") : source.stem().string();
  }

  // Coordinates.
  const toml::node* coords = model.get("coordinates");
  if (!coords && !body_form) fail(src.where, r.key("coordinates"), "the list of coordinates, e.g. [\"x\", \"y\"]");
  static const toml::array no_coordinates;
  const toml::array* ca = coords ? coords->as_array() : &no_coordinates;
  if (!ca || (ca->empty() && !body_form)) {
    fail(src.where, r.key("coordinates"), "a non-empty list of names, e.g. [\"x\", \"y\"]");
  }
  r.count(ca->size(), detail::limits::coordinates, r.key("coordinates"),
          "coordinates (M, n x n, and g, s x n, are filled densely at every evaluation)");
  for (const auto& c : *ca) {
    const std::string name = r.string(c, r.key("coordinates"), "a list of names (strings)");
    r.name(name, r.key("coordinates"));
    src.coordinates.push_back(name);
  }

  // Parameters.
  if (auto n = model.get("parameters")) {
    const toml::table& t = r.table(*n, r.key("parameters"));
    r.count(t.size(), detail::limits::parameters, r.key("parameters"), "parameters");
    for (const auto& [name, node] : in_file_order(t)) {
      const std::string k = r.key("parameters." + name);
      r.name(name, k);
      src.parameters.push_back(read_parameter(r, name, *node, k));
    }
  }

  // Definitions.
  if (auto n = model.get("define")) {
    const toml::table& t = r.table(*n, r.key("define"));
    r.count(t.size(), detail::limits::definitions, r.key("define"), "definitions");
    for (const auto& [name, node] : in_file_order(t)) {
      const std::string k = r.key("define." + name);
      r.name(name, k);
      src.definitions.push_back({name, r.expression(*node, k)});
    }
  }

  // Bodies, joints and forces (issue 22, docs/bodies.md): expanded into the energy form here,
  // before the energy-form keys, which add to what they generate.
  std::optional<bodies::Expander> expander;
  if (body_form) {
    expander.emplace(src, model);
    expander->run();
    r.count(src.coordinates.size(), detail::limits::coordinates, r.key("coordinates"),
            "coordinates with the generated ones");
  }
  // Combines an energy-form text with what the bodies generated for it.
  auto combine = [&](ExprText& generated, ExprText user) {
    if (!generated.text.empty() && !user.text.empty()) {
      user.text = generated.text + " + (" + user.text + ")";
    } else if (user.text.empty()) {
      user.text = generated.text;
      if (!generated.text.empty()) user.key = generated.key;
    }
    generated = user;
  };

  // Energies.
  const toml::node* energy = model.get("energy");
  if (!energy && !body_form) {
    fail(src.where, r.key("energy.kinetic"), "the kinetic energy T(q, q_d, t), an expression");
  }
  static const toml::table no_energy;
  const toml::table& et = energy ? r.table(*energy, r.key("energy")) : no_energy;
  r.only(et, r.key("energy"), {"kinetic", "potential", "dissipation"});
  ExprText kinetic{src.where, r.key("energy.kinetic"), ""};
  if (auto n = et.get("kinetic")) {
    kinetic = r.expression(*n, r.key("energy.kinetic"));
  } else if (!body_form) {
    fail(src.where, r.key("energy.kinetic"), "the kinetic energy T(q, q_d, t), an expression");
  }
  ExprText potential{src.where, r.key("energy.potential"), ""};
  ExprText dissipation{src.where, r.key("energy.dissipation"), ""};
  if (auto n = et.get("potential")) potential = r.expression(*n, r.key("energy.potential"));
  if (auto n = et.get("dissipation")) dissipation = r.expression(*n, r.key("energy.dissipation"));
  if (body_form) {
    combine(src.kinetic, kinetic);
    combine(src.potential, potential);
    combine(src.dissipation, dissipation);
    if (src.kinetic.text.empty())
      fail(src.where, r.key("body"), "a body with mass (or [" + r.key("energy") + "] kinetic)");
  } else {
    src.kinetic = kinetic;
    src.potential = potential;
    src.dissipation = dissipation;
  }

  // Extra generalized forces, by coordinate.
  if (auto n = model.get("forces")) {
    const toml::table& t = r.table(*n, r.key("forces"));
    for (const auto& [name, node] : in_file_order(t)) {
      const std::string k = r.key("forces." + name);
      const int i = coordinate_index(src, name);
      if (i < 0) fail(src.where, k, "a coordinate (one of: " + join(src.coordinates) + ")");
      ExprText e = r.expression(*node, k);
      bool merged = false;
      for (auto& [j, g] : src.forces)
        if (j == i) {  // a generated force on the same coordinate (body form)
          g.text = g.text + " + (" + e.text + ")";
          g.key = k;
          merged = true;
        }
      if (!merged) src.forces.push_back({i, e});
    }
  }

  // Constraints.
  if (auto n = model.get("constraint")) {
    const toml::array* arr = n->as_array();
    if (!arr) {
      fail(src.where, r.key("constraint"),
           "an array of tables, written [[" + r.key("constraint") + "]]");
    }
    r.count(arr->size(), detail::limits::constraints, r.key("constraint"), "constraints");
    int index = 0;
    for (const auto& node : *arr) {
      ++index;
      const std::string anonymous = r.key("constraint") + "[#" + std::to_string(index) + "]";
      if (!node.is_table()) fail(src.where, anonymous, "a table, written [[" + r.key("constraint") + "]]");
      const toml::table& t = *node.as_table();
      SourceConstraint sc;
      const toml::node* nm = t.get("name");
      if (!nm) fail(src.where, anonymous + ".name", "the constraint's name (a string)");
      sc.spec.name = r.string(*nm, anonymous + ".name", "the constraint's name (a string)");
      r.name(sc.spec.name, anonymous + ".name");
      sc.key = r.key("constraint") + "[" + sc.spec.name + "]";
      r.only(t, sc.key, {"name", "holonomic", "velocity", "velocity0", "active", "from_initial",
                         "unilateral", "gap_sign", "restitution", "friction", "rough", "mu_static",
                         "mu_kinetic"});
      const toml::node* hol = t.get("holonomic");
      const toml::node* vel = t.get("velocity");
      if ((hol != nullptr) == (vel != nullptr)) {
        fail(src.where, sc.key,
             "exactly one of 'holonomic' (Phi(q, t) = 0) and 'velocity' (the coefficients of "
             "g q_d + g0 = 0)");
      }
      if (auto a = t.get("active")) sc.spec.active_by_default = r.boolean(*a, sc.key + ".active");
      if (auto f = t.get("from_initial")) sc.spec.from_initial = r.boolean(*f, sc.key + ".from_initial");
      if (hol) {
        sc.spec.kind = mech::ConstraintKind::holonomic;
        sc.holonomic = r.expression(*hol, sc.key + ".holonomic");
        sc.spec.holonomic = sc.holonomic.text;
        if (t.get("velocity0")) {
          fail(src.where, sc.key + ".velocity0", "no velocity0 for a holonomic constraint");
        }
      } else {
        sc.spec.kind = mech::ConstraintKind::velocity;
        if (sc.spec.from_initial) {
          fail(src.where, sc.key + ".from_initial",
               "from_initial only for holonomic constraints (a velocity-form row has no "
               "position to start from)");
        }
        const toml::table& vt = r.table(*vel, sc.key + ".velocity");
        for (const auto& [cname, cnode] : in_file_order(vt)) {
          const std::string k = sc.key + ".velocity." + cname;
          const int i = coordinate_index(src, cname);
          if (i < 0) fail(src.where, k, "a coordinate (one of: " + join(src.coordinates) + ")");
          sc.velocity.push_back({i, r.expression(*cnode, k)});
          sc.spec.velocity.push_back({cname, sc.velocity.back().second.text});
        }
        sc.velocity0 = ExprText{src.where, sc.key + ".velocity0", ""};
        if (auto v0 = t.get("velocity0")) {
          sc.velocity0 = r.expression(*v0, sc.key + ".velocity0");
          sc.spec.velocity0 = sc.velocity0.text;
        }
      }
      read_contact_attributes(r, t, sc);
      src.constraints.push_back(std::move(sc));
    }
    link_friction_constraints(src);
  }

  // Outputs.
  if (auto n = model.get("outputs")) {
    const toml::table& t = r.table(*n, r.key("outputs"));
    r.count(t.size(), detail::limits::outputs, r.key("outputs"), "outputs");
    for (const auto& [name, node] : in_file_order(t)) {
      const std::string k = r.key("outputs." + name);
      r.name(name, k);
      src.outputs.push_back({name, r.expression(*node, k)});
    }
  }

  if (auto n = model.get("period")) src.period = r.expression(*n, r.key("period"));
  // Generated equations have no written form to keep: a body model's are expanded by default.
  src.expand_velocity_terms = body_form;
  if (auto n = model.get("velocity_terms")) {
    const std::string v = r.string(*n, r.key("velocity_terms"), "\"as_written\" or \"expanded\"");
    if (v != "as_written" && v != "expanded")
      fail(src.where, r.key("velocity_terms"),
           "\"as_written\" (h as derived from T as written) or \"expanded\" (h expanded in the "
           "velocities, like terms combined), got '" + v + "'");
    src.expand_velocity_terms = v == "expanded";
  }
  if (auto n = model.get("slow")) {
    const toml::array* arr = n->as_array();
    if (!arr) fail(src.where, r.key("slow"), "a list of coordinate names");
    for (const auto& c : *arr) {
      const std::string name = r.string(c, r.key("slow"), "a list of coordinate names");
      if (coordinate_index(src, name) < 0) {
        fail(src.where, r.key("slow"), "coordinate names (one of: " + join(src.coordinates) +
                                           "), got '" + name + "'");
      }
      if (std::find(src.slow.begin(), src.slow.end(), name) != src.slow.end()) {
        fail(src.where, r.key("slow"), "each coordinate once, got '" + name + "' twice");
      }
      src.slow.push_back(name);
    }
  }
  if (expander) {
    expander->finish();
    link_friction_constraints(src);
  }
  check_unique_names(src);
  if (auto n = model.get("draw")) detail::read_draw_table(*n, src);
  return src;
}

// ---- ModelDescription ------------------------------------------------------------------------

struct ModelDescription::Parts {
  std::shared_ptr<const ModelSource> source;
  std::shared_ptr<const CompiledModel> compiled;
};

namespace {

std::shared_ptr<const ModelDescription> build(std::shared_ptr<const ModelSource> src) {
  std::shared_ptr<CompiledModel> compiled;
  {
    std::lock_guard<std::mutex> lock(detail::ginac_mutex());
    const detail::SymbolicModel sym = detail::derive(*src);
    compiled = detail::compile_tape(sym, *src);
  }
  ModelDescription::Parts parts{std::move(src), std::move(compiled)};
  return std::make_shared<const ModelDescription>(std::move(parts));
}

}  // namespace

ModelDescription::ModelDescription(Parts parts) {
  const ModelSource& src = *parts.source;
  name_ = src.name;
  source_ = src.file;
  coordinates_ = src.coordinates;
  parameters_ = src.parameters;
  for (const auto& c : src.constraints) constraints_.push_back(c.spec);
  for (const auto& [name, e] : src.outputs) outputs_.push_back({name, e.text});
  if (src.period) period_expression_ = src.period->text;
  slow_ = src.slow;
  euler_bodies_ = src.euler_bodies;
  source_data_ = parts.source;
  compiled_ = std::move(parts.compiled);
}

ModelDescription::~ModelDescription() = default;

const ParameterSpec* ModelDescription::parameter(const std::string& name) const {
  for (const auto& p : parameters_) {
    if (p.name == name) return &p;
  }
  return nullptr;
}

int ModelDescription::constraint_index(const std::string& name) const {
  for (std::size_t i = 0; i < constraints_.size(); ++i) {
    if (constraints_[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

std::vector<std::string> ModelDescription::default_active_constraints() const {
  std::vector<std::string> names;
  for (const auto& c : constraints_) {
    if (c.active_by_default) names.push_back(c.name);
  }
  return names;
}

std::vector<double> ModelDescription::parameter_values(
    const std::map<std::string, double>& given) const {
  const std::string who = "model '" + name_ + "'" + (source_.empty() ? "" : " (" + source_.string() + ")");
  std::vector<double> values;
  for (const auto& p : parameters_) values.push_back(p.value);
  for (const auto& [key, v] : given) {
    std::size_t i = 0;
    while (i < parameters_.size() && parameters_[i].name != key) ++i;
    if (i == parameters_.size()) {
      std::vector<std::string> names;
      for (const auto& p : parameters_) names.push_back(p.name);
      fail(who, "parameters." + key,
           "not a parameter of the model (parameters: " + join(names) + ")");
    }
    const ParameterSpec& p = parameters_[i];
    if (!p.admits(v)) {
      fail(who, "parameters." + key,
           p.range_text() + (p.meaning.empty() ? "" : " (" + p.meaning + ")") + ", got " +
               number_text(v));
    }
    values[i] = v;
  }
  return values;
}

namespace {

// The constant region for these parameter values (hidden constants 0), in a full-size slot
// array (so blocks can be evaluated in it).
std::vector<double> constant_region(const CompiledModel& c, const std::vector<double>& params) {
  const Tape& tape = c.tape;
  std::vector<double> v(tape.n_slots, 0.0);
  for (const auto& [slot, value] : tape.literals) v[slot] = value;
  for (std::size_t i = 0; i < params.size(); ++i) v[tape.parameter_slots[i]] = params[i];
  run(tape.prelude, v.data());
  return v;
}

}  // namespace

double ModelDescription::period(const std::map<std::string, double>& parameter_values_in) const {
  const std::vector<double> params = parameter_values(parameter_values_in);
  if (compiled_->period_slot < 0) return std::numeric_limits<double>::quiet_NaN();
  const std::vector<double> v = constant_region(*compiled_, params);
  return v[static_cast<std::size_t>(compiled_->period_slot)];
}

std::shared_ptr<const mech::Model> ModelDescription::instantiate(
    const std::map<std::string, double>& parameters, const Eigen::VectorXd& q0, double t0) const {
  const std::vector<double> params = parameter_values(parameters);
  const CompiledModel& c = *compiled_;
  const Tape& tape = c.tape;
  std::vector<double> v = constant_region(c, params);
  bool any_hidden = false;
  for (std::size_t i = 0; i < c.constraint_blocks.size(); ++i) {
    if (c.constraint_blocks[i].hidden < 0) continue;
    if (q0.size() != n()) {
      throw InputError("model '" + name_ + "': the constraint '" + constraints_[i].name +
                       "' is fixed at the initial state (from_initial), which needs " +
                       std::to_string(n()) + " initial coordinates, got " +
                       std::to_string(q0.size()));
    }
    // Φ(q0, t0), with the hidden constant still 0.
    v[tape.t_slot] = t0;
    for (int k = 0; k < n(); ++k) v[tape.q_slot + k] = q0[k];
    const Block& b = tape.blocks[c.constraint_blocks[i].position];
    run(b.code, v.data());
    const double phi0 = v[b.results[0]];
    if (!std::isfinite(phi0)) {
      throw InputError("model '" + name_ + "': the constraint '" + constraints_[i].name +
                       "' is not finite at the initial state");
    }
    v[tape.hidden_slots[c.constraint_blocks[i].hidden]] = phi0;
    any_hidden = true;
  }
  if (any_hidden) run(tape.prelude, v.data());
  v.resize(tape.n_constant);
  auto model = std::make_shared<ExpressionModel>(compiled_, std::move(v));
  // The contact attributes for these parameter values must be physical (issue 12).
  const std::string who = "model '" + name_ + "'" + (source_.empty() ? "" : " (" + source_.string() + ")");
  for (std::size_t i = 0; i < constraints_.size(); ++i) {
    const ConstraintSpec& spec = constraints_[i];
    const mech::ContactInfo& ci = model->constraints()[i].contact;
    const std::string key = "model.constraint[" + spec.name + "]";
    auto got = [](double x, const std::string& text) {
      return ", got " + number_text(x) + " (\"" + text + "\")";
    };
    if (ci.unilateral && !(ci.restitution >= 0.0 && ci.restitution <= 1.0))
      fail(who, key + ".restitution",
           "Newton's restitution coefficient in [0, 1]" + got(ci.restitution, spec.restitution));
    if (ci.is_coulomb()) {
      if (!(ci.mu_static >= 0.0) || !std::isfinite(ci.mu_static))
        fail(who, key + ".mu_static",
             "a static friction coefficient >= 0" + got(ci.mu_static, spec.mu_static));
      if (!(ci.mu_kinetic >= 0.0 && ci.mu_kinetic <= ci.mu_static))
        fail(who, key + ".mu_kinetic",
             "a kinetic friction coefficient in [0, mu_static = " + number_text(ci.mu_static) +
                 "]" + got(ci.mu_kinetic, spec.mu_kinetic.empty() ? spec.mu_static : spec.mu_kinetic));
    }
  }
  return model;
}

std::shared_ptr<const ModelDescription> ModelDescription::with_constraints(
    const std::vector<ExtraConstraint>& extra) const {
  auto src = std::make_shared<ModelSource>(*std::static_pointer_cast<const ModelSource>(source_data_));
  for (const ExtraConstraint& e : extra) {
    SourceConstraint sc;
    sc.spec.name = e.name;
    sc.spec.kind = mech::ConstraintKind::holonomic;
    sc.spec.from_initial = e.from_initial;
    sc.spec.holonomic = e.holonomic;
    sc.spec.added = true;
    const std::string key = e.key.empty() ? "constraint." + e.name : e.key;
    sc.key = key;
    sc.holonomic = ExprText{e.origin, key, e.holonomic};
    const Reader r(e.origin, "");
    r.name(e.name, key);
    if (e.holonomic.find_first_not_of(" \t\r\n") == std::string::npos) {
      fail(e.origin, key, "an expression Phi(q, t) (the constraint Phi = 0), got an empty string");
    }
    detail::check_expression_size(sc.holonomic);
    r.count(src->constraints.size() + 1, detail::limits::constraints, key,
            "constraints with the added ones");
    src->constraints.push_back(std::move(sc));
  }
  check_unique_names(*src);
  return build(std::move(src));
}

// ---- entry points ----------------------------------------------------------------------------

std::shared_ptr<const ModelDescription> parse_model_table(const toml::table& model,
                                                          const std::filesystem::path& source,
                                                          const std::string& key_prefix) {
  auto src =
      std::make_shared<const ModelSource>(detail::read_model_source(model, source, key_prefix));
  return build(std::move(src));
}

ModelSource detail::load_model_source(const std::filesystem::path& file) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) {
    throw InputError(file.string() + ": cannot read the model file (no such file)");
  }
  std::ifstream in(file, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  if (!in && !in.eof()) throw InputError(file.string() + ": cannot read the model file");
  return parse_model_source_text(text.str(), file);
}

ModelSource detail::parse_model_source_text(const std::string& text,
                                            const std::filesystem::path& file) {
  if (text.size() > (16u << 20))
    throw InputError(file.string() + ": expected a model file of at most 16 MB, got " +
                     std::to_string(text.size()) + " bytes");
  check_toml_nesting(text, file);
  toml::table doc;
  try {
    doc = toml::parse(text, file.string());
  } catch (const toml::parse_error& err) {
    std::ostringstream os;
    os << file.string();
    if (err.source().begin.line > 0) os << ":" << err.source().begin.line;
    os << ": not a valid TOML file: " << err.description();
    throw InputError(os.str());
  }
  for (auto&& [k, v] : doc) {
    if (k.str() != "model") {
      fail(file.string(), std::string(k.str()),
           "unknown key (a model file holds one table, [model])");
    }
  }
  const toml::node* model = doc.get("model");
  if (!model || !model->is_table()) fail(file.string(), "model", "a [model] table");
  return read_model_source(*model->as_table(), file, "model");
}

std::shared_ptr<const ModelDescription> load_model_file(const std::filesystem::path& file) {
  return build(std::make_shared<const ModelSource>(detail::load_model_source(file)));
}

std::shared_ptr<const ModelDescription> load_model_text(const std::string& text,
                                                        const std::filesystem::path& name,
                                                        const std::string* precompiled,
                                                        const std::vector<NativeBlock>* native) {
  auto src = std::make_shared<const ModelSource>(detail::parse_model_source_text(text, name));
  if (precompiled) {
    if (auto compiled = deserialize_compiled(*precompiled, text)) {
      if (native && native->size() == compiled->tape.blocks.size()) compiled->native = *native;
      ModelDescription::Parts parts{std::move(src), std::move(compiled)};
      return std::make_shared<const ModelDescription>(std::move(parts));
    }
  }
  return build(std::move(src));
}

}  // namespace pcsim::modelfile
