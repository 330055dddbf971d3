// Spatial bodies (Euler parameters) and spatial joints for the body form (bodies.hpp;
// docs/bodies-spatial.md). A spatial body NAME has the coordinates NAME_x, NAME_y, NAME_z (its
// frame origin in ground) and NAME_e0..e3 (Euler parameters, |e| = 1 as the row NAME_norm); its
// rotation matrix entries are the definitions NAME_a11..a33, its angular velocity is linear in
// the rates: ω' = 2 G(e) ė (body axes), ω = 2 E(e) ė (ground axes), and its kinetic energy
// carries the regularization ½ k (e·ė)² (k = 4 trace(J)/3), which makes M positive definite and
// changes neither q̈ nor R on the manifold (proof in docs/bodies-spatial.md).
//
// Joints between bodies of which at least one is spatial write their rows in the joint frame
// (marker1's axes u1, v1, w1 on body1; d = P2 − P1 the vector between the markers), so the
// multiplier of a force row is that component of the force on body2, and the moment on body2
// (about marker2) is returned in the joint frame too.
#include <array>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "common/eigen_instances.hpp"

#include "common/eigen_instances.hpp"
#include "common/format.hpp"
#include "modelfile/bodies.hpp"

namespace pcsim::modelfile::bodies {

namespace {

std::string e_name(const Body& b, int i) { return b.name + "_e" + std::to_string(i); }

// Four Euler parameters' names: a free body's NAME_e0..e3, or a spherical tree joint's
// coordinates (marker2's frame relative to marker1's).
using EulerNames = std::array<std::string, 4>;
EulerNames e_names(const Body& b) { return {e_name(b, 0), e_name(b, 1), e_name(b, 2), e_name(b, 3)}; }

// G(e) (body rates) or E(e) (ground rates) entry (row r, column c) as a signed coordinate name,
// times 2: ω' = 2 G(e) ė, ω = 2 E(e) ė.
Expr rate_entry(const EulerNames& e, bool ground, int r, int c) {
  // index of e and sign, per row, per column
  static const int Gi[3][4] = {{1, 0, 3, 2}, {2, 3, 0, 1}, {3, 2, 1, 0}};
  static const int Gs[3][4] = {{-1, 1, 1, -1}, {-1, -1, 1, 1}, {-1, 1, -1, 1}};
  static const int Es[3][4] = {{-1, 1, -1, 1}, {-1, 1, 1, -1}, {-1, -1, 1, 1}};
  const int sign = ground ? Es[r][c] : Gs[r][c];
  const std::string& n = e[static_cast<std::size_t>(Gi[r][c])];
  return sign > 0 ? "2*" + n : "-2*" + n;
}

LinVec3 rates(const Body& b, bool ground) {
  const EulerNames e = e_names(b);
  LinVec3 w;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) w[r] = add(w[r], scale(rate_entry(e, ground, r, c), velocity_of(e[static_cast<std::size_t>(c)])));
  return w;
}

// The rotation matrix A(e) as polynomial texts (the form exact for any e on |e| = 1).
Mat3 rotation_texts(const EulerNames& e) {
  const std::string &e0 = e[0], &e1 = e[1], &e2 = e[2], &e3 = e[3];
  Mat3 A;
  A.m[0][0] = e0 + "^2 + " + e1 + "^2 - " + e2 + "^2 - " + e3 + "^2";
  A.m[0][1] = "2*(" + e1 + "*" + e2 + " - " + e0 + "*" + e3 + ")";
  A.m[0][2] = "2*(" + e1 + "*" + e3 + " + " + e0 + "*" + e2 + ")";
  A.m[1][0] = "2*(" + e1 + "*" + e2 + " + " + e0 + "*" + e3 + ")";
  A.m[1][1] = e0 + "^2 - " + e1 + "^2 + " + e2 + "^2 - " + e3 + "^2";
  A.m[1][2] = "2*(" + e2 + "*" + e3 + " - " + e0 + "*" + e1 + ")";
  A.m[2][0] = "2*(" + e1 + "*" + e3 + " - " + e0 + "*" + e2 + ")";
  A.m[2][1] = "2*(" + e2 + "*" + e3 + " + " + e0 + "*" + e1 + ")";
  A.m[2][2] = e0 + "^2 - " + e1 + "^2 - " + e2 + "^2 + " + e3 + "^2";
  return A;
}

// |e|² − 1 (the norm row) and e·ė (the rate the regularization ½ k (e·ė)² squares).
Expr norm_residual(const EulerNames& e) {
  return e[0] + "^2 + " + e[1] + "^2 + " + e[2] + "^2 + " + e[3] + "^2 - 1";
}
Expr norm_rate(const EulerNames& e) {
  std::vector<Expr> s;
  for (const auto& n : e) s.push_back(n + "*" + n + "_d");
  return sum(s);
}
// k = 4 trace(J)/3: with J = j I the Euler-parameter block of M is 4 j (I − e eᵀ) + k e eᵀ = 4 j I.
Expr norm_stiffness(const Body& b) {
  return "4*(" + sum({b.inertia.m[0][0], b.inertia.m[1][1], b.inertia.m[2][2]}) + ")/3";
}

std::string a_name(const Body& b, int i, int j) {
  return b.name + "_a" + std::to_string(i + 1) + std::to_string(j + 1);
}

// Named rates of a spatial body (kept as symbols by the derivation, so that T is written in
// them; this also keeps the tape the same from load to load, which inline sums with numeric
// coefficients squared do not): NAME_w1..3 (body-frame angular velocity) and NAME_vc1..3 (the
// centre of mass's velocity in ground).
void define_rates(Expander& x, const Body& b, const Pose& p, const std::string& key,
                  const std::array<Expr, 3>* w_text = nullptr) {
  for (int i = 0; i < 3; ++i)
    x.define(b.name + "_w" + std::to_string(i + 1), w_text ? (*w_text)[static_cast<std::size_t>(i)] : p.w_body[i].text(), key);
  const LinVec3 vc = add(p.v, cross(p.w, apply(p.A, b.com)));
  for (int i = 0; i < 3; ++i) x.define(b.name + "_vc" + std::to_string(i + 1), vc[i].text(), key);
}

bool all_numbers(const Mat3& J) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const std::string& s = J.m[i][j];
      char* end = nullptr;
      std::strtod(s.c_str(), &end);
      if (s.empty() || end != s.c_str() + s.size()) return false;
    }
  return true;
}

class SpatialBody : public BodyKind {
 public:
  std::string name() const override { return "spatial"; }
  bool planar() const override { return false; }

