// [model.draw] (issue 26): a drawing table is checked with the rest of the model file (file, key,
// what was expected), and its evaluator computes what the expressions say.
#define BOOST_TEST_MODULE modelfile_draw
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

#include "common/error.hpp"
#include "modelfile/draw.hpp"
#include "modelfile/model_file.hpp"

namespace fs = std::filesystem;
using pcsim::modelfile::DrawEvaluator;
using pcsim::modelfile::DrawShape;

namespace {

const std::string kBase = R"TOML(
[model]
name = "swing"
coordinates = ["x", "y"]
[model.parameters]
m = 1.0
L = 2.0
[model.define]
len = "sqrt(x^2 + y^2)"
[model.energy]
kinetic = "0.5*m*(x_d^2 + y_d^2)"
potential = "9.81*m*y"
[[model.constraint]]
name = "rod"
holonomic = "x^2 + y^2 - L^2"
[[model.constraint]]
name = "floor"
holonomic = "y + 3"
unilateral = true
[model.outputs]
tension = "-(R_x*x + R_y*y)/len"
)TOML";

const std::string kDraw = R"TOML(
[model.draw]
magnify = 5
[[model.draw.point]]
name = "pivot"
x = 0
y = 0
[[model.draw.point]]
name = "bob"
x = "x"
y = "y"
[[model.draw.point]]
name = "mark"
x = "x + 0.1*cos(3*t)"
y = "y + 0.1*sin(3*t)"
follows = "bob"
[[model.draw.line]]
points = ["pivot", "bob", { x = "x/len*L*1.5", y = "y/len*L*1.5" }]
[[model.draw.circle]]
centre = "bob"
radius = "0.1*L + abs(x_d)"
mode = "floor"
[[model.draw.polygon]]
points = [{ x = -1, y = -3 }, { x = 1, y = -3 }, { x = 0, y = "-3.5 + min(x, 0)^2" }]
fill = "#aabbcc"
[[model.draw.arrow]]
at = "bob"
force = "tension"
direction = { x = "-x", y = "-y" }
unit = 10.0
length = 0.5
)TOML";

// The message of the InputError that loading `text` throws ("" if none).
std::string error_of(const std::string& text) {
  try {
    pcsim::modelfile::load_model_text(text, "swing.toml");
  } catch (const pcsim::InputError& e) {
    return e.what();
  }
  return "";
}

bool has(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

struct TempModel {
  fs::path file;
  explicit TempModel(const std::string& text) {
    file = fs::temp_directory_path() / ("pcsim_draw_" + std::to_string(::getpid()) + ".toml");
    std::ofstream(file) << text;
  }
  ~TempModel() {
    std::error_code ec;
    fs::remove(file, ec);
  }
};

}  // namespace

BOOST_AUTO_TEST_CASE(a_model_with_a_drawing_loads_and_one_without_has_an_empty_drawing) {
  BOOST_TEST(error_of(kBase + kDraw) == "");
  TempModel without(kBase);
  BOOST_TEST(DrawEvaluator(without.file).spec().empty());
}

BOOST_AUTO_TEST_CASE(bad_drawing_tables_name_the_file_the_key_and_what_was_expected) {
  struct Bad {
    std::string text, key, expected;
  };
  const std::vector<Bad> bad = {
      {"[model.draw]\nfoo = 1\n[[model.draw.line]]\npoints=[{x=0,y=0},{x=1,y=1}]\n", "model.draw.foo", "unknown key"},
      {"[model.draw]\n", "model.draw", "at least one line"},
      {"[[model.draw.point]]\nx = 0\ny = 0\n", "model.draw.point[1].name", "the point's name"},
      {"[[model.draw.point]]\nname = \"1a\"\nx = 0\ny = 0\n", "model.draw.point[1].name", "letters, digits"},
      {"[[model.draw.point]]\nname = \"p\"\nx = \"q + 1\"\ny = 0\n[[model.draw.line]]\npoints=[\"p\",\"p\"]\n",
       "model.draw.point[p].x", "it uses 'q'"},
      {"[[model.draw.point]]\nname = \"p\"\nx = \"R_x\"\ny = 0\n[[model.draw.line]]\npoints=[\"p\",\"p\"]\n",
       "model.draw.point[p].x", "arrow"},
      {"[[model.draw.point]]\nname = \"p\"\ny = 0\n", "model.draw.point[p].x", "the point's x"},
      {"[[model.draw.line]]\npoints = [\"nowhere\", {x=0,y=0}]\n", "model.draw.line[1].points[1]", "the name of a [[model.draw.point]]"},
      {"[[model.draw.line]]\npoints = [{x=0,y=0}]\n", "model.draw.line[1].points", "at least 2 points"},
      {"[[model.draw.polygon]]\npoints = [{x=0,y=0},{x=1,y=0}]\n", "model.draw.polygon[1].points", "at least 3 points"},
      {"[[model.draw.circle]]\ncentre = {x=0,y=0}\n", "model.draw.circle[1].radius", "the radius"},
      {"[[model.draw.circle]]\ncentre = {x=0,y=0}\nradius = 1\ncolor = \"red\"\n", "model.draw.circle[1].color", "#rrggbb"},
      {"[[model.draw.circle]]\ncentre = {x=0,y=0}\nradius = 1\nmode = \"rod\"\n", "model.draw.circle[1].mode", "unilateral constraint"},
      {"[[model.draw.arrow]]\nat = {x=0,y=0}\nforce = \"x\"\ndirection={x=1,y=0}\nunit=1\nlength=1\n",
       "model.draw.arrow[1].force", "R_<coordinate> or an output"},
      {"[[model.draw.arrow]]\nat = {x=0,y=0}\nforce = \"R_x\"\ndirection={x=1,y=0}\nunit=0\nlength=1\n",
       "model.draw.arrow[1].unit", "a number > 0"},
      {"[[model.draw.arrow]]\nat = {x=0,y=0}\nforce = \"R_x\"\ndirection={x=1,y=0}\nlength=1\n",
       "model.draw.arrow[1].unit", "scale"},
      {"[[model.draw.line]]\npoints = [{x=0,y=0,z=1},{x=1,y=1}]\n", "model.draw.line[1].points[1].z", "view = \"3d\""},
      {"[model.draw]\nview = \"4d\"\n", "model.draw.view", "\"2d\""},
      {"[model.draw]\nmagnify = 0.5\n", "model.draw.magnify", "[1, 1e9]"},
      {"[[model.draw.point]]\nname = \"p\"\nx = 0\ny = 0\nfollows = \"q\"\n", "model.draw.point[1].follows", "declared above"},
  };
  for (const Bad& b : bad) {
    const std::string msg = error_of(kBase + b.text);
    BOOST_TEST_CONTEXT(b.text) {
      BOOST_TEST(has(msg, "swing.toml: key '" + b.key + "'"), msg);
      BOOST_TEST(has(msg, b.expected), msg);
    }
  }
}

