// Case files for any model: the schema (common keys, the model's parameters, coordinates and
// constraints, the client's extras), --set overrides, defaults, validation, setup_of, to_toml.
#include "sim/case.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>

#include "common/error.hpp"
#include "common/format.hpp"
#include "common/location.hpp"
#include "sim/client.hpp"

namespace pcsim::sim {

namespace fs = std::filesystem;
using Type = KeySpec::Type;

namespace {

constexpr const char* kFormatHelp = "the case format: README, \"Case files\"";
const std::vector<std::string> kSections = {"parameters", "initial", "constraints", "solver",
                                            "output", "contact"};

std::string where(const fs::path& file) { return input_location(file); }

[[noreturn]] void fail(const fs::path& file, const std::string& key, const std::string& expected,
                       const std::string& got = "") {
  std::string msg = where(file) + ": key '" + key + "': expected " + expected;
  if (!got.empty()) msg += ", got " + got;
  throw InputError(msg);
}

/// The text with control characters shown as \xNN and cut after 80 bytes, for messages.
std::string printable(const std::string& s) {
  std::string out;
  for (std::size_t i = 0; i < s.size() && i < 80; ++i) {
    const unsigned char ch = static_cast<unsigned char>(s[i]);
    if (ch < 0x20 || ch == 0x7f) {
      char b[8];
      std::snprintf(b, sizeof b, "\\x%02x", ch);
      out += b;
    } else {
      out += s[i];
    }
  }
  if (s.size() > 80) out += "...";
  return out;
}

std::string describe(const toml::node& n) {
  std::ostringstream os;
  switch (n.type()) {
    case toml::node_type::string: os << '"' << *n.value<std::string>() << '"'; break;
    case toml::node_type::integer: os << *n.value<int64_t>(); break;
    case toml::node_type::floating_point: os << format_significant(*n.value<double>(), 17); break;
    case toml::node_type::boolean: os << (*n.value<bool>() ? "true" : "false"); break;
    case toml::node_type::table: os << "a table"; break;
    case toml::node_type::array: os << "an array"; break;
    default: os << "a date/time"; break;
  }
  return os.str();
}

const char* type_name(Type t) {
  switch (t) {
    case Type::number: return "a number";
    case Type::integer: return "an integer";
    case Type::boolean: return "a boolean (true or false)";
    case Type::string: return "a string";
  }
  return "?";
}

std::string range_text(const KeySpec& k) {
  const bool lo = std::isfinite(k.min), hi = std::isfinite(k.max);
  if (!lo && !hi) return "";
  std::string s;
  if (lo) s += (k.min_exclusive ? "> " : ">= ") + format_number(k.min);
  if (lo && hi) s += " and ";
  if (hi) s += (k.max_exclusive ? "< " : "<= ") + format_number(k.max);
  return s;
}

bool in_range(const KeySpec& k, double v) {
  if (k.min_exclusive ? !(v > k.min) : !(v >= k.min)) return false;
  if (k.max_exclusive ? !(v < k.max) : !(v <= k.max)) return false;
  return true;
}

KeySpec number_key(std::string section, std::string name, std::string meaning,
                   std::optional<double> def, double min = -INFINITY, bool min_excl = false) {
  KeySpec k;
  k.section = std::move(section);
  k.name = std::move(name);
  k.type = Type::number;
  k.meaning = std::move(meaning);
  k.number_default = def;
  k.min = min;
  k.min_exclusive = min_excl;
  return k;
}

bool model_has_period(const ModelSource& m) {
  ParameterValues p;
  for (const auto& s : m.parameters()) p[s.name] = s.value;
  return std::isfinite(m.period(p));
}

// The initial angular-velocity keys of a spatial body with Euler parameters: NAME_w1..w3 (the
// components in body axes, as the generated definitions NAME_w1..w3), NAME_wx..wz (ground axes),
// with the axis each names.
std::vector<std::pair<std::string, std::string>> angular_velocity_keys(const EulerBody& b) {
  return {{b.name + "_w1", "body x axis"}, {b.name + "_w2", "body y axis"}, {b.name + "_w3", "body z axis"},
          {b.name + "_wx", "ground x axis"}, {b.name + "_wy", "ground y axis"}, {b.name + "_wz", "ground z axis"}};
}

// The initial orientation keys of a spatial body with Euler parameters: NAME_rx..rz, the
// rotation vector (axis times angle, ground axes) that turns ground's axes onto the body's.
std::vector<std::string> rotation_vector_keys(const EulerBody& b) {
  return {b.name + "_rx", b.name + "_ry", b.name + "_rz"};
}

const KeySpec* find(const std::vector<KeySpec>& keys, const std::string& dotted);

// The model's keys (parameters, initial values, constraints) between the common keys of the
// key table (sim/keys.hpp), then the client's.
std::vector<KeySpec> schema(const ModelSource& m, const Client* client) {
  const std::vector<KeySpec>& common = common_keys();
  std::vector<KeySpec> keys;
  keys.push_back(common_key("name"));
  for (const auto& p : m.parameters()) {
    KeySpec s = number_key("parameters", p.name,
                           (p.meaning.empty() ? "model parameter" : p.meaning) +
                               (p.unit.empty() ? "" : ", " + p.unit),
                           p.value, p.min, p.min_exclusive);
    s.max = p.max;
    s.max_exclusive = p.max_exclusive;
    keys.push_back(s);
  }
  for (const auto& c : m.coordinates()) {
    keys.push_back(number_key("initial", c, "initial " + c, std::nullopt));
    keys.push_back(number_key("initial", c + "_d", "initial velocity of " + c, std::nullopt));
  }
  // A spatial body's initial orientation as a rotation vector (issue 22), instead of its Euler
  // parameters.
  for (const auto& b : m.euler_bodies()) {
    if (!b.joint.empty()) continue;  // a spherical tree joint's: its p and ṗ only
    const char* axis[3] = {"x", "y", "z"};
    int i = 0;
    for (const auto& name : rotation_vector_keys(b))
      if (!find(keys, "initial." + name))
        keys.push_back(number_key("initial", name,
                                  "initial orientation of body " + b.name +
                                      ": the rotation vector's ground-" + axis[i++] +
                                      " component (axis times angle), rad",
                                  std::nullopt));
  }
  // A spatial body's initial angular velocity (issue 22), instead of its Euler-parameter rates.
  for (const auto& b : m.euler_bodies())
    for (const auto& [name, axes] : angular_velocity_keys(b))
      if (b.joint.empty() && !find(keys, "initial." + name))
        keys.push_back(number_key("initial", name,
                                  "initial angular velocity of body " + b.name + " about its " + axes,
                                  std::nullopt));
  // initial.from, unless the model has a coordinate of that name.
  if (std::find(m.coordinates().begin(), m.coordinates().end(), "from") == m.coordinates().end())
    keys.push_back(common_key("initial.from"));
  for (const auto& c : m.constraints()) {
    KeySpec s;
    s.section = "constraints";
    s.name = c.name;
    s.type = Type::boolean;
    s.meaning = c.meaning.empty() ? "impose constraint '" + c.name + "'" : c.meaning;
    s.bool_default = c.active_by_default;
    keys.push_back(s);
  }
  const bool periodic = model_has_period(m);
  for (const auto& k : common) {
    if (k.section.empty() || k.section == "initial") continue;  // placed above
    if (k.dotted() == "output.summary_periods" && !periodic) continue;
    keys.push_back(k);
  }
  if (client)
    for (auto& e : client->extra_keys()) keys.push_back(std::move(e));
  return keys;
}

const KeySpec* find(const std::vector<KeySpec>& keys, const std::string& dotted) {
  for (const auto& k : keys)
    if (k.dotted() == dotted) return &k;
  return nullptr;
}

// A loop, not std::regex: libstdc++'s matcher recurses once per character and overflowed the
// stack on a 50,000-character constraint name.
bool is_identifier(const std::string& s) {
  if (s.empty() || std::isdigit(static_cast<unsigned char>(s[0]))) return false;
  for (const char ch : s) {
    const auto c = static_cast<unsigned char>(ch);
    if (!((c < 128 && std::isalnum(c)) || ch == '_')) return false;
  }
  return true;
}

// The table that holds `section` (dotted, e.g. "constraints.added"), created if asked.
toml::table* section_table(toml::table& t, const std::string& section, bool create) {
  toml::table* cur = &t;
  std::size_t start = 0;
  while (start <= section.size()) {
    const std::size_t dot = section.find('.', start);
    const std::string part = section.substr(start, dot == std::string::npos ? std::string::npos : dot - start);
    toml::node* n = cur->get(part);
    if (!n) {
      if (!create) return nullptr;
      cur->insert(part, toml::table{});
      n = cur->get(part);
    }
    cur = n->as_table();
    if (!cur) return nullptr;
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  return cur;
}

// Parses the text of a --set value as the key's type and stores it.
void assign(const fs::path& file, toml::table& t, const KeySpec& k, const std::string& text) {
  const std::string setting = "--set " + k.dotted() + "=" + text;
  toml::table* target = k.section.empty() ? &t : section_table(t, k.section, true);
  if (!target) fail(file, k.section, "a table [" + k.section + "]");
  switch (k.type) {
    case Type::number: {
      char* end = nullptr;
      const double v = std::strtod(text.c_str(), &end);
      if (text.empty() || *end != '\0')
        fail(file, k.dotted(), std::string("a number (") + k.meaning + ") in " + setting,
             "'" + text + "'");
      target->insert_or_assign(k.name, v);
      break;
    }
    case Type::integer: {
      char* end = nullptr;
      errno = 0;
      const long long v = std::strtoll(text.c_str(), &end, 10);
      if (text.empty() || *end != '\0' || errno == ERANGE)
        fail(file, k.dotted(), std::string("an integer (") + k.meaning + ") in " + setting,
             "'" + text + "'");
      target->insert_or_assign(k.name, int64_t{v});
      break;
    }
    case Type::boolean:
      if (text == "true") target->insert_or_assign(k.name, true);
      else if (text == "false") target->insert_or_assign(k.name, false);
      else
        fail(file, k.dotted(), std::string("true or false (") + k.meaning + ") in " + setting,
             "'" + text + "'");
      break;
    case Type::string: {
      std::string s = text;
      if (s.size() >= 2 && ((s.front() == '"' && s.back() == '"') ||
                            (s.front() == '\'' && s.back() == '\'')))
        s = s.substr(1, s.size() - 2);
      target->insert_or_assign(k.name, s);
      break;
    }
  }
}

// Checks one present key: type and range. Integers given for number keys become floats, so
// the stored table is uniform.
void check_value(const fs::path& file, const KeySpec& k, toml::table& section) {
  toml::node* n = section.get(k.name);
  const std::string key = k.dotted();
  const std::string what = std::string(type_name(k.type)) + " (" + k.meaning + ")";
  switch (k.type) {
    case Type::number: {
      double v;
      if (n->is_integer()) {
        v = static_cast<double>(*n->value<int64_t>());
        section.insert_or_assign(k.name, v);
      } else if (n->is_floating_point()) {
        v = *n->value<double>();
      } else {
        fail(file, key, what, describe(*n));
      }
      if (!std::isfinite(v)) fail(file, key, "a finite number (" + k.meaning + ")", describe(*section.get(k.name)));
      if (!in_range(k, v)) {
        // The common ranges in the words users know; others as inequalities.
        std::string what_range = "a number " + range_text(k);
        if (k.min == 0 && !std::isfinite(k.max))
          what_range = k.min_exclusive ? "a positive number, > 0" : "a non-negative number, >= 0";
        fail(file, key, what_range + " (" + k.meaning + ")", describe(*section.get(k.name)));
      }
      break;
    }
    case Type::integer: {
      if (!n->is_integer()) fail(file, key, what, describe(*n));
      const double v = static_cast<double>(*n->value<int64_t>());
      if (!in_range(k, v)) fail(file, key, "an integer " + range_text(k) + " (" + k.meaning + ")", describe(*n));
      break;
    }
    case Type::boolean:
      if (!n->is_boolean()) fail(file, key, what, describe(*n));
      break;
    case Type::string: {
      if (!n->is_string()) fail(file, key, what, describe(*n));
      if (!k.choices.empty()) {
        const std::string s = *n->value<std::string>();
        bool ok = false;
        std::string list;
        for (const auto& c : k.choices) {
          ok = ok || s == c;
          list += (list.empty() ? "\"" : " or \"") + c + "\"";
        }
        if (!ok) fail(file, key, list, describe(*n));
      }
      break;
    }
  }
}

// The added constraints of [constraints.added], validated as NAME = "expression".
std::vector<AddedConstraint> added_constraints(const fs::path& file, const toml::table& t) {
  std::vector<AddedConstraint> out;
  const toml::node* con = t.get("constraints");
  if (!con || !con->is_table()) return out;
  const toml::node* add = con->as_table()->get("added");
  if (!add) return out;
  if (!add->is_table())
    fail(file, "constraints.added", "a table of NAME = \"holonomic expression\"", describe(*add));
  for (const auto& [k, v] : *add->as_table()) {
    const std::string name(k.str());
    if (!is_identifier(name))
      fail(file, "constraints.added." + name, "a constraint name (letters, digits, _)");
    if (!v.is_string())
      fail(file, "constraints.added." + name, "a string: the holonomic constraint Phi(q, t) = 0, "
                                              "e.g. \"s - 0.4\"", describe(v));
    out.push_back({name, *v.value<std::string>()});
  }
  return out;
}

// Resolves the `model` entry of a case table: a built-in name, a model file or an inline table.
std::shared_ptr<const ModelSource> resolve_model(const fs::path& file, const toml::table& t) {
  const toml::node* m = t.get("model");
  if (!m) {
    // The case format's default model, set by the application that owns it (the sieve,
    // architecture.md section 4); a build without that application has none.
    if (auto s = default_builtin()) return s;
    throw InputError(where(file) + ": key 'model': expected a built-in model name, a model file "
                     "or a [model] table (this build has no default model for a case without "
                     "'model')");
  }
  if (m->is_table()) return load_inline_model(*m->as_table(), file);
  if (!m->is_string())
    fail(file, "model", "a built-in model name, a model file (\"models/x.toml\") or a [model] table",
         describe(*m));
  const std::string name = *m->value<std::string>();
  const bool looks_like_file = name.find('/') != std::string::npos ||
                               (name.size() > 5 && name.compare(name.size() - 5, 5, ".toml") == 0);
  if (!looks_like_file) {
    if (auto s = find_builtin(name)) return s;
    std::string known;
    for (const auto& n : builtin_names()) known += (known.empty() ? "" : ", ") + n;
    fail(file, "model", "a built-in model (" + known + ") or a model file path ending in .toml",
         "\"" + name + "\"");
  }
  fs::path path(name);
  if (path.is_relative() && !file.empty()) path = file.parent_path() / path;
  std::error_code ec;
  if (!fs::is_regular_file(path, ec))
    fail(file, "model", "a model file (relative to the case file's directory)",
         "\"" + name + "\", and " + path.string() + " is not a readable file");
  return load_model_file(path);
}

struct Resolved {
  std::shared_ptr<const ModelSource> model;
  std::shared_ptr<const Client> client;
  std::vector<KeySpec> keys;
};

Resolved resolve(const fs::path& file, const toml::table& t) {
  Resolved r;
  r.model = resolve_model(file, t);
  if (const toml::node* m = t.get("model"); !m || m->is_string()) r.client = find_client(r.model->name());
  const auto added = added_constraints(file, t);
  if (!added.empty()) r.model = r.model->with_added_constraints(added, where(file));
  r.keys = schema(*r.model, r.client.get());
  return r;
}

// Unknown keys, misplaced tables, defaults, types and ranges, then the client's checks.
void fill_and_validate(const fs::path& file, toml::table& t, const Resolved& r) {
  for (auto& [k, v] : t) {
    const std::string key(k.str());
    if (key == "model") continue;
    // [modes] belongs to `pcsim modes`, which checks its keys (cpp/modes); other commands ignore it.
    if (key == "modes") {
      if (!v.is_table()) fail(file, key, "a table [modes] (the options of pcsim modes)", describe(v));
      continue;
    }
    bool is_section = false;
    for (const auto& s : kSections) is_section = is_section || key == s;
    if (is_section) {
      if (!v.is_table()) fail(file, key, "a table [" + key + "]", describe(v));
      for (auto& [k2, v2] : *v.as_table()) {
        const std::string sub = key + "." + std::string(k2.str());
        if (sub == "constraints.added") continue;  // checked by added_constraints()
        if (!find(r.keys, sub)) {
          std::string known;
          for (const auto& spec : r.keys)
            if (spec.section == key) known += (known.empty() ? "" : " ") + spec.name;
          fail(file, sub, "a known key of the " + r.model->origin() + "; [" + key + "] has " +
                              (known.empty() ? std::string("no keys") : "the keys: " + known) +
                              " (" + kFormatHelp + ")",
               "");
        }
        (void)v2;
      }
    } else if (!find(r.keys, key) || !find(r.keys, key)->section.empty()) {
      fail(file, key,
           "a known key: model, name, or one of the tables [parameters] [initial] "
           "[constraints] [solver] [output] [contact] [modes]");
    }
  }
  for (const auto& s : kSections)
    if (!t.contains(s)) t.insert(s, toml::table{});
  for (const auto& k : r.keys) {
    toml::table* sec = k.section.empty() ? &t : section_table(t, k.section, true);
    if (!sec) fail(file, k.section, "a table [" + k.section + "]");
    if (!sec->contains(k.name) && k.fill_default) {
      if (k.number_default) sec->insert(k.name, *k.number_default);
      else if (k.bool_default) sec->insert(k.name, *k.bool_default);
      else if (k.string_default) sec->insert(k.name, *k.string_default);
    }
    if (sec->contains(k.name)) check_value(file, k, *sec);
  }
  if (t["solver"]["form"].value_or(std::string()) == "dae" &&
      t["solver"]["method"].value_or(std::string()) == "explicit")
    fail(file, "solver.method", "\"radau\" or \"auto\" with solver.form = \"dae\" (the DAE form "
                                "has a singular mass matrix, which only Radau integrates)",
         "\"explicit\"");
  if (t["contact"]["switching"].value_or(false)) {
    if (t["solver"]["form"].value_or(std::string()) == "dae")
      fail(file, "solver.form", "\"ode\" with contact.switching = true (the switching simulation "
                                "integrates the ODE form)", "\"dae\"");
    std::string offered;
    bool any = false;
    for (const auto& con : r.model->constraints()) {
      if (!con.unilateral) continue;
      offered += (offered.empty() ? "" : ", ") + con.name;
      any = any || t["constraints"][con.name].value_or(con.active_by_default);
    }
    if (!any)
      fail(file, "contact.switching",
           "an active unilateral constraint to switch (" +
               (offered.empty() ? "the " + r.model->origin() + " declares none: unilateral = true "
                                  "in its model file"
                                : "the " + r.model->origin() + " declares " + offered +
                                      "; activate one in [constraints]") + ")",
           "true");
  }
  // A spatial body's initial angular velocity: in body axes or in ground axes, and not together
  // with its Euler-parameter rates (both would set the same velocities).
  // Euler parameters all 0 are no orientation (and leave M singular): refused by key, unless the
  // body's rotation vector gives them (setup_of).
  for (const auto& b : r.model->euler_bodies()) {
    bool rotation_vector = false;
    if (b.joint.empty())
      for (const auto& k : rotation_vector_keys(b))
        rotation_vector = rotation_vector || (t["initial"][k] && r.model->coordinate_index(k) < 0);
    double n2 = 0.0;
    for (const auto& e : b.e) n2 += std::pow(t["initial"][e].value_or(0.0), 2);
    if (!rotation_vector && !(n2 > 1e-12))
      fail(file, "initial." + b.e[0],
           b.joint.empty()
               ? "the orientation of body " + b.name + " (Euler parameters " + b.e[0] + ".." + b.e[3] +
                     " not all 0; " + b.e[0] + " = 1 for the body frame aligned with ground, or a rotation vector " +
                     b.name + "_rx.." + b.name + "_rz)"
               : "the orientation of body " + b.name + " on the spherical joint " + b.joint +
                     " (its Euler parameters " + b.e[0] + ".." + b.e[3] + " not all 0; " + b.e[0] +
                     " = 1 for marker2's frame aligned with marker1's)",
           "all 0");
  }
  for (const auto& b : r.model->euler_bodies()) {
    if (!b.joint.empty()) continue;
    const auto keys = angular_velocity_keys(b);
    std::string body_key, ground_key, rate_key;
    for (std::size_t i = 0; i < keys.size(); ++i)
      if (t["initial"][keys[i].first] && r.model->coordinate_index(keys[i].first) < 0) {
        std::string& k = i < 3 ? body_key : ground_key;
        if (k.empty()) k = "initial." + keys[i].first;
      }
    for (const auto& e : b.e)
      if (rate_key.empty() && t["initial"][e + "_d"]) rate_key = "initial." + e + "_d";
    if (!body_key.empty() && !ground_key.empty())
      fail(file, ground_key,
           "the angular velocity of body " + b.name + " in one frame: " + b.name + "_w1.." + b.name +
               "_w3 (body axes) or " + b.name + "_wx.." + b.name + "_wz (ground axes), not both (" +
               body_key + " is given too)");
    if (!rate_key.empty() && !(body_key.empty() && ground_key.empty()))
      fail(file, rate_key,
           "either the angular velocity of body " + b.name + " (" + (body_key.empty() ? ground_key : body_key) +
               ") or the rates of its Euler parameters (" + b.e[0] + "_d.." + b.e[3] +
               "_d), not both (the angular velocity sets those rates)");
    std::string rot_key, e_key;
    for (const auto& k : rotation_vector_keys(b))
      if (rot_key.empty() && t["initial"][k] && r.model->coordinate_index(k) < 0) rot_key = "initial." + k;
    for (const auto& e : b.e)
      if (e_key.empty() && t["initial"][e]) e_key = "initial." + e;
    if (!rot_key.empty() && !e_key.empty())
      fail(file, e_key,
           "either the orientation of body " + b.name + " as a rotation vector (" + rot_key +
               ") or its Euler parameters (" + b.e[0] + ".." + b.e[3] +
               "), not both (the rotation vector sets them)");
  }
  if (t["output"]["summary_periods"] && t["output"]["summary_time"])
    fail(file, "output.summary_time",
         "either output.summary_periods or output.summary_time, not both (the summary window)");
  if (r.client) r.client->validate(file, t);
}

Setup setup_of(const Case& c);  // below, with the readers of the typed keys

// Checks the parameter values by instantiating the model once (the model's own range checks),
// so bad values are refused by key before any computation.
void check_model_accepts(const fs::path& file, const Case& c) {
  const Setup& s = c.setup;
  try {
    c.model->instantiate(s.parameters, s.q0, 0.0, c.table, "");
  } catch (const InputError& e) {
    const std::string msg = e.what();
    // "parameter 'NAME'" in the message names the key (a search by hand: std::regex
    // recurses per character and a message may quote a long name).
    const std::string marker = "parameter '";
    for (std::size_t p = msg.find(marker); p != std::string::npos; p = msg.find(marker, p + 1)) {
      const std::size_t b = p + marker.size();
      const std::size_t end = msg.find('\'', b);
      const std::string name = end == std::string::npos ? std::string() : msg.substr(b, end - b);
      if (is_identifier(name))
        throw InputError(where(file) + ": key 'parameters." + name + "': " + msg);
    }
    throw InputError(where(file) + ": " + msg);
  }
}

Case finish_case(const fs::path& file, toml::table t, const std::vector<Override>& overrides) {
  // The model first (an override may change it), then the overrides by the model's schema.
  for (const auto& o : overrides)
    if (o.first == "model") t.insert_or_assign("model", o.second);
  Resolved r = resolve(file, t);
  bool added_changed = false;
  for (const auto& o : overrides) {
    if (o.first == "model") continue;
    if (o.first.rfind("constraints.added.", 0) == 0) {
      KeySpec k;
      k.section = "constraints.added";
      k.name = o.first.substr(std::string("constraints.added.").size());
      k.type = Type::string;
      k.meaning = "an added holonomic constraint";
      if (!is_identifier(k.name)) fail(file, o.first, "a constraint name (letters, digits, _)");
      assign(file, t, k, o.second);
      added_changed = true;
      continue;
    }
    const KeySpec* k = find(r.keys, o.first);
    if (!k)
      fail(file, o.first, "a key of the case format for the " + r.model->origin() + " (--set " +
                              o.first + "=" + o.second + "; " + kFormatHelp + ")");
    assign(file, t, *k, o.second);
  }
  if (added_changed) r = resolve(file, t);
  fill_and_validate(file, t, r);
  Case c;
  c.source = file;
  c.table = std::move(t);
  c.model = r.model;
  c.client = r.client;
  const bool named = c.table["name"].is_string();
  if (auto n = c.table["name"].value<std::string>()) c.name = *n;
  else c.name = file.empty() ? std::string("case") : file.stem().string();
  if (const std::string problem = case_name_problem(c.name); !problem.empty())
    fail(file, "name",
         "a case name that can name its output directory (" + problem + ")" +
             (named ? "" : "; without a 'name' key the case file's name is used, so set one"),
         "\"" + printable(c.name) + "\"");
  c.setup = setup_of(c);
  check_model_accepts(file, c);
  return c;
}

}  // namespace

namespace {

/// Length of the valid UTF-8 sequence at s[i], or 0.
std::size_t utf8_length(const std::string& s, std::size_t i) {
  const unsigned char c = static_cast<unsigned char>(s[i]);
  std::size_t n = c < 0x80 ? 1 : (c >> 5) == 0x6 ? 2 : (c >> 4) == 0xe ? 3 : (c >> 3) == 0x1e ? 4 : 0;
  if (n == 0 || i + n > s.size()) return 0;
  for (std::size_t k = 1; k < n; ++k)
    if ((static_cast<unsigned char>(s[i + k]) >> 6) != 0x2) return 0;
  if (n == 2 && c < 0xc2) return 0;  // overlong
  return n;
}

}  // namespace

std::string case_name_problem(const std::string& name) {
  if (name.empty()) return "it is empty";
  if (name.size() > kMaxCaseNameBytes)
    return "at most " + std::to_string(kMaxCaseNameBytes) + " bytes, it has " + std::to_string(name.size());
  for (std::size_t i = 0; i < name.size();) {
    const unsigned char c = static_cast<unsigned char>(name[i]);
    if (c == '/' || c == '\\') return "a file name, not a path: no '/' or '\\'";
    if (c < 0x20 || c == 0x7f) return "no control characters (line breaks, tabs, NUL)";
    const std::size_t n = utf8_length(name, i);
    if (n == 0) return "valid UTF-8";
    i += n;
  }
  if (name[0] == '.') return "it must not start with '.'";
  return "";
}

std::string derived_case_name(const std::string& base, const std::string& suffix) {
  std::string b = base;
  if (b.size() + suffix.size() > kMaxCaseNameBytes) {
    b.resize(kMaxCaseNameBytes > suffix.size() ? kMaxCaseNameBytes - suffix.size() : 0);
    while (!b.empty() && (static_cast<unsigned char>(b.back()) & 0xc0) == 0x80) b.pop_back();
    if (!b.empty() && static_cast<unsigned char>(b.back()) >= 0xc0) b.pop_back();
  }
  return b + suffix;
}

Override parse_override(const std::string& text) {
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0)
    throw InputError("--set '" + text.substr(0, 200) + "': expected KEY=VALUE, e.g. parameters.omega=300");
  return {text.substr(0, eq), text.substr(eq + 1)};
}

std::vector<Override> command_line_overrides(const std::vector<std::string>& sets,
                                             const std::vector<std::string>& added_constraints) {
  std::vector<Override> overrides;
  for (const auto& s : sets) overrides.push_back(parse_override(s));
  for (const auto& s : added_constraints) {
    const auto eq = s.find('=');
    if (eq == std::string::npos || eq == 0)
      throw InputError("--constraint '" + s.substr(0, 200) +
                       "': expected NAME=EXPR, e.g. --constraint 'hold=s - 0.4'");
    overrides.emplace_back("constraints.added." + s.substr(0, eq), s.substr(eq + 1));
  }
  return overrides;
}

Case load_case(const fs::path& file, const std::vector<Override>& overrides) {
  std::error_code ec;
  if (fs::is_directory(file, ec)) throw InputError(file.string() + ": is a directory, not a case file");
  if (!fs::exists(file, ec)) throw InputError(file.string() + ": no such case file");
  std::string text;
  {
    std::ifstream in(file, std::ios::binary);
    if (!in) throw InputError(file.string() + ": cannot read the case file: " + std::strerror(errno));
    std::ostringstream os;
    os << in.rdbuf();
    text = os.str();
  }
  return load_case_text(text, file, overrides);
}

Case load_case_text(const std::string& text, const fs::path& file,
                    const std::vector<Override>& overrides) {
  if (text.size() > kMaxCaseBytes)
    throw InputError(where(file) + ": expected a case file of at most " +
                     std::to_string(kMaxCaseBytes >> 20) + " MB, got " +
                     std::to_string(text.size()) + " bytes");
  check_toml_nesting(text, file);
  toml::table t;
  try {
    t = toml::parse(text, file.string());
  } catch (const toml::parse_error& err) {
    std::ostringstream os;
    os << where(file) << ":" << err.source().begin.line << ":" << err.source().begin.column
       << ": malformed TOML: " << err.description();
    throw InputError(os.str());
  }
  return finish_case(file, std::move(t), overrides);
}

Case case_from_table(toml::table table, const fs::path& source, const std::vector<Override>& overrides) {
  return finish_case(source, std::move(table), overrides);
}

void set_value(Case& c, const Override& o) {
  c = finish_case(c.source, c.table, {o});  // validates a copy: a rejected override changes nothing
}

std::vector<KeySpec> case_keys(const Case& c) { return schema(*c.model, c.client.get()); }

bool is_numeric_key(const Case& c, const std::string& dotted_key) {
  const auto keys = case_keys(c);
  const KeySpec* k = find(keys, dotted_key);
  return k && (k->type == Type::number || k->type == Type::integer);
}

bool is_integer_key(const Case& c, const std::string& dotted_key) {
  const auto keys = case_keys(c);
  const KeySpec* k = find(keys, dotted_key);
  return k && k->type == Type::integer;
}

std::string to_toml(const Case& c, const std::string& title) {
  toml::table t = c.table;
  t.insert_or_assign("name", c.name);
  if (const toml::node* m = t.get("model"); m && m->is_string()) {
    const std::string name = *m->value<std::string>();
    const bool file = name.find('/') != std::string::npos ||
                      (name.size() > 5 && name.compare(name.size() - 5, 5, ".toml") == 0);
    if (file) {
      fs::path p(name);
      if (p.is_relative() && !c.source.empty()) p = c.source.parent_path() / p;
      std::error_code ec;
      const fs::path abs = fs::weakly_canonical(p, ec);
      t.insert_or_assign("model", (ec ? fs::absolute(p) : abs).string());
    }
  }
  std::ostringstream os;
  os << "# " << title << " (written by pcsim; every key explicit)\n" << t << "\n";
  return os.str();
}

namespace {

// A common key's value in a validated table, or its default from the key table (the keys whose
// default is not written into the table, and tables validated before a default was added).
double number_of(const toml::table& t, const char* dotted) {
  if (auto v = t.at_path(dotted).value<double>()) return *v;
  return *common_key(dotted).number_default;
}
std::string string_of(const toml::table& t, const char* dotted) {
  if (auto v = t.at_path(dotted).value<std::string>()) return *v;
  return *common_key(dotted).string_default;
}
bool bool_of(const toml::table& t, const char* dotted) {
  if (auto v = t.at_path(dotted).value<bool>()) return *v;
  return *common_key(dotted).bool_default;
}

// The typed view of a validated case (Case::setup).
Setup setup_of(const Case& c) {
  const toml::table& t = c.table;
  const ModelSource& m = *c.model;
  Setup s;
  for (const auto& p : m.parameters()) s.parameters[p.name] = t["parameters"][p.name].value_or(p.value);
  const int n = static_cast<int>(m.coordinates().size());
  s.q0 = Eigen::VectorXd::Zero(n);
  s.qd0 = Eigen::VectorXd::Zero(n);
  for (int i = 0; i < n; ++i) {
    const std::string& name = m.coordinates()[i];
    s.q0[i] = t["initial"][name].value_or(0.0);
    s.qd0[i] = t["initial"][name + "_d"].value_or(0.0);
  }
  // A spatial body's initial orientation as a rotation vector r = χ u (ground axes) gives its
  // Euler parameters e = (cos χ/2, u sin χ/2) (fill_and_validate refused it with explicit e).
  for (const auto& b : m.euler_bodies()) {
    if (!b.joint.empty()) continue;
    Eigen::Vector3d rv = Eigen::Vector3d::Zero();
    bool given = false;
    const auto keys = rotation_vector_keys(b);
    for (int i = 0; i < 3; ++i)
      if (auto v = t["initial"][keys[static_cast<std::size_t>(i)]].value<double>();
          v && m.coordinate_index(keys[static_cast<std::size_t>(i)]) < 0) {
        rv[i] = *v;
        given = true;
      }
    if (!given) continue;
    const double chi = rv.norm();
    Eigen::Vector4d e(1.0, 0.0, 0.0, 0.0);
    if (chi > 0) {
      e[0] = std::cos(chi / 2);
      e.tail<3>() = std::sin(chi / 2) / chi * rv;
    }
    for (int k = 0; k < 4; ++k) s.q0[m.coordinate_index(b.e[static_cast<std::size_t>(k)])] = e[k];
  }
  // A spatial body's initial angular velocity ω' (body axes) or ω (ground axes) gives the rates
  // of its Euler parameters ė = ½ Gᵀ ω' = ½ Eᵀ ω at the (normalized) initial e
  // (docs/bodies-spatial.md; fill_and_validate refused the key together with explicit rates).
  for (const auto& b : m.euler_bodies()) {
    if (!b.joint.empty()) continue;
    const auto keys = angular_velocity_keys(b);
    bool body = false, ground = false;
    Eigen::Vector3d w = Eigen::Vector3d::Zero();
    for (std::size_t i = 0; i < keys.size(); ++i)
      if (auto v = t["initial"][keys[i].first].value<double>();
          v && m.coordinate_index(keys[i].first) < 0) {
        (i < 3 ? body : ground) = true;
        w[static_cast<int>(i % 3)] = *v;
      }
    if (!body && !ground) continue;
    int idx[4];
    Eigen::Vector4d e;
    for (int k = 0; k < 4; ++k) {
      idx[k] = m.coordinate_index(b.e[static_cast<std::size_t>(k)]);
      e[k] = s.q0[idx[k]];
    }
    e /= e.norm();
    Eigen::Matrix<double, 3, 4> G;
    if (body)
      G << -e[1], e[0], e[3], -e[2],  //
          -e[2], -e[3], e[0], e[1],   //
          -e[3], e[2], -e[1], e[0];
    else
      G << -e[1], e[0], -e[3], e[2],  //
          -e[2], e[3], e[0], -e[1],   //
          -e[3], -e[2], e[1], e[0];
    const Eigen::Vector4d ed = 0.5 * G.transpose() * w;
    for (int k = 0; k < 4; ++k) s.qd0[idx[k]] = ed[k];
  }
  for (const auto& con : m.constraints())
    if (t["constraints"][con.name].value_or(con.active_by_default)) s.active.push_back(con.name);
  s.kernel = *parse_kernel(string_of(t, "solver.kernel"));
  s.form = string_of(t, "solver.form") == "dae" ? mech::Form::dae : mech::Form::ode;
  s.method = *parse_ode_method(string_of(t, "solver.method"));
  const std::string la = string_of(t, "solver.linear_algebra");
  s.linear_algebra = la == "own"      ? RadauOptions::LinearAlgebra::own_lu
                     : la == "lapack" ? RadauOptions::LinearAlgebra::lapack
                                      : RadauOptions::LinearAlgebra::automatic;
  s.rtol = number_of(t, "solver.rtol");
  s.atol = number_of(t, "solver.atol");
  s.t_end = number_of(t, "solver.t_end");
  s.h0 = number_of(t, "solver.h0");
  s.max_steps = static_cast<long>(number_of(t, "solver.max_steps"));
  s.dt = number_of(t, "output.dt");
  s.npy = string_of(t, "output.format") == "npy";
  s.equilibrium_start = string_of(t, "initial.from") == "equilibrium";
  s.period = m.period(s.parameters);
  if (auto k = t["output"]["summary_periods"].value<int64_t>()) {
    s.window.periods = static_cast<int>(*k);
  } else if (auto w = t["output"]["summary_time"].value<double>()) {
    s.window.time = *w;
  } else if (std::isfinite(s.period)) {
    s.window.periods = static_cast<int>(number_of(t, "output.summary_periods"));
  } else {
    s.window.time = s.t_end;  // no excitation period: the whole run
  }
  s.contact.switching = bool_of(t, "contact.switching");
  s.contact.zeno_time = number_of(t, "contact.zeno_time");
  s.contact.max_events = static_cast<long>(number_of(t, "contact.max_events"));
  s.contact.lcp_solver = string_of(t, "contact.lcp_solver");
  if (auto h = t["contact"]["flight_hmax"].value<double>())
    s.contact.flight_hmax = *h;
  else if (std::isfinite(s.period))
    s.contact.flight_hmax = s.period / 16.0;
  if (c.client) c.client->adjust(t, s);
  return s;
}

}  // namespace

void retype(Case& c) { c.setup = setup_of(c); }

}  // namespace pcsim::sim