  // inertia = [J1, J2, J3] (principal, body axes) or [[Jxx, Jxy, Jxz], [Jxy, Jyy, Jyz],
  // [Jxz, Jyz, Jzz]] (about the centre of mass, body axes). Numbers are checked: symmetric,
  // positive definite (a semidefinite tensor leaves M singular), and the principal moments
  // satisfy the triangle inequality J_i <= J_j + J_k of every real mass distribution.
  void read_inertia(Expander& x, const toml::node* node, Body& b) const override {
    const std::string key = b.key + ".inertia";
    const char* what =
        "a spatial body's inertia about its centre of mass in body axes: [J1, J2, J3] (principal) "
        "or a symmetric 3x3 list [[Jxx, Jxy, Jxz], [Jxy, Jyy, Jyz], [Jxz, Jyz, Jzz]]";
    if (!node) x.fail(key, what);
    const toml::array* a = node->as_array();
    if (!a || a->size() != 3) x.fail(key, what);
    Mat3 J;
    const bool full = a->get(0)->is_array();
    for (int i = 0; i < 3; ++i) {
      const toml::node* row = a->get(static_cast<std::size_t>(i));
      if (full) {
        const toml::array* r = row->as_array();
        if (!r || r->size() != 3) x.fail(key, what);
        for (int j = 0; j < 3; ++j) J.m[i][j] = x.expression(*r->get(static_cast<std::size_t>(j)), key);
      } else {
        if (row->is_array()) x.fail(key, what);
        for (int j = 0; j < 3; ++j) J.m[i][j] = "0";
        J.m[i][i] = x.expression(*row, key);
      }
    }
    for (int i = 0; i < 3; ++i)
      for (int j = i + 1; j < 3; ++j)
        if (J.m[i][j] != J.m[j][i] &&
            !(all_numbers(J) && std::strtod(J.m[i][j].c_str(), nullptr) == std::strtod(J.m[j][i].c_str(), nullptr)))
          x.fail(key, std::string("a symmetric inertia tensor, got J") + "xyz"[i] + "xyz"[j] + " = " +
                          J.m[i][j] + " but J" + "xyz"[j] + "xyz"[i] + " = " + J.m[j][i]);
    if (all_numbers(J)) {
      Eigen::Matrix3d M;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) M(i, j) = std::strtod(J.m[i][j].c_str(), nullptr);
      const Eigen::Vector3d ev = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(M).eigenvalues();
      const std::string got = "principal moments " + format_number(ev[0]) + ", " + format_number(ev[1]) +
                              ", " + format_number(ev[2]);
      if (!(ev[0] > 0))
        x.fail(key, "a positive definite inertia tensor (a zero or negative principal moment leaves "
                    "the mass matrix singular), got " + got);
      if (ev[2] > (ev[0] + ev[1]) * (1 + 1e-12))
        x.fail(key, "principal moments that satisfy J_max <= J_a + J_b (every rigid mass distribution "
                    "does), got " + got);
    }
    b.inertia = J;
  }

  std::vector<std::string> coordinates(const Body& b) const override {
    std::vector<std::string> c{b.name + "_x", b.name + "_y", b.name + "_z"};
    for (int i = 0; i < 4; ++i) c.push_back(e_name(b, i));
    return c;
  }

  Pose free_pose(const Body& b) const override {
    Pose p;
    for (int i = 0; i < 3; ++i) {
      p.r[i] = b.coordinates[static_cast<std::size_t>(i)];
      p.v[i] = velocity_of(b.coordinates[static_cast<std::size_t>(i)]);
    }
    // The entries are the definitions NAME_aij (own_constraints defines them; definitions may
    // be used before they are written).
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) p.A.m[i][j] = a_name(b, i, j);
    p.w_body = rates(b, false);
    p.w = rates(b, true);
    return p;
  }

  void own_constraints(Expander& x, const Body& b) const override {
    const Mat3 A = rotation_texts(e_names(b));
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) x.define(a_name(b, i, j), A.m[i][j], b.key);
    define_rates(x, b, b.pose, b.key);
    x.define(b.name + "_s", norm_rate(e_names(b)), b.key);
    Row r;
    r.name = b.name + "_norm";
    r.holonomic = norm_residual(e_names(b));
    x.add_constraint(r, b.key);
    x.source().euler_bodies.push_back({b.name, {e_name(b, 0), e_name(b, 1), e_name(b, 2), e_name(b, 3)}, ""});
  }

  // ½ m |v_c|² + ½ ω'ᵀ J ω' (+ ½ k (e·ė)² for a body with Euler parameters), in the named rates.
  Expr kinetic(const Body& b) const override {
    const std::string n = b.name;
    Expr T = mul(mul("1/2", b.mass), "(" + n + "_vc1^2 + " + n + "_vc2^2 + " + n + "_vc3^2)");
    std::vector<Expr> rot;
    for (int i = 0; i < 3; ++i)
      for (int j = i; j < 3; ++j) {
        const Expr& J = b.inertia.m[i][j];
        if (is_zero(J)) continue;
        const std::string wi = n + "_w" + std::to_string(i + 1), wj = n + "_w" + std::to_string(j + 1);
        rot.push_back(i == j ? mul(J, wi + "^2") : mul(mul("2", J), wi + "*" + wj));
      }
    if (!rot.empty()) T = add(T, mul("1/2", paren(sum(rot))));
    // Placed by a tree joint: no Euler parameters of its own (a spherical tree joint adds the
    // regularization of its relative ones, SpatialSpherical).
    if (!b.parent_joint.empty()) return T;
    return add(T, "1/2*" + paren(norm_stiffness(b)) + "*" + n + "_s^2");
  }
};

// ---- joints ----------------------------------------------------------------------------

struct Frames {
  const Body* b1;
  const Body* b2;
  const Marker* m1;
  const Marker* m2;
  Vec3 P1, P2, d;   // marker positions, d = P2 - P1
  Mat3 E1, E2;      // marker axes in ground (columns u, v, w)
};

Frames frames(Expander& x, const Joint& j) {
  Frames f;
  f.b1 = &x.body(j.body1, j.key + ".body1");
  f.b2 = &x.body(j.body2, j.key + ".body2");
  f.m1 = &x.marker(*f.b1, j.marker1, j.key + ".marker1");
  f.m2 = &x.marker(*f.b2, j.marker2, j.key + ".marker2");
  f.P1 = x.marker_position(*f.b1, *f.m1);
  f.P2 = x.marker_position(*f.b2, *f.m2);
  f.d = sub(f.P2, f.P1);
  f.E1 = x.marker_axes(*f.b1, *f.m1);
  f.E2 = x.marker_axes(*f.b2, *f.m2);
  return f;
}

Expr lam(const Row& r) { return "lambda_" + r.name; }

// A force row: d · (axis i of the joint frame) = 0; its multiplier is that force component on
// body2 (acting at marker2).
void force_row(Joint& j, const Frames& f, int axis, Vec3& F) {
  static const char* names[3] = {"x", "y", "z"};
  Row r;
  r.name = j.name + "_" + names[axis];
  r.holonomic = dot(column(f.E1, axis), f.d);
  j.rows.push_back(r);
  F = add(F, scale(lam(r), column(f.E1, axis)));
}

// An orientation row: a2 · a1 = 0 (a2 an axis of marker2, a1 of marker1). On body2 it exerts
// the moment λ (a2 × a1) (δ(a2·a1) = δθ2 · (a2 × a1)).
void angle_row(Joint& j, const std::string& suffix, const Vec3& a1, const Vec3& a2, Vec3& M) {
  Row r;
  r.name = j.name + "_" + suffix;
  r.holonomic = dot(a2, a1);
  j.rows.push_back(r);
  M = add(M, scale(lam(r), cross(a2, a1)));
}

// Sets the joint's reaction (ground-axis vectors F, M on body2) in the joint frame.
void set_reaction(Joint& j, const Frames& f, const Vec3& F, const Vec3& M) {
  j.force = apply_transposed(f.E1, F);
  j.moment = apply_transposed(f.E1, M);
  j.has_reaction = true;
}

// Which rows a lower pair has: force rows along x, y, z of the joint frame; orientation rows.
struct PairRows {
  bool fx, fy, fz;   // d·u1, d·v1, d·w1
  bool axis;         // w2·u1, w2·v1 (the z axes parallel)
  bool twist;        // u2·v1 (no rotation about z)
};

void pair_rows(Expander& x, Joint& j, const PairRows& p) {
  const Frames f = frames(x, j);
  Vec3 F, M;
  if (p.fx) force_row(j, f, 0, F);
  if (p.fy) force_row(j, f, 1, F);
  if (p.fz) force_row(j, f, 2, F);
  const Vec3 u1 = column(f.E1, 0), v1 = column(f.E1, 1), u2 = column(f.E2, 0), w2 = column(f.E2, 2);
  if (p.axis) {
    angle_row(j, "ax", u1, w2, M);
    angle_row(j, "ay", v1, w2, M);
  }
  if (p.twist) angle_row(j, "az", v1, u2, M);
  set_reaction(j, f, F, M);
}

template <bool FX, bool FY, bool FZ, bool AXIS, bool TWIST>
class SpatialPair : public JointType {
 public:
  explicit SpatialPair(std::string name) : name_(std::move(name)) {}
  std::string name() const override { return name_; }
  void rows(Expander& x, Joint& j) const override { pair_rows(x, j, {FX, FY, FZ, AXIS, TWIST}); }

 private:
  std::string name_;
};

