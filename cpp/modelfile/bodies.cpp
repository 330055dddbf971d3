// Bodies, joints and forces expanded into the energy form (bodies.hpp, docs/bodies.md).
#include "modelfile/bodies.hpp"

#include <algorithm>
#include <cmath>
#include <mutex>
#include <set>
#include <sstream>

#include <ginac/ginac.h>

#include "common/format.hpp"
#include "modelfile/expression.hpp"

namespace pcsim::modelfile::bodies {

using detail::ExprText;

// ---- expression texts ----------------------------------------------------------------------

namespace {

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

// True if the text has a binary or unary + or - outside parentheses (after the first char,
// or a leading sign).
bool has_top_level_additive(const std::string& s) {
  int depth = 0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const char c = s[i];
    if (c == '(') ++depth;
    else if (c == ')') --depth;
    else if (depth == 0 && (c == '+' || c == '-')) {
      // exponent of a number literal: 1e-3
      if (i > 0 && (s[i - 1] == 'e' || s[i - 1] == 'E') && i >= 2 &&
          (std::isdigit(static_cast<unsigned char>(s[i - 2])) || s[i - 2] == '.')) {
        // part of a number only if the token before 'e' is numeric
        std::size_t j = i - 1;
        while (j > 0 && (std::isalnum(static_cast<unsigned char>(s[j - 1])) || s[j - 1] == '_' ||
                         s[j - 1] == '.'))
          --j;
        if (std::isdigit(static_cast<unsigned char>(s[j])) || s[j] == '.') continue;
      }
      return true;
    }
  }
  return false;
}

bool has_top_level(const std::string& s, char op) {
  int depth = 0;
  for (char c : s) {
    if (c == '(') ++depth;
    else if (c == ')') --depth;
    else if (depth == 0 && c == op) return true;
  }
  return false;
}

bool is_number_text(const std::string& s) {
  if (s.empty()) return false;
  char* end = nullptr;
  std::strtod(s.c_str(), &end);
  return end == s.c_str() + s.size() && (std::isdigit(static_cast<unsigned char>(s[0])) || s[0] == '.');
}

}  // namespace

bool is_zero(const Expr& a) {
  const std::string s = trim(a);
  if (s.empty()) return true;
  if (is_number_text(s)) return std::strtod(s.c_str(), nullptr) == 0.0;
  return s == "(0)";
}
bool is_one(const Expr& a) {
  const std::string s = trim(a);
  return is_number_text(s) && std::strtod(s.c_str(), nullptr) == 1.0;
}

Expr paren(const Expr& a) {
  const std::string s = trim(a);
  if (has_top_level_additive(s) || has_top_level(s, '/') || has_top_level(s, '^') ||
      has_top_level(s, '*'))
    return "(" + s + ")";
  return s;
}

namespace {
// Paren for a factor of a product: sums and quotients (a*b is fine).
Expr factor(const Expr& a) {
  const std::string s = trim(a);
  if (has_top_level_additive(s) || has_top_level(s, '/')) return "(" + s + ")";
  return s;
}
}  // namespace

Expr add(const Expr& a, const Expr& b) {
  if (is_zero(a)) return is_zero(b) ? "0" : trim(b);
  if (is_zero(b)) return trim(a);
  const std::string bs = trim(b);
  if (bs[0] == '-') return trim(a) + " - " + bs.substr(1);
  return trim(a) + " + " + bs;
}

Expr neg(const Expr& a) {
  if (is_zero(a)) return "0";
  const std::string s = trim(a);
  if (s[0] == '-' && !has_top_level_additive(s.substr(1))) return trim(s.substr(1));
  return "-" + factor(s);
}

Expr sub(const Expr& a, const Expr& b) {
  if (is_zero(b)) return is_zero(a) ? "0" : trim(a);
  if (is_zero(a)) return neg(b);
  const std::string bs = trim(b);
  if (bs[0] == '-' && !has_top_level_additive(bs.substr(1))) return trim(a) + " + " + bs.substr(1);
  if (has_top_level_additive(bs)) return trim(a) + " - (" + bs + ")";
  return trim(a) + " - " + bs;
}

Expr mul(const Expr& a, const Expr& b) {
  if (is_zero(a) || is_zero(b)) return "0";
  if (is_one(a)) return trim(b);
  if (is_one(b)) return trim(a);
  std::string as = trim(a), bs = trim(b);
  bool negative = false;
  if (as[0] == '-' && !has_top_level_additive(as.substr(1))) { negative = !negative; as = trim(as.substr(1)); }
  if (bs[0] == '-' && !has_top_level_additive(bs.substr(1))) { negative = !negative; bs = trim(bs.substr(1)); }
  if (is_one(as)) as.clear();
  if (is_one(bs)) bs.clear();
  std::string p;
  if (as.empty()) p = bs.empty() ? "1" : bs;
  else if (bs.empty()) p = as;
  else p = factor(as) + "*" + factor(bs);
  return negative ? "-" + factor(p) : p;
}

Expr sum(const std::vector<Expr>& terms) {
  Expr s = "0";
  for (const auto& t : terms) s = add(s, t);
  return s;
}

Mat3 Mat3::rot_z(const Expr& th) {
  Mat3 r;
  if (is_zero(th)) return r;
  const std::string c = "cos(" + trim(th) + ")", s = "sin(" + trim(th) + ")";
  r.m[0][0] = c;
  r.m[0][1] = neg(s);
  r.m[1][0] = s;
  r.m[1][1] = c;
  return r;
}

Vec3 add(const Vec3& a, const Vec3& b) {
  Vec3 r;
  for (int i = 0; i < 3; ++i) r[i] = add(a[i], b[i]);
  return r;
}
Vec3 sub(const Vec3& a, const Vec3& b) {
  Vec3 r;
  for (int i = 0; i < 3; ++i) r[i] = sub(a[i], b[i]);
  return r;
}
Vec3 scale(const Expr& s, const Vec3& a) {
  Vec3 r;
  for (int i = 0; i < 3; ++i) r[i] = mul(s, a[i]);
  return r;
}
Expr dot(const Vec3& a, const Vec3& b) {
  return sum({mul(a[0], b[0]), mul(a[1], b[1]), mul(a[2], b[2])});
}
Vec3 cross(const Vec3& a, const Vec3& b) {
  Vec3 r;
  r[0] = sub(mul(a[1], b[2]), mul(a[2], b[1]));
  r[1] = sub(mul(a[2], b[0]), mul(a[0], b[2]));
  r[2] = sub(mul(a[0], b[1]), mul(a[1], b[0]));
  return r;
}
Vec3 apply(const Mat3& A, const Vec3& v) {
  Vec3 r;
  for (int i = 0; i < 3; ++i) r[i] = sum({mul(A.m[i][0], v[0]), mul(A.m[i][1], v[1]), mul(A.m[i][2], v[2])});
  return r;
}
Vec3 apply_transposed(const Mat3& A, const Vec3& v) {
  Vec3 r;
  for (int i = 0; i < 3; ++i) r[i] = sum({mul(A.m[0][i], v[0]), mul(A.m[1][i], v[1]), mul(A.m[2][i], v[2])});
  return r;
}
Mat3 multiply(const Mat3& A, const Mat3& B) {
  Mat3 r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      r.m[i][j] = sum({mul(A.m[i][0], B.m[0][j]), mul(A.m[i][1], B.m[1][j]), mul(A.m[i][2], B.m[2][j])});
  return r;
}
Vec3 column(const Mat3& A, int j) {
  Vec3 r;
  for (int i = 0; i < 3; ++i) r[i] = A.m[i][j];
  return r;
}

Expr Lin::coefficient(const std::string& c) const {
  for (const auto& [name, e] : coef)
    if (name == c) return e;
  return "0";
}

Expr Lin::text() const {
  Expr s = "0";
  for (const auto& [name, e] : coef) s = add(s, mul(e, name + "_d"));
  return add(s, rest);
}

Lin add(const Lin& a, const Lin& b) {
  Lin r = a;
  for (const auto& [name, e] : b.coef) {
    bool found = false;
    for (auto& [n2, e2] : r.coef)
      if (n2 == name) {
        e2 = add(e2, e);
        found = true;
      }
    if (!found) r.coef.push_back({name, e});
  }
  r.rest = add(a.rest, b.rest);
  // drop zero coefficients
  r.coef.erase(std::remove_if(r.coef.begin(), r.coef.end(),
                              [](const auto& p) { return is_zero(p.second); }),
               r.coef.end());
  return r;
}
Lin scale(const Expr& s, const Lin& a) {
  Lin r;
  if (is_zero(s)) return r;
  for (const auto& [name, e] : a.coef) {
    const Expr p = mul(s, e);
    if (!is_zero(p)) r.coef.push_back({name, p});
  }
  r.rest = mul(s, a.rest);
  return r;
}
LinVec3 add(const LinVec3& a, const LinVec3& b) {
  LinVec3 r;
  for (int i = 0; i < 3; ++i) r[i] = add(a[i], b[i]);
  return r;
}
LinVec3 cross(const LinVec3& w, const Vec3& b) {
  LinVec3 r;
  r[0] = add(scale(b[2], w[1]), scale(neg(b[1]), w[2]));
  r[1] = add(scale(b[0], w[2]), scale(neg(b[2]), w[0]));
  r[2] = add(scale(b[1], w[0]), scale(neg(b[0]), w[1]));
  return r;
}
LinVec3 apply(const Mat3& A, const LinVec3& v) {
  LinVec3 r;
  for (int i = 0; i < 3; ++i)
    r[i] = add(add(scale(A.m[i][0], v[0]), scale(A.m[i][1], v[1])), scale(A.m[i][2], v[2]));
  return r;
}
LinVec3 apply_transposed(const Mat3& A, const LinVec3& v) {
  LinVec3 r;
  for (int i = 0; i < 3; ++i)
    r[i] = add(add(scale(A.m[0][i], v[0]), scale(A.m[1][i], v[1])), scale(A.m[2][i], v[2]));
  return r;
}
Lin dot(const Vec3& a, const LinVec3& v) {
  return add(add(scale(a[0], v[0]), scale(a[1], v[1])), scale(a[2], v[2]));
}
Lin velocity_of(const std::string& coordinate) {
  Lin l;
  l.coef.push_back({coordinate, "1"});
  return l;
}

namespace {
Vec3 texts(const LinVec3& v) {
  Vec3 r;
  for (int i = 0; i < 3; ++i) r[i] = v[i].text();
  return r;
}
}  // namespace
Vec3 velocity_text(const Pose& p) { return p.has_text ? p.v_text : texts(p.v); }
Vec3 angular_velocity_text(const Pose& p) { return p.has_text ? p.w_text : texts(p.w); }
Vec3 body_angular_velocity_text(const Pose& p) { return p.has_text ? p.w_body_text : texts(p.w_body); }

const Marker* Body::marker(const std::string& n) const {
  for (const auto& m : markers)
    if (m.name == n) return &m;
  return nullptr;
}

// ---- registries ----------------------------------------------------------------------------

namespace {

struct Registry {
  std::map<std::string, std::shared_ptr<const BodyKind>> kinds;
  std::map<std::string, std::shared_ptr<const JointType>> joints, spatial_joints;
  std::map<std::string, std::shared_ptr<const ForceType>> forces;
};

void register_planar(Registry& r);

Registry& registry() {
  static Registry* r = [] {
    auto* reg = new Registry;
    register_planar(*reg);
    return reg;
  }();
  return *r;
}

std::once_flag spatial_once;
void ensure_registered() {
  registry();
  std::call_once(spatial_once, [] { register_spatial_bodies(); });
}

}  // namespace

void register_body_kind(std::shared_ptr<const BodyKind> kind) {
  registry().kinds[kind->name()] = std::move(kind);
}
void register_joint_type(std::shared_ptr<const JointType> type) {
  registry().joints[type->name()] = std::move(type);
}
void register_spatial_joint_type(std::shared_ptr<const JointType> type) {
  registry().spatial_joints[type->name()] = std::move(type);
}
void register_force_type(std::shared_ptr<const ForceType> type) {
  registry().forces[type->name()] = std::move(type);
}

// ---- default BodyKind / JointType behaviour ------------------------------------------------

void BodyKind::read_inertia(Expander& x, const toml::node* node, Body& b) const {
  if (!node) x.fail(b.key + ".inertia", "the moment of inertia about the centre of mass (an expression)");
  b.inertia = Mat3{};
  b.inertia.m[0][0] = "0";
  b.inertia.m[1][1] = "0";
  b.inertia.m[2][2] = x.expression(*node, b.key + ".inertia");
}

