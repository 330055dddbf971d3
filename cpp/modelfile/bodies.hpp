// Bodies, joints and forces (issue 22; docs/bodies.md): a model described as engineers draw it
// ([model.body.NAME], [model.joint.NAME], [model.force.NAME]) is EXPANDED, before any symbolic
// work, into the energy form of docs/model-files.md (generated coordinates, definitions, T, V,
// F, generalized forces, named constraint rows, outputs, drawing) inside the parser's
// ModelSource. Everything downstream (derivation, tape, run, sweep, contacts, expand, ...) is
// the energy-form pipeline, unchanged.
//
// The kinematics layer is 3-D for every body and works on expression TEXTS (the model-file
// language), so the expansion is deterministic, readable in `pcsim expand`, and the numbers are
// read exactly as the user wrote them:
//   - a position is a Vec3 of expressions, a rotation a Mat3 (body -> ground);
//   - a velocity is LINEAR in the generated velocities: a Lin (coefficient per coordinate, plus
//     a rest that holds explicit time dependence, e.g. a drive), so that velocity-form
//     constraint rows (rolling) get their coefficients without differentiation.
// A body kind (planar, particle; spatial kinds plug in the same way) supplies its coordinates,
// its Pose (r, A, v, ω in ground, ω in the body frame) and any constraints of its own (e.g. the
// unit norm of Euler parameters). A joint type supplies constraint rows and the reaction force
// and moment on its second body in its own frame (as expressions of lambda_<row>); a joint with
// `coordinates = [...]` instead places its second body relative to its first (a tree joint: no
// rows). A force type adds to V, F (Rayleigh) or the generalized forces.
#pragma once

#include <array>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <toml++/toml.h>

#include "modelfile/model_source.hpp"

