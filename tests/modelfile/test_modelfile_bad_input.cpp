// Bad model files are rejected before anything is computed, with one InputError (the CLI's
// exit 2) whose message names the file, the key and what is wrong; a syntax error also names
// the column. Every case of the issue and of the format reference is here, each changing one
// thing in an otherwise valid file.
#define BOOST_TEST_MODULE modelfile_bad_input
#include <boost/test/unit_test.hpp>

#include <fstream>

#include "../support/build_tree.hpp"
#include "modelfile/model_file.hpp"
#include "modelfile_test_util.hpp"

using namespace pcsim;
using namespace pcsim::modelfile;
using namespace pcsim::modelfile::testing;

namespace {

// A valid pendulum; each case replaces one line (or appends some).
const std::string kValid = R"TOML([model]
coordinates = ["x", "y"]
[model.parameters]
m = 1.0
L = { value = 1.0, unit = "m", positive = true }
[model.define]
r2 = "x^2 + y^2"
[model.energy]
kinetic = "0.5*m*(x_d^2 + y_d^2)"
potential = "m*9.81*y"
[[model.constraint]]
name = "rod"
holonomic = "r2 - L^2"
[model.outputs]
tension = "-(R_x*x + R_y*y)/L"
)TOML";

std::filesystem::path write(const std::string& text) {
  static int counter = 0;
  const auto dir = pcsim_test::binary_dir() / "modelfile_bad_input";
  std::filesystem::create_directories(dir);
  const auto file = dir / ("case" + std::to_string(++counter) + ".toml");
  std::ofstream(file) << text;
  return file;
}

std::string replaced(const std::string& from, const std::string& to) {
  std::string s = kValid;
  const auto p = s.find(from);
  BOOST_REQUIRE_MESSAGE(p != std::string::npos, "no '" << from << "' in the valid model");
  s.replace(p, from.size(), to);
  return s;
}

// Loads text as a model file; the error must name the file, "key '<key>'" and every part.
void expect_rejected(const std::string& text, const std::string& key,
                     std::initializer_list<std::string> parts) {
  const auto file = write(text);
  const std::string msg = input_error_of([&] { load_model_file(file); });
  BOOST_TEST_MESSAGE(msg);
  BOOST_TEST_CONTEXT("expected key '" << key << "', got: " << msg) {
    BOOST_TEST(!msg.empty());
    BOOST_TEST(msg.find("<not an InputError>") == std::string::npos);
    BOOST_TEST(msg.find(file.string()) == 0u);
    BOOST_TEST(msg.find("key '" + key + "'") != std::string::npos);
    for (const auto& p : parts) BOOST_TEST(msg.find(p) != std::string::npos, "missing '" << p << "'");
    BOOST_TEST(msg.find('\n') == std::string::npos);  // one line
  }
}

}  // namespace

BOOST_AUTO_TEST_CASE(the_valid_base_model_loads) {
  const auto d = load_model_file(write(kValid));
  BOOST_TEST(d->n() == 2);
}