Expr BodyKind::kinetic(const Body& b) const {
  // ½ m |v_c|² + ½ ω_bᵀ J ω_b, v_c = v + ω × (A c).
  const Vec3 wb = body_angular_velocity_text(b.pose);
  std::vector<Expr> lin;
  auto squares = [&](const Vec3& v) {
    for (int i = 0; i < 3; ++i)
      if (!is_zero(v[i])) lin.push_back("(" + v[i] + ")^2");
  };
  // v_c = V_o + A (ω_b × c), V_o the velocity of the body frame's origin; and for a body placed
  // on a parent P, V_o = V_P + A_P u_o (u_o: the origin's velocity relative to P's, in P's
  // frame, P's rotation included). Rotations keep lengths, so |v_c|² is written as the sum of
  // the squares of the rotation-free parts and cross terms: no sin² + cos² for the algebra to
  // miss (the sieve's roller gives the paper's m2 (s² + u²) θ̇², its rotor m0 e² (θ̇ + ω)²).
  const Vec3 wc = cross(wb, b.com);  // body frame
  auto cross_term = [&](const Expr& e) {
    if (!is_zero(e)) lin.push_back(mul("2", paren(e)));
  };
  // |ω × r|²: in the plane (ω along z, r in x-y) ω_z² (r_x² + r_y²), the paper's form (and
  // one whose derivatives the tape orders the same way in every process).
  auto squares_of_cross = [&](const Vec3& w, const Vec3& r) {
    if (is_zero(w[0]) && is_zero(w[1]) && is_zero(r[2])) {
      std::vector<Expr> rr;
      for (int i = 0; i < 2; ++i)
        if (!is_zero(r[i])) rr.push_back(paren(r[i]) + "^2");
      if (!rr.empty() && !is_zero(w[2])) lin.push_back(mul(paren(w[2]) + "^2", paren(sum(rr))));
    } else {
      squares(cross(w, r));
    }
  };
  if (b.parent.empty()) {
    const Vec3 V = velocity_text(b.pose);
    squares(V);
    cross_term(dot(V, apply(b.pose.A, wc)));
  } else {
    const Pose& P = b.parent_pose;
    Vec3 rel_v;
    for (int i = 0; i < 3; ++i) rel_v[i] = b.relative.v[i].text();
    const Vec3 wP = body_angular_velocity_text(P);
    const Vec3 uo = add(cross(wP, b.relative.r), rel_v);
    const Vec3 VP = velocity_text(P);
    squares(VP);
    // |u_o|² = |ṙ|² + 2 ṙ·(ω_P × r) + |ω_P × r|² (the sieve's s_d² + u_d² + 2 θ̇ (s u_d − u s_d)
    // + θ̇² (s² + u²)).
    squares(rel_v);
    cross_term(dot(rel_v, cross(wP, b.relative.r)));
    squares_of_cross(wP, b.relative.r);
    // 2 V_P·A_P (u_o + A_rel (ω_b × c)) as one term (two terms V_P·A_P u_o + V_P·A (ω_b × c)
    // meet an ordering tie of the tape compiler: different tapes in different processes).
    if (planar())
      cross_term(dot(VP, add(apply(P.A, uo), apply(b.pose.A, wc))));
    else
      cross_term(dot(VP, apply(P.A, add(uo, apply(b.relative.A, wc)))));
    cross_term(dot(uo, apply(b.relative.A, wc)));
  }
  squares_of_cross(wb, b.com);
  Expr T = "0";
  if (!lin.empty()) {
    std::vector<Expr> each;
    for (const Expr& e : lin) each.push_back(mul(mul("1/2", b.mass), paren(e)));
    T = sum(each);
  }
  std::vector<Expr> rot;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      if (is_zero(b.inertia.m[i][j])) continue;
      const Expr wi = wb[i], wj = wb[j];
      if (is_zero(wi) || is_zero(wj)) continue;
      if (i == j) rot.push_back(mul(b.inertia.m[i][j], "(" + wi + ")^2"));
      else rot.push_back(mul(b.inertia.m[i][j], mul("(" + wi + ")", "(" + wj + ")")));
    }
  if (!rot.empty()) T = add(T, mul("1/2", paren(sum(rot))));
  return T;
}

Pose JointType::tree_pose(Expander& x, const Joint& j, Pose&) const {
  x.fail(j.key + ".coordinates", "a joint of type '" + j.type + "' cannot place a body by coordinates");
}

// ---- the expander --------------------------------------------------------------------------

struct Expander::Impl {
  const toml::table* model = nullptr;
  std::vector<Body> bodies;              // bodies[0] = ground
  std::vector<Joint> joints;
  std::vector<Expr> kinetic, potential, dissipation;
  std::map<std::string, std::vector<Expr>> forces;  // coordinate -> terms
  std::vector<std::string> force_order;
  std::set<std::string> names;           // bodies, joints, forces
  std::string reactions = "joint";       // [model] reactions
};

namespace {

std::vector<std::pair<std::string, const toml::node*>> file_order(const toml::table& t) {
  std::vector<std::pair<std::string, const toml::node*>> out;
  std::vector<std::pair<std::pair<toml::source_index, toml::source_index>, std::size_t>> pos;
  for (auto&& [k, v] : t) {
    pos.push_back({{k.source().begin.line, k.source().begin.column}, out.size()});
    out.push_back({std::string(k.str()), &v});
  }
  std::stable_sort(pos.begin(), pos.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<std::pair<std::string, const toml::node*>> sorted;
  for (const auto& p : pos) sorted.push_back(out[p.second]);
  return sorted;
}

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
  return s;
}

template <class Map>
std::vector<std::string> keys_of(const Map& m) {
  std::vector<std::string> k;
  for (const auto& [name, v] : m) k.push_back(name);
  return k;
}

}  // namespace

Expander::Expander(detail::ModelSource& src, const toml::table& model)
    : impl_(std::make_shared<Impl>()), src_(src) {
  impl_->model = &model;
}

const std::string& Expander::where() const { return src_.where; }

void Expander::fail(const std::string& key, const std::string& what) const {
  detail::fail(src_.where, key, what);
}

Expr Expander::expression(const toml::node& node, const std::string& key) const {
  if (auto s = node.as_string()) {
    std::string text = s->get();
    if (trim(text).empty()) fail(key, "an expression, got an empty string");
    ExprText e{src_.where, key, text};
    detail::check_expression_size(e);
    return trim(text);
  }
  if (node.is_number()) return format_number(number(node, key));
  fail(key, "an expression (a string such as \"m*L^2/12\") or a number");
}

double Expander::number(const toml::node& node, const std::string& key) const {
  double v;
  if (auto i = node.as_integer()) v = static_cast<double>(i->get());
  else if (auto f = node.as_floating_point()) v = f->get();
  else fail(key, "a number");
  if (!std::isfinite(v)) fail(key, "a finite number, got " + format_number(v));
  return v;
}

Vec3 Expander::vector(const toml::node& node, const std::string& key, bool planar) const {
  const toml::array* a = node.as_array();
  const std::size_t want = planar ? 2 : 3;
  if (!a || !(a->size() == want || (planar && a->size() == 3)))
    fail(key, std::string("a list of ") + (planar ? "2 expressions [x, y]" : "3 expressions [x, y, z]"));
  Vec3 v;
  for (std::size_t i = 0; i < a->size(); ++i)
    v[static_cast<int>(i)] = expression(*a->get(i), key);
  if (planar && a->size() == 3 && !is_zero(v[2]))
    fail(key, "a planar vector [x, y] (its z component must be 0), got z = " + v[2]);
  return v;
}

std::string Expander::string(const toml::node& node, const std::string& key, const std::string& what) const {
  if (auto s = node.as_string()) return s->get();
  fail(key, what);
}

bool Expander::boolean(const toml::node& node, const std::string& key) const {
  if (auto b = node.as_boolean()) return b->get();
  fail(key, "a boolean (true or false)");
}

Expr Expander::optional(const toml::table& t, const std::string& table_key, const std::string& name) const {
  if (auto n = t.get(name)) return expression(*n, table_key + "." + name);
  return "";
}

Expr Expander::required(const toml::table& t, const std::string& table_key, const std::string& name,
                        const std::string& what) const {
  if (auto n = t.get(name)) return expression(*n, table_key + "." + name);
  fail(table_key + "." + name, what);
}

const Body& Expander::body(const std::string& name, const std::string& key) const {
  for (const auto& b : impl_->bodies)
    if (b.name == name) return b;
  std::vector<std::string> names;
  for (const auto& b : impl_->bodies) names.push_back(b.name);
  fail(key, "the name of a body (declared: " + join(names) + "), got '" + name + "'");
}

const Marker& Expander::marker(const Body& b, const std::string& name, const std::string& key) const {
  if (const Marker* m = b.marker(name)) return *m;
  std::vector<std::string> names;
  for (const auto& m : b.markers) names.push_back(m.name);
  fail(key, "a marker of body '" + b.name + "' (declared: " + join(names) + "), got '" + name + "'");
}

Vec3 Expander::marker_position(const Body& b, const Marker& m) const {
  return add(b.pose.r, apply(b.pose.A, m.p));
}
Mat3 Expander::marker_axes(const Body& b, const Marker& m) const { return multiply(b.pose.A, m.R); }
LinVec3 Expander::marker_velocity(const Body& b, const Marker& m) const {
  return add(b.pose.v, cross(b.pose.w, apply(b.pose.A, m.p)));
}
LinVec3 Expander::point_velocity(const Body& b, const Vec3& P) const {
  return add(b.pose.v, cross(b.pose.w, sub(P, b.pose.r)));
}
Expr Expander::planar_angle(const Body& b) const {
  // A = Rz(th): th is what rot_z was given; recover it from the sin entry.
  const std::string& s = b.pose.A.m[1][0];
  if (is_zero(s)) return "0";
  return s.substr(4, s.size() - 5);  // "sin(th)"
}

std::string Expander::define(const std::string& name, const Expr& value, const std::string& key) {
  src_.definitions.push_back({name, ExprText{src_.where, key, value}});
  return name;
}

void Expander::add_coordinate(const std::string& name, const std::string& key) {
  if (std::find(src_.coordinates.begin(), src_.coordinates.end(), name) != src_.coordinates.end())
    return;  // declared in [model] coordinates (fixes the order)
  if (!detail::is_identifier(name) || detail::is_reserved_name(name))
    fail(key, "a coordinate name (letters, digits and '_', not reserved), got '" + name + "'");
  src_.coordinates.push_back(name);
}

void Expander::add_kinetic(const Expr& e) { if (!is_zero(e)) impl_->kinetic.push_back(e); }
void Expander::add_potential(const Expr& e) { if (!is_zero(e)) impl_->potential.push_back(e); }
void Expander::add_dissipation(const Expr& e) { if (!is_zero(e)) impl_->dissipation.push_back(e); }

void Expander::add_power(const Lin& v, const Expr& f, const std::string& key) {
  (void)key;
  if (is_zero(f)) return;
  for (const auto& [c, coef] : v.coef) {
    const Expr term = mul(coef, f);
    if (is_zero(term)) continue;
    if (!impl_->forces.count(c)) impl_->force_order.push_back(c);
    impl_->forces[c].push_back(term);
  }
}

void Expander::add_constraint(const Row& row, const std::string& key) {
  detail::SourceConstraint sc;
  sc.spec.name = row.name;
  sc.key = key;
  sc.spec.active_by_default = row.active;
  sc.spec.from_initial = row.from_initial;
  if (!row.velocity_form) {
    sc.spec.kind = mech::ConstraintKind::holonomic;
    sc.holonomic = ExprText{src_.where, key, row.holonomic};
    sc.spec.holonomic = row.holonomic;
  } else {
    sc.spec.kind = mech::ConstraintKind::velocity;
    for (const auto& [c, coef] : row.velocity.coef) {
      auto it = std::find(src_.coordinates.begin(), src_.coordinates.end(), c);
      const int i = static_cast<int>(it - src_.coordinates.begin());
      sc.velocity.push_back({i, ExprText{src_.where, key, coef}});
      sc.spec.velocity.push_back({c, coef});
    }
    if (sc.velocity.empty()) fail(key, "a velocity row that involves a coordinate (this joint's row is 0)");
    sc.velocity0 = ExprText{src_.where, key, is_zero(row.velocity.rest) ? "" : row.velocity.rest};
    sc.spec.velocity0 = sc.velocity0.text;
  }
  sc.spec.unilateral = row.unilateral;
  sc.spec.gap_sign = row.gap_sign;
  sc.restitution = ExprText{src_.where, key + ".restitution", row.restitution};
  sc.spec.restitution = row.restitution;
  sc.mu_static = ExprText{src_.where, key + ".mu_static", row.mu_static};
  sc.spec.mu_static = row.mu_static;
  sc.mu_kinetic = ExprText{src_.where, key + ".mu_kinetic", row.mu_kinetic};
  sc.spec.mu_kinetic = row.mu_kinetic;
  sc.spec.friction = row.friction;
  sc.spec.rough = row.rough;
  src_.constraints.push_back(std::move(sc));
}

void Expander::add_output(const std::string& name, const Expr& e, const std::string& key) {
  src_.outputs.push_back({name, ExprText{src_.where, key, e}});
}

bool has_body_form(const toml::table& model) {
  return model.get("body") || model.get("joint") || model.get("force");
}

const std::vector<std::string>& body_form_keys() {
  static const std::vector<std::string> k{"body", "joint", "force", "reactions"};
  return k;
}

// ---- the planar kinds, joints and forces ---------------------------------------------------