namespace pcsim::modelfile::bodies {

// ---- expression texts ----------------------------------------------------------------------

/// An expression in the model-file language. "0" and "1" are recognized by the helpers below,
/// which fold them (so a body at the origin of its frame adds no terms).
using Expr = std::string;
bool is_zero(const Expr& a);
bool is_one(const Expr& a);
/// a wrapped in parentheses unless it is a name, a number or already atomic.
Expr paren(const Expr& a);
Expr add(const Expr& a, const Expr& b);
Expr sub(const Expr& a, const Expr& b);
Expr mul(const Expr& a, const Expr& b);
Expr neg(const Expr& a);
Expr sum(const std::vector<Expr>& terms);

struct Vec3 {
  std::array<Expr, 3> c{"0", "0", "0"};
  Expr& operator[](int i) { return c[static_cast<std::size_t>(i)]; }
  const Expr& operator[](int i) const { return c[static_cast<std::size_t>(i)]; }
};
/// Row-major 3x3; m[i][j].
struct Mat3 {
  std::array<std::array<Expr, 3>, 3> m{{{"1", "0", "0"}, {"0", "1", "0"}, {"0", "0", "1"}}};
  static Mat3 identity() { return Mat3{}; }
  /// The planar rotation by angle th about z.
  static Mat3 rot_z(const Expr& th);
};
Vec3 add(const Vec3& a, const Vec3& b);
Vec3 sub(const Vec3& a, const Vec3& b);
Vec3 scale(const Expr& s, const Vec3& a);
Expr dot(const Vec3& a, const Vec3& b);
Vec3 cross(const Vec3& a, const Vec3& b);
Vec3 apply(const Mat3& A, const Vec3& v);            ///< A v
Vec3 apply_transposed(const Mat3& A, const Vec3& v); ///< Aᵀ v
Mat3 multiply(const Mat3& A, const Mat3& B);
Vec3 column(const Mat3& A, int j);

/// An expression linear in the velocities: Σ coef[c]·c_d + rest (rest: q- and t-dependent
/// terms, e.g. a drive's ḟ(t)). Keyed by coordinate name, kept in insertion order of names.
struct Lin {
  std::vector<std::pair<std::string, Expr>> coef;  ///< coordinate -> coefficient
  Expr rest = "0";
  Expr coefficient(const std::string& coordinate) const;  ///< "0" if absent
  /// The expression itself: Σ coef·c_d + rest.
  Expr text() const;
};
Lin add(const Lin& a, const Lin& b);
Lin scale(const Expr& s, const Lin& a);
struct LinVec3 {
  std::array<Lin, 3> c;
  Lin& operator[](int i) { return c[static_cast<std::size_t>(i)]; }
  const Lin& operator[](int i) const { return c[static_cast<std::size_t>(i)]; }
};
LinVec3 add(const LinVec3& a, const LinVec3& b);
LinVec3 cross(const LinVec3& w, const Vec3& r);      ///< ω × r (ω linear, r a position)
LinVec3 apply(const Mat3& A, const LinVec3& v);
LinVec3 apply_transposed(const Mat3& A, const LinVec3& v);
Lin dot(const Vec3& a, const LinVec3& v);
/// The velocity of a single coordinate: 1·c_d.
Lin velocity_of(const std::string& coordinate);

// ---- bodies --------------------------------------------------------------------------------

/// The pose of a body frame and its velocity, all in ground unless said otherwise.
struct Pose {
  Vec3 r;         ///< origin of the body frame
  Mat3 A;         ///< body -> ground
  LinVec3 v;      ///< velocity of the origin
  LinVec3 w;      ///< angular velocity, ground components
  LinVec3 w_body; ///< angular velocity, body components (T uses ½ ω_bᵀ J ω_b)
  /// Optional: v, w and w_body as short texts (names of generated definitions), which the
  /// kinetic energy uses instead of the expanded linear forms (a chain of tree joints would
  /// otherwise repeat each parent's velocity in every child: quadratic text). Empty: unused.
  bool has_text = false;
  Vec3 v_text, w_text, w_body_text;
};
/// The velocity of the body's origin, its angular velocity (ground, body) as texts: the
/// definitions of has_text, or the linear forms written out.
Vec3 velocity_text(const Pose& p);
Vec3 angular_velocity_text(const Pose& p);
Vec3 body_angular_velocity_text(const Pose& p);

/// A named point (and frame) on a body: position p and axes R (marker -> body) in the body frame.
struct Marker {
  std::string name;
  Vec3 p;
  Mat3 R;
  std::string key;  ///< where it was declared (messages)
};

/// A simple drawing shape (docs/bodies.md "Shapes").
struct Shape {
  std::string type;   ///< "" none, "rod", "box", "circle", "cylinder", "sphere"
  std::string from, to;      ///< rod: markers
  Expr width = "0", height = "0", radius = "0";
  std::string fill;
};

struct Body {
  std::string name;
  std::string kind;        ///< "planar" (default), "particle", or a spatial kind
  std::string key;         ///< "model.body.NAME"
  bool ground = false;
  Expr mass = "0";
  Vec3 com;                ///< in the body frame
  Mat3 inertia;            ///< about the centre of mass, body frame (planar: only m[2][2] used)
  std::vector<Marker> markers;  ///< "origin" (0) is implicit
  Shape shape;
  std::vector<std::string> coordinates;  ///< generated, or the tree joint's coordinates
  std::string parent_joint;  ///< "" = absolute coordinates; else the tree joint placing it
  Pose pose;                 ///< filled by the expander
  /// A body placed by a tree joint: its pose relative to its parent body (r, A in the parent's
  /// frame; v, w the rates of r and of the relative rotation, parent components).
  Pose relative;
  std::string parent;        ///< the parent body of a tree-placed body
  Pose parent_pose;          ///< ... and its pose (the kinetic energy is written in its frame)
  const Marker* marker(const std::string& name) const;
};

class Expander;

/// A kind of body: planar (x, y, th), particle (x, y[, z]), or (BODIES-SPATIAL) a spatial body.
/// Register one with register_body_kind(); the expander calls it for every body of that kind.
class BodyKind {
 public:
  virtual ~BodyKind() = default;
  virtual std::string name() const = 0;
  /// True if the body moves in the x-y plane (joints then generate only the in-plane rows).
  virtual bool planar() const = 0;
  /// Extra keys this kind accepts in [model.body.NAME] besides the common ones.
  virtual std::vector<std::string> extra_keys() const { return {}; }
  /// Reads the kind's inertia (planar: a scalar = J about z through the centre of mass; spatial:
  /// a 3x3 table or a list of 3 principal values) into b.inertia; default reads a scalar.
  virtual void read_inertia(Expander& x, const toml::node* node, Body& b) const;
  /// The generated names of an absolutely placed body's coordinates (NAME_x, NAME_y, NAME_th).
  virtual std::vector<std::string> coordinates(const Body& b) const = 0;
  /// The pose of an absolutely placed body from its coordinates b.coordinates.
  virtual Pose free_pose(const Body& b) const = 0;
  /// Constraints of the body itself (Euler parameters: e0²+e1²+e2²+e3² − 1), added to src.
  virtual void own_constraints(Expander& x, const Body& b) const { (void)x; (void)b; }
  /// Kinetic energy of the body: ½ m |v_c|² + ½ ω_bᵀ J ω_b by default.
  virtual Expr kinetic(const Body& b) const;
};

/// One constraint row a joint generates. Exactly one of holonomic / velocity.
struct Row {
  std::string name;         ///< the constraint's name: <joint>_<suffix>, or <joint> for one row
  Expr holonomic;           ///< Φ(q, t) ("" for a velocity-form row)
  Lin velocity;             ///< g q̇ + g0 (velocity form), used when holonomic is ""
  bool velocity_form = false;
  bool from_initial = false;
  bool active = true;
  // Contact attributes (mapped onto [[model.constraint]]'s; docs/model-files.md "Contact").
  bool unilateral = false;
  int gap_sign = 1;
  Expr restitution;         ///< "" absent
  std::string friction;     ///< the unilateral row's name, "" none
  Expr mu_static, mu_kinetic;
  bool rough = false;       ///< with friction: held while that contact is closed, no μ
};

/// What a joint reads and generates. The frame of a joint is marker1's frame on body1 unless
/// the joint type says otherwise (docs/bodies.md lists each type's frame and rows).
struct Joint {
  std::string name, type, key;
  std::string body1, marker1, body2, marker2;  ///< body1 = "ground" allowed
  std::vector<std::string> coordinates;        ///< a tree joint's coordinates (then no rows)
  const toml::table* table = nullptr;          ///< the joint's TOML table (type-specific keys)
  std::vector<Row> rows;                       ///< filled by the joint type
  /// Reaction on body2, joint frame, as expressions of lambda_<row> and q (and R): "" = none.
  Vec3 force, moment;
  bool has_reaction = false;
  Mat3 axes;  ///< the joint frame -> ground (for reactions in ground); marker1's axes by default
  bool planar = true;  ///< both bodies planar: only F_x, F_y, M_z are reported
  /// Scalar reactions besides F and M, as (column, expression): a coupler's torque or force on
  /// each member joint's motion (columns M_<coupler>_<member> or F_<coupler>_<member>).
  std::vector<std::pair<std::string, Expr>> member_reactions;
};

/// One motion of a joint, as gears, couplers and joint spring-dampers see it: a tree joint's
/// coordinate, or the relative rotation about (translation along) the axis of a revolute,
/// prismatic or cylindrical joint written as rows.
struct JointMotion {
  Expr position;  ///< the displacement as an expression of q; "" when none exists (a spatial
                  ///< rotation written as rows: its angle is not a function of q, only its rate)
  Lin rate;       ///< its rate, linear in q_d
  bool rotation = false;  ///< an angle (rad; its force is a torque) or a travel (m)
  bool planar = true;     ///< the joint is planar (its reactions: F_x, F_y, M_z)
  Mat3 axes;              ///< the joint frame (marker1's axes) -> ground
  int axis = 2;           ///< the motion's axis in that frame: z for a rotation, x or z a travel
};
/// The motion `dof` of joint j ("" = its only motion; a tree joint's coordinate name; a
/// cylindrical joint's "rotation" or "translation"); failures name `key` (and `dof_key`).
JointMotion joint_motion(Expander& x, const Joint& j, const std::string& dof, const std::string& key,
                         const std::string& dof_key);

/// A joint type: revolute, prismatic, fixed, distance, point_on_line, drive, gear, rolling, ...
class JointType {
 public:
  virtual ~JointType() = default;
  virtual std::string name() const = 0;
  /// Type-specific keys accepted besides type, body1, marker1, body2, marker2 and coordinates
  /// (the joints that can lift off or slip list contact_keys() here).
  virtual std::vector<std::string> extra_keys() const { return {}; }
  /// Number of coordinates this joint takes as a tree joint (0: it cannot be one); for a
  /// planar first body.
  virtual int tree_coordinates(bool planar) const { (void)planar; return 0; }
  /// A tree joint: the pose of body2 from the pose of body1 and the joint's coordinates;
  /// `relative` receives body2's pose relative to body1 (see Body::relative).
  virtual Pose tree_pose(Expander& x, const Joint& j, Pose& relative) const;
  /// A constraint joint: fills j.rows (and j.force/j.moment/j.has_reaction).
  virtual void rows(Expander& x, Joint& j) const = 0;
};

/// A force element: gravity, spring_damper, rotational_spring_damper, joint_spring_damper,
/// force, torque, bushing, ...
class ForceType {
 public:
  virtual ~ForceType() = default;
  virtual std::string name() const = 0;
  virtual std::vector<std::string> keys() const = 0;  ///< accepted keys besides `type`
  /// Adds potential / dissipation / generalized forces (Expander::add_potential, ...).
  virtual void apply(Expander& x, const std::string& name, const std::string& key,
                     const toml::table& t) const = 0;
};

void register_body_kind(std::shared_ptr<const BodyKind> kind);
void register_joint_type(std::shared_ptr<const JointType> type);
void register_force_type(std::shared_ptr<const ForceType> type);
/// The spatial kinds, joints and forces register themselves here (bodies_spatial.cpp); called
/// once, before the first expansion.
void register_spatial_bodies();
/// A joint type for bodies that are not planar under a name a planar type also uses (revolute,
/// prismatic, fixed, ...): the expander picks it when either body of the joint is not planar.
void register_spatial_joint_type(std::shared_ptr<const JointType> type);
/// (BODIES-SPATIAL, bodies_spatial.cpp) A spatial marker's axes (marker -> body) from its table
/// { at = [...], axis = [ax, ay, az], angle = "..." }: the body frame turned by angle about axis.
Mat3 spatial_marker_axes(Expander& x, const toml::table& t, const std::string& key);

/// (CONTACT, bodies_contact.cpp) The contact attributes of issue 12 on a joint's rows
/// (docs/bodies.md "Contact"): the joint keys `unilateral`, `restitution`, `mu_static`,
/// `mu_kinetic`, accepted only by the joints that can lift off or slip.
const std::vector<std::string>& contact_keys();
/// True if the joint's table has any of contact_keys().
bool has_contact_keys(const Joint& j);
/// Reads them onto `normal` (unilateral, restitution) and `friction` (mu_static, mu_kinetic,
/// friction = normal's name), checking them (at the parameters' defaults where they are
/// numbers). `friction` null: mu_static/mu_kinetic are refused with `no_friction` as the reason.
/// `friction2` (a contact that slides in a plane: the second of its two Coulomb rows, the
/// sliding velocity along a tangent orthonormal to the first's) receives the same attributes.
void read_joint_contact(Expander& x, const Joint& j, Row& normal, Row* friction,
                        const std::string& no_friction = "", Row* friction2 = nullptr);
/// The surface a rolling body rolls on (docs/bodies.md "Rolling on a circle",
/// docs/bodies-spatial.md): the flat one (the planar `rolling` joint: marker1's x axis, "line";
/// the spatial `wheel` and `ball`: marker1's x-y plane, "plane") or a curved one of body1 centred
/// at marker1 (`surface = "circle"` / `"sphere"`) with its radius `<curved>_radius` and
/// `inside = true` (the body inside it: a ring, a bowl) or false (default: outside, a drum).
struct RollingSurface {
  bool curved = false;
  Expr radius;          ///< the curved surface's radius ("" on the flat one)
  bool inside = false;
};
/// The keys `surface`, `<curved>_radius` and `inside` of a rolling joint whose body (`body`:
/// "wheel", "ball") has the radius `body_radius`; `flat_where` says where the flat surface is.
/// Refused, naming the key: an unknown surface; the curved keys on the flat surface; a radius
/// of the body or of the curved surface not > 0, inside a surface not larger than the body (each
/// checked at the parameters' defaults where it is a number).
RollingSurface read_rolling_surface(Expander& x, const Joint& j, const std::string& body,
                                    const Expr& body_radius, const std::string& flat,
                                    const std::string& flat_where, const std::string& curved);
/// Fails (naming the first contact key of the joint) with `why` if the joint has any.
void refuse_contact_keys(Expander& x, const Joint& j, const std::string& why);
/// A number for an expression of the parameters at their defaults (NaN if it is not one).
double default_parameter_value(Expander& x, const Expr& e, const std::string& key);

/// The expansion of one [model] table: used by the parser; the kinds, joints and forces call
/// back into it to read keys and to add to the energy form.
class Expander {
 public:
  Expander(detail::ModelSource& src, const toml::table& model);