// A point on a plane (row <joint>_z: d·w1, marker2 above marker1's x-y plane) that can lift off
// (CONTACT): `unilateral`, `restitution` on that row (a distance: its multiplier is the normal
// force in N). With `mu_static` (`mu_kinetic`) the contact slides in the plane with Coulomb
// friction: two velocity-form rows <joint>_slide_x and <joint>_slide_y, the sliding velocity of
// marker2's origin relative to body1's material point coincident with it, along u1 and v1 (m/s).
// u1, v1 are orthonormal tangents of the plane, so the rows' multipliers are the friction force's
// components on body2 in N and the pair bounds it isotropically, |λ_t| <= μ_s λ_z (the 2-D
// Coulomb cone of docs/switching.md): both rows carry friction = <joint>_z and the same μ.
class SpatialPointOnPlane : public JointType {
 public:
  std::string name() const override { return "point_on_plane"; }
  std::vector<std::string> extra_keys() const override { return contact_keys(); }
  void rows(Expander& x, Joint& j) const override {
    pair_rows(x, j, {false, false, true, false, false});
    if (!has_contact_keys(j)) return;
    Row sx, sy;
    sx.name = j.name + "_slide_x";
    sy.name = j.name + "_slide_y";
    read_joint_contact(x, j, j.rows.back(), &sx, "", &sy);
    if (sx.friction.empty()) return;
    const Frames f = frames(x, j);
    LinVec3 vrel = x.marker_velocity(*f.b2, *f.m2);
    if (!f.b1->ground) {
      const LinVec3 v1 = x.point_velocity(*f.b1, f.P2);
      for (int i = 0; i < 3; ++i) vrel[i] = add(vrel[i], scale("-1", v1[i]));
    }
    const Row gap = j.rows.back();
    Row* slide[2] = {&sx, &sy};
    // The force on body2 at marker2 (no moment about it): λ_z w1 + λ_slide_x u1 + λ_slide_y v1,
    // whose joint-frame components are (λ_slide_x, λ_slide_y, λ_z).
    Vec3 F = scale(lam(gap), column(f.E1, 2));
    for (int i = 0; i < 2; ++i) {
      slide[i]->velocity_form = true;
      slide[i]->velocity = dot(column(f.E1, i), vrel);
      j.rows.push_back(*slide[i]);
      F = add(F, scale(lam(*slide[i]), column(f.E1, i)));
    }
    set_reaction(j, f, F, Vec3{});
  }
};

// A point on a line in space: its two rows have no side to lift off to (no gap row).
class SpatialPointOnLine : public JointType {
 public:
  std::string name() const override { return "point_on_line"; }
  void rows(Expander& x, Joint& j) const override {
    refuse_contact_keys(x, j, "no contact attributes on a spatial point_on_line: its two rows (x, y) "
                              "have no side to lift off to (no gap); a point_on_plane, or a planar "
                              "point_on_line, takes them");
    pair_rows(x, j, {true, true, false, false, false});
  }
};

// A spatial tree joint's bodies, markers and its coordinates (`what` names them in messages):
// c the first (a revolute's angle, a prismatic's travel, a cylindrical's angle), c2 the second
// (a cylindrical's travel).
struct TreeJoint {
  const Body* b1;
  const Body* b2;
  const Marker* m1;
  const Marker* m2;
  std::string c, c2;
};
TreeJoint tree_joint(Expander& x, const Joint& j, const std::string& what, std::size_t count = 1) {
  TreeJoint t{&x.body(j.body1, j.key + ".body1"), &x.body(j.body2, j.key + ".body2"), nullptr, nullptr, "", ""};
  t.m1 = &x.marker(*t.b1, j.marker1, j.key + ".marker1");
  t.m2 = &x.marker(*t.b2, j.marker2, j.key + ".marker2");
  bool named = j.coordinates.size() == count;
  for (const std::string& c : j.coordinates) named = named && !c.empty();
  static const char* counts[] = {"", "one coordinate name, ", "two coordinate names, ", "three coordinate names, ",
                                 "four coordinate names, "};
  if (!named) x.fail(j.key + ".coordinates", std::string(counts[count < 5 ? count : 0]) + what);
  t.c = j.coordinates[0];
  if (count > 1) t.c2 = j.coordinates[1];
  return t;
}

// Body2's rotation relative to body1, Arel = R1 Rj R2ᵀ (Rj: the joint's own turn of marker2's
// frame from marker1's), and in ground, A1 Arel, as the definitions NAME_aij (into p.A).
Mat3 tree_rotation(Expander& x, const Joint& j, const TreeJoint& t, const Mat3& Rj, Pose& p) {
  Mat3 R2t;  // R2ᵀ
  for (int a = 0; a < 3; ++a)
    for (int c = 0; c < 3; ++c) R2t.m[a][c] = t.m2->R.m[c][a];
  const Mat3 Arel = multiply(multiply(t.m1->R, Rj), R2t);
  const Mat3 A2t = multiply(t.b1->pose.A, Arel);
  for (int a = 0; a < 3; ++a)
    for (int c = 0; c < 3; ++c) p.A.m[a][c] = x.define(a_name(*t.b2, a, c), A2t.m[a][c], j.key);
  return Arel;
}

// The joint's own rotation: per unit rate of a coordinate, in body2's axes (none for a travel).
struct OwnRate {
  Vec3 per_unit;
  std::string coordinate;
};

// Body2's named rates (define_rates), its body-axis angular velocity ω'2 = Arelᵀ ω'1 + Σ ċ own
// written in body1's named rates when body1 is spatial (a short T).
void tree_rates(Expander& x, const Joint& j, const TreeJoint& t, const Pose& p, const Mat3& Arel,
                const std::vector<OwnRate>& own) {
  std::array<Expr, 3> wt;
  const bool named = !t.b1->ground && !x.kind(*t.b1).planar();
  for (int i = 0; i < 3; ++i) {
    std::vector<Expr> terms;
    if (named)
      for (int k = 0; k < 3; ++k) terms.push_back(mul(Arel.m[k][i], t.b1->name + "_w" + std::to_string(k + 1)));
    for (const OwnRate& o : own)
      if (!is_zero(o.per_unit[i])) terms.push_back(mul(o.per_unit[i], o.coordinate + "_d"));
    wt[static_cast<std::size_t>(i)] = sum(terms);
  }
  define_rates(x, *t.b2, p, j.key, (named || t.b1->ground) ? &wt : nullptr);
}

// Revolute joint: the markers coincide and their z axes are parallel (rows <joint>_x, _y, _z,
// _ax, _ay); as a tree joint (`coordinates = ["angle"]`) it places body2 by the angle of
// marker2's x axis from marker1's about their common z axis (no rows, no Euler parameters for
// body2: a wheel turning on its frame).
class SpatialRevolute : public JointType {
 public:
  std::string name() const override { return "revolute"; }
  int tree_coordinates(bool) const override { return 1; }
  void rows(Expander& x, Joint& j) const override { pair_rows(x, j, {true, true, true, true, false}); }
  Pose tree_pose(Expander& x, const Joint& j, Pose& rel) const override {
    const TreeJoint t = tree_joint(x, j, "the joint's angle (a revolute tree joint)");
    const Body& b1 = *t.b1;
    const Marker& m1 = *t.m1;
    const Marker& m2 = *t.m2;
    const std::string& th = t.c;
    Pose p;
    const Mat3 Arel = tree_rotation(x, j, t, Mat3::rot_z(th), p);
    const Vec3 r2 = sub(add(b1.pose.r, apply(b1.pose.A, m1.p)), apply(p.A, m2.p));
    for (int a = 0; a < 3; ++a) p.r[a] = x.define(t.b2->name + "_" + "xyz"[a], r2[a], j.key);
    const Vec3 z1 = column(m1.R, 2);               // the axis in body1's frame
    const LinVec3 wrel_parent = [&] {
      LinVec3 w;
      for (int a = 0; a < 3; ++a) w[a] = scale(z1[a], velocity_of(th));
      return w;
    }();
    p.w = add(b1.pose.w, apply(b1.pose.A, wrel_parent));
    LinVec3 w2b_own;
    for (int a = 0; a < 3; ++a) w2b_own[a] = scale(m2.R.m[a][2], velocity_of(th));  // θ̇ R2 ẑ
    p.w_body = add(apply_transposed(Arel, b1.pose.w_body), w2b_own);
    p.v = add(add(b1.pose.v, cross(b1.pose.w, apply(b1.pose.A, m1.p))),
              cross(p.w, scale("-1", apply(p.A, m2.p))));
    tree_rates(x, j, t, p, Arel, {{column(m2.R, 2), th}});  // θ̇ R2 ẑ
    rel.A = Arel;
    rel.r = sub(m1.p, apply(Arel, m2.p));
    rel.w = wrel_parent;
    rel.w_body = w2b_own;
    rel.v = cross(wrel_parent, scale("-1", apply(Arel, m2.p)));
    return p;
  }
};