namespace {

class PlanarBody : public BodyKind {
 public:
  std::string name() const override { return "planar"; }
  bool planar() const override { return true; }
  std::vector<std::string> coordinates(const Body& b) const override {
    return {b.name + "_x", b.name + "_y", b.name + "_th"};
  }
  Pose free_pose(const Body& b) const override {
    Pose p;
    p.r[0] = b.coordinates[0];
    p.r[1] = b.coordinates[1];
    p.A = Mat3::rot_z(b.coordinates[2]);
    p.v[0] = velocity_of(b.coordinates[0]);
    p.v[1] = velocity_of(b.coordinates[1]);
    p.w[2] = velocity_of(b.coordinates[2]);
    p.w_body[2] = p.w[2];
    return p;
  }
};

class PlanarParticle : public BodyKind {
 public:
  std::string name() const override { return "particle"; }
  bool planar() const override { return true; }
  void read_inertia(Expander& x, const toml::node* node, Body& b) const override {
    if (node) x.fail(b.key + ".inertia", "no inertia for a particle (a point mass)");
    b.inertia = Mat3{};
    for (int i = 0; i < 3; ++i) b.inertia.m[i][i] = "0";
  }
  std::vector<std::string> coordinates(const Body& b) const override {
    return {b.name + "_x", b.name + "_y"};
  }
  Pose free_pose(const Body& b) const override {
    Pose p;
    p.r[0] = b.coordinates[0];
    p.r[1] = b.coordinates[1];
    p.v[0] = velocity_of(b.coordinates[0]);
    p.v[1] = velocity_of(b.coordinates[1]);
    return p;
  }
};

// The planar relative transform of a tree joint: body2's marker2 frame = marker1's frame
// translated by (tx, ty) (marker1 axes) and turned by phi. Each of tx, ty, phi is a coordinate,
// a prescribed motion f(t) with its rate, or 0.
struct PlanarDof {
  Expr value = "0";
  Lin rate;  // its time derivative, linear in the velocities
};

Pose planar_tree_pose(Expander& x, const Joint& j, const PlanarDof& tx, const PlanarDof& ty,
                      const PlanarDof& phi, Pose& rel) {
  const Body& b1 = x.body(j.body1, j.key + ".body1");
  const Body& b2 = x.body(j.body2, j.key + ".body2");
  const Marker& m1 = x.marker(b1, j.marker1, j.key + ".marker1");
  const Marker& m2 = x.marker(b2, j.marker2, j.key + ".marker2");
  if (!x.body(j.body1, j.key).ground && b1.kind != "planar" && b1.kind != "particle")
    x.fail(j.key + ".body1", "a planar body or ground for a planar tree joint");
  Pose p;
  const Expr a1 = x.planar_angle(b1);
  const Expr am1 = m1.R.m[1][0].empty() || is_zero(m1.R.m[1][0]) ? "0" : m1.R.m[1][0].substr(4, m1.R.m[1][0].size() - 5);
  const Expr am2 = m2.R.m[1][0].empty() || is_zero(m2.R.m[1][0]) ? "0" : m2.R.m[1][0].substr(4, m2.R.m[1][0].size() - 5);
  // th2 = th1 + am1 + phi - am2
  Expr th2 = sub(add(add(a1, am1), phi.value), am2);
  // position of marker2 origin: r1 + A1 (p1 + R(am1) t)
  Vec3 t;
  t[0] = tx.value;
  t[1] = ty.value;
  const Mat3 Rm1 = Mat3::rot_z(am1);
  const Vec3 local = add(m1.p, apply(Rm1, t));
  const Vec3 rm2 = add(b1.pose.r, apply(b1.pose.A, local));
  // define the angle and position of body2 (readable expansion, shared on the tape)
  const std::string key = j.key;
  Expr th_name = "0";
  if (!is_zero(th2)) th_name = x.define(b2.name + "_th", th2, key);
  const Mat3 A2 = Mat3::rot_z(th_name);
  const Vec3 r2v = sub(rm2, apply(A2, m2.p));
  // Defined for outputs and drawings, but the equations use the texts: the tape compiler orders
  // derivatives of alike position definitions (x + sin(theta)*y0 + ..., x + sin(theta)*s + ...)
  // differently from process to process (a tie of its structural order).
  x.define(b2.name + "_x", r2v[0], key);
  x.define(b2.name + "_y", r2v[1], key);
  p.r[0] = r2v[0];
  p.r[1] = r2v[1];
  p.A = A2;
  // velocities: w2 = w1 + phi_d; v_m2 = v1 + w1 × (A1 local) + A1 Rm1 ṫ; v2 = v_m2 - w2 × (A2 p2)
  p.w = b1.pose.w;
  p.w[2] = add(p.w[2], phi.rate);
  p.w_body = p.w;
  LinVec3 tdot;
  tdot[0] = tx.rate;
  tdot[1] = ty.rate;
  const LinVec3 vm2 = add(add(b1.pose.v, cross(b1.pose.w, apply(b1.pose.A, local))),
                          apply(b1.pose.A, apply(Rm1, tdot)));
  p.v = add(vm2, cross(p.w, scale("-1", apply(A2, m2.p))));
  // The same velocities as short texts on the parent's (definitions): for the energy.
  {
    const Vec3 v1 = velocity_text(b1.pose), w1 = angular_velocity_text(b1.pose);
    Vec3 w2;
    w2[2] = add(w1[2], phi.rate.text());
    Vec3 tdt;
    tdt[0] = tx.rate.text();
    tdt[1] = ty.rate.text();
    const Vec3 vm2t = add(add(v1, cross(w1, apply(b1.pose.A, local))), apply(b1.pose.A, apply(Rm1, tdt)));
    const Vec3 v2 = add(vm2t, cross(w2, scale("-1", apply(A2, m2.p))));
    p.has_text = true;
    const char* ax[3] = {"x", "y", "z"};
    for (int i = 0; i < 2; ++i) {
      const Expr e = v2[i];
      p.v_text[i] = (is_zero(e) || !has_top_level_additive(e)) ? e : x.define(b2.name + "_v" + ax[i], e, key);
    }
    p.w_text[2] = (is_zero(w2[2]) || !has_top_level_additive(w2[2])) ? w2[2] : x.define(b2.name + "_w", w2[2], key);
    p.w_body_text = p.w_text;
  }
  // relative to body1: r = local - R(th_rel) p2, A = R(th_rel), rates in body1 components
  const Expr th_rel = sub(add(am1, phi.value), am2);
  rel.A = Mat3::rot_z(th_rel);
  rel.r = sub(local, apply(rel.A, m2.p));
  rel.w[2] = phi.rate;
  rel.w_body = rel.w;
  rel.v = add(apply(Rm1, tdot), cross(rel.w, scale("-1", apply(rel.A, m2.p))));
  return p;
}


// d/dt of an expression of t and the parameters (a prescribed motion), by GiNaC, printed back
// in the model-file language.
Expr time_derivative(Expander& x, const Expr& f, const std::string& key) {
  std::lock_guard<std::mutex> lock(detail::ginac_mutex());
  detail::ExpressionParser p;
  const GiNaC::realsymbol t("t");
  p.define("t", t);
  for (const auto& par : x.source().parameters) p.define(par.name, GiNaC::realsymbol(par.name));
  p.add_hint({"", "", "a prescribed motion may use t, the parameters and numbers only"});
  const GiNaC::ex e = p.parse(ExprText{x.where(), key, f});
  return detail::canonical_text(e.diff(t));
}

// Degree of freedom `index` of a tree joint: its coordinate, or its prescribed motion.
PlanarDof tree_dof(Expander& x, const Joint& j, std::size_t index) {
  PlanarDof d;
  if (index < j.coordinates.size()) {
    const std::string& c = j.coordinates[index];
    if (c.empty()) return d;  // fixed at 0
    d.value = c;
    d.rate = velocity_of(c);
    return d;
  }
  if (const toml::node* m = j.table->get("motion")) {
    const toml::array* a = m->as_array();
    if (!a || index >= a->size()) return d;
    const std::string key = j.key + ".motion";
    d.value = x.expression(*a->get(index), key);
    d.rate.rest = time_derivative(x, d.value, key);
  }
  return d;
}

class PlanarRevolute : public JointType {
 public:
  std::string name() const override { return "revolute"; }
  std::vector<std::string> extra_keys() const override { return {"frame", "motion"}; }
  int tree_coordinates(bool) const override { return 1; }
  Pose tree_pose(Expander& x, const Joint& j, Pose& rel) const override {
    return planar_tree_pose(x, j, PlanarDof{}, PlanarDof{}, tree_dof(x, j, 0), rel);
  }
  void rows(Expander& x, Joint& j) const override {
    const Body& b1 = x.body(j.body1, j.key + ".body1");
    const Body& b2 = x.body(j.body2, j.key + ".body2");
    const Marker& m1 = x.marker(b1, j.marker1, j.key + ".marker1");
    const Marker& m2 = x.marker(b2, j.marker2, j.key + ".marker2");
    const Vec3 d = sub(x.marker_position(b2, m2), x.marker_position(b1, m1));
    Mat3 E = x.marker_axes(b1, m1);
    if (auto f = j.table->get("frame")) {
      const std::string fr = x.string(*f, j.key + ".frame", "\"marker1\" or \"ground\"");
      if (fr == "ground") E = Mat3{};
      else if (fr != "marker1") x.fail(j.key + ".frame", "\"marker1\" (default) or \"ground\", got '" + fr + "'");
    }
    const char* axis[2] = {"x", "y"};
    for (int i = 0; i < 2; ++i) {
      Row r;
      r.name = j.name + "_" + axis[i];
      r.holonomic = dot(column(E, i), d);
      j.rows.push_back(r);
      j.force[i] = "lambda_" + r.name;
    }
    j.moment[2] = "0";
    j.has_reaction = true;
  }
};

// The relative angle of two planar bodies' markers: (th2 + a_m2) - (th1 + a_m1).
Expr relative_angle(Expander& x, const Body& b1, const Marker& m1, const Body& b2, const Marker& m2) {
  auto marker_angle = [](const Marker& m) -> Expr {
    const std::string& s = m.R.m[1][0];
    return is_zero(s) ? "0" : s.substr(4, s.size() - 5);
  };
  return sub(add(x.planar_angle(b2), marker_angle(m2)), add(x.planar_angle(b1), marker_angle(m1)));
}

Lin relative_rate(const Body& b1, const Body& b2) {
  return add(b2.pose.w[2], scale("-1", b1.pose.w[2]));
}

}  // namespace

JointMotion joint_motion(Expander& x, const Joint& j, const std::string& dof, const std::string& key,
                         const std::string& dof_key) {
  JointMotion m;
  const std::string what = "'" + j.name + "' (" + j.type + ")";
  if (!j.coordinates.empty()) {  // a tree joint: its coordinate
    if (j.type == "spherical")
      x.fail(key, "a joint with a motion; the coordinates of the spherical joint " + what +
                      " are Euler parameters, which no drive, gear or spring-damper acts on (place the "
                      "body by revolute or universal joints, or use a bushing)");
    std::size_t i = 0;
    if (!dof.empty()) {
      auto it = std::find(j.coordinates.begin(), j.coordinates.end(), dof);
      if (it == j.coordinates.end())
        x.fail(dof_key, "one of the coordinates of the joint " + what + " (" + join(j.coordinates) + "), got '" + dof + "'");
      i = static_cast<std::size_t>(it - j.coordinates.begin());
    } else if (j.coordinates.size() != 1) {
      x.fail(dof_key, "which coordinate of the joint " + what + " (one of: " + join(j.coordinates) + ")");
    }
    m.position = j.coordinates[i];
    m.rate = velocity_of(j.coordinates[i]);
    m.rotation = j.type == "revolute" || (j.type == "planar" && i == 2) ||
                 (j.type == "cylindrical" && i == 0) || j.type == "universal";
    const Body& b1 = x.body(j.body1, key);
    m.planar = x.kind(x.body(j.body2, key)).planar();
    m.axes = x.marker_axes(b1, x.marker(b1, j.marker1, key));
    // The axis: z for a rotation; a planar joint's travels along marker1's x and y; a
    // prismatic joint's along x in the plane, along z in space.
    // A universal joint's angles: about its cross's arms, marker1's x (α) and marker2's y (β,
    // an arm that turns with α: its reaction column M_y is the torque about that arm).
    m.axis = j.type == "universal" ? static_cast<int>(i)
             : m.rotation          ? 2
             : j.type == "planar"  ? static_cast<int>(i)
             : m.planar            ? 0
                                   : 2;
    return m;
  }
  const bool rows = j.type == "revolute" || j.type == "prismatic" || j.type == "cylindrical";
  if (!rows || j.body2.empty())
    x.fail(key, "a revolute, prismatic or cylindrical joint (written as rows, or a tree joint with coordinates), got " + what);
  const Body& b2 = x.body(j.body2, key);
  if (b2.parent_joint == j.name)
    x.fail(key, "a joint with a coordinate; " + what + " prescribes its motion (motion = [...]) and has none");
  const Body& b1 = x.body(j.body1, key);
  const Marker& mk1 = x.marker(b1, j.marker1, key);
  const Marker& mk2 = x.marker(b2, j.marker2, key);
  m.planar = j.planar;
  m.axes = x.marker_axes(b1, mk1);
  std::string kind = j.type == "revolute" ? "rotation" : "translation";
  if (j.type == "cylindrical") {
    if (dof != "rotation" && dof != "translation")
      x.fail(dof_key, "\"rotation\" or \"translation\" (which motion of the cylindrical joint '" + j.name + "')" +
                          (dof.empty() ? std::string() : ", got '" + dof + "'"));
    kind = dof;
  } else if (!dof.empty() && dof != kind) {
    x.fail(dof_key, "\"" + kind + "\" or nothing (the only motion of the " + j.type + " joint '" + j.name + "'), got '" + dof + "'");
  }
  m.rotation = kind == "rotation";
  // The axis: z of marker1's frame, or x for a planar prismatic joint's travel.
  m.axis = (m.planar && !m.rotation) ? 0 : 2;
  const Vec3 axis = column(m.axes, m.axis);
  if (m.rotation) {
    // (ω2 − ω1)·axis; in the plane also the angle itself.
    m.rate = dot(axis, add(b2.pose.w, [&] {
               LinVec3 w1 = b1.pose.w;
               for (int i = 0; i < 3; ++i) w1[i] = scale("-1", w1[i]);
               return w1;
             }()));
    if (m.planar) {
      m.position = relative_angle(x, b1, mk1, b2, mk2);
      m.rate = relative_rate(b1, b2);
    }
  } else {
    // d·axis and its rate (v2 − v1 at marker2)·axis: d/dt(d·a) = (ḋ − ω1 × d)·a.
    const Vec3 P2 = x.marker_position(b2, mk2);
    m.position = dot(axis, sub(P2, x.marker_position(b1, mk1)));
    const LinVec3 v2 = x.marker_velocity(b2, mk2), v1 = x.point_velocity(b1, P2);
    LinVec3 rel;
    for (int i = 0; i < 3; ++i) rel[i] = add(v2[i], scale("-1", v1[i]));
    m.rate = dot(axis, rel);
  }
  return m;
}

