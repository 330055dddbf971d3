// Bad bodies, joints and forces (issue 22, docs/bodies.md "Errors"): each is one InputError in
// the model-file format "<file>: key '<key>': <expected>" before anything is derived.
#define BOOST_TEST_MODULE test_bodies_bad_input
#include <boost/test/unit_test.hpp>

#include <string>

#include "modelfile/model_file.hpp"
#include "modelfile_test_util.hpp"

using namespace pcsim;
using namespace pcsim::modelfile;
using namespace pcsim::modelfile::testing;

namespace {

// A two-body pendulum, body-form; `extra` is appended (TOML tables may follow).
const std::string kBase = R"([model]
name = "m"
[model.parameters]
m = 1.0
L = 1.0
[model.body.a]
mass = "m"
inertia = "m*L^2/12"
markers = { tip = ["L", 0] }
[model.body.b]
mass = "m"
inertia = "m*L^2/12"
)";

std::string error_of(const std::string& text) {
  return input_error_of([&] { load_model_text(text, "m.toml"); });
}

void expect_error(const std::string& text, std::initializer_list<std::string> parts) {
  const std::string e = error_of(text);
  BOOST_TEST_MESSAGE(e);
  BOOST_CHECK_MESSAGE(e.rfind("m.toml: key '", 0) == 0 && contains_all(e, parts), "got: " + e);
}

}  // namespace

BOOST_AUTO_TEST_CASE(the_base_model_loads) {
  BOOST_CHECK_EQUAL(error_of(kBase + "[model.joint.j]\ntype = \"revolute\"\nbody2 = \"a\"\n"), "");
}

BOOST_AUTO_TEST_CASE(a_massless_body_is_refused) {
  expect_error(R"([model]
[model.body.a]
inertia = 1
)", {"model.body.a.mass", "mass"});
  expect_error(R"([model]
[model.body.a]
mass = 0
inertia = 1
)", {"model.body.a.mass", "a mass > 0", "singular"});
  expect_error(R"([model]
[model.parameters]
m = -2.0
[model.body.a]
mass = "m"
inertia = 1
)", {"model.body.a.mass", "a mass > 0", "= -2"});
}

BOOST_AUTO_TEST_CASE(an_inertia_that_leaves_the_mass_matrix_singular_is_refused) {
  expect_error(R"([model]
[model.body.a]
mass = 1
inertia = 0
)", {"model.body.a.inertia", "> 0", "particle"});
  expect_error(R"([model]
[model.body.a]
mass = 1
)", {"model.body.a.inertia"});
  expect_error(R"([model]
[model.body.a]
kind = "particle"
mass = 1
inertia = 2
)", {"model.body.a.inertia", "no inertia for a particle"});
}

BOOST_AUTO_TEST_CASE(a_joint_naming_an_unknown_body_or_marker_is_refused) {
  expect_error(kBase + "[model.joint.j]\ntype = \"revolute\"\nbody2 = \"c\"\n",
               {"model.joint.j.body2", "the name of a body", "got 'c'", "a, b"});
  expect_error(kBase + "[model.joint.j]\ntype = \"revolute\"\nbody1 = \"a\"\nmarker1 = \"top\"\nbody2 = \"b\"\n",
               {"model.joint.j.marker1", "a marker of body 'a'", "tip", "got 'top'"});
  expect_error(kBase + "[model.joint.j]\ntype = \"hinge\"\nbody2 = \"a\"\n",
               {"model.joint.j.type", "revolute", "got 'hinge'"});
}

BOOST_AUTO_TEST_CASE(a_joint_between_a_body_and_itself_is_refused) {
  expect_error(kBase + "[model.joint.j]\ntype = \"revolute\"\nbody1 = \"a\"\nbody2 = \"a\"\n",
               {"model.joint.j.body2", "a body other than body1", "itself"});
}

BOOST_AUTO_TEST_CASE(duplicate_names_are_refused) {
  // A joint named like a body.
  expect_error(kBase + "[model.joint.a]\ntype = \"revolute\"\nbody2 = \"b\"\n",
               {"model.joint.a", "already used by a body, joint or force"});
  // Two tables of one name: TOML itself refuses them (with the line).
  const std::string e = error_of(kBase + "[model.joint.j]\ntype = \"revolute\"\nbody2 = \"a\"\n"
                                         "[model.joint.j]\ntype = \"revolute\"\nbody2 = \"b\"\n");
  BOOST_CHECK_MESSAGE(contains_all(e, {"m.toml:", "not a valid TOML file"}), e);
  // A generated name clashing with a user's: the coordinate a_x.
  expect_error(kBase + "[model.define]\na_x = \"1\"\n", {"a_x", "already used"});
}