BOOST_AUTO_TEST_CASE(syntax_errors_name_file_key_and_column) {
  // "0.5*m*x_d**2": the second '*' (column 11) cannot start an operand.
  expect_rejected(replaced("\"0.5*m*(x_d^2 + y_d^2)\"", "\"0.5*m*x_d**2\""),
                  "model.energy.kinetic", {"syntax error", "column 11", "0.5*m*x_d**2"});
  // A missing ')' is found at the end: column 17 of the 16-character text.
  expect_rejected(replaced("\"m*9.81*y\"", "\"m*9.81*sin(y + 1\""), "model.energy.potential",
                  {"syntax error", "column 17", "end of the expression"});
  // An operand missing in the middle.
  expect_rejected(replaced("\"r2 - L^2\"", "\"r2 - * L^2\""), "model.constraint[rod].holonomic",
                  {"syntax error", "column 6"});
  // Two operands in a row.
  expect_rejected(replaced("\"r2 - L^2\"", "\"r2 L^2\""), "model.constraint[rod].holonomic",
                  {"syntax error", "column 4"});
  // A character that is no operator.
  expect_rejected(replaced("\"m*9.81*y\"", "\"m*9.81 % y\""), "model.energy.potential",
                  {"syntax error", "column 8"});
  // A number that is not one.
  expect_rejected(replaced("\"m*9.81*y\"", "\"m*9.8.1*y\""), "model.energy.potential",
                  {"bad number '9.8.1'", "column 3"});
  // GiNaC cannot read a^b^c; the message says how to write it.
  expect_rejected(replaced("\"m*9.81*y\"", "\"m*9.81*y^2^3\""), "model.energy.potential",
                  {"parentheses", "column 11"});
  expect_rejected(replaced("\"m*9.81*y\"", "\"  \""), "model.energy.potential",
                  {"empty string"});
}

BOOST_AUTO_TEST_CASE(unknown_names_and_functions_are_named_with_their_column) {
  expect_rejected(replaced("\"m*9.81*y\"", "\"m*g*y\""), "model.energy.potential",
                  {"unknown name 'g'", "column 3"});
  expect_rejected(replaced("\"m*9.81*y\"", "\"m*9.81*cosh(y) + foo(y)\""), "model.energy.potential",
                  {"unknown function 'foo'", "column 18"});
  expect_rejected(replaced("\"m*9.81*y\"", "\"m*9.81*m(y)\""), "model.energy.potential",
                  {"'m' is not a function", "column 8"});
  expect_rejected(replaced("\"m*9.81*y\"", "\"m*9.81*sin\""), "model.energy.potential",
                  {"needs arguments", "column 8"});
  // GiNaC's literals are not names of the format (I would make the expression complex).
  expect_rejected(replaced("\"m*9.81*y\"", "\"m*9.81*y*I\""), "model.energy.potential",
                  {"unknown name 'I'", "column 10"});
  expect_rejected(replaced("\"m*9.81*y\"", "\"Euler*y\""), "model.energy.potential",
                  {"unknown name 'Euler'"});
  // A number beyond double.
  expect_rejected(replaced("\"m*9.81*y\"", "\"1e400*y\""), "model.energy.potential",
                  {"out of the range of double"});
  expect_rejected(replaced("\"m*9.81*y\"", "\"1e9999999999*y\""), "model.energy.potential",
                  {"out of the range of double"});
  expect_rejected(replaced("\"m*9.81*y\"", "\"0.5e-500*y\""), "model.energy.potential",
                  {"out of the range of double"});
  // Velocities of coordinates that do not exist.
  expect_rejected(replaced("\"0.5*m*(x_d^2 + y_d^2)\"", "\"0.5*m*(x_d^2 + z_d^2)\""),
                  "model.energy.kinetic", {"unknown name 'z_d'", "column 16"});
}

BOOST_AUTO_TEST_CASE(reactions_and_accelerations_only_in_outputs) {
  expect_rejected(replaced("\"m*9.81*y\"", "\"m*9.81*y + R_x\""), "model.energy.potential",
                  {"unknown name 'R_x'", "only in [model.outputs]"});
  expect_rejected(kValid + "[model.forces]\nx = \"-x_dd\"\n", "model.forces.x",
                  {"unknown name 'x_dd'", "only in [model.outputs]"});
  // An output using a reaction that does not exist.
  expect_rejected(replaced("\"-(R_x*x + R_y*y)/L\"", "\"-(R_x*x + R_z*y)/L\""),
                  "model.outputs.tension", {"unknown name 'R_z'", "coordinates are x, y", "column 11"});
}

