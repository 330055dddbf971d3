// Sieve case files: schema, defaults, --set overrides, validation, typed settings, to_toml.
#include "sieve/case.hpp"

#include <cmath>
#include <cstdlib>
#include <map>
#include <optional>
#include <sstream>

#include "common/error.hpp"
#include "sieve/settings.hpp"

namespace pcsim::sieve {

namespace {

enum class Type { number, integer, boolean, string };

// What a key must hold, beyond its type.
enum class Rule {
  any_finite,    // any finite number
  positive,      // > 0
  non_negative,  // >= 0
  kernel,        // "fortran" | "cpp"
  form,          // "ode" | "dae"
  model,         // "sieve"
  integer_ge1,   // integer >= 1
  none,
};

struct KeySpec {
  const char* section;  // "" for top level
  const char* name;
  Type type;
  Rule rule;
  const char* meaning;  // unit and meaning, used in error messages
  std::optional<double> number_default = std::nullopt;
};

// The case format of architecture.md section 4; defaults of sieve-model.md section 5.
const std::vector<KeySpec>& schema() {
  static const std::vector<KeySpec> keys = {
      {"", "model", Type::string, Rule::model, "the model name"},
      {"", "name", Type::string, Rule::none, "the case name"},
      // Printed in the paper.
      {"parameters", "m0", Type::number, Rule::non_negative, "unbalanced mass, kg", 1.27},
      {"parameters", "m1", Type::number, Rule::positive, "desk mass, kg", 400.0},
      {"parameters", "m2", Type::number, Rule::positive, "roller mass, kg", 0.5},
      {"parameters", "J0", Type::number, Rule::non_negative, "exciter inertia, kg m^2", 0.127e-3},
      {"parameters", "J1", Type::number, Rule::positive, "desk inertia, kg m^2", 200.0},
      {"parameters", "J2", Type::number, Rule::positive, "roller inertia, kg m^2", 0.25e-4},
      {"parameters", "r", Type::number, Rule::positive, "roller radius, m", 0.1},
      {"parameters", "e", Type::number, Rule::non_negative, "eccentricity, m", 0.01},
      {"parameters", "cx", Type::number, Rule::non_negative, "vertical stiffness, N/m", 5e4},
      {"parameters", "cy", Type::number, Rule::non_negative, "horizontal stiffness, N/m", 5e4},
      {"parameters", "ctheta", Type::number, Rule::non_negative, "torsional stiffness, N m/rad",
       5e4},
      {"parameters", "bx", Type::number, Rule::non_negative, "vertical damping, N s/m", 1e5},
      {"parameters", "by", Type::number, Rule::non_negative, "horizontal damping, N s/m", 1e5},
      {"parameters", "btheta", Type::number, Rule::non_negative,
       "torsional damping, N m s/rad", 1e4},
      {"parameters", "omega", Type::number, Rule::non_negative, "excitation frequency, rad/s",
       280.0},
      // Not printed: the project's documented defaults (assumptions).
      {"parameters", "g", Type::number, Rule::non_negative, "gravity, m/s^2", 9.81},
      {"parameters", "x0", Type::number, Rule::any_finite, "exciter axis eta, m", 0.10},
      {"parameters", "y0", Type::number, Rule::any_finite, "exciter axis xi, m", 0.20},
      {"parameters", "xc", Type::number, Rule::any_finite, "horizontal spring eta, m", 0.0},
      {"parameters", "yc", Type::number, Rule::any_finite, "vertical spring xi, m", 0.0},
      {"parameters", "xb", Type::number, Rule::any_finite, "horizontal damper eta, m", 0.0},
      {"parameters", "yb", Type::number, Rule::any_finite, "vertical damper xi, m", 0.0},
      {"parameters", "a", Type::number, Rule::any_finite, "horizontal spring/damper xi, m", 0.50},
      {"parameters", "b", Type::number, Rule::any_finite, "vertical spring/damper eta, m", -0.20},
      {"parameters", "u0", Type::number, Rule::any_finite, "roller centre height over C, m",
       0.15},
      {"parameters", "f", Type::number, Rule::positive, "friction coefficient roller/deck", 0.3},
      {"initial", "s0", Type::number, Rule::any_finite, "initial roller position, m", 0.40},
      {"initial", "x", Type::number, Rule::any_finite, "initial x, m"},
      {"initial", "y", Type::number, Rule::any_finite, "initial y, m"},
      {"initial", "theta", Type::number, Rule::any_finite, "initial theta, rad"},
      {"initial", "s", Type::number, Rule::any_finite, "initial s, m"},
      {"initial", "u", Type::number, Rule::any_finite, "initial u, m"},
      {"initial", "phi", Type::number, Rule::any_finite, "initial phi, rad"},
      {"initial", "x_d", Type::number, Rule::any_finite, "initial x velocity, m/s"},
      {"initial", "y_d", Type::number, Rule::any_finite, "initial y velocity, m/s"},
      {"initial", "theta_d", Type::number, Rule::any_finite, "initial theta rate, rad/s"},
      {"initial", "s_d", Type::number, Rule::any_finite, "initial s velocity, m/s"},
      {"initial", "u_d", Type::number, Rule::any_finite, "initial u velocity, m/s"},
      {"initial", "phi_d", Type::number, Rule::any_finite, "initial phi rate, rad/s"},
      {"constraints", "contact", Type::boolean, Rule::none, "(3.1) u = u0"},
      {"constraints", "rolling", Type::boolean, Rule::none, "(3.2) rolling without slip"},
      {"constraints", "rolling_as_printed", Type::boolean, Rule::none,
       "(3.2) with the paper's printed sign s - r phi = const instead of s + r phi = const "
       "(erratum 7)"},
      {"constraints", "lock_theta", Type::boolean, Rule::none, "theta = 0"},
      {"solver", "kernel", Type::string, Rule::kernel, "the kernel implementation"},
      {"solver", "form", Type::string, Rule::form, "the formulation"},
      {"solver", "rtol", Type::number, Rule::positive, "relative tolerance", 1e-6},
      {"solver", "atol", Type::number, Rule::positive, "absolute tolerance", 1e-8},
      {"solver", "t_end", Type::number, Rule::positive, "end time, s", 10.0},
      {"solver", "h0", Type::number, Rule::non_negative, "initial step, s (0: automatic)", 0.0},
      {"output", "dt", Type::number, Rule::positive, "output interval, s", 1e-3},
      {"output", "summary_periods", Type::integer, Rule::integer_ge1,
       "excitation periods in the summary window"},
  };
  return keys;
}

const std::vector<const char*>& sections() {
  static const std::vector<const char*> s = {"parameters", "initial", "constraints", "solver",
                                             "output"};
  return s;
}

std::string dotted(const KeySpec& k) {
  return std::string(k.section).empty() ? std::string(k.name)
                                        : std::string(k.section) + "." + k.name;
}

const KeySpec* find_key(const std::string& dotted_key) {
  for (const auto& k : schema())
    if (dotted(k) == dotted_key) return &k;
  return nullptr;
}

std::string where(const std::filesystem::path& file) {
  return file.empty() ? std::string("<case>") : file.string();
}

[[noreturn]] void fail(const std::filesystem::path& file, const std::string& key,
                       const std::string& expected, const std::string& got = "") {
  std::string msg = where(file) + ": key '" + key + "': expected " + expected;
  if (!got.empty()) msg += ", got " + got;
  throw InputError(msg);
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

std::string describe(const toml::node& n) {
  std::ostringstream os;
  switch (n.type()) {
    case toml::node_type::string: os << '"' << *n.value<std::string>() << '"'; break;
    case toml::node_type::integer: os << *n.value<int64_t>(); break;
    case toml::node_type::floating_point: os << *n.value<double>(); break;
    case toml::node_type::boolean: os << (*n.value<bool>() ? "true" : "false"); break;
    case toml::node_type::table: os << "a table"; break;
    case toml::node_type::array: os << "an array"; break;
    default: os << "a date/time"; break;
  }
  return os.str();
}

// Checks one present key: type and rule. Converts integers to floats for number keys so the
// stored table is uniform.
void check_value(const std::filesystem::path& file, const KeySpec& k, toml::table& section) {
  toml::node* n = section.get(k.name);
  const std::string key = dotted(k);
  switch (k.type) {
    case Type::number: {
      double v;
      if (n->is_integer()) {
        v = static_cast<double>(*n->value<int64_t>());
        section.insert_or_assign(k.name, v);
      } else if (n->is_floating_point()) {
        v = *n->value<double>();
      } else {
        fail(file, key, std::string(type_name(k.type)) + " (" + k.meaning + ")", describe(*n));
      }
      if (!std::isfinite(v)) fail(file, key, std::string("a finite number (") + k.meaning + ")",
                                  describe(*section.get(k.name)));
      if (k.rule == Rule::positive && !(v > 0))
        fail(file, key, std::string("a positive number, > 0 (") + k.meaning + ")",
             describe(*section.get(k.name)));
      if (k.rule == Rule::non_negative && !(v >= 0))
        fail(file, key, std::string("a non-negative number, >= 0 (") + k.meaning + ")",
             describe(*section.get(k.name)));
      break;
    }
    case Type::integer: {
      if (!n->is_integer())
        fail(file, key, std::string(type_name(k.type)) + " (" + k.meaning + ")", describe(*n));
      if (k.rule == Rule::integer_ge1 && *n->value<int64_t>() < 1)
        fail(file, key, std::string("an integer >= 1 (") + k.meaning + ")", describe(*n));
      break;
    }
    case Type::boolean:
      if (!n->is_boolean())
        fail(file, key, std::string(type_name(k.type)) + " (" + k.meaning + ")", describe(*n));
      break;
    case Type::string: {
      if (!n->is_string())
        fail(file, key, std::string(type_name(k.type)) + " (" + k.meaning + ")", describe(*n));
      const std::string s = *n->value<std::string>();
      if (k.rule == Rule::kernel && !parse_kernel(s))
        fail(file, key, "\"fortran\" or \"cpp\"", describe(*n));
      if (k.rule == Rule::form && s != "ode" && s != "dae")
        fail(file, key, "\"ode\" or \"dae\"", describe(*n));
      if (k.rule == Rule::model && s != "sieve") fail(file, key, "\"sieve\"", describe(*n));
      break;
    }
  }
}

double number(const toml::table& t, const char* section, const char* name) {
  return *t[section][name].value<double>();
}

// Fills documented defaults, checks every key, and checks the initial state against the
// imposed constraints. The table must already hold only known keys of the right shape.
void fill_and_validate(const std::filesystem::path& file, toml::table& t) {
  // Unknown keys and misplaced tables.
  for (auto& [k, v] : t) {
    const std::string key(k.str());
    bool is_section = false;
    for (const char* s : sections()) is_section = is_section || key == s;
    if (is_section) {
      if (!v.is_table()) fail(file, key, "a table [" + key + "]", describe(v));
      for (auto& [k2, v2] : *v.as_table()) {
        (void)v2;
        const std::string sub = key + "." + std::string(k2.str());
        if (!find_key(sub))
          fail(file, sub, "a known key; [" + key + "] has no key '" + std::string(k2.str()) +
                              "' (the case format: README, \"Case files\"; cases/sieve_1995.toml lists every key)");
      }
    } else if (!find_key(key) || std::string(find_key(key)->section) != "") {
      fail(file, key,
           "a known key: model, name, or one of the tables [parameters] [initial] "
           "[constraints] [solver] [output]");
    }
  }
  for (const char* s : sections())
    if (!t.contains(s)) t.insert(s, toml::table{});
  // Defaults.
  if (!t.contains("model")) t.insert("model", "sieve");
  for (const auto& k : schema()) {
    if (std::string(k.section).empty()) continue;
    toml::table& sec = *t[k.section].as_table();
    if (sec.contains(k.name)) continue;
    if (k.number_default) sec.insert(k.name, *k.number_default);
  }
  toml::table& con = *t["constraints"].as_table();
  for (const char* c : {"contact", "rolling"})
    if (!con.contains(c)) con.insert(c, true);
  if (!con.contains("lock_theta")) con.insert("lock_theta", false);
  if (!con.contains("rolling_as_printed")) con.insert("rolling_as_printed", false);
  toml::table& sol = *t["solver"].as_table();
  if (!sol.contains("kernel")) sol.insert("kernel", "fortran");
  if (!sol.contains("form")) sol.insert("form", "ode");
  toml::table& out = *t["output"].as_table();
  if (!out.contains("summary_periods")) out.insert("summary_periods", int64_t{5});
  // Types and ranges.
  for (const auto& k : schema()) {
    if (std::string(k.section).empty()) {
      if (t.contains(k.name)) check_value(file, k, t);
    } else {
      toml::table& sec = *t[k.section].as_table();
      if (sec.contains(k.name)) check_value(file, k, sec);
    }
  }
  // The initial state must satisfy the constraints that are imposed.
  const toml::table& ini = *t["initial"].as_table();
  auto initial = [&](const char* name, double fallback) {
    return ini.contains(name) ? *ini[name].value<double>() : fallback;
  };
  const double s0 = number(t, "initial", "s0");
  if (ini.contains("s") && initial("s", s0) != s0)
    fail(file, "initial.s", "the same value as initial.s0 (both give the initial s), or only one "
                            "of them", describe(*ini.get("s")));
  const double u0 = number(t, "parameters", "u0"), r = number(t, "parameters", "r");
  auto near = [](double a, double b) { return std::abs(a - b) <= 1e-12 * (1 + std::abs(a) + std::abs(b)); };
  if (*con["contact"].value<bool>()) {
    if (!near(initial("u", u0), u0))
      fail(file, "initial.u", "parameters.u0 (constraints.contact = true imposes u = u0)",
           describe(*ini.get("u")));
    if (!near(initial("u_d", 0), 0))
      fail(file, "initial.u_d", "0 (constraints.contact = true imposes u = u0)",
           describe(*ini.get("u_d")));
  }
  if (*con["rolling"].value<bool>()) {
    if (*con["rolling_as_printed"].value<bool>()) {
      if (!near(initial("s_d", 0), r * initial("phi_d", 0)))
        fail(file, "initial.s_d",
             "r * initial.phi_d (constraints.rolling = true with rolling_as_printed imposes "
             "s' = r phi')",
             describe(*ini.get(ini.contains("s_d") ? "s_d" : "phi_d")));
    } else if (!near(initial("s_d", 0), -r * initial("phi_d", 0))) {
      fail(file, "initial.s_d", "-r * initial.phi_d (constraints.rolling = true imposes s' = -r phi')",
           describe(*ini.get(ini.contains("s_d") ? "s_d" : "phi_d")));
    }
  }
  if (*con["lock_theta"].value<bool>()) {
    if (!near(initial("theta", 0), 0))
      fail(file, "initial.theta", "0 (constraints.lock_theta = true imposes theta = 0)",
           describe(*ini.get("theta")));
    if (!near(initial("theta_d", 0), 0))
      fail(file, "initial.theta_d", "0 (constraints.lock_theta = true imposes theta = 0)",
           describe(*ini.get("theta_d")));
  }
}

// Parses the text of a --set value as the key's type and stores it.
void assign_override(const std::filesystem::path& file, toml::table& t, const Override& o) {
  const KeySpec* k = find_key(o.first);
  if (!k)
    fail(file, o.first, "a key of the sieve case format (--set " + o.first + "=" + o.second +
                            "; the case format: README, \"Case files\")");
  const std::string& text = o.second;
  const std::string setting = "--set " + o.first + "=" + text;
  toml::table* target = &t;
  if (!std::string(k->section).empty()) {
    if (!t.contains(k->section)) t.insert(k->section, toml::table{});
    target = t[k->section].as_table();
    if (!target) fail(file, k->section, "a table [" + std::string(k->section) + "]");
  }
  switch (k->type) {
    case Type::number: {
      char* end = nullptr;
      const double v = std::strtod(text.c_str(), &end);
      if (text.empty() || *end != '\0')
        fail(file, o.first, std::string("a number (") + k->meaning + ") in " + setting,
             "'" + text + "'");
      target->insert_or_assign(k->name, v);
      break;
    }
    case Type::integer: {
      char* end = nullptr;
      const long long v = std::strtoll(text.c_str(), &end, 10);
      if (text.empty() || *end != '\0')
        fail(file, o.first, std::string("an integer (") + k->meaning + ") in " + setting,
             "'" + text + "'");
      target->insert_or_assign(k->name, int64_t{v});
      break;
    }
    case Type::boolean:
      if (text == "true") target->insert_or_assign(k->name, true);
      else if (text == "false") target->insert_or_assign(k->name, false);
      else
        fail(file, o.first, std::string("true or false (") + k->meaning + ") in " + setting,
             "'" + text + "'");
      break;
    case Type::string: {
      std::string s = text;
      if (s.size() >= 2 && ((s.front() == '"' && s.back() == '"') ||
                            (s.front() == '\'' && s.back() == '\'')))
        s = s.substr(1, s.size() - 2);
      target->insert_or_assign(k->name, s);
      break;
    }
  }
}

}  // namespace

Override parse_override(const std::string& text) {
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0)
    throw InputError("--set '" + text + "': expected KEY=VALUE, e.g. parameters.omega=300");
  return {text.substr(0, eq), text.substr(eq + 1)};
}

Case load_case(const std::filesystem::path& file, const std::vector<Override>& overrides) {
  Case c;
  c.source = file;
  try {
    c.table = toml::parse_file(file.string());
  } catch (const toml::parse_error& err) {
    std::ostringstream os;
    os << file.string() << ":" << err.source().begin.line << ":" << err.source().begin.column
       << ": malformed TOML: " << err.description();
    throw InputError(os.str());
  }
  for (const auto& o : overrides) assign_override(file, c.table, o);
  fill_and_validate(file, c.table);
  if (auto n = c.table["name"].value<std::string>())
    c.name = *n;
  else
    c.name = file.stem().string();
  return c;
}

void set_value(Case& c, const Override& o) {
  toml::table t = c.table;  // validate a copy: a rejected override leaves the case unchanged
  assign_override(c.source, t, o);
  fill_and_validate(c.source, t);
  c.table = std::move(t);
  if (auto n = c.table["name"].value<std::string>()) c.name = *n;
}

bool is_numeric_key(const std::string& dotted_key) {
  const KeySpec* k = find_key(dotted_key);
  return k && (k->type == Type::number || k->type == Type::integer);
}

std::string to_toml(const Case& c) {
  toml::table t = c.table;
  t.insert_or_assign("name", c.name);
  std::ostringstream os;
  os << "# pcsim sieve case (written by pcsim; every key explicit)\n" << t << "\n";
  return os.str();
}


SieveSettings settings_from_case(const Case& c) {
  const toml::table& t = c.table;
  SieveSettings s;
  auto par = [&](const char* name) { return number(t, "parameters", name); };
  SieveParameters& p = s.p;
  p.m0 = par("m0"); p.m1 = par("m1"); p.m2 = par("m2");
  p.J0 = par("J0"); p.J1 = par("J1"); p.J2 = par("J2");
  p.r = par("r"); p.e = par("e");
  p.cx = par("cx"); p.cy = par("cy"); p.ctheta = par("ctheta");
  p.bx = par("bx"); p.by = par("by"); p.btheta = par("btheta");
  p.omega = par("omega"); p.g = par("g");
  p.x0 = par("x0"); p.y0 = par("y0"); p.xc = par("xc"); p.yc = par("yc");
  p.xb = par("xb"); p.yb = par("yb"); p.a = par("a"); p.b = par("b");
  p.u0 = par("u0"); p.f = par("f");
  s.constraints.contact = *t["constraints"]["contact"].value<bool>();
  s.constraints.rolling = *t["constraints"]["rolling"].value<bool>();
  s.constraints.lock_theta = *t["constraints"]["lock_theta"].value<bool>();
  s.constraints.rolling_as_printed = *t["constraints"]["rolling_as_printed"].value<bool>();
  const toml::table& ini = *t["initial"].as_table();
  const double s0 = *ini["s0"].value<double>();
  const std::array<double, 6> q_default = {0, 0, 0, s0, p.u0, 0};
  for (int i = 0; i < 6; ++i) {
    const std::string name = kCoordinateNames[i];
    s.q0[i] = ini[name].value_or(q_default[i]);
    s.qd0[i] = ini[name + "_d"].value_or(0.0);
  }
  s.solver.kernel = *parse_kernel(*t["solver"]["kernel"].value<std::string>());
  s.solver.form = *t["solver"]["form"].value<std::string>() == "ode" ? Form::ode : Form::dae;
  s.solver.rtol = number(t, "solver", "rtol");
  s.solver.atol = number(t, "solver", "atol");
  s.solver.t_end = number(t, "solver", "t_end");
  s.solver.h0 = number(t, "solver", "h0");
  s.output.dt = number(t, "output", "dt");
  s.output.summary_periods = static_cast<int>(*t["output"]["summary_periods"].value<int64_t>());
  return s;
}

const std::vector<std::string>& unprinted_parameter_keys() {
  static const std::vector<std::string> keys = {
      "parameters.g",  "parameters.x0", "parameters.y0", "parameters.yc", "parameters.b",
      "parameters.yb", "parameters.a",  "parameters.xc", "parameters.xb", "parameters.u0",
      "initial.s0",    "parameters.f",  "solver.t_end"};
  return keys;
}

}  // namespace pcsim::sieve