BOOST_AUTO_TEST_CASE(a_marker_outside_any_body_is_refused) {
  // Markers live in a body's table; one named on a joint must be on the joint's body.
  expect_error(kBase + "[model.joint.j]\ntype = \"revolute\"\nmarker1 = \"tip\"\nbody2 = \"b\"\n",
               {"model.joint.j.marker1", "a marker of body 'ground'", "got 'tip'"});
  expect_error(kBase + "[model.body.c]\nmass = 1\ninertia = 1\nmarkers = { p = [1, 2, 3] }\n",
               {"model.body.c.markers.p", "planar vector", "z component"});
}

BOOST_AUTO_TEST_CASE(a_body_placed_twice_or_in_a_loop_of_tree_joints_is_refused) {
  expect_error(kBase + "[model.joint.j]\ntype = \"revolute\"\nbody2 = \"a\"\ncoordinates = [\"p\"]\n"
                       "[model.joint.k]\ntype = \"revolute\"\nbody1 = \"b\"\nbody2 = \"a\"\ncoordinates = [\"q\"]\n",
               {"model.joint.k.coordinates", "'j' already does"});
  expect_error(kBase + "[model.joint.j]\ntype = \"revolute\"\nbody1 = \"b\"\nbody2 = \"a\"\ncoordinates = [\"p\"]\n"
                       "[model.joint.k]\ntype = \"revolute\"\nbody1 = \"a\"\nbody2 = \"b\"\ncoordinates = [\"q\"]\n",
               {"model.body.", "loop"});
  expect_error(kBase + "[model.joint.j]\ntype = \"distance\"\nbody2 = \"a\"\nlength = 1\ncoordinates = [\"p\"]\n",
               {"model.joint.j.coordinates", "cannot place its body by coordinates"});
}

BOOST_AUTO_TEST_CASE(unknown_keys_and_missing_values_name_the_key) {
  expect_error(kBase + "[model.joint.j]\ntype = \"revolute\"\nbody2 = \"a\"\nstiffness = 3\n",
               {"model.joint.j.stiffness", "unknown key"});
  expect_error(kBase + "[model.joint.j]\ntype = \"distance\"\nbody2 = \"a\"\n",
               {"model.joint.j.length", "the distance"});
  expect_error(kBase + "[model.force.f]\ntype = \"spring\"\n", {"model.force.f.type", "spring_damper", "got 'spring'"});
  expect_error(kBase + "[model.force.gravity]\ntype = \"gravity\"\n", {"model.force.gravity.g", "gravity vector"});
  expect_error(kBase + "[model.body.c]\nmass = 1\ninertia = 1\ncolour = 2\n", {"model.body.c.colour", "unknown key"});
  expect_error(kBase + "[model.joint.j]\ntype = \"revolute\"\nbody2 = \"a\"\n[model.outputs]\nz = \"lambda_k_x\"\n",
               {"model.outputs.z", "unknown name 'lambda_k_x'"});
  expect_error(kBase + "[model.joint.j]\ntype = \"revolute\"\nbody2 = \"a\"\n[model.energy]\npotential = \"lambda_j_x\"\n",
               {"model.energy.potential", "lambda_<constraint>", "only in [model.outputs]"});
}

BOOST_AUTO_TEST_CASE(a_prescribed_motion_uses_time_and_parameters_only) {
  expect_error(kBase + "[model.joint.j]\ntype = \"revolute\"\nbody2 = \"a\"\nmotion = [\"a_x*t\"]\n",
               {"model.joint.j.motion", "unknown name 'a_x'"});
}

// ---- Contact attributes on joints (issue 22 with issue 12's attributes; docs/bodies.md
// "Contact on joints"). The base: body a on a point_on_line joint to ground's line.
namespace {
std::string on_line(const std::string& keys) {
  return kBase + "[model.parameters.mu]\nvalue = 0.3\n[model.joint.c]\ntype = \"point_on_line\"\nbody2 = \"a\"\n" + keys;
}
std::string on_roll(const std::string& keys) {
  return kBase + "[model.joint.w]\ntype = \"rolling\"\nbody2 = \"a\"\nradius = \"L\"\n" + keys;
}
// A spatial body over ground's plane.
const std::string kSpatial = R"([model]
name = "m"
[model.body.ground]
markers = { floor = [0, 0, 0] }
[model.body.s]
kind = "spatial"
mass = 1
inertia = [1, 1, 1]
)";
}  // namespace