BOOST_AUTO_TEST_CASE(a_definition_with_reactions_is_for_outputs_only) {
  // Rr uses a reaction: outputs may use it, the potential may not.
  const std::string ok = replaced("r2 = \"x^2 + y^2\"", "r2 = \"x^2 + y^2\"\nRr = \"R_x*x\"");
  BOOST_TEST(input_error_of([&] { load_model_file(write(ok)); }).empty());
  std::string bad = ok;
  bad.replace(bad.find("\"m*9.81*y\""), 10, "\"m*9.81*y + Rr\"");
  expect_rejected(bad, "model.energy.potential", {"unknown name 'Rr'", "only [model.outputs] may use it"});
}

BOOST_AUTO_TEST_CASE(kinetic_energy_must_be_quadratic_in_the_velocities) {
  expect_rejected(replaced("\"0.5*m*(x_d^2 + y_d^2)\"", "\"0.5*m*(x_d^2 + y_d^2) + x_d^3\""),
                  "model.energy.kinetic", {"quadratic in the velocities", "x_d"});
  expect_rejected(replaced("\"0.5*m*(x_d^2 + y_d^2)\"", "\"0.5*m*(x_d^2 + y_d^2)*(1 + y_d)\""),
                  "model.energy.kinetic", {"quadratic in the velocities", "depends on y_d"});
  expect_rejected(replaced("\"0.5*m*(x_d^2 + y_d^2)\"", "\"0.5*m*(x_d^2 + y_d^2) + sin(x_d)\""),
                  "model.energy.kinetic", {"quadratic in the velocities"});
  // Terms linear in the velocities are fine (a moving frame), and so is T(q, t).
  BOOST_TEST(input_error_of([&] {
               load_model_file(write(replaced("\"0.5*m*(x_d^2 + y_d^2)\"",
                                              "\"0.5*m*(x_d^2 + y_d^2) + t*x*y_d + x^2\"")));
             }).empty());
}

BOOST_AUTO_TEST_CASE(potential_and_constraints_may_not_use_velocities) {
  expect_rejected(replaced("\"m*9.81*y\"", "\"m*9.81*y*y_d\""), "model.energy.potential",
                  {"may not depend on the velocities", "y_d"});
  expect_rejected(replaced("\"r2 - L^2\"", "\"r2 - L^2 + x_d\""), "model.constraint[rod].holonomic",
                  {"may not depend on the velocities", "x_d"});
  expect_rejected(kValid + "[[model.constraint]]\nname = \"v\"\nvelocity = { x = \"y_d\" }\n",
                  "model.constraint[v].velocity.x", {"may not depend on the velocities"});
  // Through a definition, too.
  expect_rejected(replaced("r2 = \"x^2 + y^2\"", "r2 = \"x^2 + y^2 + x_d\""),
                  "model.constraint[rod].holonomic", {"may not depend on the velocities"});
}

BOOST_AUTO_TEST_CASE(a_constraint_must_involve_a_coordinate) {
  expect_rejected(replaced("\"r2 - L^2\"", "\"L - 1\""), "model.constraint[rod].holonomic",
                  {"'rod' involves no coordinate"});
  // GiNaC simplifies before the check.
  expect_rejected(replaced("\"r2 - L^2\"", "\"x - x + t\""), "model.constraint[rod].holonomic",
                  {"involves no coordinate"});
  expect_rejected(kValid + "[[model.constraint]]\nname = \"v\"\nvelocity = { x = \"0\", y = \"x - x\" }\n",
                  "model.constraint[v].velocity", {"involves no coordinate"});
}

