// Hostile model files and added constraints from the shell (issue 19): every one ends with exit
// 2 and one message naming the file and the key, within seconds (before: SIGSEGV for exp() and a
// 50,000-character constraint name, stack overflow for 10,000 nested parentheses, 1.6 GB and a
// GMP abort for 10^(10^10)); a model whose parameters carry GiNaC's names runs (exit 0).
// PCSIM_EXE (set by pcsim_boost_tests) is the executable.
#define BOOST_TEST_MODULE sim_hostile_model_cli
#include <boost/test/unit_test.hpp>

#include "../support/cli_util.hpp"

#include <chrono>
#include <fstream>
#include <string>

namespace fs = std::filesystem;
using pcsim_test::exe;
using pcsim_test::has;
using pcsim_test::Result;
using pcsim_test::sh;

namespace {

const char* const kModel = R"TOML([model]
coordinates = ["x", "y"]
[model.parameters]
m = 1.0
L = 1.0
I = 2.0
Pi = 0.5
Euler = 1.0
Catalan = 0.0
D = 0.1
E = 9.81
[model.energy]
kinetic = "0.5*m*(x_d^2 + y_d^2)*I/2"
potential = "m*E*y*Pi*2*Euler + Catalan*x"
dissipation = "0.5*D*0*(x_d^2 + y_d^2)"
[[model.constraint]]
name = "rod"
holonomic = "x^2 + y^2 - L^2"
)TOML";

struct Dir : pcsim_test::TempDir {
  Dir() : pcsim_test::TempDir("hostile_model") {
    std::ofstream(path / "m.toml") << kModel;
    std::ofstream(path / "c.toml") << "model = \"m.toml\"\n[initial]\nx = 1.0\n[solver]\nt_end = 0.05\n";
  }
};

// Runs pcsim with the arguments (already quoted for the shell); exit 2, the message names the
// file and the key and each part, within 10 s.
void refused(const Dir& d, const std::string& args, const std::string& key,
             std::initializer_list<std::string> parts) {
  const auto t0 = std::chrono::steady_clock::now();
  const Result r = sh("'" + exe() + "' run c.toml --out out " + args, d.path);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  BOOST_TEST_CONTEXT(args.substr(0, 200) << " -> " << r.out.substr(0, 600)) {
    BOOST_TEST(r.status == 2);
    const std::string file = key.rfind("model.", 0) == 0 ? "m.toml" : "c.toml";
    BOOST_TEST(has(r.out, file + ": key '" + key));
    for (const auto& p : parts) BOOST_TEST(has(r.out, p), "missing '" << p << "'");
    BOOST_TEST(r.out.size() < 2000u);
    BOOST_TEST(s < 10.0);
    BOOST_TEST(!fs::exists(d.path / "out" / "summary.json"));
  }
}

}  // namespace

BOOST_AUTO_TEST_CASE(the_model_with_ginacs_names_runs) {
  Dir d;
  const Result r = sh("'" + exe() + "' run c.toml --out out", d.path);
  BOOST_TEST(r.status == 0, r.out);
  BOOST_TEST(fs::exists(d.path / "out" / "summary.json"));
}

BOOST_AUTO_TEST_CASE(hostile_added_constraints_end_with_exit_2) {
  Dir d;
  refused(d, "--constraint 'c=sin()'", "constraints.added.c", {"'sin' takes 1 argument", "got 0"});
  refused(d, "--constraint 'c=x - exp()'", "constraints.added.c", {"'exp' takes 1 argument"});
  refused(d, "--constraint 'c=atan2(x)'", "constraints.added.c", {"'atan2' takes 2 arguments"});
  refused(d, "--constraint 'c=x*10^(10^10)'", "constraints.added.c", {"exponent of at most 1000"});
  refused(d, "--constraint 'c=(x+2)^(10^9)'", "constraints.added.c", {"exponent of at most 1000"});
  refused(d, "--constraint 'c=x*2^(2^(2^10))'", "constraints.added.c", {"exponent of at most 1000"});
  refused(d, "--constraint 'c=x*1e-400'", "constraints.added.c", {"out of the range of double"});
  refused(d, "--constraint 'c=" + std::string(10000, '(') + "x" + std::string(10000, ')') + "'",
          "constraints.added.c", {"nested at most 200 levels"});
  refused(d, "--constraint 'c=" + std::string(10000, '-') + "x'", "constraints.added.c",
          {"nested at most 200 levels"});
  for (const std::string bad : {"=x", "x"}) {
    const Result r = sh("'" + exe() + "' run c.toml --out out --constraint '" + bad + "'", d.path);
    BOOST_TEST(r.status == 2, r.out);
    BOOST_TEST(has(r.out, "--constraint '" + bad + "': expected NAME=EXPR"), r.out);
  }
  const std::string name(50000, 'c');
  refused(d, "--constraint '" + name + "=x'", "constraints.added.ccc", {"at most 128 characters"});
  refused(d, "--set 'constraints.added." + name + "=x'", "constraints.added.ccc", {"at most 128 characters"});
}