BOOST_AUTO_TEST_CASE(the_contact_attributes_load_on_the_joints_that_can_lift_off_or_slip) {
  BOOST_CHECK_EQUAL(error_of(on_line("unilateral = true\nrestitution = 0.5\nmu_static = \"mu\"\nmu_kinetic = 0.2\n")), "");
  BOOST_CHECK_EQUAL(error_of(on_roll("unilateral = true\nmu_static = 0.3\n")), "");
  BOOST_CHECK_EQUAL(error_of(kSpatial + "[model.joint.p]\ntype = \"point_on_plane\"\nmarker1 = \"floor\"\nbody2 = \"s\"\n"
                                        "unilateral = true\nrestitution = 0.5\n"), "");
  // The 2-D Coulomb cone (docs/bodies.md "Contact on joints"): a point_on_plane's two sliding
  // rows, a rolling wheel's no-slip rows (on a plane or a sphere) as the contact's friction rows.
  BOOST_CHECK_EQUAL(error_of(kSpatial + "[model.joint.p]\ntype = \"point_on_plane\"\nmarker1 = \"floor\"\nbody2 = \"s\"\n"
                                        "unilateral = true\nmu_static = 0.4\nmu_kinetic = 0.3\n"), "");
  const std::string wheel = kSpatial + "[model.joint.w]\ntype = \"wheel\"\nmarker1 = \"floor\"\nbody2 = \"s\"\nradius = 0.3\n";
  BOOST_CHECK_EQUAL(error_of(wheel + "unilateral = true\nrestitution = 0.5\nmu_static = 0.3\n"), "");
  BOOST_CHECK_EQUAL(error_of(wheel + "surface = \"sphere\"\nsphere_radius = 2.0\nunilateral = true\nmu_static = 0.3\nmu_kinetic = 0.1\n"), "");
}

BOOST_AUTO_TEST_CASE(contact_attributes_on_a_joint_that_cannot_lift_off_are_refused) {
  expect_error(kBase + "[model.joint.j]\ntype = \"revolute\"\nbody2 = \"a\"\nunilateral = true\n",
               {"model.joint.j.unilateral", "only on a joint that can lift off or slip", "'revolute'", "point_on_line"});
  expect_error(kBase + "[model.joint.j]\ntype = \"distance\"\nbody2 = \"a\"\nlength = 1\nmu_static = 0.3\n",
               {"model.joint.j.mu_static", "only on a joint that can lift off or slip", "'distance'"});
  expect_error(kBase + "[model.joint.j]\ntype = \"prismatic\"\nbody2 = \"a\"\ncoordinates = [\"p\"]\nrestitution = 0.5\n",
               {"model.joint.j.restitution", "only on a joint that can lift off or slip"});
}