BOOST_AUTO_TEST_CASE(names_are_unique_identifiers_and_not_reserved) {
  expect_rejected(replaced("m = 1.0", "x = 1.0"), "model.parameters.x", {"'x' is already used", "coordinate"});
  expect_rejected(replaced("m = 1.0", "m = 1.0\nx_d = 2.0"), "model.parameters.x_d",
                  {"already used", "velocity of coordinate 'x'"});
  expect_rejected(replaced("m = 1.0", "m = 1.0\nR_y = 2.0"), "model.parameters.R_y", {"already used"});
  expect_rejected(replaced("r2 = \"x^2 + y^2\"", "m = \"x^2 + y^2\""), "model.define.m",
                  {"'m' is already used", "parameter"});
  expect_rejected(replaced("name = \"rod\"", "name = \"L\""), "model.constraint[L].name",
                  {"already used"});
  expect_rejected(replaced("tension = ", "rod = "), "model.outputs.rod", {"already used", "constraint"});
  expect_rejected(replaced("coordinates = [\"x\", \"y\"]", "coordinates = [\"x\", \"x\"]"),
                  "model.coordinates", {"'x' is already used"});
  // A coordinate named like a function, and other reserved names.
  expect_rejected(replaced("coordinates = [\"x\", \"y\"]", "coordinates = [\"sin\", \"y\"]"),
                  "model.coordinates", {"'sin' is reserved"});
  expect_rejected(replaced("m = 1.0", "m = 1.0\nt = 2.0"), "model.parameters.t", {"'t' is reserved"});
  expect_rejected(replaced("m = 1.0", "m = 1.0\npi = 3.0"), "model.parameters.pi", {"reserved"});
  // GiNaC's names (I, Pi, Euler, ...) are not reserved: users name inertias I (issue 19).
  BOOST_TEST(load_model_file(write(replaced("m = 1.0", "m = 1.0\nI = 3.0")))->n() == 2);
  expect_rejected(replaced("tension = ", "residual_pos = "), "model.outputs.residual_pos", {"reserved"});
  expect_rejected(replaced("m = 1.0", "m = 1.0\n2m = 3.0"), "model.parameters.2m",
                  {"letters, digits and '_'"});
  expect_rejected(replaced("coordinates = [\"x\", \"y\"]", "coordinates = [\"x\", \"y z\"]"),
                  "model.coordinates", {"letters, digits"});
}

BOOST_AUTO_TEST_CASE(parameters_need_a_finite_value_in_their_range) {
  expect_rejected(replaced("L = { value = 1.0, unit = \"m\", positive = true }", "L = { unit = \"m\" }"),
                  "model.parameters.L.value", {"has none"});
  expect_rejected(replaced("m = 1.0", "m = \"1.0\""), "model.parameters.m", {"a number"});
  expect_rejected(replaced("m = 1.0", "m = nan"), "model.parameters.m", {"finite"});
  expect_rejected(replaced("L = { value = 1.0, unit = \"m\", positive = true }",
                           "L = { value = -1.0, unit = \"m\", positive = true }"),
                  "model.parameters.L.value", {"> 0", "got -1"});
  expect_rejected(replaced("L = { value = 1.0, unit = \"m\", positive = true }",
                           "L = { value = 1.0, units = \"m\" }"),
                  "model.parameters.L.units", {"unknown key"});
  expect_rejected(replaced("L = { value = 1.0, unit = \"m\", positive = true }",
                           "L = { value = 1.0, min = 2.0, max = 0.5 }"),
                  "model.parameters.L.min", {"min <= max"});
}

BOOST_AUTO_TEST_CASE(unknown_keys_and_wrong_structure_are_named) {
  expect_rejected(replaced("coordinates =", "coordinate = [\"q\"]\ncoordinates ="), "model.coordinate",
                  {"unknown key", "coordinates"});
  expect_rejected(replaced("kinetic =", "kinetik = \"0\"\nkinetic ="), "model.energy.kinetik",
                  {"unknown key", "kinetic, potential, dissipation"});
  expect_rejected(replaced("holonomic =", "holonomik = \"x\"\nholonomic ="), "model.constraint[rod].holonomik",
                  {"unknown key"});
  expect_rejected(replaced("[model.outputs]", "[model.output]"), "model.output", {"unknown key"});
  expect_rejected(kValid + "[extra]\na = 1\n", "extra", {"one table, [model]"});
  expect_rejected(replaced("coordinates = [\"x\", \"y\"]", "coordinates = []"), "model.coordinates",
                  {"non-empty list"});
  expect_rejected(replaced("coordinates = [\"x\", \"y\"]", ""), "model.coordinates", {"list of coordinates"});
  expect_rejected(replaced("kinetic = \"0.5*m*(x_d^2 + y_d^2)\"", ""), "model.energy.kinetic",
                  {"kinetic energy"});
  expect_rejected(replaced("kinetic = \"0.5*m*(x_d^2 + y_d^2)\"", "kinetic = [1]"), "model.energy.kinetic",
                  {"an expression"});
  expect_rejected(kValid + "[model.forces]\nz = \"1\"\n", "model.forces.z", {"a coordinate (one of: x, y)"});
}