namespace {

class PlanarPrismatic : public JointType {
 public:
  std::string name() const override { return "prismatic"; }
  std::vector<std::string> extra_keys() const override { return {"motion"}; }
  int tree_coordinates(bool) const override { return 1; }
  Pose tree_pose(Expander& x, const Joint& j, Pose& rel) const override {
    return planar_tree_pose(x, j, tree_dof(x, j, 0), PlanarDof{}, PlanarDof{}, rel);
  }
  void rows(Expander& x, Joint& j) const override {
    const Body& b1 = x.body(j.body1, j.key + ".body1");
    const Body& b2 = x.body(j.body2, j.key + ".body2");
    const Marker& m1 = x.marker(b1, j.marker1, j.key + ".marker1");
    const Marker& m2 = x.marker(b2, j.marker2, j.key + ".marker2");
    const Vec3 d = sub(x.marker_position(b2, m2), x.marker_position(b1, m1));
    const Mat3 E = x.marker_axes(b1, m1);
    Row ry;
    ry.name = j.name + "_y";
    ry.holonomic = dot(column(E, 1), d);
    j.rows.push_back(ry);
    j.force[1] = "lambda_" + ry.name;
    if (b2.kind != "particle") {
      Row rr;
      rr.name = j.name + "_rot";
      rr.holonomic = relative_angle(x, b1, m1, b2, m2);
      if (is_zero(rr.holonomic)) x.fail(j.key, "a joint whose rotation row involves a coordinate");
      j.rows.push_back(rr);
      j.moment[2] = "lambda_" + rr.name;
    }
    j.has_reaction = true;
  }
};

class PlanarFixed : public JointType {
 public:
  std::string name() const override { return "fixed"; }
  void rows(Expander& x, Joint& j) const override {
    PlanarRevolute().rows(x, j);
    const Body& b1 = x.body(j.body1, j.key + ".body1");
    const Body& b2 = x.body(j.body2, j.key + ".body2");
    Row rr;
    rr.name = j.name + "_rot";
    rr.holonomic = relative_angle(x, b1, x.marker(b1, j.marker1, j.key), b2, x.marker(b2, j.marker2, j.key));
    j.rows.push_back(rr);
    j.moment[2] = "lambda_" + rr.name;
  }
  std::vector<std::string> extra_keys() const override { return {"frame"}; }
};

// A free planar relative placement (x, y, angle in marker1's frame): the sieve's s, u, phi.
class PlanarPlanar : public JointType {
 public:
  std::string name() const override { return "planar"; }
  std::vector<std::string> extra_keys() const override { return {"motion"}; }
  int tree_coordinates(bool) const override { return 3; }
  Pose tree_pose(Expander& x, const Joint& j, Pose& rel) const override {
    return planar_tree_pose(x, j, tree_dof(x, j, 0), tree_dof(x, j, 1), tree_dof(x, j, 2), rel);
  }
  void rows(Expander& x, Joint& j) const override {
    x.fail(j.key + ".coordinates", "a planar joint places its second body by 3 coordinates "
                                   "[x, y, angle] (it generates no constraint rows)");
  }
};

class Distance : public JointType {
 public:
  std::string name() const override { return "distance"; }
  std::vector<std::string> extra_keys() const override { return {"length"}; }
  void rows(Expander& x, Joint& j) const override {
    const Body& b1 = x.body(j.body1, j.key + ".body1");
    const Body& b2 = x.body(j.body2, j.key + ".body2");
    const Vec3 d = sub(x.marker_position(b2, x.marker(b2, j.marker2, j.key + ".marker2")),
                       x.marker_position(b1, x.marker(b1, j.marker1, j.key + ".marker1")));
    const Expr L = x.required(*j.table, j.key, "length", "the distance between the markers (an expression)");
    Row r;
    r.name = j.name;
    std::vector<Expr> sq;
    for (int i = 0; i < 3; ++i)
      if (!is_zero(d[i])) sq.push_back(paren(d[i]) + "^2");
    r.holonomic = sub(sum(sq), paren(L) + "^2");
    j.rows.push_back(r);
    // Φ = |d|² − L²: the force on body2 is 2λ d, along the rod (x of the joint frame).
    j.force[0] = "2*lambda_" + r.name + "*sqrt(" + sum(sq) + ")";
    j.has_reaction = true;
  }
};

class PointOnLine : public JointType {
 public:
  std::string name() const override { return "point_on_line"; }
  std::vector<std::string> extra_keys() const override { return contact_keys(); }
  void rows(Expander& x, Joint& j) const override {
    const Body& b1 = x.body(j.body1, j.key + ".body1");
    const Body& b2 = x.body(j.body2, j.key + ".body2");
    const Marker& m1 = x.marker(b1, j.marker1, j.key + ".marker1");
    const Vec3 d = sub(x.marker_position(b2, x.marker(b2, j.marker2, j.key + ".marker2")),
                       x.marker_position(b1, m1));
    Row r;
    r.name = j.name;
    r.holonomic = dot(column(x.marker_axes(b1, m1), 1), d);
    if (has_contact_keys(j)) {
      point_on_line_contact(x, j, r);
      return;
    }
    j.rows.push_back(r);
    j.force[1] = "lambda_" + r.name;
    j.has_reaction = true;
  }