  // Reading (messages: "<file>: key '<key>': <what>").
  const std::string& where() const;
  [[noreturn]] void fail(const std::string& key, const std::string& what) const;
  Expr expression(const toml::node& node, const std::string& key) const;
  Vec3 vector(const toml::node& node, const std::string& key, bool planar) const;
  std::string string(const toml::node& node, const std::string& key, const std::string& what) const;
  bool boolean(const toml::node& node, const std::string& key) const;
  double number(const toml::node& node, const std::string& key) const;
  /// An optional expression key of a table ("" if absent).
  Expr optional(const toml::table& t, const std::string& table_key, const std::string& name) const;
  /// A required expression key.
  Expr required(const toml::table& t, const std::string& table_key, const std::string& name,
                const std::string& what) const;

  // Bodies and markers.
  const Body& body(const std::string& name, const std::string& key) const;  ///< fails if unknown
  const Marker& marker(const Body& b, const std::string& name, const std::string& key) const;
  const Joint& joint(const std::string& name, const std::string& key) const;  ///< fails if unknown
  /// Every body (ground first), in file order.
  const std::vector<Body>& bodies() const;
  /// The kind of a body (registered BodyKind).
  const BodyKind& kind(const Body& b) const;
  /// A marker's position, frame axes (marker -> ground) and velocity in ground.
  Vec3 marker_position(const Body& b, const Marker& m) const;
  Mat3 marker_axes(const Body& b, const Marker& m) const;
  LinVec3 marker_velocity(const Body& b, const Marker& m) const;
  /// The velocity of a point fixed on body b whose ground position is P (an expression).
  LinVec3 point_velocity(const Body& b, const Vec3& P) const;
  /// The rotation angle of a planar body (its th coordinate or composed angle).
  Expr planar_angle(const Body& b) const;