BOOST_AUTO_TEST_CASE(restitution_or_friction_without_a_unilateral_gap_row_is_refused) {
  expect_error(on_line("restitution = 0.5\n"), {"model.joint.c.restitution", "only with unilateral = true"});
  expect_error(on_line("mu_static = 0.3\n"), {"model.joint.c.mu_static", "only with unilateral = true"});
  expect_error(on_line("unilateral = true\nmu_kinetic = 0.2\n"), {"model.joint.c.mu_kinetic", "only with mu_static"});
  // A rolling joint that may lift off needs its rolling row released in flight: friction.
  expect_error(on_roll("unilateral = true\n"), {"model.joint.w.mu_static", "in the air"});
  // A point on a line in space has two rows and no side: no gap.
  expect_error(kSpatial + "[model.joint.l]\ntype = \"point_on_line\"\nmarker1 = \"floor\"\nbody2 = \"s\"\nunilateral = true\n",
               {"model.joint.l.unilateral", "no side", "point_on_plane"});
  // Friction on a plane (the 2-D cone's two sliding rows) needs a gap that can open, as on a line.
  const std::string plane = kSpatial + "[model.joint.p]\ntype = \"point_on_plane\"\nmarker1 = \"floor\"\nbody2 = \"s\"\n";
  expect_error(plane + "mu_static = 0.3\n", {"m.toml", "model.joint.p.mu_static", "only with unilateral = true"});
  expect_error(plane + "unilateral = true\nmu_kinetic = 0.2\n", {"model.joint.p.mu_kinetic", "only with mu_static"});
  // Issue 22 (WHL): a wheel's contact keys, each refused by name with the reason. A rolling wheel
  // takes unilateral and restitution (its no-slip rows become rough rows), and mu_static (its
  // no-slip rows become the contact's Coulomb rows); the frictionless disk no friction.
  const std::string wheel = kSpatial + "[model.joint.w]\ntype = \"wheel\"\nmarker1 = \"floor\"\nbody2 = \"s\"\nradius = 0.3\n";
  BOOST_CHECK_EQUAL(error_of(wheel + "unilateral = true\nrestitution = 0.5\n"), "");
  expect_error(wheel + "restitution = 0.5\n", {"m.toml", "model.joint.w.restitution", "only with unilateral = true"});
  expect_error(wheel + "mu_static = 0.3\n", {"m.toml", "model.joint.w.mu_static", "only with unilateral = true"});
  expect_error(wheel + "surface = \"sphere\"\nsphere_radius = 2.0\nmu_static = 0.3\n",
               {"m.toml", "model.joint.w.mu_static", "only with unilateral = true"});
  // The surface a wheel rolls on (docs/bodies-spatial.md "Joints").
  expect_error(wheel + "surface = \"cylinder\"\n", {"m.toml", "model.joint.w.surface", "\"plane\"", "\"sphere\"", "got 'cylinder'"});
  expect_error(wheel + "surface = \"sphere\"\n", {"m.toml", "model.joint.w.sphere_radius", "the sphere's radius"});
  expect_error(wheel + "sphere_radius = 2.0\n", {"m.toml", "model.joint.w.sphere_radius", "surface = \"sphere\""});
  expect_error(wheel + "inside = true\n", {"m.toml", "model.joint.w.inside", "surface = \"sphere\""});
  expect_error(wheel + "surface = \"sphere\"\nsphere_radius = 2.0\ninside = 1\n", {"m.toml", "model.joint.w.inside"});
  expect_error(wheel + "no_slip = false\nunilateral = true\nmu_static = 0.3\n",
               {"m.toml", "model.joint.w.mu_static", "no_slip = false", "frictionless disk",
                "drop no_slip = false to get Coulomb friction on its rows w_x, w_y"});
  expect_error(wheel + "no_slip = false\nunilateral = true\nmu_static = 0.3\nmu_kinetic = 0.2\n",
               {"model.joint.w.mu_static", "frictionless disk"});
  expect_error(wheel + "surface = \"sphere\"\nsphere_radius = 2.0\nno_slip = false\nunilateral = true\nmu_static = 0.3\n",
               {"model.joint.w.mu_static", "frictionless disk"});
  expect_error(wheel + "no_slip = false\nrestitution = 0.5\n", {"model.joint.w.restitution", "only with unilateral = true"});
  expect_error(wheel + "no_slip = false\nunilateral = true\nrestitution = 2\n", {"model.joint.w.restitution", "[0, 1]"});
  expect_error(wheel + "no_slip = \"no\"\n", {"model.joint.w.no_slip"});
  // A frictionless wheel (no_slip = false) takes unilateral and restitution.
  BOOST_CHECK_EQUAL(error_of(wheel + "no_slip = false\nunilateral = true\nrestitution = 0.5\n"), "");
  BOOST_CHECK_EQUAL(error_of(wheel + "no_slip = false\n"), "");
}

BOOST_AUTO_TEST_CASE(coefficients_outside_their_ranges_are_refused_at_the_defaults) {
  expect_error(on_line("unilateral = true\nmu_static = \"mu\"\nmu_kinetic = 0.5\n"),
               {"model.joint.c.mu_kinetic", "a kinetic friction coefficient in [0, mu_static = 0.3]", "0.5"});
  expect_error(on_line("unilateral = true\nmu_static = -0.1\n"), {"model.joint.c.mu_static", ">= 0", "-0.1"});
  expect_error(on_line("unilateral = true\nrestitution = 1.5\n"), {"model.joint.c.restitution", "[0, 1]", "1.5"});
  // The same on the 2-D cone's joints (a point_on_plane, a rolling wheel).
  const std::string plane = kSpatial + "[model.parameters.mu]\nvalue = 0.3\n[model.joint.p]\ntype = \"point_on_plane\"\n"
                                       "marker1 = \"floor\"\nbody2 = \"s\"\nunilateral = true\n";
  expect_error(plane + "mu_static = \"mu\"\nmu_kinetic = 0.5\n",
               {"m.toml", "model.joint.p.mu_kinetic", "a kinetic friction coefficient in [0, mu_static = 0.3]", "0.5"});
  expect_error(plane + "mu_static = -0.1\n", {"model.joint.p.mu_static", ">= 0", "-0.1"});
  const std::string wheel = kSpatial + "[model.joint.w]\ntype = \"wheel\"\nmarker1 = \"floor\"\nbody2 = \"s\"\n"
                                       "radius = 0.3\nunilateral = true\n";
  expect_error(wheel + "mu_static = 0.3\nmu_kinetic = 0.4\n",
               {"m.toml", "model.joint.w.mu_kinetic", "a kinetic friction coefficient in [0, mu_static = 0.3]", "0.4"});
  // A case's value, checked when the model is instantiated, names the generated row.
  const auto p = load_model_text(plane + "mu_static = \"mu\"\nmu_kinetic = 0.2\n", "m.toml");
  const std::string ep = input_error_of([&] { p->instantiate({{"mu", 0.1}}); });
  BOOST_CHECK_MESSAGE(contains_all(ep, {"m.toml", "model.constraint[p_slide_x].mu_kinetic", "mu_static = 0.1"}), ep);
  // A case's value is checked when the model is instantiated, naming the generated row.
  const auto d = load_model_text(on_line("unilateral = true\nmu_static = \"mu\"\nmu_kinetic = 0.2\n"), "m.toml");
  const std::string e = input_error_of([&] { d->instantiate({{"mu", 0.1}}); });
  BOOST_CHECK_MESSAGE(contains_all(e, {"m.toml", "model.constraint[c_slide].mu_kinetic", "mu_static = 0.1"}), e);
}