BOOST_AUTO_TEST_CASE(constraint_tables_are_checked) {
  expect_rejected(replaced("name = \"rod\"\n", ""), "model.constraint[#1].name", {"name"});
  expect_rejected(replaced("holonomic = \"r2 - L^2\"", "holonomic = \"r2 - L^2\"\nvelocity = { x = \"1\" }"),
                  "model.constraint[rod]", {"exactly one of"});
  expect_rejected(replaced("holonomic = \"r2 - L^2\"", ""), "model.constraint[rod]", {"exactly one of"});
  expect_rejected(kValid + "[[model.constraint]]\nname = \"v\"\nvelocity = { x = \"1\" }\nfrom_initial = true\n",
                  "model.constraint[v].from_initial", {"only for holonomic"});
  expect_rejected(kValid + "[[model.constraint]]\nname = \"v\"\nvelocity = { q = \"1\" }\n",
                  "model.constraint[v].velocity.q", {"a coordinate"});
  expect_rejected(replaced("holonomic = \"r2 - L^2\"", "holonomic = \"r2 - L^2\"\nactive = \"no\""),
                  "model.constraint[rod].active", {"a boolean"});
  expect_rejected(replaced("[[model.constraint]]", "[model.constraint]"), "model.constraint",
                  {"array of tables"});
}

BOOST_AUTO_TEST_CASE(definitions_period_and_slow_are_checked) {
  expect_rejected(replaced("r2 = \"x^2 + y^2\"", "r2 = \"x^2 + y^2 + a\"\na = \"2*r2\""), "model.define.r2",
                  {"cycle", "r2 -> a -> r2"});
  expect_rejected(replaced("[model]\n", "[model]\nperiod = \"2*pi/x\"\n"), "model.period",
                  {"parameters only"});
  expect_rejected(replaced("[model]\n", "[model]\nslow = [\"s\"]\n"), "model.slow", {"got 's'"});
  expect_rejected(replaced("[model]\n", "[model]\nslow = [\"x\", \"x\"]\n"), "model.slow", {"twice"});
  expect_rejected(replaced("[model]\n", "[model]\nvelocity_terms = \"fast\"\n"), "model.velocity_terms",
                  {"\"as_written\"", "\"expanded\"", "got 'fast'"});
  expect_rejected(replaced("[model]\n", "[model]\nvelocity_terms = true\n"), "model.velocity_terms",
                  {"\"as_written\" or \"expanded\""});
}

BOOST_AUTO_TEST_CASE(unreadable_files_are_named) {
  const std::string missing = input_error_of([] { load_model_file("no/such/model.toml"); });
  BOOST_TEST(contains_all(missing, {"no/such/model.toml", "cannot read"}));
  const auto file = write("[model\ncoordinates = 1\n");
  const std::string bad = input_error_of([&] { load_model_file(file); });
  BOOST_TEST_MESSAGE(bad);
  BOOST_TEST(contains_all(bad, {file.string() + ":1", "not a valid TOML file"}));
}