  // Adding to the energy form.
  std::string define(const std::string& name, const Expr& value, const std::string& key);
  void add_coordinate(const std::string& name, const std::string& key);
  void add_kinetic(const Expr& e);
  void add_potential(const Expr& e);
  void add_dissipation(const Expr& e);
  /// A generalized force by virtual power: Σ_c coef_c(δ) f — adds f·coef to Q_c of every
  /// coordinate in the linear velocity v (force f along the direction whose rate is v).
  void add_power(const Lin& v, const Expr& f, const std::string& key);
  void add_constraint(const Row& r, const std::string& key);
  void add_output(const std::string& name, const Expr& e, const std::string& key);

  /// Runs the whole expansion (bodies, tree joints, kinetic energy, joints, forces, outputs,
  /// drawing) into the ModelSource.
  void run();
  /// After the energy-form keys are read: the per-joint reaction outputs (after the user's).
  void finish();

  detail::ModelSource& source() { return src_; }

 private:
  struct Impl;
  std::shared_ptr<Impl> impl_;
  detail::ModelSource& src_;
};

/// (bodies_kinematics.cpp) Defines the generated kinematic names that the outputs, definitions
/// or drawing of `model` use and the user has not defined: angular velocities (BODY_w; BODY_wx,
/// _wy, _wz), angular accelerations (BODY_alpha; BODY_alphax.., BODY_alpha1..) and marker
/// accelerations (BODY_MARKER_ax, _ay, _az), the accelerations as total time derivatives of the
/// velocities' definitions (outputs only). Called by Expander::finish().
void define_requested_kinematics(Expander& x, const toml::table& model);

/// True if the [model] table uses the body form (body, joint or force keys).
bool has_body_form(const toml::table& model);
/// The keys of [model] the body form adds.
const std::vector<std::string>& body_form_keys();

/// Prints a ModelSource in the energy form of docs/model-files.md (`pcsim expand`): a model
/// file that, read back, gives the same ModelSource and so the same tape, bit for bit.
std::string energy_form_text(const detail::ModelSource& src);

}  // namespace pcsim::modelfile::bodies