BOOST_AUTO_TEST_CASE(the_evaluator_computes_the_drawing_as_written) {
  TempModel m(kBase + kDraw);
  const DrawEvaluator ev(m.file);
  const auto& spec = ev.spec();
  BOOST_TEST(spec.magnify == 5.0);
  BOOST_TEST(spec.points.size() == 7u);  // 3 named, 1 in the line, 3 in the polygon
  BOOST_TEST(spec.points[2].follows == 1);
  const std::vector<std::string> names = {"t", "x", "y", "x_d", "y_d", "m", "L"};
  BOOST_TEST(ev.input_names() == names, boost::test_tools::per_element());
  // inputs: t, x, y, x_d, y_d, m, L
  const double t = 0.7, x = 1.2, y = -1.6, xd = -0.4, L = 2.0;
  std::vector<double> in = {t, x, y, xd, 0.3, 1.0, L};
  std::vector<double> out(ev.size());
  ev.evaluate(in, out.data());
  // 7 points x 3, then the circle's radius, then the arrow's direction (3).
  BOOST_TEST_REQUIRE(out.size() == 7u * 3 + 1 + 3);
  const double tol = 1e-14;
  BOOST_TEST(std::abs(out[3] - x) < tol);
  BOOST_TEST(std::abs(out[4] - y) < tol);
  BOOST_TEST(std::abs(out[6] - (x + 0.1 * std::cos(3 * t))) < tol);
  BOOST_TEST(std::abs(out[7] - (y + 0.1 * std::sin(3 * t))) < tol);
  const double len = std::sqrt(x * x + y * y);  // a definition, inlined
  BOOST_TEST(std::abs(out[9] - x / len * L * 1.5) < tol);
  BOOST_TEST(std::abs(out[10] - y / len * L * 1.5) < tol);
  BOOST_TEST(std::abs(out[19] - (-3.5 + std::pow(std::min(x, 0.0), 2))) < tol);
  BOOST_TEST(std::abs(out[21] - (0.1 * L + std::abs(xd))) < tol);
  BOOST_TEST(std::abs(out[22] + x) < tol);
  BOOST_TEST(std::abs(out[23] + y) < tol);
  BOOST_TEST(out[24] == 0.0);
  // the parameters: their defaults come with the evaluator
  BOOST_TEST(ev.parameter_defaults().size() == 2u);
  BOOST_TEST(ev.parameter_defaults()[1].second == 2.0);
}

BOOST_AUTO_TEST_CASE(every_model_in_models_has_a_drawing) {
  std::vector<fs::path> files;
  for (const auto& dir : {fs::path(PCSIM_SOURCE_DIR) / "models", fs::path(PCSIM_SOURCE_DIR) / "models" / "contact"})
    for (const auto& e : fs::directory_iterator(dir))
      if (e.path().extension() == ".toml") files.push_back(e.path());
  BOOST_TEST(files.size() >= 14u);
  for (const auto& f : files) {
    BOOST_TEST_CONTEXT(f) {
      const DrawEvaluator ev(f);
      BOOST_TEST(!ev.spec().empty());
      BOOST_TEST(!ev.spec().shapes.empty());
    }
  }
}