// Prismatic joint: marker2's origin on marker1's z axis, the frames parallel (rows <joint>_x,
// _y, _ax, _ay, _az); as a tree joint (`coordinates = ["travel"]`) it places body2 by the travel
// of marker2's origin along marker1's z axis, marker2's frame parallel to marker1's (no rows, no
// Euler parameters for body2: a slider on its guide).
class SpatialPrismatic : public JointType {
 public:
  std::string name() const override { return "prismatic"; }
  int tree_coordinates(bool) const override { return 1; }
  void rows(Expander& x, Joint& j) const override { pair_rows(x, j, {true, true, false, true, true}); }
  Pose tree_pose(Expander& x, const Joint& j, Pose& rel) const override {
    const TreeJoint t = tree_joint(x, j, "the joint's travel (a prismatic tree joint)");
    const Body& b1 = *t.b1;
    const Marker& m1 = *t.m1;
    const Marker& m2 = *t.m2;
    const std::string& s = t.c;
    Pose p;
    const Mat3 Arel = tree_rotation(x, j, t, Mat3{}, p);
    const Vec3 z1 = column(m1.R, 2);  // the guide's direction in body1's frame
    // body2's origin in body1's frame: marker1's origin + s z1 − Arel (marker2's position)
    const Vec3 rel_r = sub(add(m1.p, scale(s, z1)), apply(Arel, m2.p));
    const Vec3 r2 = add(b1.pose.r, apply(b1.pose.A, rel_r));
    for (int a = 0; a < 3; ++a) p.r[a] = x.define(t.b2->name + "_" + "xyz"[a], r2[a], j.key);
    LinVec3 vrel;  // ṡ z1, body1's components
    for (int a = 0; a < 3; ++a) vrel[a] = scale(z1[a], velocity_of(s));
    p.w = b1.pose.w;
    p.w_body = apply_transposed(Arel, b1.pose.w_body);
    p.v = add(add(b1.pose.v, cross(b1.pose.w, apply(b1.pose.A, rel_r))), apply(b1.pose.A, vrel));
    tree_rates(x, j, t, p, Arel, {});  // no rotation of its own
    rel.A = Arel;
    rel.r = rel_r;
    rel.v = vrel;
    return p;
  }
};

// Cylindrical joint: marker2's origin on marker1's z axis, the z axes parallel (rows <joint>_x,
// _y, _ax, _ay); as a tree joint (`coordinates = ["angle", "travel"]`) it places body2 by the
// angle of marker2's x axis from marker1's about their common z axis and the travel of
// marker2's origin along it (no rows, no Euler parameters for body2: a sleeve that turns and
// slides on its shaft).
class SpatialCylindrical : public JointType {
 public:
  std::string name() const override { return "cylindrical"; }
  int tree_coordinates(bool) const override { return 2; }
  void rows(Expander& x, Joint& j) const override { pair_rows(x, j, {true, true, false, true, false}); }
  Pose tree_pose(Expander& x, const Joint& j, Pose& rel) const override {
    const TreeJoint t = tree_joint(x, j, "the joint's angle and travel (a cylindrical tree joint)", 2);
    const Body& b1 = *t.b1;
    const Marker& m1 = *t.m1;
    const Marker& m2 = *t.m2;
    const std::string& th = t.c;
    const std::string& s = t.c2;
    Pose p;
    const Mat3 Arel = tree_rotation(x, j, t, Mat3::rot_z(th), p);
    const Vec3 z1 = column(m1.R, 2);  // the axis in body1's frame
    // body2's origin in body1's frame: marker1's origin + s z1 − Arel (marker2's position)
    const Vec3 arm = scale("-1", apply(Arel, m2.p));  // from marker2's origin to body2's
    const Vec3 rel_r = add(add(m1.p, scale(s, z1)), arm);
    const Vec3 r2 = add(b1.pose.r, apply(b1.pose.A, rel_r));
    for (int a = 0; a < 3; ++a) p.r[a] = x.define(t.b2->name + "_" + "xyz"[a], r2[a], j.key);
    LinVec3 wrel_parent, slide;  // θ̇ z1, ṡ z1: body1's components
    for (int a = 0; a < 3; ++a) {
      wrel_parent[a] = scale(z1[a], velocity_of(th));
      slide[a] = scale(z1[a], velocity_of(s));
    }
    p.w = add(b1.pose.w, apply(b1.pose.A, wrel_parent));
    LinVec3 w2b_own;
    for (int a = 0; a < 3; ++a) w2b_own[a] = scale(m2.R.m[a][2], velocity_of(th));  // θ̇ R2 ẑ
    p.w_body = add(apply_transposed(Arel, b1.pose.w_body), w2b_own);
    // V2 = V1 + ω1 × A1 (m1 + s z1) + A1 ṡ z1 + ω2 × (−A2 m2)
    p.v = add(add(add(b1.pose.v, cross(b1.pose.w, apply(b1.pose.A, add(m1.p, scale(s, z1))))),
                  apply(b1.pose.A, slide)),
              cross(p.w, scale("-1", apply(p.A, m2.p))));
    tree_rates(x, j, t, p, Arel, {{column(m2.R, 2), th}});  // θ̇ R2 ẑ
    rel.A = Arel;
    rel.r = rel_r;
    rel.w = wrel_parent;
    rel.w_body = w2b_own;
    rel.v = add(slide, cross(wrel_parent, arm));
    return p;
  }
};

// Planar joint between spatial bodies: marker2's origin in marker1's x-y plane, the z axes
// parallel (rows <joint>_z, _ax, _ay); as a tree joint (`coordinates = ["x", "y", "angle"]`,
// names of the user's choice) it places body2 by the travels of marker2's origin along
// marker1's x and y and the angle of marker2's x from marker1's about their common z (no rows,
// no Euler parameters for body2: a puck on a table, a part on a moving platform).
class SpatialPlanar : public JointType {
 public:
  std::string name() const override { return "planar"; }
  int tree_coordinates(bool) const override { return 3; }
  void rows(Expander& x, Joint& j) const override { pair_rows(x, j, {false, false, true, true, false}); }
  Pose tree_pose(Expander& x, const Joint& j, Pose& rel) const override {
    const TreeJoint t = tree_joint(x, j, "the joint's travels along marker1's x and y and its angle about z (a planar tree joint)", 3);
    const Body& b1 = *t.b1;
    const Marker& m1 = *t.m1;
    const Marker& m2 = *t.m2;
    const std::string &sx = j.coordinates[0], &sy = j.coordinates[1], &th = j.coordinates[2];
    Pose p;
    const Mat3 Arel = tree_rotation(x, j, t, Mat3::rot_z(th), p);
    const Vec3 u1 = column(m1.R, 0), v1 = column(m1.R, 1), z1 = column(m1.R, 2);  // body1's frame
    const Vec3 centre = add(m1.p, add(scale(sx, u1), scale(sy, v1)));  // marker2's origin, body1's frame
    const Vec3 arm = scale("-1", apply(Arel, m2.p));                   // from it to body2's origin
    const Vec3 rel_r = add(centre, arm);
    const Vec3 r2 = add(b1.pose.r, apply(b1.pose.A, rel_r));
    for (int a = 0; a < 3; ++a) p.r[a] = x.define(t.b2->name + "_" + "xyz"[a], r2[a], j.key);
    LinVec3 wrel_parent, slide;  // θ̇ z1 and ẋ u1 + ẏ v1, body1's components
    for (int a = 0; a < 3; ++a) {
      wrel_parent[a] = scale(z1[a], velocity_of(th));
      slide[a] = add(scale(u1[a], velocity_of(sx)), scale(v1[a], velocity_of(sy)));
    }
    p.w = add(b1.pose.w, apply(b1.pose.A, wrel_parent));
    LinVec3 w2b_own;
    for (int a = 0; a < 3; ++a) w2b_own[a] = scale(m2.R.m[a][2], velocity_of(th));  // θ̇ R2 ẑ
    p.w_body = add(apply_transposed(Arel, b1.pose.w_body), w2b_own);
    // V2 = V1 + ω1 × A1 centre + A1 (ẋ u1 + ẏ v1) + ω2 × (−A2 m2)
    p.v = add(add(add(b1.pose.v, cross(b1.pose.w, apply(b1.pose.A, centre))), apply(b1.pose.A, slide)),
              cross(p.w, scale("-1", apply(p.A, m2.p))));
    tree_rates(x, j, t, p, Arel, {{column(m2.R, 2), th}});  // θ̇ R2 ẑ
    rel.A = Arel;
    rel.r = rel_r;
    rel.w = wrel_parent;
    rel.w_body = w2b_own;
    rel.v = add(slide, cross(wrel_parent, arm));
    return p;
  }
};

// Rotations about x and y by a symbolic angle (Mat3::rot_z's kin).
Mat3 rot_x(const Expr& a) {
  Mat3 r;
  const std::string c = "cos(" + a + ")", s = "sin(" + a + ")";
  r.m[1][1] = c;
  r.m[1][2] = neg(s);
  r.m[2][1] = s;
  r.m[2][2] = c;
  return r;
}
Mat3 rot_y(const Expr& b) {
  Mat3 r;
  const std::string c = "cos(" + b + ")", s = "sin(" + b + ")";
  r.m[0][0] = c;
  r.m[0][2] = s;
  r.m[2][0] = neg(s);
  r.m[2][2] = c;
  return r;
}

