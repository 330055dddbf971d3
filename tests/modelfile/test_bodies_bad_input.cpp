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