 private:
  // The contact attributes (bodies_contact.cpp): the row is the gap (marker2 on the +y side of
  // marker1's x axis); with mu_static a second row <joint>_slide, the sliding velocity of
  // marker2 relative to body1's material point under it, along the line (velocity form).
  static void point_on_line_contact(Expander& x, Joint& j, Row& gap) {
    const Body& b1 = x.body(j.body1, j.key + ".body1");
    const Body& b2 = x.body(j.body2, j.key + ".body2");
    const Marker& m1 = x.marker(b1, j.marker1, j.key + ".marker1");
    const Marker& m2 = x.marker(b2, j.marker2, j.key + ".marker2");
    Row slide;
    slide.name = j.name + "_slide";
    read_joint_contact(x, j, gap, &slide);
    j.rows.push_back(gap);
    j.force[1] = "lambda_" + gap.name;
    if (!slide.friction.empty()) {
      const LinVec3 v2 = x.marker_velocity(b2, m2);
      const LinVec3 v1 = x.point_velocity(b1, x.marker_position(b2, m2));
      LinVec3 rel;
      for (int i = 0; i < 3; ++i) rel[i] = add(v2[i], scale("-1", v1[i]));
      slide.velocity = dot(column(x.marker_axes(b1, m1), 0), rel);
      slide.velocity_form = true;
      j.rows.push_back(slide);
      j.force[0] = "lambda_" + slide.name;
    }
    j.has_reaction = true;
  }
};

class Drive : public JointType {
 public:
  std::string name() const override { return "drive"; }
  std::vector<std::string> extra_keys() const override { return {"joint", "coordinate", "motion"}; }
  void rows(Expander& x, Joint& j) const override;
};

class Gear : public JointType {
 public:
  std::string name() const override { return "gear"; }
  std::vector<std::string> extra_keys() const override { return {"joint1", "joint2", "ratio", "dof1", "dof2"}; }
  void rows(Expander& x, Joint& j) const override;
};

class Coupler : public JointType {
 public:
  std::string name() const override { return "coupler"; }
  std::vector<std::string> extra_keys() const override { return {"joints", "ratios", "dofs"}; }
  void rows(Expander& x, Joint& j) const override;
};

class Rolling : public JointType {
 public:
  std::string name() const override { return "rolling"; }
  std::vector<std::string> extra_keys() const override {
    std::vector<std::string> k{"radius", "form", "row_names", "surface", "circle_radius", "inside"};
    for (const auto& c : contact_keys()) k.push_back(c);
    return k;
  }
  void rows(Expander& x, Joint& j) const override;
};

void Drive::rows(Expander& x, Joint& j) const {
  const toml::table& t = *j.table;
  const Expr f = x.required(t, j.key, "motion", "the prescribed motion f(t) of the coordinate (an expression of t and the parameters)");
  std::string coordinate;
  int index = 0;
  std::string type;
  bool planar_tree = true;
  if (auto jn = t.get("joint")) {
    const Joint& tj = x.joint(x.string(*jn, j.key + ".joint", "the name of a joint"), j.key + ".joint");
    if (tj.coordinates.empty()) {
      // A revolute, prismatic or cylindrical joint written as rows: its motion c (the members'
      // table of docs/bodies.md) is prescribed, c − f(t) = 0, or in velocity form
      // ċ − ḟ(t) = 0 for a spatial rotation (its angle is not a function of q).
      std::string dof;
      if (auto c = t.get("coordinate")) dof = x.string(*c, j.key + ".coordinate", "\"rotation\" or \"translation\"");
      const JointMotion m = joint_motion(x, tj, dof, j.key + ".joint", j.key + ".coordinate");
      Row r;
      r.name = j.name;
      if (!m.position.empty()) {
        r.holonomic = sub(m.position, f);
      } else {
        r.velocity_form = true;
        r.velocity = m.rate;
        r.velocity.rest = add(r.velocity.rest, neg(time_derivative(x, f, j.key + ".motion")));
      }
      j.rows.push_back(r);
      if (m.rotation) j.moment[m.axis] = "lambda_" + r.name;
      else j.force[m.axis] = "lambda_" + r.name;
      j.axes = m.axes;
      j.planar = m.planar;
      j.has_reaction = true;
      return;
    }
    if (tj.type == "spherical")
      x.fail(j.key + ".joint", "a joint with a motion to prescribe; the coordinates of the spherical joint '" + tj.name +
                                   "' are Euler parameters (drive revolute or universal joints)");
    type = tj.type;
    planar_tree = tj.planar;
    if (auto c = t.get("coordinate")) {
      coordinate = x.string(*c, j.key + ".coordinate", "one of the joint's coordinates");
      auto it = std::find(tj.coordinates.begin(), tj.coordinates.end(), coordinate);
      if (it == tj.coordinates.end())
        x.fail(j.key + ".coordinate", "one of the joint's coordinates (" + join(tj.coordinates) + "), got '" + coordinate + "'");
      index = static_cast<int>(it - tj.coordinates.begin());
    } else {
      coordinate = tj.coordinates[0];
    }
  } else if (auto c = t.get("coordinate")) {
    coordinate = x.string(*c, j.key + ".coordinate", "a coordinate name");
    const auto& cs = x.source().coordinates;
    if (std::find(cs.begin(), cs.end(), coordinate) == cs.end())
      x.fail(j.key + ".coordinate", "a coordinate (one of: " + join(cs) + "), got '" + coordinate + "'");
  } else {
    x.fail(j.key + ".joint", "the joint whose coordinate the drive prescribes (or coordinate = \"NAME\")");
  }
  Row r;
  r.name = j.name;
  r.holonomic = sub(coordinate, f);
  j.rows.push_back(r);
  const std::string l = "lambda_" + r.name;
  if (type == "revolute") j.moment[2] = l;
  else if (type == "prismatic") j.force[0] = l;
  else if (type == "cylindrical") {  // (spatial) its angle about z, its travel along z
    if (index == 0) j.moment[2] = l;
    else j.force[2] = l;
    j.planar = false;  // the spatial columns F_x..F_z, M_x..M_z
  } else if (type == "universal") {  // the torques about the cross's arms (joint_motion)
    j.moment[index] = l;
    j.planar = false;
  } else if (type == "planar") {
    if (index < 2) j.force[index] = l;
    else j.moment[2] = l;
    j.planar = planar_tree;  // between spatial bodies: the spatial columns F_x..F_z, M_x..M_z
  } else {
    j.force[0] = l;  // the generalized force on the coordinate
  }
  j.has_reaction = true;
}

// Two members that are the same motion have the same displacement (or rate) text.
std::string motion_id(const JointMotion& m) { return m.position.empty() ? m.rate.text() : m.position; }

// The gear's row couples joint2's motion to joint1's: holonomic, c2 − ratio·c1 fixed at the
// initial state, when both displacements are functions of q (tree coordinates, planar joints
// written as rows, translations); in velocity form, ċ2 − ratio·ċ1 = 0, when either is a
// spatial rotation written as rows (its angle is not a function of q: the paper's velocity
// form, as for a rolling wheel). Its multiplier is the torque (force) on joint2's body2 about
// (along) joint2's axis; joint1's receives −ratio·λ.
void Gear::rows(Expander& x, Joint& j) const {
  const toml::table& t = *j.table;
  auto member = [&](const char* k, const char* dk) {
    const toml::node* n = t.get(k);
    if (!n) x.fail(j.key + "." + k, "the joint whose motion the gear couples (a revolute, prismatic or cylindrical joint, a tree joint or rows)");
    const Joint& mj = x.joint(x.string(*n, j.key + "." + k, "the name of a joint"), j.key + "." + k);
    std::string dof;
    if (const toml::node* d = t.get(dk)) dof = x.string(*d, j.key + "." + dk, "a coordinate name, or \"rotation\" / \"translation\"");
    return joint_motion(x, mj, dof, j.key + "." + k, j.key + "." + dk);
  };
  const JointMotion c1 = member("joint1", "dof1");
  const JointMotion c2 = member("joint2", "dof2");
  if (motion_id(c1) == motion_id(c2)) x.fail(j.key + ".joint2", "a motion other than joint1's (a gear couples two motions)");
  const Expr ratio = x.required(t, j.key, "ratio", "the ratio: coordinate2 = ratio * coordinate1 (+ its initial offset)");
  Row r;
  r.name = j.name;
  if (!c1.position.empty() && !c2.position.empty()) {
    r.holonomic = sub(c2.position, mul(ratio, c1.position));
    r.from_initial = true;
  } else {
    r.velocity_form = true;
    r.velocity = add(c2.rate, scale(neg(ratio), c1.rate));
  }
  j.rows.push_back(r);
  // The torque (force) on joint2's coordinate, about (along) its axis in joint2's frame.
  const std::string l = "lambda_" + r.name;
  if (c2.rotation) j.moment[c2.axis] = l;
  else j.force[c2.axis] = l;
  j.axes = c2.axes;
  j.planar = c2.planar;
  j.has_reaction = true;
}

// A coupler: Σ ratio_i·c_i fixed at the initial state (or Σ ratio_i·ċ_i = 0, in velocity form
// when a member is a spatial rotation written as rows), e.g. a differential or a planetary
// gear's Willis equation. Member i receives ratio_i·λ about (along) its axis.
void Coupler::rows(Expander& x, Joint& j) const {
  const toml::table& t = *j.table;
  const toml::array* js = t.get("joints") ? t.get("joints")->as_array() : nullptr;
  if (!js || js->size() < 2) x.fail(j.key + ".joints", "a list of two or more joint names (the motions the coupler ties)");
  const toml::array* rs = t.get("ratios") ? t.get("ratios")->as_array() : nullptr;
  if (!rs || rs->size() != js->size())
    x.fail(j.key + ".ratios", "a list of " + std::to_string(js->size()) + " expressions (one coefficient per joint: sum of ratio_i * c_i stays at its initial value)");
  const toml::array* ds = t.get("dofs") ? t.get("dofs")->as_array() : nullptr;
  if (t.get("dofs") && (!ds || ds->size() != js->size()))
    x.fail(j.key + ".dofs", "a list of " + std::to_string(js->size()) + " strings (per joint: a coordinate name, \"rotation\", \"translation\" or \"\")");
  std::vector<JointMotion> ms;
  std::vector<Expr> ratios;
  std::vector<std::string> seen, names;
  bool holonomic = true;
  for (std::size_t i = 0; i < js->size(); ++i) {
    const std::string k = j.key + ".joints[" + std::to_string(i) + "]";
    const std::string dk = j.key + ".dofs[" + std::to_string(i) + "]";
    const Joint& mj = x.joint(x.string(*js->get(i), k, "the name of a joint"), k);
    const std::string dof = ds ? x.string(*ds->get(i), dk, "a coordinate name, \"rotation\", \"translation\" or \"\"") : "";
    ms.push_back(joint_motion(x, mj, dof, k, dk));
    const std::string id = motion_id(ms.back());
    if (std::find(seen.begin(), seen.end(), id) != seen.end()) x.fail(k, "each motion once, got '" + mj.name + "' again");
    seen.push_back(id);
    names.push_back(dof.empty() ? mj.name : mj.name + "_" + dof);
    ratios.push_back(x.expression(*rs->get(i), j.key + ".ratios[" + std::to_string(i) + "]"));
    holonomic = holonomic && !ms.back().position.empty();
  }
  Row r;
  r.name = j.name;
  if (holonomic) {
    std::vector<Expr> terms;
    for (std::size_t i = 0; i < ms.size(); ++i) terms.push_back(mul(ratios[i], ms[i].position));
    r.holonomic = sum(terms);
    r.from_initial = true;
  } else {
    r.velocity_form = true;
    for (std::size_t i = 0; i < ms.size(); ++i) r.velocity = add(r.velocity, scale(ratios[i], ms[i].rate));
  }
  if (is_zero(r.holonomic) && !r.velocity_form) x.fail(j.key + ".ratios", "coefficients that are not all zero");
  j.rows.push_back(r);
  for (std::size_t i = 0; i < ms.size(); ++i)
    j.member_reactions.push_back({std::string(ms[i].rotation ? "M_" : "F_") + j.name + "_" + names[i],
                                  mul(ratios[i], "lambda_" + r.name)});
}

// The contact's sliding velocity: the velocity of the wheel's material point at its contact
// P = C − r n (C its centre, marker2; n the unit normal at the contact towards the wheel, ground
// axes) relative to body1's material point there, along the tangent tg (ground axes).
Lin contact_sliding_velocity(Expander& x, const Body& b1, const Body& b2, const Marker& m2, const Expr& r,
                             const Vec3& n, const Vec3& tg) {
  const Vec3 P = sub(x.marker_position(b2, m2), scale(r, n));
  const LinVec3 v2 = add(x.marker_velocity(b2, m2), cross(b2.pose.w, scale(neg(r), n)));
  const LinVec3 v1 = x.point_velocity(b1, P);
  LinVec3 rel;
  for (int i = 0; i < 3; ++i) rel[i] = add(v2[i], scale("-1", v1[i]));
  return dot(tg, rel);
}

// A wheel on a circle of body1 (`surface = "circle"`: centre O = marker1, radius R =
// `circle_radius`), outside it (a roller on a drum) or inside (`inside = true`: a roller in a
// ring). With d = C − O (named <joint>_dx, _dy) and its length <joint>_dist:
//   _contact  |d| − (R + r) outside, (R − r) − |d| inside: the gap in m, a distance (its gradient
//             in C is the unit normal n, so its multiplier is the normal force in N; the
//             squared form |d|² − (R ± r)² would scale it by 2|d|). Singular only at d = 0 (the
//             wheel's centre on the circle's: inside, R − r away from any contact);
//   _rolling  the contact point's sliding velocity along tg (contact_sliding_velocity),
// with n = ±d/|d| the normal towards the wheel (+ outside, − inside; <joint>_nx, _ny) and
// tg = (n_y, −n_x) the tangent: the joint frame at the contact is (tg, n), the line's (x along
// the surface, y its normal) turned to the contact, which it is at the top of a drum and at the
// bottom of a ring (n = +y). The rolling condition integrates to (R + r) ψ − r φ fixed outside,
// (R − r) ψ + r φ inside (ψ the centre's polar angle about O, φ the wheel's angle, both relative
// to body1), but ψ is an atan2 that jumps by 2π once per turn around the circle: there is no
// holonomic form, and `form = "holonomic"` is refused.
void circle_rows(Expander& x, Joint& j, const Body& b1, const Body& b2, const Marker& m1, const Marker& m2,
                 const Expr& r, const RollingSurface& s, Row& contact, Row& roll) {
  const std::string pre = j.name + "_";
  const Vec3 d = sub(x.marker_position(b2, m2), x.marker_position(b1, m1));
  const Expr dx = x.define(pre + "dx", d[0], j.key), dy = x.define(pre + "dy", d[1], j.key);
  const Expr dist = x.define(pre + "dist", "sqrt(" + dx + "^2 + " + dy + "^2)", j.key);
  const std::string sign = s.inside ? "-" : "";
  Vec3 n, tg;
  n[0] = x.define(pre + "nx", sign + dx + "/" + dist, j.key);
  n[1] = x.define(pre + "ny", sign + dy + "/" + dist, j.key);
  tg[0] = n[1];
  tg[1] = neg(n[0]);
  contact.holonomic = s.inside ? sub(sub(s.radius, r), dist) : sub(dist, paren(add(s.radius, r)));
  roll.velocity = contact_sliding_velocity(x, b1, b2, m2, r, n, tg);
  roll.velocity_form = true;
  for (int i = 0; i < 2; ++i) {  // the joint frame (tg, n, z) -> ground
    j.axes.m[i][0] = tg[i];
    j.axes.m[i][1] = n[i];
  }
}

void Rolling::rows(Expander& x, Joint& j) const {
  const toml::table& t = *j.table;
  const Body& b1 = x.body(j.body1, j.key + ".body1");
  const Body& b2 = x.body(j.body2, j.key + ".body2");
  const Marker& m1 = x.marker(b1, j.marker1, j.key + ".marker1");
  const Marker& m2 = x.marker(b2, j.marker2, j.key + ".marker2");
  if (!x.kind(b2).planar() || !(b1.ground || x.kind(b1).planar()))
    x.fail(j.key, "planar bodies (a wheel rolling on a line or a circle); spatial rolling is a spatial joint");
  const Expr r = x.required(t, j.key, "radius", "the wheel's radius (an expression)");
  const RollingSurface surface = read_rolling_surface(x, j, "wheel", r, "line", "marker1's x axis", "circle");
  std::string form = "velocity";
  if (auto f = t.get("form")) {
    form = x.string(*f, j.key + ".form", "\"velocity\" or \"holonomic\"");
    if (form != "velocity" && form != "holonomic")
      x.fail(j.key + ".form", "\"velocity\" (default: the paper's velocity form) or \"holonomic\" (s + r phi fixed at the initial state), got '" + form + "'");
    if (form == "holonomic" && surface.curved)
      x.fail(j.key + ".form", "\"velocity\" on a circle (the default): rolling on a circle integrates to (R + r) psi - r phi "
                              "fixed (inside: (R - r) psi + r phi), psi the centre's polar angle about marker1, an atan2 "
                              "that jumps by 2 pi once per turn, so it has no holonomic row");
  }
  std::string contact_name = j.name + "_contact", rolling_name = j.name + "_rolling";
  if (auto rn = t.get("row_names")) {
    const toml::table* rt = rn->as_table();
    if (!rt) x.fail(j.key + ".row_names", "a table { contact = \"NAME\", rolling = \"NAME\" }");
    for (auto&& [k, v] : *rt) {
      const std::string kk(k.str());
      const std::string key = j.key + ".row_names." + kk;
      const std::string name = x.string(v, key, "a constraint name");
      if (kk == "contact") contact_name = name;
      else if (kk == "rolling") rolling_name = name;
      else x.fail(key, "unknown key (expected one of: contact, rolling)");
    }
  }
  const Vec3 tb = column(m1.R, 0), nb = column(m1.R, 1);  // line axes, body1 frame
  Row contact, roll;
  contact.name = contact_name;
  roll.name = rolling_name;
  const bool child = b2.parent == b1.name && !b1.name.empty();
  if (surface.curved) {
    circle_rows(x, j, b1, b2, m1, m2, r, surface, contact, roll);
  } else if (child) {
    // In body1's frame, from the tree joint's relative coordinates (no rotation of body1 enters).
    const Vec3 c = add(b2.relative.r, apply(b2.relative.A, m2.p));
    const Vec3 d = sub(c, m1.p);
    contact.holonomic = sub(dot(nb, d), r);
    if (form == "holonomic") {
      const Expr th_rel = b2.relative.A.m[1][0];
      const Expr ang = is_zero(th_rel) ? "0" : th_rel.substr(4, th_rel.size() - 5);
      roll.holonomic = add(dot(tb, d), mul(r, paren(ang)));
      roll.from_initial = true;
    } else {
      const LinVec3 vc = add(b2.relative.v, cross(b2.relative.w, apply(b2.relative.A, m2.p)));
      const LinVec3 vp = add(vc, cross(b2.relative.w, scale(neg(r), nb)));
      roll.velocity = dot(tb, vp);
      roll.velocity_form = true;
    }
  } else {
    if (form == "holonomic")
      x.fail(j.key + ".form", "\"velocity\": the holonomic form needs the wheel placed on the line's body by a planar joint (its relative coordinates)");
    const Mat3 E = x.marker_axes(b1, m1);
    const Vec3 n = column(E, 1), tg = column(E, 0);
    contact.holonomic = sub(dot(n, sub(x.marker_position(b2, m2), x.marker_position(b1, m1))), r);
    roll.velocity = contact_sliding_velocity(x, b1, b2, m2, r, n, tg);
    roll.velocity_form = true;
  }
  read_joint_contact(x, j, contact, &roll);  // bodies_contact.cpp
  if (contact.unilateral && roll.friction.empty())
    x.fail(j.key + ".mu_static",
           "Coulomb's static coefficient with unilateral = true: the rolling row is then the "
           "contact's friction row, released in flight and in slip (without it the wheel would "
           "keep rolling in the air)");
  j.rows.push_back(contact);
  j.rows.push_back(roll);
  j.force[0] = "lambda_" + roll.name;
  j.force[1] = "lambda_" + contact.name;
  j.moment[2] = mul(r, "lambda_" + roll.name);
  j.has_reaction = true;
}

// ---- forces --------------------------------------------------------------------------------

// Every body with mass.
class Gravity : public ForceType {
 public:
  std::string name() const override { return "gravity"; }
  std::vector<std::string> keys() const override { return {"g"}; }
  void apply(Expander& x, const std::string&, const std::string& key, const toml::table& t) const override;
};

class SpringDamper : public ForceType {
 public:
  std::string name() const override { return "spring_damper"; }
  std::vector<std::string> keys() const override {
    return {"body1", "marker1", "body2", "marker2", "stiffness", "length", "damping"};
  }
  void apply(Expander& x, const std::string&, const std::string& key, const toml::table& t) const override {
    const Body& b1 = x.body(t.get("body1") ? x.string(*t.get("body1"), key + ".body1", "a body name") : "ground", key + ".body1");
    const Body& b2 = x.body(t.get("body2") ? x.string(*t.get("body2"), key + ".body2", "a body name") : "", key + ".body2");
    const Marker& m1 = x.marker(b1, t.get("marker1") ? x.string(*t.get("marker1"), key + ".marker1", "a marker name") : "origin", key + ".marker1");
    const Marker& m2 = x.marker(b2, t.get("marker2") ? x.string(*t.get("marker2"), key + ".marker2", "a marker name") : "origin", key + ".marker2");
    const Vec3 d = sub(x.marker_position(b2, m2), x.marker_position(b1, m1));
    const LinVec3 v2 = x.marker_velocity(b2, m2), v1 = x.marker_velocity(b1, m1);
    LinVec3 dv;
    for (int i = 0; i < 3; ++i) dv[i] = add(v2[i], scale("-1", v1[i]));
    std::vector<Expr> sq;
    for (int i = 0; i < 3; ++i)
      if (!is_zero(d[i])) sq.push_back(paren(d[i]) + "^2");
    const Expr len = "sqrt(" + sum(sq) + ")";
    const Expr k = x.optional(t, key, "stiffness"), L0 = x.optional(t, key, "length"),
               c = x.optional(t, key, "damping");
    if (k.empty() && c.empty()) x.fail(key + ".stiffness", "a stiffness or a damping (expressions)");
    if (!k.empty()) x.add_potential(mul(mul("1/2", k), "(" + sub(len, L0.empty() ? "0" : L0) + ")^2"));
    if (!c.empty()) {
      const Expr rate = "(" + dot(d, dv).text() + ")/" + paren(len);
      x.add_dissipation(mul(mul("1/2", c), "(" + rate + ")^2"));
    }
  }
};

// Linear springs and dampers along the axes of marker1's frame (and about z), between marker1
// and marker2: V = ½ Σ k_i (d·e_i − rest_i)², F = ½ Σ c_i ((v2 − v1)·e_i)². Between bodies of
// which one is spatial, the rotational terms use the relative rotation A = E1ᵀ E2 of the marker
// frames (spatial_rotational_terms, docs/bodies-spatial.md "Bushings").
class Bushing : public ForceType {
 public:
  std::string name() const override { return "bushing"; }
  std::vector<std::string> keys() const override {
    return {"body1", "marker1", "body2", "marker2", "stiffness", "rest", "damping",
            "rotational_stiffness", "rotational_rest", "rotational_damping"};
  }
  void apply(Expander& x, const std::string& name, const std::string& key, const toml::table& t) const override {
    const Body& b1 = x.body(t.get("body1") ? x.string(*t.get("body1"), key + ".body1", "a body name") : "ground", key + ".body1");
    const Body& b2 = x.body(t.get("body2") ? x.string(*t.get("body2"), key + ".body2", "a body name") : "", key + ".body2");
    const Marker& m1 = x.marker(b1, t.get("marker1") ? x.string(*t.get("marker1"), key + ".marker1", "a marker name") : "origin", key + ".marker1");
    const Marker& m2 = x.marker(b2, t.get("marker2") ? x.string(*t.get("marker2"), key + ".marker2", "a marker name") : "origin", key + ".marker2");
    // Planar unless either body is spatial (ground is neither: it takes the other's kind).
    const bool planar = (b1.ground || x.kind(b1).planar()) && (b2.ground || x.kind(b2).planar());
    const Mat3 E = x.marker_axes(b1, m1);
    const Vec3 d = sub(x.marker_position(b2, m2), x.marker_position(b1, m1));
    const LinVec3 v2 = x.marker_velocity(b2, m2), v1 = x.marker_velocity(b1, m1);
    LinVec3 dv;
    for (int i = 0; i < 3; ++i) dv[i] = add(v2[i], scale("-1", v1[i]));
    Vec3 k, rest, c;
    if (auto n = t.get("stiffness")) k = x.vector(*n, key + ".stiffness", planar);
    if (auto n = t.get("rest")) rest = x.vector(*n, key + ".rest", planar);
    if (auto n = t.get("damping")) c = x.vector(*n, key + ".damping", planar);
    for (int i = 0; i < (planar ? 2 : 3); ++i) {
      const Expr di = dot(column(E, i), d);
      if (!is_zero(k[i])) x.add_potential(mul(mul("1/2", k[i]), "(" + sub(di, rest[i]) + ")^2"));
      if (!is_zero(c[i])) x.add_dissipation(mul(mul("1/2", c[i]), "(" + dot(column(E, i), dv).text() + ")^2"));
    }
    if (!planar) {
      spatial_rotational_terms(x, name, key, t, b1, m1, b2, m2);
      return;
    }
    const Expr kr = x.optional(t, key, "rotational_stiffness"), rr = x.optional(t, key, "rotational_rest"),
               cr = x.optional(t, key, "rotational_damping");
    if (!kr.empty()) x.add_potential(mul(mul("1/2", kr), "(" + sub(relative_angle(x, b1, m1, b2, m2), rr.empty() ? "0" : rr) + ")^2"));
    if (!cr.empty()) x.add_dissipation(mul(mul("1/2", cr), "(" + relative_rate(b1, b2).text() + ")^2"));
  }

