// [model.draw]: reading and checking the drawing table (with the rest of a model file), and its
// evaluator (draw.hpp).
#include "modelfile/draw.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <set>

#include <toml++/toml.h>

#include "common/error.hpp"
#include "common/format.hpp"
#include "modelfile/expression.hpp"
#include "modelfile/model_source.hpp"
#include "modelfile/tape.hpp"

namespace pcsim::modelfile {

using detail::ExprText;
using detail::fail;
using detail::ModelSource;

namespace {

constexpr std::size_t kMaxDrawPoints = 2000;
constexpr std::size_t kMaxDrawShapes = 2000;

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
  return s;
}

// The names a drawing expression may use: the coordinates, their velocities, t, pi, the
// parameters and the definitions.
struct Names {
  std::set<std::string> known;
  std::string listing;
};

Names drawable_names(const ModelSource& src) {
  Names n;
  for (const auto& c : src.coordinates) {
    n.known.insert(c);
    n.known.insert(c + "_d");
  }
  for (const auto& p : src.parameters) n.known.insert(p.name);
  for (const auto& [name, e] : src.definitions) n.known.insert(name);
  n.known.insert("t");
  n.known.insert("pi");
  n.listing = "the coordinates (" + join(src.coordinates) + "), their velocities <name>_d, t, "
              "the parameters and the definitions";
  return n;
}

class DrawReader {
 public:
  DrawReader(ModelSource& src, const std::string& prefix)
      : src_(src), where_(src.where), prefix_(prefix), names_(drawable_names(src)) {}

  void read(const toml::node& node) {
    const toml::table* t = node.as_table();
    if (!t) fail(where_, prefix_, "a table [" + prefix_ + "] with point, line, polygon, circle and arrow entries");
    only(*t, prefix_, {"view", "magnify", "point", "line", "polygon", "circle", "arrow"});
    DrawSpec& d = src_.draw;
    if (auto v = t->get("view")) {
      const auto s = v->as_string();
      if (!s || (s->get() != "2d" && s->get() != "3d"))
        fail(where_, prefix_ + ".view", "\"2d\" (points in x, y) or \"3d\" (points in x, y, z)");
      d.spatial = s->get() == "3d";
    }
    if (auto m = t->get("magnify")) {
      const double v = number(*m, prefix_ + ".magnify");
      if (!(v >= 1 && v <= 1e9)) fail(where_, prefix_ + ".magnify", "a number in [1, 1e9] (the displacement magnification shown first), got " + format_number(v));
      d.magnify = v;
    }
    // Named points first: shapes refer to them in any order.
    if (auto p = t->get("point")) {
      const toml::array& arr = array(*p, prefix_ + ".point");
      if (arr.size() > kMaxDrawPoints)
        fail(where_, prefix_ + ".point", "at most " + std::to_string(kMaxDrawPoints) + " points, got " + std::to_string(arr.size()));
      std::size_t i = 0;
      for (const auto& e : arr) {
        const std::string key = prefix_ + ".point[" + std::to_string(++i) + "]";
        const toml::table& pt = table(e, key);
        only(pt, key, {"name", "x", "y", "z", "follows"});
        const toml::node* nm = pt.get("name");
        if (!nm || !nm->as_string())
          fail(where_, key + ".name", "the point's name (a string: tests and the page find points by it)");
        const std::string name = nm->as_string()->get();
        if (!detail::is_identifier(name) || name.size() > detail::limits::name_length)
          fail(where_, key + ".name", "a name of letters, digits and '_' not starting with a digit, got '" + detail::shortened(name) + "'");
        if (point_index(name) >= 0) fail(where_, key + ".name", "a new name, got '" + name + "' twice");
        DrawPoint dp = coordinates(pt, prefix_ + ".point[" + name + "]");
        dp.name = name;
        dp.named = true;
        if (auto f = pt.get("follows")) {
          dp.follows = f->as_string() ? point_index(f->as_string()->get()) : -1;
          if (dp.follows < 0)
            fail(where_, key + ".follows", "the name of a point declared above this one (its magnified "
                                           "displacement carries this point at its true offset)");
        }
        d.points.push_back(dp);
      }
    }
    std::size_t count = 0;
    for (const char* kind : {"line", "polygon", "circle", "arrow"}) {
      const toml::node* n = t->get(kind);
      if (!n) continue;
      const toml::array& arr = array(*n, prefix_ + "." + kind);
      count += arr.size();
      if (count > kMaxDrawShapes)
        fail(where_, prefix_ + "." + kind, "at most " + std::to_string(kMaxDrawShapes) + " shapes in all");
      std::size_t i = 0;
      for (const auto& e : arr) shape(kind, e, prefix_ + "." + kind + "[" + std::to_string(++i) + "]");
    }
    if (d.shapes.empty())
      fail(where_, prefix_, "at least one line, polygon, circle or arrow ([[" + prefix_ + ".line]] points = [\"A\", \"B\"])");
  }