BOOST_AUTO_TEST_CASE(instantiate_rejects_unknown_and_out_of_range_parameters) {
  const auto d = load_model_file(write(kValid));
  const std::string unknown = input_error_of([&] { d->instantiate({{"mass", 2.0}}); });
  BOOST_TEST(contains_all(unknown, {"key 'parameters.mass'", "not a parameter", "m, L"}));
  const std::string range = input_error_of([&] { d->instantiate({{"L", 0.0}}); });
  BOOST_TEST(contains_all(range, {"key 'parameters.L'", "> 0", "got 0"}));
  const std::string nan = input_error_of([&] { d->instantiate({{"m", NAN}}); });
  BOOST_TEST(contains_all(nan, {"key 'parameters.m'", "finite"}));
  BOOST_TEST(input_error_of([&] { d->period({{"L", -1.0}}); }).find("parameters.L") != std::string::npos);
  // A from_initial constraint needs the initial coordinates.
  const auto f = load_model_file(write(replaced("holonomic = \"r2 - L^2\"", "holonomic = \"x\"\nfrom_initial = true")));
  const std::string q0 = input_error_of([&] { f->instantiate({}); });
  BOOST_TEST(contains_all(q0, {"'rod'", "from_initial", "2 initial coordinates"}));
  BOOST_TEST(input_error_of([&] { f->instantiate({}, Eigen::Vector2d(0.3, 0.1)); }).empty());
}

BOOST_AUTO_TEST_CASE(added_constraints_are_checked_like_the_files) {
  const auto d = load_model_file(write(kValid));
  auto error = [&](const ExtraConstraint& e) {
    return input_error_of([&] { d->with_constraints({e}); });
  };
  auto extra = [](const std::string& name, const std::string& phi) {
    ExtraConstraint e;
    e.name = name;
    e.holonomic = phi;
    return e;
  };
  BOOST_TEST(contains_all(error(extra("hold", "x - * 1")),
                          {"command line: key 'constraint.hold'", "syntax error", "column 5"}));
  BOOST_TEST(contains_all(error(extra("rod", "x")), {"key 'constraint.rod'", "already used"}));
  BOOST_TEST(contains_all(error(extra("hold", "L - 1")), {"involves no coordinate"}));
  BOOST_TEST(contains_all(error(extra("hold", "q")), {"unknown name 'q'"}));
  BOOST_TEST(contains_all(error(extra("sin", "x")), {"reserved"}));
  BOOST_TEST(contains_all(error(extra("hold", "")), {"empty"}));
  ExtraConstraint e = extra("hold", "x - ");
  e.origin = "case.toml";
  e.key = "constraints.hold";
  BOOST_TEST(contains_all(error(e), {"case.toml: key 'constraints.hold'"}));
}