BOOST_AUTO_TEST_CASE(unknown_keys_of_a_contact_joint_name_the_key) {
  expect_error(on_line("unilateral = true\ngap_side = -1\n"), {"model.joint.c.gap_side", "unknown key", "unilateral", "mu_kinetic"});
  expect_error(on_line("unilateral = true\nfriction = \"c\"\n"), {"model.joint.c.friction", "unknown key"});
  expect_error(on_line("unilateral = \"yes\"\n"), {"model.joint.c.unilateral"});
}

// Spatial bushings (issue 22, BSH): the rotational keys take a scalar (isotropic) or 3 values;
// a rest rotation is a marker frame (rotate marker2), so a nonzero rotational_rest is refused.
namespace {
std::string spatial_bushing(const std::string& keys) {
  return kSpatial + "[model.force.mount]\ntype = \"bushing\"\nmarker1 = \"floor\"\nbody2 = \"s\"\n"
                    "stiffness = [1, 2, 3]\n" + keys;
}
}  // namespace

BOOST_AUTO_TEST_CASE(a_spatial_bushing_takes_rotational_terms_as_a_scalar_or_three_values) {
  BOOST_CHECK_EQUAL(error_of(spatial_bushing("rotational_stiffness = 5\nrotational_damping = 0.1\n")), "");
  BOOST_CHECK_EQUAL(error_of(spatial_bushing("rotational_stiffness = [1, 2, \"3\"]\nrotational_damping = [0, 0.1, 0.2]\n")), "");
  BOOST_CHECK_EQUAL(error_of(spatial_bushing("rotational_stiffness = 5\nrotational_rest = 0\n")), "");
  BOOST_CHECK_EQUAL(error_of(spatial_bushing("rotational_stiffness = 5\nrotational_rest = [0, 0, 0]\n")), "");
  // Ground as body2, the spatial body as body1.
  BOOST_CHECK_EQUAL(error_of(kSpatial + "[model.force.mount]\ntype = \"bushing\"\nbody1 = \"s\"\nbody2 = \"ground\"\n"
                                        "marker2 = \"floor\"\nrotational_stiffness = 5\n"), "");
}

BOOST_AUTO_TEST_CASE(a_nonzero_rotational_rest_on_a_spatial_bushing_is_refused_naming_the_key) {
  expect_error(spatial_bushing("rotational_stiffness = 5\nrotational_rest = 0.1\n"),
               {"model.force.mount.rotational_rest", "0 (or absent)", "rotate marker2 instead"});
  expect_error(spatial_bushing("rotational_stiffness = 5\nrotational_rest = [0, \"a\", 0]\n"),
               {"model.force.mount.rotational_rest", "rotate marker2 instead"});
}

BOOST_AUTO_TEST_CASE(a_spatial_bushing_vector_of_the_wrong_length_is_refused_naming_the_key) {
  expect_error(spatial_bushing("rotational_stiffness = [1, 2]\n"),
               {"model.force.mount.rotational_stiffness", "a list of 3 expressions"});
  expect_error(spatial_bushing("rotational_damping = [1, 2, 3, 4]\n"),
               {"model.force.mount.rotational_damping", "a list of 3 expressions"});
  expect_error(spatial_bushing("rotational_stiffness = 1\nrotational_rest = [0, 0]\n"),
               {"model.force.mount.rotational_rest", "a list of 3 expressions"});
  expect_error(kSpatial + "[model.force.mount]\ntype = \"bushing\"\nmarker1 = \"floor\"\nbody2 = \"s\"\nstiffness = [1, 2]\n",
               {"model.force.mount.stiffness", "a list of 3 expressions"});
}