 private:
  // A scalar (isotropic: the same for the three axes) or a list of 3 expressions.
  static Vec3 scalar_or_vector(Expander& x, const toml::node& n, const std::string& key) {
    if (n.is_array()) return x.vector(n, key, false);
    const Expr e = x.expression(n, key);
    Vec3 v;
    for (int i = 0; i < 3; ++i) v[i] = e;
    return v;
  }

  // The rotational terms between spatial bodies (either may be ground). With E1, E2 the marker
  // frames in ground (body rotation · marker axes) and A = E1ᵀ E2 the rotation of marker2's frame
  // relative to marker1's (marker1 axes), the measure
  //   θ = vee(A − Aᵀ) / √(1 + tr A) = 2 sin(φ/2) n   (rotation by φ about the unit axis n)
  // is smooth and ≈ φ n for small φ, defined below a half turn (1 + tr A = 2 + 2 cos φ > 0);
  // at a half turn the division gives a non-finite value, which the engine reports (exit 3).
  //   V += ½ Σ k_i θ_i²,   F += ½ Σ c_i (e1_iᵀ (ω2 − ω1))²
  // with ω the bodies' angular velocities in ground (2 E(e) ė for Euler parameters). Definitions
  // NAME_r11..r33 (A), NAME_th1..3 (θ) and NAME_wr1..3 (the relative angular velocity in
  // marker1's axes) keep the texts short and may be used in outputs.
  static void spatial_rotational_terms(Expander& x, const std::string& name, const std::string& key,
                                       const toml::table& t, const Body& b1, const Marker& m1,
                                       const Body& b2, const Marker& m2) {
    if (auto n = t.get("rotational_rest")) {
      const Vec3 r = scalar_or_vector(x, *n, key + ".rotational_rest");
      if (!is_zero(r[0]) || !is_zero(r[1]) || !is_zero(r[2]))
        x.fail(key + ".rotational_rest",
               "0 (or absent) on a bushing between spatial bodies: the bushing is unloaded when the "
               "markers' frames coincide, so a rest rotation is a marker frame (rotate marker2 "
               "instead: marker2 = { at = [...], axis = [...], angle = \"...\" })");
    }
    Vec3 k, c;
    if (auto n = t.get("rotational_stiffness")) k = scalar_or_vector(x, *n, key + ".rotational_stiffness");
    if (auto n = t.get("rotational_damping")) c = scalar_or_vector(x, *n, key + ".rotational_damping");
    const bool stiff = !is_zero(k[0]) || !is_zero(k[1]) || !is_zero(k[2]);
    const bool damped = !is_zero(c[0]) || !is_zero(c[1]) || !is_zero(c[2]);
    if (!stiff && !damped) return;
    // A marker frame turned on its body has entries that are sums with numeric coefficients
    // (cos(pi/6)*NAME_a12 + ...): written into A's products, GiNaC's order of those sums
    // changes from load to load and so would the tape. So the marker's axes (marker -> body) are
    // named (NAME_um.., NAME_vm..; on ground they are the axes in ground, NAME_u.., NAME_v..) and
    // so are its axes in ground (NAME_u.., NAME_v..): A's entries are products of names, as the
    // body's own rotation matrix is.
    auto atomic = [](const Mat3& M) {
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          if (paren(M.m[i][j]) != M.m[i][j] || M.m[i][j].find('(') != std::string::npos) return false;
      return true;
    };
    auto define_all = [&](const Mat3& M, const std::string& prefix) {
      Mat3 N;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          N.m[i][j] = x.define(name + "_" + prefix + std::to_string(i + 1) + std::to_string(j + 1), M.m[i][j], key);
      return N;
    };
    auto named = [&](const Body& b, const Marker& m, const std::string& prefix) {
      const Mat3 E = x.marker_axes(b, m);
      if (atomic(E)) return E;
      if (b.ground) return define_all(m.R, prefix);
      const Mat3 R = atomic(m.R) ? m.R : define_all(m.R, prefix + "m");
      return define_all(multiply(b.pose.A, R), prefix);
    };
    const Mat3 E1 = named(b1, m1, "u");
    if (stiff) {
      const Mat3 E2 = named(b2, m2, "v");
      auto r = [&](int i, int j) { return name + "_r" + std::to_string(i + 1) + std::to_string(j + 1); };
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) x.define(r(i, j), dot(column(E1, i), column(E2, j)), key);
      const std::string root = "sqrt(1 + " + r(0, 0) + " + " + r(1, 1) + " + " + r(2, 2) + ")";
      // vee(A − Aᵀ) = (A32 − A23, A13 − A31, A21 − A12)
      static const int P[3][2] = {{2, 1}, {0, 2}, {1, 0}};
      std::vector<Expr> V;
      for (int i = 0; i < 3; ++i) {
        const std::string th = name + "_th" + std::to_string(i + 1);
        x.define(th, "(" + r(P[i][0], P[i][1]) + " - " + r(P[i][1], P[i][0]) + ")/" + root, key);
        if (!is_zero(k[i])) V.push_back(mul(k[i], th + "^2"));
      }
      x.add_potential(mul("1/2", paren(sum(V))));
    }
    if (damped) {
      LinVec3 dw;
      for (int i = 0; i < 3; ++i) dw[i] = add(b2.pose.w[i], scale("-1", b1.pose.w[i]));
      std::vector<Expr> F;
      for (int i = 0; i < 3; ++i) {
        const std::string wr = name + "_wr" + std::to_string(i + 1);
        x.define(wr, dot(column(E1, i), dw).text(), key);
        if (!is_zero(c[i])) F.push_back(mul(c[i], wr + "^2"));
      }
      x.add_dissipation(mul("1/2", paren(sum(F))));
    }
  }
};

// A spring-damper on a joint's coordinate (rotational on a revolute joint, linear on a
// prismatic one), or on the relative angle of a revolute constraint joint.
class JointSpringDamper : public ForceType {
 public:
  explicit JointSpringDamper(std::string n) : name_(std::move(n)) {}
  std::string name() const override { return name_; }
  std::vector<std::string> keys() const override { return {"joint", "coordinate", "stiffness", "rest", "damping"}; }
  void apply(Expander& x, const std::string&, const std::string& key, const toml::table& t) const override {
    const toml::node* jn = t.get("joint");
    if (!jn) x.fail(key + ".joint", "the joint the spring-damper acts on");
    const Joint& j = x.joint(x.string(*jn, key + ".joint", "a joint name"), key + ".joint");
    // A tree joint's coordinate (default its first), or the motion of a revolute, prismatic or
    // cylindrical joint written as rows (`coordinate` = "rotation" / "translation").
    std::string dof = j.coordinates.empty() ? "" : j.coordinates[0];
    if (auto cn = t.get("coordinate")) dof = x.string(*cn, key + ".coordinate", "one of the joint's coordinates");
    const JointMotion m = joint_motion(x, j, dof, key + ".joint", key + ".coordinate");
    const Expr q = m.position;
    const Lin rate = m.rate;
    const Expr k = x.optional(t, key, "stiffness"), r = x.optional(t, key, "rest"), c = x.optional(t, key, "damping");
    if (k.empty() && c.empty()) x.fail(key + ".stiffness", "a stiffness or a damping (expressions)");
    if (!k.empty() && q.empty())
      x.fail(key + ".stiffness", "no stiffness on the joint '" + j.name + "': the angle of a spatial revolute (cylindrical) joint written as rows is not a function of the coordinates, only its rate is (a damping is accepted); place the body by the joint (coordinates = [\"angle\"]), or use a bushing");
    if (!k.empty()) x.add_potential(mul(mul("1/2", k), "(" + sub(q, r.empty() ? "0" : r) + ")^2"));
    if (!c.empty()) x.add_dissipation(mul(mul("1/2", c), "(" + rate.text() + ")^2"));
  }

 private:
  std::string name_;
};

// An applied force on a marker (ground or marker axes) or a torque on a body.
class AppliedForce : public ForceType {
 public:
  std::string name() const override { return "force"; }
  std::vector<std::string> keys() const override { return {"body", "marker", "force", "frame"}; }
  void apply(Expander& x, const std::string&, const std::string& key, const toml::table& t) const override {
    const toml::node* bn = t.get("body");
    if (!bn) x.fail(key + ".body", "the body the force acts on");
    const Body& b = x.body(x.string(*bn, key + ".body", "a body name"), key + ".body");
    const Marker& m = x.marker(b, t.get("marker") ? x.string(*t.get("marker"), key + ".marker", "a marker name") : "origin", key + ".marker");
    const toml::node* fn = t.get("force");
    if (!fn) x.fail(key + ".force", "the force vector [fx, fy] (expressions of t, q, q_d, parameters)");
    Vec3 f = x.vector(*fn, key + ".force", x.kind(b).planar());
    std::string frame = "ground";
    if (auto fr = t.get("frame")) frame = x.string(*fr, key + ".frame", "\"ground\" or \"marker\"");
    if (frame == "marker") f = ::pcsim::modelfile::bodies::apply(x.marker_axes(b, m), f);
    else if (frame != "ground") x.fail(key + ".frame", "\"ground\" (default) or \"marker\", got '" + frame + "'");
    const LinVec3 v = x.marker_velocity(b, m);
    for (int i = 0; i < 3; ++i) x.add_power(v[i], f[i], key);
  }
};

class AppliedTorque : public ForceType {
 public:
  std::string name() const override { return "torque"; }
  std::vector<std::string> keys() const override { return {"body", "torque"}; }
  void apply(Expander& x, const std::string&, const std::string& key, const toml::table& t) const override {
    const toml::node* bn = t.get("body");
    if (!bn) x.fail(key + ".body", "the body the torque acts on");
    const Body& b = x.body(x.string(*bn, key + ".body", "a body name"), key + ".body");
    const toml::node* tn = t.get("torque");
    if (!tn) x.fail(key + ".torque", "the torque (an expression; a vector [tx, ty, tz] for a spatial body)");
    if (x.kind(b).planar()) {
      x.add_power(b.pose.w[2], x.expression(*tn, key + ".torque"), key);
    } else {
      const Vec3 tq = x.vector(*tn, key + ".torque", false);
      for (int i = 0; i < 3; ++i) x.add_power(b.pose.w[i], tq[i], key);
    }
  }
};

void register_planar(Registry& r) {
  auto kind = [&](std::shared_ptr<const BodyKind> k) { r.kinds[k->name()] = std::move(k); };
  auto joint = [&](std::shared_ptr<const JointType> j) { r.joints[j->name()] = std::move(j); };
  auto force = [&](std::shared_ptr<const ForceType> f) { r.forces[f->name()] = std::move(f); };
  kind(std::make_shared<PlanarBody>());
  kind(std::make_shared<PlanarParticle>());
  joint(std::make_shared<PlanarRevolute>());
  joint(std::make_shared<PlanarPrismatic>());
  joint(std::make_shared<PlanarFixed>());
  joint(std::make_shared<PlanarPlanar>());
  joint(std::make_shared<Distance>());
  joint(std::make_shared<PointOnLine>());
  joint(std::make_shared<Drive>());
  joint(std::make_shared<Gear>());
  joint(std::make_shared<Coupler>());
  joint(std::make_shared<Rolling>());
  force(std::make_shared<Gravity>());
  force(std::make_shared<SpringDamper>());
  force(std::make_shared<Bushing>());
  force(std::make_shared<JointSpringDamper>("joint_spring_damper"));
  force(std::make_shared<JointSpringDamper>("rotational_spring_damper"));
  force(std::make_shared<AppliedForce>());
  force(std::make_shared<AppliedTorque>());
}

}  // namespace