// Universal joint: the markers coincide; the cross's arms are marker1's x axis (on body1) and
// marker2's y axis (on body2), kept perpendicular (row <joint>_cross: u1 · v2 = 0). As a tree
// joint (`coordinates = ["alpha", "beta"]`) it places body2 by the turn α of the cross about
// marker1's x and the turn β of marker2's frame about the cross's other arm (marker2's y):
// marker2's frame = marker1's · Rx(α) Ry(β) (no rows, no Euler parameters for body2; the
// cross's arms stay perpendicular by construction).
class SpatialUniversal : public JointType {
 public:
  std::string name() const override { return "universal"; }
  int tree_coordinates(bool) const override { return 2; }
  void rows(Expander& x, Joint& j) const override {
    const Frames f = frames(x, j);
    Vec3 F, M;
    for (int i = 0; i < 3; ++i) force_row(j, f, i, F);
    angle_row(j, "cross", column(f.E1, 0), column(f.E2, 1), M);
    set_reaction(j, f, F, M);
  }
  Pose tree_pose(Expander& x, const Joint& j, Pose& rel) const override {
    const TreeJoint t = tree_joint(x, j, "the cross's two angles (a universal tree joint)", 2);
    const Body& b1 = *t.b1;
    const Marker& m1 = *t.m1;
    const Marker& m2 = *t.m2;
    const std::string& al = t.c;
    const std::string& be = t.c2;
    Pose p;
    const Mat3 Arel = tree_rotation(x, j, t, multiply(rot_x(al), rot_y(be)), p);
    const Vec3 arm = scale("-1", apply(Arel, m2.p));  // from the joint's centre to body2's origin
    const Vec3 rel_r = add(m1.p, arm);
    const Vec3 r2 = add(b1.pose.r, apply(b1.pose.A, rel_r));
    for (int a = 0; a < 3; ++a) p.r[a] = x.define(t.b2->name + "_" + "xyz"[a], r2[a], j.key);
    // The relative angular velocity α̇ x + β̇ Rx(α) y in marker1's axes; in body1's, R1 of it.
    const Vec3 arm1 = column(m1.R, 0);                                       // x1
    const Vec3 arm2 = apply(m1.R, Vec3{"0", "cos(" + al + ")", "sin(" + al + ")"});  // Rx(α) y
    LinVec3 wrel_parent;
    for (int a = 0; a < 3; ++a)
      wrel_parent[a] = add(scale(arm1[a], velocity_of(al)), scale(arm2[a], velocity_of(be)));
    p.w = add(b1.pose.w, apply(b1.pose.A, wrel_parent));
    // The same in body2's axes: R2 (α̇ Ry(β)ᵀ x + β̇ y) = R2 (α̇ (cos β, 0, sin β) + β̇ (0, 1, 0)).
    const Vec3 own_a = apply(m2.R, Vec3{"cos(" + be + ")", "0", "sin(" + be + ")"});
    const Vec3 own_b = column(m2.R, 1);
    LinVec3 w2b_own;
    for (int a = 0; a < 3; ++a)
      w2b_own[a] = add(scale(own_a[a], velocity_of(al)), scale(own_b[a], velocity_of(be)));
    p.w_body = add(apply_transposed(Arel, b1.pose.w_body), w2b_own);
    p.v = add(add(b1.pose.v, cross(b1.pose.w, apply(b1.pose.A, m1.p))),
              cross(p.w, scale("-1", apply(p.A, m2.p))));
    tree_rates(x, j, t, p, Arel, {{own_a, al}, {own_b, be}});
    rel.A = Arel;
    rel.r = rel_r;
    rel.w = wrel_parent;
    rel.w_body = w2b_own;
    rel.v = cross(wrel_parent, arm);
    return p;
  }
};

// Spherical joint: the markers coincide (rows <joint>_x, _y, _z). As a tree joint (`coordinates
// = ["p0", "p1", "p2", "p3"]`, names of the user's choice) it places body2 by the Euler
// parameters p of marker2's frame relative to marker1's: marker2's frame = marker1's · A(p), with
// |p| = 1 as the row <joint>_norm and the regularization ½ k (p·ṗ)² in T (k = 4 trace(J2)/3, as
// for a free body: it changes neither q̈ nor R on |p| = 1, docs/bodies-spatial.md). Three angles
// would do with one coordinate less but have an orientation where they are singular; Euler
// parameters have none, so a ball joint turns without bound. Body2 has no coordinates or norm row
// of its own. The relative angular velocity is 2 G(p) ṗ in marker2's axes, 2 E(p) ṗ in
// marker1's. The coordinates are no motion a drive, gear or spring-damper could name
// (joint_motion refuses them).
class SpatialSpherical : public JointType {
 public:
  std::string name() const override { return "spherical"; }
  int tree_coordinates(bool) const override { return 4; }
  void rows(Expander& x, Joint& j) const override { pair_rows(x, j, {true, true, true, false, false}); }
  Pose tree_pose(Expander& x, const Joint& j, Pose& rel) const override {
    const TreeJoint t = tree_joint(x, j, "the Euler parameters of marker2's frame relative to marker1's (a spherical tree joint)", 4);
    const Body& b1 = *t.b1;
    const Marker& m1 = *t.m1;
    const Marker& m2 = *t.m2;
    const EulerNames e{j.coordinates[0], j.coordinates[1], j.coordinates[2], j.coordinates[3]};
    Pose p;
    const Mat3 Arel = tree_rotation(x, j, t, rotation_texts(e), p);
    const Vec3 arm = scale("-1", apply(Arel, m2.p));  // from the joint's centre to body2's origin
    const Vec3 rel_r = add(m1.p, arm);
    const Vec3 r2 = add(b1.pose.r, apply(b1.pose.A, rel_r));
    for (int a = 0; a < 3; ++a) p.r[a] = x.define(t.b2->name + "_" + "xyz"[a], r2[a], j.key);
    // Per unit rate of p_c: the relative angular velocity 2 E[:, c] in marker1's axes (body1's:
    // R1 of it) and 2 G[:, c] in marker2's (body2's: R2 of it).
    LinVec3 wrel_parent, w2b_own;
    std::vector<OwnRate> own;
    for (int c = 0; c < 4; ++c) {
      const std::string& pc = e[static_cast<std::size_t>(c)];
      const Vec3 in1 = apply(m1.R, Vec3{rate_entry(e, true, 0, c), rate_entry(e, true, 1, c), rate_entry(e, true, 2, c)});
      const Vec3 in2 = apply(m2.R, Vec3{rate_entry(e, false, 0, c), rate_entry(e, false, 1, c), rate_entry(e, false, 2, c)});
      for (int a = 0; a < 3; ++a) {
        wrel_parent[a] = add(wrel_parent[a], scale(in1[a], velocity_of(pc)));
        w2b_own[a] = add(w2b_own[a], scale(in2[a], velocity_of(pc)));
      }
      own.push_back({in2, pc});
    }
    p.w = add(b1.pose.w, apply(b1.pose.A, wrel_parent));
    p.w_body = add(apply_transposed(Arel, b1.pose.w_body), w2b_own);
    p.v = add(add(b1.pose.v, cross(b1.pose.w, apply(b1.pose.A, m1.p))),
              cross(p.w, scale("-1", apply(p.A, m2.p))));
    tree_rates(x, j, t, p, Arel, own);
    Row r;
    r.name = j.name + "_norm";
    r.holonomic = norm_residual(e);
    x.add_constraint(r, j.key);
    x.source().euler_bodies.push_back({t.b2->name, {e[0], e[1], e[2], e[3]}, j.name});
    x.define(j.name + "_s", norm_rate(e), j.key);
    x.add_kinetic("1/2*" + paren(norm_stiffness(*t.b2)) + "*" + j.name + "_s^2");
    rel.A = Arel;
    rel.r = rel_r;
    rel.w = wrel_parent;
    rel.w_body = w2b_own;
    rel.v = cross(wrel_parent, arm);
    return p;
  }
};

// Spatial distance (rod): sqrt(d·d) − L = 0; its multiplier is the rod's tension-positive force
// on body2 along d (pushing body2 away from marker1 when positive).
class SpatialDistance : public JointType {
 public:
  std::string name() const override { return "distance"; }
  std::vector<std::string> extra_keys() const override { return {"length"}; }
  void rows(Expander& x, Joint& j) const override {
    const Frames f = frames(x, j);
    const Expr L = x.required(*j.table, j.key, "length", "the distance between the markers (an expression)");
    const Expr len = "sqrt(" + dot(f.d, f.d) + ")";
    Row r;
    r.name = j.name;
    r.holonomic = sub(len, L);
    j.rows.push_back(r);
    Vec3 F = scale(lam(r) + "/" + len, f.d), M;
    set_reaction(j, f, F, M);
  }
};