// A spherical tree joint places its body by four Euler parameters: three are refused naming the
// key and the count. They are no motion: a drive or a joint spring-damper on the joint, and a
// prescribed `motion` (not a key of a spherical joint), are refused naming the key.
BOOST_AUTO_TEST_CASE(a_spherical_tree_joint_needs_four_euler_parameters_which_nothing_drives) {
  const std::string ball = R"([model]
name = "m"
[model.body.s]
kind = "spatial"
mass = 1.0
inertia = [0.1, 0.1, 0.1]
[model.joint.b]
type = "spherical"
body2 = "s"
)";
  const std::string four = "coordinates = [\"p0\", \"p1\", \"p2\", \"p3\"]\n";
  expect_error(ball + "coordinates = [\"a\", \"b\", \"c\"]\n",
               {"model.joint.b.coordinates", "a list of 4 coordinate name(s) for a spherical joint"});
  BOOST_CHECK_EQUAL(error_of(ball + four), "");
  expect_error(ball + four + "[model.joint.d]\ntype = \"drive\"\njoint = \"b\"\nmotion = \"t\"\n",
               {"model.joint.d.joint", "the spherical joint 'b' are Euler parameters"});
  expect_error(ball + four + "[model.force.k]\ntype = \"joint_spring_damper\"\njoint = \"b\"\nstiffness = 1\n",
               {"model.force.k.joint", "spherical joint 'b' (spherical) are Euler parameters"});
  expect_error(ball + "motion = [\"1\", \"0\", \"0\", \"0\"]\n",
               {"model.joint.b.motion", "unknown key"});
}

// A cylindrical tree joint places its body by two coordinates (its angle, its travel): one is
// refused naming the key and the count, as is a drive naming a coordinate it does not have.
BOOST_AUTO_TEST_CASE(a_cylindrical_tree_joint_needs_its_two_coordinates) {
  const std::string sleeve = R"([model]
name = "m"
[model.body.s]
kind = "spatial"
mass = 1.0
inertia = [0.1, 0.1, 0.1]
[model.joint.c]
type = "cylindrical"
body2 = "s"
)";
  expect_error(sleeve + "coordinates = [\"psi\"]\n",
               {"model.joint.c.coordinates", "a list of 2 coordinate name(s) for a cylindrical joint"});
  std::string cross = sleeve;
  cross.replace(cross.find("\"cylindrical\""), 13, "\"universal\"");
  expect_error(cross + "coordinates = [\"al\", \"be\", \"ga\"]\n",
               {"model.joint.c.coordinates", "a list of 2 coordinate name(s) for a universal joint"});
  BOOST_CHECK_EQUAL(error_of(cross + "coordinates = [\"al\", \"be\"]\n"), "");
  BOOST_CHECK_EQUAL(error_of(sleeve + "coordinates = [\"psi\", \"z\"]\n"), "");
  expect_error(sleeve + "coordinates = [\"psi\", \"z\"]\n[model.joint.d]\ntype = \"drive\"\njoint = \"c\"\n"
                        "coordinate = \"x\"\nmotion = \"t\"\n",
               {"model.joint.d.coordinate", "one of the joint's coordinates (psi, z), got 'x'"});
  // A drive on either coordinate: its reaction is the torque about (force along) the axis, z.
  for (const std::string c : {"psi", "z"}) {
    const auto desc = load_model_text(sleeve + "coordinates = [\"psi\", \"z\"]\n[model.joint.d]\ntype = \"drive\"\n"
                                                "joint = \"c\"\ncoordinate = \"" + c + "\"\nmotion = \"t\"\n", "m.toml");
    bool found = false;
    for (const auto& o : desc->outputs()) found = found || o.name == (c == "psi" ? "M_d_z" : "F_d_z");
    BOOST_TEST(found, c);
  }
}