BOOST_AUTO_TEST_CASE(hostile_model_files_end_with_exit_2) {
  Dir d;
  auto with = [&](const std::string& from, const std::string& to) {
    std::string s = kModel;
    s.replace(s.find(from), from.size(), to);
    std::ofstream(d.path / "m.toml") << s;
  };
  with("\"m*E*y*Pi*2*Euler + Catalan*x\"", "\"m*E*y + exp()\"");
  refused(d, "", "model.energy.potential", {"'exp' takes 1 argument"});
  with("\"m*E*y*Pi*2*Euler + Catalan*x\"", "\"10^(10^10)*y\"");
  refused(d, "", "model.energy.potential", {"exponent of at most 1000"});
  with("\"m*E*y*Pi*2*Euler + Catalan*x\"", "\"" + std::string(10000, '(') + "y" + std::string(10000, ')') + "\"");
  refused(d, "", "model.energy.potential", {"nested at most 200"});
  with("\"0.5*m*(x_d^2 + y_d^2)*I/2\"", "\"0.5*x_d^2 + abs(x_d) + 0.5*y_d^2\"");
  refused(d, "", "model.energy.kinetic", {"quadratic in the velocities", "abs"});
  std::string coords;
  for (int i = 0; i < 10000; ++i) coords += (i ? ", \"q" : "\"q") + std::to_string(i) + "\"";
  with("coordinates = [\"x\", \"y\"]", "coordinates = [\"x\", \"y\", " + coords + "]");
  refused(d, "", "model.coordinates", {"at most 3000 coordinates"});
}

// Issue 22: a spatial body's initial angular velocity (initial.b_w1..w3, body axes, or
// b_wx..wz, ground axes) together with the rates of its Euler parameters, or in both frames,
// ends with exit 2 naming the key, and writes nothing.
BOOST_AUTO_TEST_CASE(initial_angular_velocity_with_euler_rates_or_in_two_frames_ends_with_exit_2) {
  Dir d;
  std::ofstream(d.path / "m.toml") << "[model]\nname = \"spinner\"\n[model.body.b]\nkind = \"spatial\"\n"
                                      "mass = 2.0\ninertia = [0.1, 0.2, 0.3]\n";
  std::ofstream(d.path / "c.toml") << "model = \"m.toml\"\n[initial]\nb_e0 = 1.0\nb_w1 = 3.0\n"
                                      "[solver]\nt_end = 0.01\n";
  refused(d, "--set initial.b_e3_d=0.5", "initial.b_e3_d", {"not both", "b_e0_d..b_e3_d"});
  refused(d, "--set initial.b_wy=0.5", "initial.b_wy", {"not both", "initial.b_w1 is given too"});
  refused(d, "--set initial.b_e0=0", "initial.b_e0", {"not all 0"});
  const Result r = sh("'" + exe() + "' run c.toml --out out", d.path);
  BOOST_TEST(r.status == 0, r.out);
}

// Issue 22 (BSH): a spatial bushing from the shell. A nonzero rotational_rest and a rotational
// stiffness of the wrong length end with exit 2 naming the key; a body started at a half turn of
// the bushing's markers (1 + tr A = 0: the measure is 0/0) ends with exit 3 naming the time, not
// with numbers; a quarter turn runs (exit 0).
BOOST_AUTO_TEST_CASE(spatial_bushing_bad_keys_end_with_exit_2_and_a_half_turn_with_exit_3) {
  Dir d;
  const std::string model = "[model]\nname = \"mount\"\n[model.body.b]\nkind = \"spatial\"\n"
                            "mass = 2.0\ninertia = [0.1, 0.2, 0.3]\n[model.force.mount]\ntype = \"bushing\"\n"
                            "body2 = \"b\"\nstiffness = [100, 100, 100]\n";
  std::ofstream(d.path / "m.toml") << model << "rotational_stiffness = 5.0\nrotational_rest = 0.1\n";
  std::ofstream(d.path / "c.toml") << "model = \"m.toml\"\n[initial]\nb_e0 = 1.0\n[solver]\nt_end = 0.01\n";
  refused(d, "", "model.force.mount.rotational_rest", {"rotate marker2 instead"});
  std::ofstream(d.path / "m.toml") << model << "rotational_stiffness = [5.0, 5.0]\n";
  refused(d, "", "model.force.mount.rotational_stiffness", {"a list of 3 expressions"});
  std::ofstream(d.path / "m.toml") << model << "rotational_stiffness = [5.0, 6.0, 7.0]\nrotational_damping = 0.1\n";
  std::ofstream(d.path / "c.toml") << "model = \"m.toml\"\n[initial]\nb_e0 = 0.0\nb_e2 = 1.0\n[solver]\nt_end = 0.01\n";
  const Result half = sh("'" + exe() + "' run c.toml --out out", d.path);
  BOOST_TEST(half.status == 3, half.out);
  BOOST_TEST(has(half.out, "t = 0"), half.out);
  BOOST_TEST(has(half.out, "not finite"), half.out);
  std::ofstream(d.path / "c.toml") << "model = \"m.toml\"\n[initial]\nb_e0 = 0.7071067811865476\nb_e2 = 0.7071067811865476\n"
                                      "[solver]\nt_end = 0.01\n";
  const Result quarter = sh("'" + exe() + "' run c.toml --out out2", d.path);
  BOOST_TEST(quarter.status == 0, quarter.out);
}