// ---- rolling contacts (wheel, ball) ----------------------------------------------------------
// A body2 that rolls on body1 touches it at one point: the row n (the gap, a distance) and, when it
// rolls without slip (`no_slip`, default true), the rows x, y (velocity form: the velocity of
// body2's material point at the contact relative to body1's there, along two ORTHONORMAL tangents,
// so that they are the sliding velocity's components in m/s and their multipliers the friction
// force's components in N). The wheel and the ball share the reading of their contact keys and
// these rows.

// The keys a rolling body (`body`: "wheel", "ball") reads before its rows, in this order:
// `no_slip` (default true), its markers, `radius`, and its surface: marker1's x-y plane
// (default) or `surface = "sphere"` (body1's sphere centred at marker1, `sphere_radius`, and
// `inside = true` for a bowl; those two keys are refused on a plane): read_rolling_surface
// (bodies_contact.cpp), as the planar rolling joint's line or circle.
struct RollingKeys {
  bool no_slip = true;
  Frames f;
  Expr radius;
  bool sphere = false;
  Expr sphere_radius;   ///< with surface = "sphere"
  bool inside = false;  ///< with surface = "sphere": a bowl
};
// A vector as three named definitions <joint>_<stem>x, _y, _z. Written inline, the sums GiNaC
// reorders survive into the tape, which then differs from load to load
// (test_modelfile_evaluation_order).
Vec3 named_vector(Expander& x, const Joint& j, const std::string& stem, const Vec3& v) {
  Vec3 out;
  for (int i = 0; i < 3; ++i) out[i] = x.define(j.name + "_" + stem + "xyz"[i], v[i], j.key);
  return out;
}
std::vector<std::string> rolling_extra_keys() {
  std::vector<std::string> k{"radius", "no_slip", "surface", "sphere_radius", "inside"};
  for (const auto& c : contact_keys()) k.push_back(c);
  return k;
}
RollingKeys read_rolling_keys(Expander& x, const Joint& j, const std::string& body) {
  RollingKeys k;
  if (const toml::node* ns = j.table->get("no_slip")) k.no_slip = x.boolean(*ns, j.key + ".no_slip");
  k.f = frames(x, j);
  k.radius = x.required(*j.table, j.key, "radius", "the " + body + "'s radius (an expression)");
  const RollingSurface s = read_rolling_surface(x, j, body, k.radius, "plane", "marker1's x-y plane", "sphere");
  k.sphere = s.curved;
  k.sphere_radius = s.radius;
  k.inside = s.inside;
  return k;
}

// The contact keys (bodies_contact.cpp): `unilateral`, `restitution` on the row n; `mu_static`,
// `mu_kinetic` on the no-slip rows x, y, which become the contact's two Coulomb rows. A
// frictionless body (no_slip = false; `frictionless` names it: "frictionless disk") has no rows to
// carry friction.
void read_rolling_contact(Expander& x, const Joint& j, Row& n, bool no_slip, Row& rx, Row& ry,
                          const std::string& frictionless) {
  read_joint_contact(x, j, n, no_slip ? &rx : nullptr,
                     "no friction on a " + j.type + " with no_slip = false: it is a " + frictionless +
                     " (its one row " + n.name + " is the contact); drop no_slip = false to get "
                     "Coulomb friction on its rows " + rx.name + ", " + ry.name,
                     no_slip ? &ry : nullptr);
}

// A rolling body that can lift off (`unilateral = true` on its row n) without `mu_static`: its
// no-slip rows are the rough rows of that contact, imposed while it is closed and released in
// flight (the perfectly rough limit of Coulomb's law: it never slips; a landing is a rough
// impact, docs/switching.md). With `mu_static` they are its Coulomb rows instead
// (read_rolling_contact).
void hold_while_closed(const Row& normal, Row& row) {
  if (!normal.unilateral) return;
  row.friction = normal.name;
  row.rough = true;
}

// The no-slip rows x, y after the row n: body2's material point at the contact P has body1's
// velocity there along the orthonormal tangents t1, t2 (body1's velocity omitted when it is
// ground); their forces λ t are added to F (on body2, acting at P).
void no_slip_rows(Expander& x, Joint& j, const Frames& f, const Vec3& P, const Vec3& t1, const Vec3& t2,
                  const Row& rn, Row& rx, Row& ry, Vec3& F) {
  LinVec3 vrel = x.point_velocity(*f.b2, P);
  if (!f.b1->ground) {
    const LinVec3 v1 = x.point_velocity(*f.b1, P);
    for (int i = 0; i < 3; ++i) vrel[i] = add(vrel[i], scale("-1", v1[i]));
  }
  const Vec3* t[2] = {&t1, &t2};
  Row* slip[2] = {&rx, &ry};
  for (int i = 0; i < 2; ++i) {
    Row& rt = *slip[i];
    rt.velocity_form = true;
    rt.velocity = dot(*t[i], vrel);
    if (rt.friction.empty()) hold_while_closed(rn, rt);
    j.rows.push_back(rt);
    F = add(F, scale(lam(rt), *t[i]));
  }
}

// A wheel (a thin disk: marker2 at its centre, marker2's z its axis, radius `radius`) rolling
// without slip on a plane (marker1's x-y plane; normal w1). Rows: <joint>_n (holonomic: the
// centre is r σ above the plane, σ = |w1 × a|), <joint>_x and <joint>_y (velocity form: the
// material point of the wheel at the contact has zero velocity along u1, v1 relative to the
// plane's body). The contact point is C + ρ, ρ = −r (w1 − (w1·a) a)/σ.
// `no_slip = false` keeps the row n only: a frictionless thin disk on the plane (it slides and
// spins freely; its contact force is normal, acting at the contact point).
// Contact (issue 12, bodies_contact.cpp): `unilateral` and `restitution` on the row n: a disk
// that lifts off, flies and lands. On a rolling wheel its no-slip rows x, y are then the rough
// rows of that contact (held while it touches, released in flight: hold_while_closed), or, with
// `mu_static` (`mu_kinetic`), its two Coulomb friction rows (friction = <joint>_n, the same μ):
// it rolls while the friction force is inside the cone |λ_t| <= μ_s λ_n and slips beyond.
// x, y are the sliding velocity's components along two ORTHONORMAL tangents (the plane: u1, v1;
// the sphere: t1 and ν × t1, sphere_rows), so their multipliers are the friction force's
// components in N and the cone is isotropic (docs/switching.md). A frictionless disk
// (`no_slip = false`) refuses `mu_static`.
class SpatialWheel : public JointType {
 public:
  std::string name() const override { return "wheel"; }
  std::vector<std::string> extra_keys() const override { return rolling_extra_keys(); }
  void rows(Expander& x, Joint& j) const override {
    const RollingKeys k = read_rolling_keys(x, j, "wheel");
    const bool no_slip = k.no_slip;
    const Frames& f = k.f;
    const Expr& r = k.radius;
    if (k.sphere) return sphere_rows(x, j, k);
    const Vec3 n = column(f.E1, 2), a = column(f.E2, 2);
    const Vec3 c = cross(n, a);
    const std::string pre = j.name + "_";
    const Expr sigma = x.define(pre + "sigma", "sqrt(" + dot(c, c) + ")", j.key);
    const Expr na = x.define(pre + "na", dot(n, a), j.key);
    Vec3 rho;
    for (int i = 0; i < 3; ++i) {
      const Expr comp = "-" + paren(r) + "*(" + sub(n[i], mul(na, paren(a[i]))) + ")/" + sigma;
      rho[i] = x.define(pre + "rho" + "xyz"[i], comp, j.key);
    }
    Row rn;
    rn.name = pre + "n";
    rn.holonomic = sub(dot(n, f.d), mul(r, sigma));
    // The no-slip rows x, y (written below): with mu_static, the contact's Coulomb rows.
    Row rx, ry;
    rx.name = pre + "x";
    ry.name = pre + "y";
    if (has_contact_keys(j)) read_contact(x, j, rn, no_slip, rx, ry);
    j.rows.push_back(rn);
    Vec3 F = scale(lam(rn), n);
    // Along u1 and v1: orthonormal tangents of the plane (marker1's axes), so x, y are the
    // contact point's sliding velocity components in m/s (an isotropic Coulomb cone).
    if (no_slip) no_slip_rows(x, j, f, add(f.P2, rho), column(f.E1, 0), column(f.E1, 1), rn, rx, ry, F);
    // The force acts at the contact point: its moment about the wheel's centre is ρ × F.
    set_reaction(j, f, F, cross(rho, F));
  }