namespace {

void Gravity::apply(Expander& x, const std::string&, const std::string& key, const toml::table& t) const {
  const toml::node* gn = t.get("g");
  if (!gn) x.fail(key + ".g", "the gravity vector [gx, gy] (or [gx, gy, gz]), e.g. [0, \"-g\"]");
  bool all_planar = true;
  for (const Body& b : x.bodies())
    if (!b.ground && !x.kind(b).planar()) all_planar = false;
  const Vec3 g = x.vector(*gn, key + ".g", all_planar);
  for (const Body& b : x.bodies()) {
    if (b.ground) continue;
    const Vec3 c = add(b.pose.r, bodies::apply(b.pose.A, b.com));
    x.add_potential(mul(b.mass, paren(neg(dot(g, c)))));
  }
}

}  // namespace

const std::vector<Body>& Expander::bodies() const { return impl_->bodies; }

const BodyKind& Expander::kind(const Body& b) const {
  const auto& kinds = registry().kinds;
  auto it = kinds.find(b.ground ? std::string("planar") : b.kind);
  return *it->second;
}

const Joint& Expander::joint(const std::string& name, const std::string& key) const {
  for (const auto& j : impl_->joints)
    if (j.name == name) return j;
  std::vector<std::string> names;
  for (const auto& j : impl_->joints) names.push_back(j.name);
  fail(key, "the name of a joint (declared: " + join(names) + "), got '" + name + "'");
}

namespace {

// A numeric value of an expression of the parameters at their defaults (NaN if it uses
// anything else), for the checks of mass and inertia.
double default_value(Expander& x, const Expr& e, const std::string& key) {
  std::lock_guard<std::mutex> lock(detail::ginac_mutex());
  detail::ExpressionParser p;
  for (const auto& par : x.source().parameters) p.define(par.name, GiNaC::numeric(par.value));
  // definitions of parameters only: substitute when they parse
  for (int pass = 0; pass < 3; ++pass)
    for (const auto& [name, text] : x.source().definitions) {
      if (p.knows(name)) continue;
      try {
        const GiNaC::ex v = GiNaC::evalf(p.parse(text));
        if (GiNaC::is_a<GiNaC::numeric>(v)) p.define(name, v);
      } catch (...) {
      }
    }
  try {
    const GiNaC::ex v = GiNaC::evalf(p.parse(ExprText{x.where(), key, e}));
    if (GiNaC::is_a<GiNaC::numeric>(v) && GiNaC::ex_to<GiNaC::numeric>(v).is_real())
      return GiNaC::ex_to<GiNaC::numeric>(v).to_double();
  } catch (const InputError&) {
  }
  return std::nan("");
}

}  // namespace

double default_parameter_value(Expander& x, const Expr& e, const std::string& key) {
  return default_value(x, e, key);
}

namespace {

Marker read_marker(Expander& x, const Body& b, bool planar, const std::string& name,
                   const toml::node& node, const std::string& key) {
  Marker m;
  m.name = name;
  m.key = key;
  // Ground's markers serve planar and spatial bodies: [x, y] or [x, y, z] (BODIES-SPATIAL).
  auto position_planar = [&](const toml::node& n) {
    const toml::array* a = n.as_array();
    return b.ground ? !(a && a->size() == 3) : planar;
  };
  if (node.is_array()) {
    m.p = x.vector(node, key, position_planar(node));
    return m;
  }
  const toml::table* t = node.as_table();
  if (!t) x.fail(key, "a position [x, y] in the body frame, or { at = [x, y], angle = \"...\" }");
  for (auto&& [k, v] : *t) {
    const std::string kk(k.str());
    if (kk != "at" && kk != "angle" && kk != "axis")
      x.fail(key + "." + kk, "unknown key (expected one of: at, angle, axis)");
  }
  if (auto at = t->get("at")) m.p = x.vector(*at, key + ".at", position_planar(*at));
  if (t->get("axis") || (!planar && !b.ground)) {
    m.R = spatial_marker_axes(x, *t, key);  // bodies_spatial.cpp: turned by angle about axis
  } else if (auto a = t->get("angle")) {
    m.R = Mat3::rot_z(x.expression(*a, key + ".angle"));
  }
  return m;
}

}  // namespace