 private:
  void only(const toml::table& t, const std::string& key, const std::vector<std::string>& allowed) const {
    for (auto&& [k, v] : t) {
      const std::string name(k.str());
      if (std::find(allowed.begin(), allowed.end(), name) == allowed.end())
        fail(where_, key + "." + detail::shortened(name), "unknown key (expected one of: " + join(allowed) + ")");
    }
  }
  const toml::table& table(const toml::node& n, const std::string& key) const {
    if (!n.is_table()) fail(where_, key, "a table");
    return *n.as_table();
  }
  const toml::array& array(const toml::node& n, const std::string& key) const {
    if (!n.is_array()) fail(where_, key, "an array of tables, written [[" + key + "]]");
    return *n.as_array();
  }
  double number(const toml::node& n, const std::string& key) const {
    double v;
    if (auto i = n.as_integer()) v = static_cast<double>(i->get());
    else if (auto f = n.as_floating_point()) v = f->get();
    else fail(where_, key, "a number");
    if (!std::isfinite(v)) fail(where_, key, "a finite number");
    return v;
  }
  std::string color(const toml::table& t, const std::string& name, const std::string& key) const {
    const toml::node* n = t.get(name);
    if (!n) return "";
    const auto s = n->as_string();
    bool ok = s && s->get().size() == 7 && s->get()[0] == '#';
    if (ok)
      for (std::size_t i = 1; i < 7; ++i) ok = ok && std::isxdigit(static_cast<unsigned char>(s->get()[i]));
    if (!ok) fail(where_, key + "." + name, "a colour \"#rrggbb\" (six hexadecimal digits)");
    return s->get();
  }
  // An expression of the drawable names; checked by its names here, parsed when drawn.
  std::string expression(const toml::node& n, const std::string& key) const {
    std::string text;
    if (auto s = n.as_string()) text = s->get();
    else if (n.is_number()) text = format_number(number(n, key));
    else fail(where_, key, "an expression (a string such as \"L*sin(phi)\") or a number");
    if (text.find_first_not_of(" \t\r\n") == std::string::npos) fail(where_, key, "an expression, got an empty string");
    detail::check_expression_size(ExprText{where_, key, text});
    for (const auto& name : detail::names_used(text)) {
      if (names_.known.count(name)) continue;
      std::string hint;
      if (name.rfind("R_", 0) == 0)
        hint = " (reactions are drawn by [[" + prefix_ + ".arrow]] force = \"" + name + "\")";
      fail(where_, key, "an expression of " + names_.listing + ", but it uses '" + detail::shortened(name) + "'" + hint);
    }
    return text;
  }
  int point_index(const std::string& name) const {
    for (std::size_t i = 0; i < src_.draw.points.size(); ++i)
      if (src_.draw.points[i].named && src_.draw.points[i].name == name) return static_cast<int>(i);
    return -1;
  }
  DrawPoint coordinates(const toml::table& t, const std::string& key) const {
    DrawPoint p;
    p.name = key;
    p.named = false;
    const toml::node* x = t.get("x");
    const toml::node* y = t.get("y");
    if (!x) fail(where_, key + ".x", "the point's x (an expression)");
    if (!y) fail(where_, key + ".y", "the point's y (an expression)");
    p.x = expression(*x, key + ".x");
    p.y = expression(*y, key + ".y");
    if (auto z = t.get("z")) {
      if (!src_.draw.spatial) fail(where_, key + ".z", "z only in a drawing with view = \"3d\"");
      p.z = expression(*z, key + ".z");
    }
    return p;
  }
  // A point reference: the name of a [[draw.point]] or a table {x = ..., y = ...}.
  int reference(const toml::node& n, const std::string& key) {
    if (auto s = n.as_string()) {
      const int i = point_index(s->get());
      if (i < 0) {
        std::vector<std::string> named;
        for (const auto& p : src_.draw.points)
          if (p.named) named.push_back(p.name);
        fail(where_, key, "the name of a [[" + prefix_ + ".point]] (" +
                              (named.empty() ? std::string("there are none") : "points: " + join(named)) +
                              ") or a table { x = \"...\", y = \"...\" }, got '" + detail::shortened(s->get()) + "'");
      }
      return i;
    }
    if (n.is_table()) {
      const toml::table& t = *n.as_table();
      only(t, key, {"x", "y", "z"});
      src_.draw.points.push_back(coordinates(t, key));
      if (src_.draw.points.size() > kMaxDrawPoints + kMaxDrawShapes) fail(where_, key, "fewer points");
      return static_cast<int>(src_.draw.points.size()) - 1;
    }
    fail(where_, key, "a point: the name of a [[" + prefix_ + ".point]] or a table { x = \"...\", y = \"...\" }");
  }
  void shape(const std::string& kind, const toml::node& node, const std::string& key) {
    const toml::table& t = table(node, key);
    DrawShape s;
    s.key = key;
    if (kind == "line" || kind == "polygon") {
      s.kind = kind == "line" ? DrawShape::Kind::line : DrawShape::Kind::polygon;
      only(t, key, kind == "line" ? std::vector<std::string>{"points", "closed", "color", "mode"}
                                  : std::vector<std::string>{"points", "color", "fill", "mode"});
      const toml::node* p = t.get("points");
      const std::size_t need = kind == "line" ? 2 : 3;
      if (!p || !p->is_array() || p->as_array()->size() < need)
        fail(where_, key + ".points", "a list of at least " + std::to_string(need) + " points (names of [[" + prefix_ + ".point]] or tables { x = \"...\", y = \"...\" })");
      std::size_t i = 0;
      for (const auto& e : *p->as_array()) s.points.push_back(reference(e, key + ".points[" + std::to_string(++i) + "]"));
      if (auto c = t.get("closed")) {
        if (!c->as_boolean()) fail(where_, key + ".closed", "a boolean (true or false)");
        s.closed = c->as_boolean()->get();
      }
    } else if (kind == "circle") {
      s.kind = DrawShape::Kind::circle;
      only(t, key, {"centre", "radius", "color", "fill", "mode"});
      const toml::node* c = t.get("centre");
      if (!c) fail(where_, key + ".centre", "the centre: a point's name or a table { x = \"...\", y = \"...\" }");
      s.points.push_back(reference(*c, key + ".centre"));
      const toml::node* r = t.get("radius");
      if (!r) fail(where_, key + ".radius", "the radius (an expression)");
      s.radius = expression(*r, key + ".radius");
    } else {
      s.kind = DrawShape::Kind::arrow;
      only(t, key, {"at", "force", "direction", "unit", "length", "unit_name", "color"});
      const toml::node* a = t.get("at");
      if (!a) fail(where_, key + ".at", "the arrow's foot: a point's name or a table { x = \"...\", y = \"...\" }");
      s.points.push_back(reference(*a, key + ".at"));
      const toml::node* f = t.get("force");
      std::vector<std::string> columns;
      for (const auto& q : src_.coordinates) columns.push_back("R_" + q);
      for (const auto& [name, e] : src_.outputs) columns.push_back(name);
      if (!f || !f->as_string() ||
          std::find(columns.begin(), columns.end(), f->as_string()->get()) == columns.end())
        fail(where_, key + ".force", "a time-series column to draw: a reaction R_<coordinate> or an output (one of: " + join(columns) + ")");
      s.force = f->as_string()->get();
      const toml::node* d = t.get("direction");
      if (!d || !d->is_table()) fail(where_, key + ".direction", "the direction of a positive force, a table { x = \"...\", y = \"...\" } (normalized when drawn)");
      const toml::table& dt = *d->as_table();
      only(dt, key + ".direction", {"x", "y", "z"});
      if (!dt.get("x") || !dt.get("y")) fail(where_, key + ".direction", "both x and y");
      s.dx = expression(*dt.get("x"), key + ".direction.x");
      s.dy = expression(*dt.get("y"), key + ".direction.y");
      if (auto z = dt.get("z")) {
        if (!src_.draw.spatial) fail(where_, key + ".direction.z", "z only in a drawing with view = \"3d\"");
        s.dz = expression(*z, key + ".direction.z");
      }
      for (const char* k : {"unit", "length"}) {
        const toml::node* n = t.get(k);
        if (!n) fail(where_, key + "." + k, "the arrow's scale: an arrow `length` long (drawing units) shows `unit` of the force (both numbers > 0)");
        const double v = number(*n, key + "." + k);
        if (!(v > 0)) fail(where_, key + "." + k, "a number > 0, got " + format_number(v));
        (std::string(k) == "unit" ? s.unit : s.length) = v;
      }
      s.unit_name = "N";
      if (auto u = t.get("unit_name")) {
        if (!u->as_string() || u->as_string()->get().empty() || u->as_string()->get().size() > 16)
          fail(where_, key + ".unit_name", "a short string (the force's unit, default \"N\")");
        s.unit_name = u->as_string()->get();
        for (char ch : s.unit_name)
          if (!(std::isalnum(static_cast<unsigned char>(ch)) || ch == ' ' || ch == '*' || ch == '/' || ch == '.' || ch == '^'))
            fail(where_, key + ".unit_name", "letters, digits, spaces and * / . ^ only");
      }
    }
    s.color = color(t, "color", key);
    if (s.kind == DrawShape::Kind::polygon || s.kind == DrawShape::Kind::circle) s.fill = color(t, "fill", key);
    if (auto m = t.get("mode")) {
      std::vector<std::string> unilateral;
      for (const auto& c : src_.constraints)
        if (c.spec.unilateral) unilateral.push_back(c.spec.name);
      if (!m->as_string() || std::find(unilateral.begin(), unilateral.end(), m->as_string()->get()) == unilateral.end())
        fail(where_, key + ".mode", "the name of a unilateral constraint whose contact mode colours the shape (" +
                                        (unilateral.empty() ? std::string("the model has none") : "one of: " + join(unilateral)) + ")");
      s.mode = m->as_string()->get();
    }
    src_.draw.shapes.push_back(std::move(s));
  }