// The planar `rolling` joint on a circle (docs/bodies.md "Rolling on a circle"): surface =
// "circle" with circle_radius and inside, the spatial wheel's and ball's words (shared code), each
// refusal naming the key; the radii checked at the parameters' defaults.
BOOST_AUTO_TEST_CASE(rolling_on_a_circle_bad_keys_are_refused_naming_the_key) {
  const std::string circle = on_roll("surface = \"circle\"\n");
  BOOST_CHECK_EQUAL(error_of(circle + "circle_radius = 3.0\n"), "");
  BOOST_CHECK_EQUAL(error_of(circle + "circle_radius = 0.5\n"), "");  // a drum smaller than the wheel
  BOOST_CHECK_EQUAL(error_of(circle + "circle_radius = \"3*L\"\ninside = true\nunilateral = true\nrestitution = 0.2\n"
                                      "mu_static = 0.3\nmu_kinetic = 0.1\nrow_names = { contact = \"touch\", rolling = \"roll\" }\n"), "");
  BOOST_CHECK_EQUAL(error_of(on_roll("surface = \"line\"\n")), "");
  // An unknown surface; the circle's keys on the line; its radius required.
  expect_error(on_roll("surface = \"cylinder\"\n"),
               {"m.toml", "model.joint.w.surface", "\"line\" (default: marker1's x axis)", "\"circle\"", "circle_radius", "got 'cylinder'"});
  expect_error(on_roll("surface = 2\n"), {"m.toml", "model.joint.w.surface", "\"line\" or \"circle\""});
  expect_error(circle, {"m.toml", "model.joint.w.circle_radius", "the circle's radius"});
  expect_error(on_roll("circle_radius = 3.0\n"),
               {"m.toml", "model.joint.w.circle_radius", "no circle_radius on a wheel on a line (surface = \"circle\" takes it)"});
  expect_error(on_roll("inside = true\n"), {"m.toml", "model.joint.w.inside", "no inside on a wheel on a line"});
  expect_error(circle + "circle_radius = 3.0\ninside = \"yes\"\n", {"m.toml", "model.joint.w.inside"});
  // Radii > 0, and inside a circle larger than the wheel (radius L = 1).
  expect_error(circle + "circle_radius = -3.0\n", {"m.toml", "model.joint.w.circle_radius", "the circle's radius > 0, got -3"});
  expect_error(circle + "circle_radius = \"-2*L\"\n", {"model.joint.w.circle_radius", "the circle's radius > 0, got -2*L = -2"});
  expect_error(circle + "circle_radius = 1.0\ninside = true\n",
               {"m.toml", "model.joint.w.circle_radius", "a radius > the wheel's radius = 1 with inside = true", "got 1"});
  expect_error(circle + "circle_radius = \"L/2\"\ninside = true\n", {"model.joint.w.circle_radius", "got L/2 = 0.5"});
  expect_error(kBase + "[model.joint.w]\ntype = \"rolling\"\nbody2 = \"a\"\nradius = \"-L\"\n",
               {"m.toml", "model.joint.w.radius", "the wheel's radius > 0, got -L = -1"});
  expect_error(kBase + "[model.joint.w]\ntype = \"rolling\"\nbody2 = \"a\"\nradius = 0\nsurface = \"circle\"\ncircle_radius = 3\n",
               {"model.joint.w.radius", "the wheel's radius > 0, got 0"});
  // No holonomic row on a circle (the polar angle's atan2 jumps once per turn).
  expect_error(circle + "circle_radius = 3.0\nform = \"holonomic\"\n", {"m.toml", "model.joint.w.form", "\"velocity\" on a circle", "atan2"});
  // Unknown keys list the circle's; the contact keys' rules as on the line.
  expect_error(circle + "circle_radius = 3.0\nsphere_radius = 3.0\n",
               {"model.joint.w.sphere_radius", "unknown key", "surface", "circle_radius", "inside", "mu_static"});
  expect_error(circle + "circle_radius = 3.0\nunilateral = true\n", {"model.joint.w.mu_static", "in the air"});
  expect_error(circle + "circle_radius = 3.0\nmu_static = 0.3\n", {"model.joint.w.mu_static", "only with unilateral = true"});
  expect_error(circle + "circle_radius = 3.0\nunilateral = true\nmu_static = 0.3\nmu_kinetic = 0.5\n",
               {"model.joint.w.mu_kinetic", "[0, mu_static = 0.3]"});
}