void Expander::run() {
  ensure_registered();
  Impl& I = *impl_;
  const toml::table& model = *I.model;
  const std::string pre = src_.prefix.empty() ? "" : src_.prefix + ".";
  const auto& reg = registry();

  if (auto r = model.get("reactions")) {
    I.reactions = string(*r, pre + "reactions", "\"joint\", \"ground\" or \"none\"");
    if (I.reactions != "joint" && I.reactions != "ground" && I.reactions != "none")
      fail(pre + "reactions", "\"joint\" (default: each joint's reaction in its own frame), \"ground\" or \"none\", got '" + I.reactions + "'");
  }

  // Ground.
  {
    Body g;
    g.name = "ground";
    g.ground = true;
    g.kind = "planar";
    g.key = pre + "body.ground";
    g.markers.push_back(Marker{"origin", Vec3{}, Mat3{}, g.key});
    I.bodies.push_back(g);
  }
  auto declare = [&](const std::string& name, const std::string& key, const std::string& what) {
    if (!detail::is_identifier(name) || detail::is_reserved_name(name))
      fail(key, "a name of letters, digits and '_' not starting with a digit (not reserved), got '" + name + "'");
    if (!I.names.insert(name).second)
      fail(key, "the name '" + name + "' is already used by a body, joint or force (" + what + " names are unique)");
  };
  I.names.insert("ground");

  // Bodies.
  if (auto bn = model.get("body")) {
    const toml::table* bt = bn->as_table();
    if (!bt) fail(pre + "body", "tables [model.body.NAME]");
    for (const auto& [name, node] : file_order(*bt)) {
      const std::string key = pre + "body." + name;
      const toml::table* t = node->as_table();
      if (!t) fail(key, "a table [" + key + "] (mass, com, inertia, markers, ...)");
      if (name == "ground") {
        for (auto&& [k, v] : *t)
          if (k.str() != "markers") fail(key + "." + std::string(k.str()), "unknown key (ground has only: markers)");
        if (auto mk = t->get("markers")) {
          const toml::table* mt = mk->as_table();
          if (!mt) fail(key + ".markers", "a table of markers: NAME = [x, y]");
          for (const auto& [mname, mnode] : file_order(*mt)) {
            if (!detail::is_identifier(mname)) fail(key + ".markers." + mname, "a marker name (an identifier)");
            if (mname == "origin") fail(key + ".markers.origin", "'origin' is every body's frame origin (implicit)");
            I.bodies[0].markers.push_back(read_marker(*this, I.bodies[0], true, mname, *mnode, key + ".markers." + mname));
          }
        }
        continue;
      }
      declare(name, key, "body");
      Body b;
      b.name = name;
      b.key = key;
      b.kind = "planar";
      if (auto k = t->get("kind")) b.kind = string(*k, key + ".kind", "a body kind");
      auto kit = reg.kinds.find(b.kind);
      if (kit == reg.kinds.end()) fail(key + ".kind", "a body kind (one of: " + join(keys_of(reg.kinds)) + "), got '" + b.kind + "'");
      const BodyKind& kind = *kit->second;
      std::vector<std::string> allowed{"kind", "mass", "com", "inertia", "markers", "shape", "coordinates"};
      for (const auto& e : kind.extra_keys()) allowed.push_back(e);
      for (auto&& [k, v] : *t) {
        const std::string kk(k.str());
        if (std::find(allowed.begin(), allowed.end(), kk) == allowed.end())
          fail(key + "." + kk, "unknown key (expected one of: " + join(allowed) + ")");
      }
      const toml::node* mass = t->get("mass");
      if (!mass) fail(key + ".mass", "the body's mass (an expression > 0; a massless body leaves the mass matrix singular)");
      b.mass = expression(*mass, key + ".mass");
      const double mv = default_value(*this, b.mass, key + ".mass");
      if (!(mv > 0.0) && !std::isnan(mv))
        fail(key + ".mass", "a mass > 0 (a massless body leaves the mass matrix singular), got " + b.mass + " = " + format_number(mv));
      if (auto c = t->get("com")) b.com = vector(*c, key + ".com", kind.planar());
      kind.read_inertia(*this, t->get("inertia"), b);
      if (kind.planar() && b.kind == "planar") {
        const double jv = default_value(*this, b.inertia.m[2][2], key + ".inertia");
        if (!(jv > 0.0) && !std::isnan(jv))
          fail(key + ".inertia", "a moment of inertia > 0 about the centre of mass (0 or less leaves the mass matrix singular or indefinite; a point mass is kind = \"particle\"), got " + b.inertia.m[2][2] + " = " + format_number(jv));
      }
      b.markers.push_back(Marker{"origin", Vec3{}, Mat3{}, key});
      if (auto mk = t->get("markers")) {
        const toml::table* mt = mk->as_table();
        if (!mt) fail(key + ".markers", "a table of markers: NAME = [x, y] or { at = [x, y], angle = ... }");
        for (const auto& [mname, mnode] : file_order(*mt)) {
          const std::string mkey = key + ".markers." + mname;
          if (!detail::is_identifier(mname)) fail(mkey, "a marker name (an identifier)");
          if (mname == "origin") fail(mkey, "'origin' is every body's frame origin (implicit)");
          b.markers.push_back(read_marker(*this, b, kind.planar(), mname, *mnode, mkey));
        }
      }
      if (auto sh = t->get("shape")) {
        const toml::table* st = sh->as_table();
        if (!st) fail(key + ".shape", "a table { type = \"rod\" | \"box\" | \"circle\", ... }");
        for (auto&& [k, v] : *st) {
          const std::string kk(k.str());
          if (kk != "type" && kk != "from" && kk != "to" && kk != "width" && kk != "height" && kk != "radius" && kk != "fill")
            fail(key + ".shape." + kk, "unknown key (expected one of: type, from, to, width, height, radius, fill)");
        }
        const toml::node* ty = st->get("type");
        if (!ty) fail(key + ".shape.type", "\"rod\", \"box\" or \"circle\"");
        b.shape.type = string(*ty, key + ".shape.type", "\"rod\", \"box\" or \"circle\"");
        if (b.shape.type != "rod" && b.shape.type != "box" && b.shape.type != "circle")
          fail(key + ".shape.type", "\"rod\", \"box\" or \"circle\", got '" + b.shape.type + "'");
        if (auto f = st->get("from")) b.shape.from = string(*f, key + ".shape.from", "a marker name");
        if (auto f = st->get("to")) b.shape.to = string(*f, key + ".shape.to", "a marker name");
        for (const std::string& mn : {b.shape.from, b.shape.to})
          if (!mn.empty()) marker(b, mn, key + ".shape");
        if (b.shape.type == "rod" && (b.shape.from.empty() || b.shape.to.empty()))
          fail(key + ".shape", "a rod from one marker to another: from = \"A\", to = \"B\"");
        b.shape.width = optional(*st, key + ".shape", "width");
        b.shape.height = optional(*st, key + ".shape", "height");
        b.shape.radius = optional(*st, key + ".shape", "radius");
        if (auto f = st->get("fill")) b.shape.fill = string(*f, key + ".shape.fill", "a colour \"#rrggbb\"");
      }
      if (auto cs = t->get("coordinates")) {
        const toml::array* a = cs->as_array();
        const std::size_t want = kind.coordinates(b).size();
        if (!a || a->size() != want)
          fail(key + ".coordinates", "a list of " + std::to_string(want) + " coordinate names (" + join(kind.coordinates(b)) + " by default)");
        for (const auto& c : *a) b.coordinates.push_back(string(c, key + ".coordinates", "coordinate names (strings)"));
      }
      I.bodies.push_back(std::move(b));
    }
  }

  // Joints (read; tree joints mark their second body).
  if (auto jn = model.get("joint")) {
    const toml::table* jt = jn->as_table();
    if (!jt) fail(pre + "joint", "tables [model.joint.NAME]");
    for (const auto& [name, node] : file_order(*jt)) {
      const std::string key = pre + "joint." + name;
      const toml::table* t = node->as_table();
      if (!t) fail(key, "a table [" + key + "] (type, body1, marker1, body2, marker2, ...)");
      declare(name, key, "joint");
      Joint j;
      j.name = name;
      j.key = key;
      j.table = t;
      const toml::node* ty = t->get("type");
      if (!ty) fail(key + ".type", "the joint's type (one of: " + join(keys_of(reg.joints)) + ")");
      j.type = string(*ty, key + ".type", "a joint type");
      auto it = reg.joints.find(j.type);
      auto sit = reg.spatial_joints.find(j.type);
      if (it == reg.joints.end() && sit == reg.spatial_joints.end()) {
        std::set<std::string> all;
        for (const auto& k : keys_of(reg.joints)) all.insert(k);
        for (const auto& k : keys_of(reg.spatial_joints)) all.insert(k);
        fail(key + ".type", "a joint type (one of: " + join(std::vector<std::string>(all.begin(), all.end())) + "), got '" + j.type + "'");
      }
      const JointType& type = it != reg.joints.end() ? *it->second : *sit->second;
      std::vector<std::string> allowed{"type", "body1", "marker1", "body2", "marker2", "coordinates"};
      for (const auto& e : type.extra_keys()) allowed.push_back(e);
      if (sit != reg.spatial_joints.end())
        for (const auto& e : sit->second->extra_keys()) allowed.push_back(e);
      for (auto&& [k, v] : *t) {
        const std::string kk(k.str());
        if (std::find(allowed.begin(), allowed.end(), kk) == allowed.end()) {
          const auto& ck = contact_keys();  // bodies_contact.cpp
          if (std::find(ck.begin(), ck.end(), kk) != ck.end())
            fail(key + "." + kk, "contact attributes (" + join(ck) + ") only on a joint that can lift off or slip (rolling, point_on_line; spatial: point_on_plane, wheel, ball); a '" + j.type + "' joint's rows are bilateral");
          fail(key + "." + kk, "unknown key (expected one of: " + join(allowed) + ")");
        }
      }
      const bool needs_bodies = j.type != "drive" && j.type != "gear" && j.type != "coupler";
      j.body1 = "ground";
      if (auto b = t->get("body1")) j.body1 = string(*b, key + ".body1", "a body name");
      if (auto m = t->get("marker1")) j.marker1 = string(*m, key + ".marker1", "a marker name");
      if (auto b = t->get("body2")) j.body2 = string(*b, key + ".body2", "a body name");
      else if (needs_bodies) fail(key + ".body2", "the joint's second body (the one its reaction acts on)");
      if (auto m = t->get("marker2")) j.marker2 = string(*m, key + ".marker2", "a marker name");
      if (j.marker1.empty()) j.marker1 = "origin";
      if (j.marker2.empty()) j.marker2 = "origin";
      if (needs_bodies) {
        const Body& b1 = body(j.body1, key + ".body1");
        const Body& b2 = body(j.body2, key + ".body2");
        if (b1.name == b2.name) fail(key + ".body2", "a body other than body1 (a joint between '" + b1.name + "' and itself constrains nothing)");
        if (b2.ground) fail(key + ".body2", "a moving body (write the ground as body1)");
        marker(b1, j.marker1, key + ".marker1");
        marker(b2, j.marker2, key + ".marker2");
        j.planar = kind(b1).planar() && kind(b2).planar();
        j.axes = marker_axes(b1, *b1.marker(j.marker1));  // refined after the poses
      }
      if (auto cs = t->get("coordinates")) {
        const toml::array* a = cs->as_array();
        const int want = type.tree_coordinates(true);
        if (want == 0) fail(key + ".coordinates", "a joint of type '" + j.type + "' generates constraint rows; it cannot place its body by coordinates");
        if (!a || static_cast<int>(a->size()) != want)
          fail(key + ".coordinates", "a list of " + std::to_string(want) + " coordinate name(s) for a " + j.type + " joint (the coordinates of " + j.body2 + " relative to " + j.body1 + ")");
        for (const auto& c : *a) j.coordinates.push_back(string(c, key + ".coordinates", "coordinate names"));
      } else if (t->get("motion") && type.tree_coordinates(true) > 0) {
        const toml::array* a = t->get("motion")->as_array();
        const int want = type.tree_coordinates(true);
        if (!a || static_cast<int>(a->size()) != want)
          fail(key + ".motion", "a list of " + std::to_string(want) + " expression(s) of t (the prescribed joint motion)");
      }
      I.joints.push_back(std::move(j));
    }
  }
  // Tree joints: coordinates or a prescribed motion place body2 relative to body1.
  std::map<std::string, int> parent_joint;  // body -> joint index
  for (std::size_t k = 0; k < I.joints.size(); ++k) {
    Joint& j = I.joints[k];
    const bool tree = !j.coordinates.empty() ||
                      (j.table->get("motion") && reg.joints.count(j.type) &&
                       reg.joints.at(j.type)->tree_coordinates(true) > 0);
    if (!tree) continue;
    if (parent_joint.count(j.body2))
      fail(j.key + ".coordinates", "one joint that places '" + j.body2 + "' by coordinates; '" +
                                       I.joints[static_cast<std::size_t>(parent_joint[j.body2])].name + "' already does");
    parent_joint[j.body2] = static_cast<int>(k);
  }
  for (auto& b : I.bodies)
    if (parent_joint.count(b.name)) {
      b.parent_joint = I.joints[static_cast<std::size_t>(parent_joint[b.name])].name;
      b.parent = I.joints[static_cast<std::size_t>(parent_joint[b.name])].body1;
      if (!b.coordinates.empty())
        fail(b.key + ".coordinates", "no coordinates of its own: the joint '" + b.parent_joint + "' places it");
    }

  // Poses, in file order, parents first; coordinates in that order.
  std::vector<int> state(I.bodies.size(), 0);  // 0 new, 1 in progress, 2 done
  std::function<void(std::size_t)> place = [&](std::size_t i) {
    if (state[i] == 2) return;
    Body& b = I.bodies[i];
    if (state[i] == 1) fail(b.key, "an assembly without a loop of joints that place bodies by coordinates ('" + b.name + "' is placed, through its parents, relative to itself)");
    state[i] = 1;
    if (b.ground) {
      b.pose.r = Vec3{};
      b.pose.A = Mat3{};
    } else if (b.parent_joint.empty()) {
      const BodyKind& k = kind(b);
      if (b.coordinates.empty()) b.coordinates = k.coordinates(b);
      for (const auto& c : b.coordinates) add_coordinate(c, b.key + ".coordinates");
      b.pose = k.free_pose(b);
      k.own_constraints(*this, b);
    } else {
      const Joint& j = joint(b.parent_joint, b.key);
      for (std::size_t p = 0; p < I.bodies.size(); ++p)
        if (I.bodies[p].name == j.body1) place(p);
      if (!kind(I.bodies[i]).planar() || !(I.bodies[0].name == j.body1 || kind(body(j.body1, j.key)).planar())) {
        auto sit = reg.spatial_joints.find(j.type);
        if (sit == reg.spatial_joints.end()) fail(j.key + ".type", "a joint type for spatial bodies ('" + j.type + "' is planar here)");
      }
      for (const auto& c : j.coordinates) add_coordinate(c, j.key + ".coordinates");
      I.bodies[i].coordinates = j.coordinates;
      Pose rel;
      const bool spatial = !kind(I.bodies[i]).planar();
      const JointType& type = spatial ? *reg.spatial_joints.at(j.type) : *reg.joints.at(j.type);
      Pose p = type.tree_pose(*this, j, rel);
      I.bodies[i].pose = p;
      I.bodies[i].relative = rel;
      I.bodies[i].parent_pose = body(j.body1, j.key).pose;
    }
    state[i] = 2;
  };
  for (std::size_t i = 0; i < I.bodies.size(); ++i) place(i);

  // Kinetic energy.
  for (const Body& b : I.bodies)
    if (!b.ground) add_kinetic(kind(b).kinetic(b));

  // Constraint joints.
  for (Joint& j : I.joints) {
    if (!j.coordinates.empty() || body(j.body2.empty() ? "ground" : j.body2, j.key).parent_joint == j.name) continue;
    const bool spatial = !j.planar;
    auto it = reg.joints.find(j.type);
    auto sit = reg.spatial_joints.find(j.type);
    const JointType* type = nullptr;
    if (spatial && sit != reg.spatial_joints.end()) type = sit->second.get();
    else if (it != reg.joints.end()) type = it->second.get();
    else type = sit->second.get();
    if (j.type != "drive" && j.type != "gear" && j.type != "coupler") {
      const Body& b1 = body(j.body1, j.key);
      j.axes = marker_axes(b1, *b1.marker(j.marker1));
      if (j.type == "revolute" || j.type == "fixed")
        if (auto f = j.table->get("frame"); f && f->value_or(std::string()) == "ground") j.axes = Mat3{};
      if (j.type == "distance") {
        const Body& b2 = body(j.body2, j.key);
        const Vec3 d = sub(marker_position(b2, *b2.marker(j.marker2)), marker_position(b1, *b1.marker(j.marker1)));
        std::vector<Expr> sq;
        for (int i = 0; i < 3; ++i)
          if (!is_zero(d[i])) sq.push_back(paren(d[i]) + "^2");
        const Expr len = "sqrt(" + sum(sq) + ")";
        Mat3 E;
        for (int i = 0; i < 3; ++i) E.m[i][0] = is_zero(d[i]) ? "0" : paren(d[i]) + "/" + len;
        E.m[0][1] = neg(E.m[1][0]);
        E.m[1][1] = E.m[0][0];
        E.m[2][1] = "0";
        j.axes = E;
      }
    } else {
      j.axes = Mat3{};
    }
    type->rows(*this, j);
    for (const Row& r : j.rows) add_constraint(r, j.key);
  }

  // Forces.
  if (auto fn = model.get("force")) {
    const toml::table* ft = fn->as_table();
    if (!ft) fail(pre + "force", "tables [model.force.NAME]");
    for (const auto& [name, node] : file_order(*ft)) {
      const std::string key = pre + "force." + name;
      const toml::table* t = node->as_table();
      if (!t) fail(key, "a table [" + key + "] (type, ...)");
      declare(name, key, "force");
      const toml::node* ty = t->get("type");
      if (!ty) fail(key + ".type", "the force's type (one of: " + join(keys_of(reg.forces)) + ")");
      const std::string type = string(*ty, key + ".type", "a force type");
      auto it = reg.forces.find(type);
      if (it == reg.forces.end()) fail(key + ".type", "a force type (one of: " + join(keys_of(reg.forces)) + "), got '" + type + "'");
      std::vector<std::string> allowed{"type"};
      for (const auto& k : it->second->keys()) allowed.push_back(k);
      for (auto&& [k, v] : *t) {
        const std::string kk(k.str());
        if (std::find(allowed.begin(), allowed.end(), kk) == allowed.end())
          fail(key + "." + kk, "unknown key (expected one of: " + join(allowed) + ")");
      }
      it->second->apply(*this, name, key, *t);
    }
  }

  // Marker positions and velocities as definitions: <body>_<marker>_x, _y (, _z), _vx, ...
  for (const Body& b : I.bodies) {
    if (b.ground) continue;
    const bool planar = kind(b).planar();
    for (const Marker& m : b.markers) {
      if (m.name == "origin") continue;
      const Vec3 P = marker_position(b, m);
      const Vec3 V = add(velocity_text(b.pose), cross(angular_velocity_text(b.pose), apply(b.pose.A, m.p)));
      const char* ax[3] = {"x", "y", "z"};
      for (int i = 0; i < (planar ? 2 : 3); ++i) {
        define(b.name + "_" + m.name + "_" + ax[i], P[i], m.key);
        define(b.name + "_" + m.name + "_v" + ax[i], V[i], m.key);
      }
    }
  }

  // The energy form.
  const std::string bkey = pre + "body";
  src_.kinetic = ExprText{src_.where, bkey, sum(I.kinetic)};
  src_.potential = ExprText{src_.where, bkey, sum(I.potential)};
  src_.dissipation = ExprText{src_.where, bkey, sum(I.dissipation)};
  if (is_zero(src_.potential.text)) src_.potential.text.clear();
  if (is_zero(src_.dissipation.text)) src_.dissipation.text.clear();
  for (const auto& c : I.force_order) {
    const int i = static_cast<int>(std::find(src_.coordinates.begin(), src_.coordinates.end(), c) - src_.coordinates.begin());
    src_.forces.push_back({i, ExprText{src_.where, pre + "force", sum(I.forces[c])}});
  }
}

void Expander::finish() {
  Impl& I = *impl_;
  define_requested_kinematics(*this, *I.model);
  // A default drawing from the bodies' shapes, when the model has no [model.draw].
  bool any_shape = false;
  for (const Body& b : I.bodies) any_shape = any_shape || !b.shape.type.empty();
  if (any_shape && !I.model->get("draw")) {
    bool planar = true;
    for (const Body& b : I.bodies)
      if (!b.ground && !kind(b).planar()) planar = false;
    toml::table draw;
    draw.insert("view", planar ? "2d" : "3d");
    toml::array points, lines, polygons, circles;
    auto point_table = [&](const Vec3& P) {
      toml::table t;
      t.insert("x", P[0]);
      t.insert("y", P[1]);
      if (!planar) t.insert("z", P[2]);
      return t;
    };
    for (const Body& b : I.bodies) {
      if (b.shape.type.empty()) continue;
      const Shape& sh = b.shape;
      toml::table style;
      if (sh.type == "rod") {
        toml::array pts;
        pts.push_back(point_table(marker_position(b, *b.marker(sh.from))));
        pts.push_back(point_table(marker_position(b, *b.marker(sh.to))));
        toml::table line;
        line.insert("points", pts);
        lines.push_back(line);
      } else if (sh.type == "box") {
        const Expr w = mul("1/2", sh.width.empty() ? "0" : sh.width), h = mul("1/2", sh.height.empty() ? "0" : sh.height);
        toml::array pts;
        for (const auto& [sx, sy] : std::vector<std::pair<int, int>>{{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}) {
          Vec3 c;
          c[0] = sx < 0 ? neg(w) : w;
          c[1] = sy < 0 ? neg(h) : h;
          pts.push_back(point_table(add(b.pose.r, bodies::apply(b.pose.A, c))));
        }
        toml::table poly;
        poly.insert("points", pts);
        if (!sh.fill.empty()) poly.insert("fill", sh.fill);
        polygons.push_back(poly);
      } else if (sh.type == "circle") {
        toml::table circle;
        circle.insert("centre", point_table(b.pose.r));
        circle.insert("radius", sh.radius.empty() ? "0" : sh.radius);
        if (!sh.fill.empty()) circle.insert("fill", sh.fill);
        circles.push_back(circle);
      }
    }
    if (!lines.empty()) draw.insert("line", lines);
    if (!polygons.empty()) draw.insert("polygon", polygons);
    if (!circles.empty()) draw.insert("circle", circles);
    detail::read_draw_table(draw, src_);
  }
  if (I.reactions == "none") return;
  for (const Joint& j : I.joints) {
    for (const auto& [column, value] : j.member_reactions)  // a coupler's, per member
      add_output(column, define(j.name + "_" + column.substr(0, 1) + "_" + column.substr(j.name.size() + 3), value, j.key), j.key);
    if (!j.has_reaction) continue;
    const std::string key = j.key;
    Vec3 F = j.force, M = j.moment;
    if (I.reactions == "ground") {
      F = bodies::apply(j.axes, F);
      M = bodies::apply(j.axes, M);
    }
    // Each component is a definition <joint>_Fx (usable in the user's outputs) and a column
    // F_<joint>_x.
    const char* ax[3] = {"x", "y", "z"};
    for (int i = 0; i < 3; ++i) {
      if (j.planar && i == 2) continue;
      const std::string d = define(j.name + "_F" + ax[i], F[i].empty() ? "0" : F[i], key);
      add_output("F_" + j.name + "_" + ax[i], d, key);
    }
    for (int i = 0; i < 3; ++i) {
      if (j.planar && i < 2) continue;
      const std::string d = define(j.name + "_M" + ax[i], M[i].empty() ? "0" : M[i], key);
      add_output("M_" + j.name + "_" + ax[i], d, key);
    }
  }
}

}  // namespace pcsim::modelfile::bodies