  ModelSource& src_;
  std::string where_, prefix_;
  Names names_;
};

}  // namespace

void detail::read_draw_table(const toml::node& node, ModelSource& src) {
  DrawReader(src, src.prefix.empty() ? "draw" : src.prefix + ".draw").read(node);
}

// ---- the evaluator ---------------------------------------------------------------------------

namespace {

// A straight-line program on a value stack.
enum class Code : unsigned char { input, constant, add, mul, powi, pow, fn1, fn2 };
enum class Fn : unsigned char { sin, cos, tan, asin, acos, atan, sinh, cosh, tanh, exp, log, abs, step, atan2, min, max };
struct Step {
  Code code;
  Fn fn = Fn::sin;
  int arg = 0;       // input index, operand count (add, mul) or the integer exponent
  double value = 0;  // constant
};
using Program = std::vector<Step>;

double run_program(const Program& p, const std::vector<double>& in, std::vector<double>& stack) {
  stack.clear();
  for (const Step& s : p) {
    switch (s.code) {
      case Code::input: stack.push_back(in[static_cast<std::size_t>(s.arg)]); break;
      case Code::constant: stack.push_back(s.value); break;
      case Code::add: {
        double v = 0;
        for (int k = 0; k < s.arg; ++k) { v += stack.back(); stack.pop_back(); }
        stack.push_back(v);
        break;
      }
      case Code::mul: {
        double v = 1;
        for (int k = 0; k < s.arg; ++k) { v *= stack.back(); stack.pop_back(); }
        stack.push_back(v);
        break;
      }
      case Code::powi: stack.back() = powi(stack.back(), s.arg); break;
      case Code::pow: {
        const double e = stack.back();
        stack.pop_back();
        stack.back() = std::pow(stack.back(), e);
        break;
      }
      case Code::fn1: {
        double& a = stack.back();
        switch (s.fn) {
          case Fn::sin: a = std::sin(a); break;
          case Fn::cos: a = std::cos(a); break;
          case Fn::tan: a = std::tan(a); break;
          case Fn::asin: a = std::asin(a); break;
          case Fn::acos: a = std::acos(a); break;
          case Fn::atan: a = std::atan(a); break;
          case Fn::sinh: a = std::sinh(a); break;
          case Fn::cosh: a = std::cosh(a); break;
          case Fn::tanh: a = std::tanh(a); break;
          case Fn::exp: a = std::exp(a); break;
          case Fn::log: a = std::log(a); break;
          case Fn::abs: a = std::abs(a); break;
          case Fn::step: a = step(a); break;
          default: break;
        }
        break;
      }
      case Code::fn2: {
        const double b = stack.back();
        stack.pop_back();
        double& a = stack.back();
        if (s.fn == Fn::atan2) a = std::atan2(a, b);
        else if (s.fn == Fn::min) a = std::min(a, b);
        else a = std::max(a, b);
        break;
      }
    }
  }
  return stack.empty() ? std::numeric_limits<double>::quiet_NaN() : stack.back();
}

// GiNaC expression -> program (under ginac_mutex).
void compile(const GiNaC::ex& e, const std::map<std::string, int>& inputs, Program& p, const ExprText& where) {
  using namespace GiNaC;
  if (is_a<numeric>(e)) {
    const numeric& v = ex_to<numeric>(e);
    if (!v.is_real()) fail(where.where, where.key, "a real expression");
    p.push_back({Code::constant, Fn::sin, 0, v.to_double()});
  } else if (is_a<constant>(e)) {
    p.push_back({Code::constant, Fn::sin, 0, ex_to<numeric>(e.evalf()).to_double()});
  } else if (is_a<symbol>(e)) {
    const auto it = inputs.find(ex_to<symbol>(e).get_name());
    if (it == inputs.end()) fail(where.where, where.key, "no name '" + ex_to<symbol>(e).get_name() + "' in a drawing");
    p.push_back({Code::input, Fn::sin, it->second, 0});
  } else if (is_a<add>(e) || is_a<mul>(e)) {
    for (std::size_t i = 0; i < e.nops(); ++i) compile(e.op(i), inputs, p, where);
    p.push_back({is_a<add>(e) ? Code::add : Code::mul, Fn::sin, static_cast<int>(e.nops()), 0});
  } else if (is_a<power>(e)) {
    compile(e.op(0), inputs, p, where);
    const ex x = e.op(1);
    if (is_a<numeric>(x) && ex_to<numeric>(x).is_integer() && abs(ex_to<numeric>(x)) <= 64) {
      p.push_back({Code::powi, Fn::sin, ex_to<numeric>(x).to_int(), 0});
    } else {
      compile(x, inputs, p, where);
      p.push_back({Code::pow, Fn::sin, 0, 0});
    }
  } else if (is_a<function>(e)) {
    const std::string name = ex_to<function>(e).get_name();
    static const std::map<std::string, Fn> one = {
        {"sin", Fn::sin},   {"cos", Fn::cos},   {"tan", Fn::tan},   {"asin", Fn::asin},
        {"acos", Fn::acos}, {"atan", Fn::atan}, {"sinh", Fn::sinh}, {"cosh", Fn::cosh},
        {"tanh", Fn::tanh}, {"exp", Fn::exp},   {"log", Fn::log},   {"abs", Fn::abs},
        {"heaviside", Fn::step}};
    static const std::map<std::string, Fn> two = {{"atan2", Fn::atan2}, {"min", Fn::min}, {"max", Fn::max}};
    for (std::size_t i = 0; i < e.nops(); ++i) compile(e.op(i), inputs, p, where);
    if (auto it = one.find(name); it != one.end() && e.nops() == 1) p.push_back({Code::fn1, it->second, 0, 0});
    else if (auto jt = two.find(name); jt != two.end() && e.nops() == 2) p.push_back({Code::fn2, jt->second, 0, 0});
    else fail(where.where, where.key, "a function pcsim can draw, got '" + name + "'");
  } else {
    fail(where.where, where.key, "an expression pcsim can draw");
  }
}

}  // namespace