 private:
  static void read_contact(Expander& x, const Joint& j, Row& n, bool no_slip, Row& rx, Row& ry) {
    read_rolling_contact(x, j, n, no_slip, rx, ry, "frictionless disk");
  }
  // On a sphere of body1 (centre marker1, radius R), outside (default) or inside (`inside =
  // true`, a wheel in a spherical bowl). With d = C − S (the wheel's centre from the sphere's)
  // and d_p = d − (d·a) a its part in the wheel's plane (σ = |d_p|), the contact is the rim
  // point nearest to S (outside: ρ = −r d_p/σ) or farthest (inside: ρ = +r d_p/σ); the row n
  // is |d + ρ| − R (outside) or R − |d + ρ| (inside): a distance, its multiplier the normal
  // force, acting along ν = ±(d + ρ)/|d + ρ| on the wheel (the rim is tangent to the sphere at
  // the contact, so the selection of the rim point does not enter the row's gradient). The
  // no-slip rows x, y (velocity form): the wheel's material point at the contact has no velocity
  // relative to body1's along t1 = a × ρ / r (the rim's tangent, the rolling direction) and
  // t2 = ν × t1. Singular where S lies on the wheel's axis (σ = 0), as the plane's flat coin.
  // t1, t2 are orthonormal tangents of the sphere at the contact: ρ ⊥ a with |ρ| = r, so
  // |t1| = 1; t1 is normal to a and to d_p, hence to d + ρ = (1 ∓ r/σ) d_p + (d·a) a, i.e. to ν;
  // so t2 = ν × t1 is a unit vector normal to both. The rows are the sliding velocity's
  // components in m/s, and as Coulomb rows (mu_static) their cone is isotropic.
  static void sphere_rows(Expander& x, Joint& j, const RollingKeys& k) {
    const Frames& f = k.f;
    const Expr& r = k.radius;
    const Expr& R = k.sphere_radius;
    const bool inside = k.inside, no_slip = k.no_slip;
    // Every intermediate vector is a named definition (named_vector).
    const std::string pre = j.name + "_";
    auto named = [&](const std::string& stem, const Vec3& v) { return named_vector(x, j, stem, v); };
    const Vec3 a = named("a", column(f.E2, 2));
    const Vec3 d = named("d", f.d);
    const Expr da = x.define(pre + "da", dot(d, a), j.key);
    Vec3 dp0;
    for (int i = 0; i < 3; ++i) dp0[i] = sub(d[i], mul(da, a[i]));
    const Vec3 dp = named("dp", dp0);
    const Expr sigma = x.define(pre + "sigma", "sqrt(" + dot(dp, dp) + ")", j.key);
    Vec3 rho, ps0;
    for (int i = 0; i < 3; ++i) {
      const Expr comp = (inside ? "" : "-") + paren(r) + "*" + dp[i] + "/" + sigma;
      rho[i] = x.define(pre + "rho" + "xyz"[i], comp, j.key);
      ps0[i] = add(d[i], rho[i]);  // the contact point from the sphere's centre
    }
    const Vec3 ps = named("p", ps0);
    const Expr dist = x.define(pre + "dist", "sqrt(" + dot(ps, ps) + ")", j.key);
    Vec3 nu;  // the normal force's direction on the wheel
    for (int i = 0; i < 3; ++i)
      nu[i] = x.define(pre + "nu" + "xyz"[i], (inside ? "-" : "") + ps[i] + "/" + dist, j.key);
    Row rn;
    rn.name = pre + "n";
    rn.holonomic = inside ? sub(R, dist) : sub(dist, R);
    Row rx, ry;
    rx.name = pre + "x";
    ry.name = pre + "y";
    if (has_contact_keys(j)) read_contact(x, j, rn, no_slip, rx, ry);
    j.rows.push_back(rn);
    Vec3 F = scale(lam(rn), nu);
    if (no_slip) {
      Vec3 t1, t2;
      const Vec3 c1 = cross(a, rho);
      for (int i = 0; i < 3; ++i) t1[i] = x.define(pre + "t1" + "xyz"[i], paren(c1[i]) + "/" + paren(r), j.key);
      const Vec3 c2 = cross(nu, t1);
      for (int i = 0; i < 3; ++i) t2[i] = x.define(pre + "t2" + "xyz"[i], c2[i], j.key);
      no_slip_rows(x, j, f, add(f.P2, rho), t1, t2, rn, rx, ry, F);
    }
    set_reaction(j, f, F, cross(rho, F));
  }
};

// A ball (a rigid sphere of radius `radius` centred at marker2; marker2's axes do not enter)
// on a plane (marker1's x-y plane, on its +w1 side). Rows: <joint>_n (holonomic: (P2 − P1)·w1 − R,
// the centre's height above the plane minus the radius: a distance, its multiplier the normal
// force in N); <joint>_x, <joint>_y (velocity form: the ball's material point at the contact
// C = P2 + ρ, ρ = −R w1, has body1's velocity there along u1, v1: u1·(v_P2 + ω2 × ρ − v_B1(C)),
// v1·(...); orthonormal tangents, so their multipliers are the friction force's components in N).
// `no_slip = false` keeps the row n only: a frictionless ball (it slides and spins freely).
// Contact keys as on the wheel (read_rolling_contact): `unilateral`, `restitution` on the row n;
// the no-slip rows are then rough rows, or with `mu_static` (`mu_kinetic`) the contact's two
// Coulomb rows (a 2-D cone; refused on a frictionless ball). Reaction on the ball, in the joint
// frame: F = λ_x u1 + λ_y v1 + λ_n w1 acting at C, and its moment about the centre (marker2),
// ρ × F. On a plane a ball has no singular pose (the contact point is always −R w1 from the
// centre). `surface = "sphere"` (sphere_rows): on a sphere of body1, or inside a bowl.
class SpatialBall : public JointType {
 public:
  std::string name() const override { return "ball"; }
  std::vector<std::string> extra_keys() const override { return rolling_extra_keys(); }
  void rows(Expander& x, Joint& j) const override {
    const RollingKeys k = read_rolling_keys(x, j, "ball");  // the wheel's keys and refusals
    const bool no_slip = k.no_slip;
    const Frames& f = k.f;
    const Expr& R = k.radius;
    if (k.sphere) return sphere_rows(x, j, k);
    const Vec3 n = column(f.E1, 2);
    const std::string pre = j.name + "_";
    Vec3 rho;  // from the centre to the contact point, −R w1 (named: drawings use it)
    for (int i = 0; i < 3; ++i) rho[i] = x.define(pre + "rho" + "xyz"[i], neg(mul(R, n[i])), j.key);
    Row rn, rx, ry;
    rn.name = pre + "n";
    rn.holonomic = sub(dot(n, f.d), R);
    rx.name = pre + "x";
    ry.name = pre + "y";
    if (has_contact_keys(j)) read_rolling_contact(x, j, rn, no_slip, rx, ry, "frictionless ball");
    j.rows.push_back(rn);
    Vec3 F = scale(lam(rn), n);
    if (no_slip) no_slip_rows(x, j, f, add(f.P2, rho), column(f.E1, 0), column(f.E1, 1), rn, rx, ry, F);
    set_reaction(j, f, F, cross(rho, F));
  }