// The spatial `ball` joint (a sphere on a plane, docs/bodies-spatial.md "Joints"): the wheel's
// contact keys with the wheel's rules (shared code), each refusal naming the key.
BOOST_AUTO_TEST_CASE(ball_joint_bad_keys_are_refused_naming_the_key) {
  const std::string ball = kSpatial + "[model.joint.b]\ntype = \"ball\"\nmarker1 = \"floor\"\nbody2 = \"s\"\n";
  const std::string rolling = ball + "radius = 0.3\n";
  BOOST_CHECK_EQUAL(error_of(rolling), "");
  BOOST_CHECK_EQUAL(error_of(rolling + "unilateral = true\nrestitution = 0.5\n"), "");
  BOOST_CHECK_EQUAL(error_of(rolling + "unilateral = true\nrestitution = 0.5\nmu_static = 0.3\nmu_kinetic = 0.2\n"), "");
  BOOST_CHECK_EQUAL(error_of(rolling + "no_slip = false\nunilateral = true\nrestitution = 0.5\n"), "");
  // The radius is required.
  expect_error(ball, {"m.toml", "model.joint.b.radius", "the ball's radius"});
  expect_error(ball + "unilateral = true\n", {"m.toml", "model.joint.b.radius", "the ball's radius"});
  // On a sphere (surface = "sphere"), the wheel's keys with the wheel's refusals: sphere_radius
  // required with it and refused without it, inside only on a sphere and a boolean; at the
  // parameters' defaults a sphere_radius > 0, inside larger than the ball.
  BOOST_CHECK_EQUAL(error_of(rolling + "surface = \"sphere\"\nsphere_radius = 2.0\n"), "");
  BOOST_CHECK_EQUAL(error_of(rolling + "surface = \"sphere\"\nsphere_radius = 2.0\ninside = true\n"), "");
  BOOST_CHECK_EQUAL(error_of(rolling + "surface = \"sphere\"\nsphere_radius = 2.0\nunilateral = true\nmu_static = 0.3\nmu_kinetic = 0.1\n"), "");
  BOOST_CHECK_EQUAL(error_of(rolling + "surface = \"plane\"\n"), "");
  expect_error(rolling + "surface = \"cylinder\"\n", {"m.toml", "model.joint.b.surface", "\"plane\"", "\"sphere\"", "got 'cylinder'"});
  expect_error(rolling + "surface = \"sphere\"\n", {"m.toml", "model.joint.b.sphere_radius", "the sphere's radius"});
  expect_error(rolling + "sphere_radius = 1.0\n", {"m.toml", "model.joint.b.sphere_radius", "surface = \"sphere\""});
  expect_error(rolling + "inside = true\n", {"m.toml", "model.joint.b.inside", "surface = \"sphere\""});
  expect_error(rolling + "surface = \"sphere\"\nsphere_radius = 2.0\ninside = 1\n", {"m.toml", "model.joint.b.inside"});
  expect_error(rolling + "surface = \"sphere\"\nsphere_radius = 0.3\ninside = true\n",
               {"m.toml", "model.joint.b.sphere_radius", "a radius > the ball's radius = 0.3 with inside = true", "got 0.3"});
  expect_error(rolling + "surface = \"sphere\"\nsphere_radius = 0\n", {"model.joint.b.sphere_radius", "the sphere's radius > 0, got 0"});
  expect_error(ball + "radius = -0.3\n", {"m.toml", "model.joint.b.radius", "the ball's radius > 0, got -0.3"});
  expect_error(rolling + "surface = \"sphere\"\nsphere_radius = 2.0\nno_slip = false\nunilateral = true\nmu_static = 0.3\n",
               {"model.joint.b.mu_static", "frictionless ball"});
  // Unknown keys name the ball's own.
  expect_error(rolling + "axle = 1.0\n",
               {"m.toml", "model.joint.b.axle", "unknown key", "radius", "no_slip", "surface", "sphere_radius", "inside", "unilateral", "mu_kinetic"});
  expect_error(rolling + "unilateral = true\nfriction = \"b_n\"\n", {"model.joint.b.friction", "unknown key"});
  // Friction and restitution need a gap that can open.
  expect_error(rolling + "mu_static = 0.3\n", {"m.toml", "model.joint.b.mu_static", "only with unilateral = true"});
  expect_error(rolling + "mu_static = 0.3\nmu_kinetic = 0.2\n", {"model.joint.b.mu_static", "only with unilateral = true"});
  expect_error(rolling + "restitution = 0.5\n", {"model.joint.b.restitution", "only with unilateral = true"});
  expect_error(rolling + "unilateral = true\nmu_kinetic = 0.2\n", {"model.joint.b.mu_kinetic", "only with mu_static"});
  // A frictionless ball (no_slip = false) has no rows to carry friction.
  expect_error(rolling + "no_slip = false\nunilateral = true\nmu_static = 0.3\n",
               {"m.toml", "model.joint.b.mu_static", "no_slip = false", "frictionless ball",
                "drop no_slip = false to get Coulomb friction on its rows b_x, b_y"});
  // Coefficients in range; no_slip a boolean.
  expect_error(rolling + "unilateral = true\nmu_static = 0.3\nmu_kinetic = 0.4\n",
               {"model.joint.b.mu_kinetic", "a kinetic friction coefficient in [0, mu_static = 0.3]", "0.4"});
  expect_error(rolling + "unilateral = true\nrestitution = 1.5\n", {"model.joint.b.restitution", "[0, 1]"});
  expect_error(rolling + "no_slip = 1\n", {"model.joint.b.no_slip"});
}