// Contact attributes (issue 12): where they may appear, what they must name, their ranges.
BOOST_AUTO_TEST_CASE(contact_attributes_are_checked) {
  const std::string floor = "[[model.constraint]]\nname = \"floor\"\nholonomic = \"y\"\nunilateral = true\n";
  const std::string base = kValid + floor;
  expect_rejected(base + "gap_sign = 2\n", "model.constraint[floor].gap_sign", {"1", "-1", "got 2"});
  expect_rejected(replaced("holonomic = \"r2 - L^2\"", "holonomic = \"r2 - L^2\"\ngap_sign = -1"),
                  "model.constraint[rod].gap_sign", {"unilateral = true"});
  expect_rejected(replaced("holonomic = \"r2 - L^2\"", "holonomic = \"r2 - L^2\"\nrestitution = 0.5"),
                  "model.constraint[rod].restitution", {"unilateral = true"});
  expect_rejected(kValid + "[[model.constraint]]\nname = \"v\"\nvelocity = { x = \"1\" }\nunilateral = true\n",
                  "model.constraint[v].unilateral", {"holonomic"});
  expect_rejected(base + "[[model.constraint]]\nname = \"slide\"\nvelocity = { x = \"1\" }\nfriction = \"rod\"\nmu_static = 0.3\n",
                  "model.constraint[slide].friction", {"unilateral constraint", "declared: floor", "got 'rod'"});
  expect_rejected(base + "[[model.constraint]]\nname = \"slide\"\nvelocity = { x = \"1\" }\nfriction = \"floor\"\n",
                  "model.constraint[slide].mu_static", {"Coulomb"});
  expect_rejected(base + "[[model.constraint]]\nname = \"slide\"\nvelocity = { x = \"1\" }\nmu_static = 0.3\n",
                  "model.constraint[slide].mu_static", {"friction = \"NAME\""});
  expect_rejected(base + "[[model.constraint]]\nname = \"slide\"\nholonomic = \"x\"\nunilateral = true\nfriction = \"floor\"\nmu_static = 0.3\n",
                  "model.constraint[slide].friction", {"either unilateral", "not both"});
  expect_rejected(base + "restitution = \"x\"\n", "model.constraint[floor].restitution", {"parameters only"});
  // Ranges depend on the parameter values: instantiate() checks them.
  const auto d = load_model_file(write(base + "restitution = \"m\"\n[[model.constraint]]\nname = \"slide\"\n"
                                       "velocity = { x = \"1\" }\nfriction = \"floor\"\nmu_static = \"L\"\nmu_kinetic = 0.5\n"));
  BOOST_TEST(input_error_of([&] { d->instantiate({{"m", 0.5}}); }).empty());
  BOOST_TEST(contains_all(input_error_of([&] { d->instantiate({{"m", 1.5}}); }),
                          {"key 'model.constraint[floor].restitution'", "[0, 1]", "got 1.5", "\"m\""}));
  BOOST_TEST(contains_all(input_error_of([&] { d->instantiate({{"m", 0.5}, {"L", 0.25}}); }),
                          {"key 'model.constraint[slide].mu_kinetic'", "mu_static = 0.25", "got 0.5"}));
  // What instantiate() gives the engine.
  const auto model = d->instantiate({{"m", 0.5}, {"L", 0.75}});
  const auto& c = model->constraints();
  BOOST_TEST(c[1].contact.unilateral);
  BOOST_TEST(c[1].contact.restitution == 0.5);
  BOOST_TEST(c[2].contact.friction_of == 1);
  BOOST_TEST(c[2].contact.mu_static == 0.75);
  BOOST_TEST(c[2].contact.mu_kinetic == 0.5);
  BOOST_TEST(!c[0].contact.unilateral);
  BOOST_TEST(!c[0].contact.is_friction());
  // Rough rows (issue 22): `rough = true` with friction, in velocity form, without coefficients.
  const std::string rough = base + "[[model.constraint]]\nname = \"grip\"\nvelocity = { x = \"1\" }\nfriction = \"floor\"\n"
                                   "rough = true\n";
  expect_rejected(rough + "mu_static = 0.3\n", "model.constraint[grip].mu_static", {"rough = true, not both", "never slips"});
  expect_rejected(base + "[[model.constraint]]\nname = \"grip\"\nholonomic = \"x\"\nfriction = \"floor\"\nrough = true\n",
                  "model.constraint[grip].rough", {"velocity form"});
  expect_rejected(base + "[[model.constraint]]\nname = \"grip\"\nvelocity = { x = \"1\" }\nrough = true\n",
                  "model.constraint[grip].rough", {"only with friction = \"NAME\""});
  expect_rejected(base + "[[model.constraint]]\nname = \"grip\"\nvelocity = { x = \"1\" }\nfriction = \"floor\"\nrough = 1\n",
                  "model.constraint[grip].rough", {});
  const auto rm = load_model_file(write(rough))->instantiate({});
  BOOST_TEST(rm->constraints()[2].contact.rough);
  BOOST_TEST(rm->constraints()[2].contact.friction_of == 1);
  BOOST_TEST(!rm->constraints()[2].contact.is_coulomb());
}