 private:
  // On a sphere of body1 (centre S = marker1's origin, radius Rs = `sphere_radius`), outside
  // (default) or inside (`inside = true`, a ball in a spherical bowl). With d = C − S (the ball's
  // centre from the sphere's) and ν̂ = d/|d|: the row n is |d| − (Rs + R) outside, (Rs − R) − |d|
  // inside (a distance, its multiplier the normal force in N); the contact point is S + Rs ν̂,
  // the ball's material point there C − R n̂, with n̂ = ν̂ outside and −ν̂ inside the surface's
  // normal towards the ball (the normal force's direction on the ball). ρ = −R n̂.
  // Tangents: the rotation of least angle taking w1 to n̂ (two reflections, across the plane
  // normal to w1 + n̂, then across the one normal to n̂) applied to u1 and v1:
  //   t1 = u1 − (n̂·u1)/(1 + w1·n̂) (w1 + n̂),  t2 = v1 − (n̂·v1)/(1 + w1·n̂) (w1 + n̂),
  // exactly orthonormal and normal to n̂ (n̂·t1 = n̂·u1 − (n̂·u1)(w1·n̂ + 1)/(1 + w1·n̂) = 0), equal to
  // u1, v1 where n̂ = w1 (the top of the sphere outside, the bottom of the bowl inside, with w1
  // up). This chart is singular at n̂ = −w1, where 1 + w1·n̂ = 0 (a tangent field on a sphere must
  // vanish somewhere), so it serves the hemisphere w1·n̂ >= 0 only; on the other one the second
  // chart, the rotation of least angle taking −w1 to n̂ applied to the right-handed (u1, −v1, −w1):
  //   t1 = u1 − (n̂·u1)/(1 − w1·n̂) (n̂ − w1),  t2 = −(v1 − (n̂·v1)/(1 − w1·n̂) (n̂ − w1)),
  // singular only at n̂ = w1. Both are one formula with σ = +1 (the first chart) where
  // w1·n̂ > −1/2 and σ = −1 (the second) where w1·n̂ < −1/2:
  //   t1 = u1 − (n̂·u1) k (σ w1 + n̂),  t2 = σ (v1 − (n̂·v1) k (σ w1 + n̂)),  k = 1/(1 + σ w1·n̂),
  // with 1 + σ w1·n̂ >= 1/2: no division by less than one half anywhere. The charts meet on the
  // circle w1·n̂ = −1/2, where both are regular (not at w1·n̂ = 0, which symmetric states hit
  // exactly) and t1 × t2 = n̂ in both; there the pair turns about n̂. The rows span the same
  // tangent plane on either side, so no-slip (rough) rows impose the same motion across the
  // circle and only the multipliers λ_x, λ_y are taken along the other pair (F_JOINT_x/_y/_z, the
  // force in joint axes, is continuous). A 2-D cone's reference direction (the sliding direction,
  // Config::dir) is held in the pair's components, so a contact sliding across the circle sees
  // it turn until it is renewed after the step (test_switching_cli: a ball skidding through the
  // switch moves as with one chart, without an event; docs/bodies-spatial.md).
  static void sphere_rows(Expander& x, Joint& j, const RollingKeys& k) {
    const Frames& f = k.f;
    const Expr& R = k.radius;
    const Expr& Rs = k.sphere_radius;
    const bool inside = k.inside, no_slip = k.no_slip;
    // Every intermediate vector is a named definition (named_vector).
    const std::string pre = j.name + "_";
    auto named = [&](const std::string& stem, const Vec3& v) { return named_vector(x, j, stem, v); };
    const Vec3 d = named("d", f.d);
    const Expr dist = x.define(pre + "dist", "sqrt(" + dot(d, d) + ")", j.key);
    Vec3 nh;  // the surface's normal at the contact, towards the ball: the normal force's direction
    for (int i = 0; i < 3; ++i)
      nh[i] = x.define(pre + "nu" + "xyz"[i], (inside ? "-" : "") + d[i] + "/" + dist, j.key);
    Vec3 rho;  // from the centre to the contact point, −R n̂ (named: drawings use it)
    for (int i = 0; i < 3; ++i) rho[i] = x.define(pre + "rho" + "xyz"[i], neg(mul(R, nh[i])), j.key);
    Row rn, rx, ry;
    rn.name = pre + "n";
    rn.holonomic = inside ? sub(sub(Rs, R), dist) : sub(dist, paren(add(Rs, R)));
    rx.name = pre + "x";
    ry.name = pre + "y";
    if (has_contact_keys(j)) read_rolling_contact(x, j, rn, no_slip, rx, ry, "frictionless ball");
    j.rows.push_back(rn);
    Vec3 F = scale(lam(rn), nh);
    if (no_slip) {
      const Vec3 u1 = named("u1", column(f.E1, 0)), v1 = named("v1", column(f.E1, 1)), w1 = named("w1", column(f.E1, 2));
      const Expr c = x.define(pre + "cw", dot(w1, nh), j.key);
      // σ = ±1 on either side of w1·n̂ = −1/2: a step made of min and max (their derivatives are
      // steps, exactly zero away from the switch; 1e300 |c + 1/2| >= 1 unless c is −1/2 to the last bit).
      const Expr sg = x.define(pre + "chart", "max(-1, min(1, 1e300*(" + c + " + 1/2)))", j.key);
      const Expr kc = x.define(pre + "k", "1/(1 + " + mul(sg, c) + ")", j.key);
      const Expr nu = x.define(pre + "nu1", dot(nh, u1), j.key), nv = x.define(pre + "nv1", dot(nh, v1), j.key);
      Vec3 s0;
      for (int i = 0; i < 3; ++i) s0[i] = add(mul(sg, w1[i]), nh[i]);
      const Vec3 s = named("wn", s0);
      Vec3 t1, t2;
      for (int i = 0; i < 3; ++i) {
        t1[i] = x.define(pre + "t1" + "xyz"[i], sub(u1[i], nu + "*" + kc + "*" + s[i]), j.key);
        t2[i] = x.define(pre + "t2" + "xyz"[i], mul(sg, sub(v1[i], nv + "*" + kc + "*" + s[i])), j.key);
      }
      no_slip_rows(x, j, f, add(f.P2, rho), t1, t2, rn, rx, ry, F);
    }
    set_reaction(j, f, F, cross(rho, F));
  }
};

}  // namespace

Mat3 spatial_marker_axes(Expander& x, const toml::table& t, const std::string& key) {
  Vec3 axis;
  axis[2] = "1";
  if (const toml::node* a = t.get("axis")) axis = x.vector(*a, key + ".axis", false);
  Expr angle = "0";
  if (const toml::node* a = t.get("angle")) angle = x.expression(*a, key + ".angle");
  if (is_zero(angle)) return Mat3{};
  // u = axis/|axis| (numerically when the axis is numbers).
  Vec3 u;
  bool numeric = true;
  double v[3];
  for (int i = 0; i < 3; ++i) {
    char* end = nullptr;
    v[i] = std::strtod(axis[i].c_str(), &end);
    if (axis[i].empty() || end != axis[i].c_str() + axis[i].size()) numeric = false;
  }
  if (numeric) {
    const double n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (!(n > 0)) x.fail(key + ".axis", "a nonzero axis [x, y, z] (the marker's rotation from the body frame)");
    for (int i = 0; i < 3; ++i) u[i] = v[i] == 0 ? "0" : format_number(v[i] / n);
    // exact unit axes stay exact
    for (int i = 0; i < 3; ++i)
      if (std::abs(v[i]) == n) u[i] = v[i] > 0 ? "1" : "-1";
  } else {
    const Expr len = "sqrt(" + dot(axis, axis) + ")";
    for (int i = 0; i < 3; ++i) u[i] = is_zero(axis[i]) ? "0" : paren(axis[i]) + "/" + len;
  }
  // Rodrigues: R = c I + (1 - c) u u^T + s [u]x.
  const Expr c = "cos(" + angle + ")", sn = "sin(" + angle + ")", omc = "(1 - cos(" + angle + "))";
  Mat3 R;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) R.m[i][j] = add(i == j ? c : "0", mul(omc, mul(u[i], u[j])));
  R.m[0][1] = sub(R.m[0][1], mul(sn, u[2]));
  R.m[0][2] = add(R.m[0][2], mul(sn, u[1]));
  R.m[1][0] = add(R.m[1][0], mul(sn, u[2]));
  R.m[1][2] = sub(R.m[1][2], mul(sn, u[0]));
  R.m[2][0] = sub(R.m[2][0], mul(sn, u[1]));
  R.m[2][1] = add(R.m[2][1], mul(sn, u[0]));
  return R;
}

void register_spatial_bodies() {
  register_body_kind(std::make_shared<SpatialBody>());
  // Lower pairs: rows in the joint frame (marker1's axes).
  // Spherical: no planar counterpart; in both tables, so that it is a tree joint for spatial bodies.
  register_joint_type(std::make_shared<SpatialSpherical>());
  register_spatial_joint_type(std::make_shared<SpatialSpherical>());
  register_spatial_joint_type(std::make_shared<SpatialCylindrical>());
  register_joint_type(std::make_shared<SpatialPointOnPlane>());
  register_spatial_joint_type(std::make_shared<SpatialUniversal>());
  register_joint_type(std::make_shared<SpatialWheel>());
  register_joint_type(std::make_shared<SpatialBall>());
  register_spatial_joint_type(std::make_shared<SpatialRevolute>());
  register_spatial_joint_type(std::make_shared<SpatialPrismatic>());
  register_spatial_joint_type(std::make_shared<SpatialPair<true, true, true, true, true>>("fixed"));
  register_spatial_joint_type(std::make_shared<SpatialPlanar>());
  register_spatial_joint_type(std::make_shared<SpatialPointOnLine>());
  register_spatial_joint_type(std::make_shared<SpatialDistance>());
}

}  // namespace pcsim::modelfile::bodies