struct DrawEvaluator::Impl {
  ModelSource src;
  std::vector<Program> programs;  // in the order of evaluate()'s output
  Program period;
  bool has_period = false;
  std::vector<std::pair<std::string, double>> defaults;
  std::vector<std::string> names;
  mutable std::vector<double> stack;
  mutable std::mutex mutex;  // the stack
};

DrawEvaluator::DrawEvaluator(const std::filesystem::path& model_file)
    : impl_(std::make_unique<Impl>()) {
  Impl& im = *impl_;
  im.src = detail::load_model_source(model_file);
  const ModelSource& src = im.src;
  for (const auto& p : src.parameters) im.defaults.push_back({p.name, p.value});
  std::vector<std::string>& names = im.names;
  names.push_back("t");
  for (const auto& c : src.coordinates) names.push_back(c);
  for (const auto& c : src.coordinates) names.push_back(c + "_d");
  for (const auto& p : src.parameters) names.push_back(p.name);
  std::map<std::string, int> inputs;
  for (std::size_t i = 0; i < names.size(); ++i) inputs[names[i]] = static_cast<int>(i);
  std::lock_guard<std::mutex> lock(detail::ginac_mutex());
  detail::ExpressionParser parser;
  for (const auto& n : names) parser.define(n, GiNaC::realsymbol(n));
  // The definitions inlined, in file order (each may use those above it); one that uses what a
  // drawing has not (accelerations) stays unknown, and a drawing that uses it is refused.
  for (const auto& [name, text] : src.definitions) {
    try {
      parser.define(name, parser.parse(text));
    } catch (const InputError&) {
    }
  }
  // Symbols by name: the parser made one realsymbol per name; compile() looks them up by name.
  auto add = [&](const std::string& text, const std::string& key) {
    const ExprText e{src.where, key, text};
    Program p;
    compile(parser.parse(e), inputs, p, e);
    im.programs.push_back(std::move(p));
  };
  const DrawSpec& d = src.draw;
  for (const DrawPoint& pt : d.points) {
    const std::string k = pt.named ? (src.prefix + ".draw.point[" + pt.name + "]") : pt.name;
    add(pt.x, k + ".x");
    add(pt.y, k + ".y");
    add(pt.z.empty() ? std::string("0") : pt.z, k + ".z");
  }
  for (const DrawShape& s : d.shapes) {
    if (s.kind == DrawShape::Kind::circle) add(s.radius, s.key + ".radius");
    if (s.kind == DrawShape::Kind::arrow) {
      add(s.dx, s.key + ".direction.x");
      add(s.dy, s.key + ".direction.y");
      add(s.dz.empty() ? std::string("0") : s.dz, s.key + ".direction.z");
    }
  }
  if (src.period) {
    compile(parser.parse(*src.period), inputs, im.period, *src.period);
    im.has_period = true;
  }
}

DrawEvaluator::~DrawEvaluator() = default;
DrawEvaluator::DrawEvaluator(DrawEvaluator&&) noexcept = default;

const DrawSpec& DrawEvaluator::spec() const { return impl_->src.draw; }
const std::string& DrawEvaluator::model_name() const { return impl_->src.name; }
const std::vector<std::string>& DrawEvaluator::coordinates() const { return impl_->src.coordinates; }
const std::vector<std::pair<std::string, double>>& DrawEvaluator::parameter_defaults() const {
  return impl_->defaults;
}
const std::vector<std::string>& DrawEvaluator::input_names() const { return impl_->names; }
std::size_t DrawEvaluator::size() const { return impl_->programs.size(); }

double DrawEvaluator::period(const std::vector<double>& inputs) const {
  if (!impl_->has_period) return std::numeric_limits<double>::quiet_NaN();
  std::lock_guard<std::mutex> lock(impl_->mutex);
  return run_program(impl_->period, inputs, impl_->stack);
}

void DrawEvaluator::evaluate(const std::vector<double>& inputs, double* out) const {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  for (std::size_t i = 0; i < impl_->programs.size(); ++i) out[i] = run_program(impl_->programs[i], inputs, impl_->stack);
}

}  // namespace pcsim::modelfile
