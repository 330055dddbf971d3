// Cases of any model through the generic layer: the registered models run from a case exactly
// as through the C++ API, constraints are chosen per case, keys are the model's, the summary
// has the generic contract, and the output directory is written whole and locked.
#define BOOST_TEST_MODULE sim_case_any_model
#include <boost/test/unit_test.hpp>

#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include "common/error.hpp"
#include "common/files.hpp"
#include "mech/models/registry.hpp"
#include "mech/simulation.hpp"
#include "sim/case.hpp"
#include "sim/run.hpp"

using namespace pcsim;
using namespace pcsim::sim;
namespace fs = std::filesystem;

namespace {

/// The options of a run that writes its output into `dir`.
RunOptions writing_to(const fs::path& dir) {
  RunOptions o;
  o.out_dir = dir;
  return o;
}

struct TempDir {
  fs::path path;
  TempDir() {
    static int n = 0;
    path = fs::temp_directory_path() / ("pcsim_sim_case_" + std::to_string(::getpid()) + "_" +
                                        std::to_string(n++));
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  fs::path write(const std::string& name, const std::string& text) const {
    std::ofstream(path / name) << text;
    return path / name;
  }
};

std::string error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

bool has(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

const char* kPendulum = R"(model = "pendulum"
[parameters]
L = 2.0
m = 1.5
[initial]
x = 1.0
y = -1.7320508075688772
x_d = 0.3
y_d = 0.17320508075688773
[solver]
t_end = 2.0
rtol = 1e-8
atol = 1e-10
)";

}  // namespace

// The built-in pendulum from a case file (its embedded model file, models/pendulum.toml) and
// the C++ model of the registry through mech::create_model + mech::simulate with the same
// options end in the same state to 1e-10: two independent derivations of the same system (the
// model file's symbolic one and the C++ struct's AD), integrated alike (M, h, Q agree to
// rounding, test_modelfile_builtin_models; the 2 s run at rtol 1e-8 amplifies that to ~1e-14).
BOOST_AUTO_TEST_CASE(registered_model_from_a_case_equals_the_cpp_api) {
  TempDir d;
  const Case c = load_case(d.write("pend.toml", kPendulum));
  const auto summary = to_json(run_case(c));
  const auto model = mech::create_model("pendulum", {{"L", 2.0}, {"m", 1.5}});
  mech::SimulationOptions o;
  o.method = OdeMethod::automatic;  // the case's default
  o.t_end = 2.0;
  o.rtol = 1e-8;
  o.atol = 1e-10;
  o.active_constraints = {"length"};
  const auto r = mech::simulate(*model, Eigen::Vector2d(1.0, -1.7320508075688772),
                                Eigen::Vector2d(0.3, 0.17320508075688773), o);
  BOOST_REQUIRE(r.status == mech::SimulationStatus::success);
  BOOST_TEST(std::abs(summary["q_end"]["x"].get<double>() - r.q_end[0]) < 1e-10);
  BOOST_TEST(std::abs(summary["q_end"]["y"].get<double>() - r.q_end[1]) < 1e-10);
  BOOST_TEST(std::abs(summary["qd_end"]["x_d"].get<double>() - r.qd_end[0]) < 1e-10);
  BOOST_TEST(summary["stats"]["steps"].get<long>() == r.stats.steps);
}

// The generic summary contract (model-files.md): window (the whole run when the model has no
// excitation period), extremes of every coordinate, velocity, reaction and output, q_end,
// qd_end, residuals. The pendulum's tension output is an independent check of the reactions:
// its extremes equal those of |R| (R = tension along the rod).
BOOST_AUTO_TEST_CASE(summary_of_any_model_has_the_generic_keys) {
  TempDir d;
  const Case c = load_case(d.write("pend.toml", kPendulum));
  const auto s = to_json(run_case(c, writing_to(d.path / "out")));
  BOOST_TEST(s["model"] == "pendulum");
  BOOST_TEST(s["window"][0].get<double>() == 0.0);
  BOOST_TEST(s["window"][1].get<double>() == 2.0);
  for (const char* col : {"x", "y", "x_d", "y_d", "R_x", "R_y", "tension"}) {
    BOOST_TEST_CONTEXT(col) {
      BOOST_TEST_REQUIRE(s["extremes"].contains(col));
      const auto& e = s["extremes"][col];
      BOOST_TEST(e["max"].get<double>() >= e["min"].get<double>());
      BOOST_TEST(e["amplitude"].get<double>() ==
                 0.5 * (e["max"].get<double>() - e["min"].get<double>()));
    }
  }
  BOOST_TEST(s["constraint_residual_max"].get<double>() < 1e-12);
  for (const char* k : {"case", "model", "kernel", "form", "t_end", "window", "stats", "q_end",
                        "qd_end", "extremes", "constraint_residual_max"})
    BOOST_TEST(s.contains(k), k);
  // The time series has the contracted columns.
  std::ifstream csv(d.path / "out" / "timeseries.csv");
  std::string header;
  std::getline(csv, header);
  BOOST_TEST(header == "t,x,y,x_d,y_d,R_x,R_y,tension,residual_pos,residual_vel");
  // A summary window of the last 0.5 s instead.
  const Case w = load_case(d.path / "pend.toml", {{"output.summary_time", "0.5"}});
  const auto sw = to_json(run_case(w));
  BOOST_TEST(sw["window"][0].get<double>() == 1.5);
}

// output.dt far below t_end / 1e7 (found by libFuzzer: 2e-33 s): a run that writes no time
// series (a sweep point, a summary) has no rows to count and runs; the row count, 1e30 here, was
// converted to an integer all the same, which is undefined behaviour (UBSan in Debug). A run that
// writes the series is refused, naming the key.
BOOST_AUTO_TEST_CASE(tiny_output_dt_runs_without_a_series_and_is_refused_with_one) {
  TempDir d;
  const Case c = load_case(d.write("pend.toml", kPendulum),
                           {{"output.dt", "2e-33"}, {"solver.t_end", "0.002"}});
  const auto s = to_json(run_case(c));
  BOOST_TEST(s["complete"].get<bool>());
  BOOST_CHECK_EXCEPTION(run_case(c, writing_to(d.path / "out")), InputError, [](const InputError& e) {
    return std::string(e.what()).find("output.dt") != std::string::npos;
  });
  BOOST_TEST(!fs::exists(d.path / "out"));
}

// Constraints are chosen per case: a model's keys are its constraints' names, a dependent set is
// refused naming the constraint, and unknown keys name the model's keys.
BOOST_AUTO_TEST_CASE(constraints_and_keys_follow_the_model) {
  TempDir d;
  const fs::path f = d.write("sc.toml", "model = \"slider_crank\"\n[solver]\nt_end = 0.05\n");
  const Case c = load_case(f);
  const Setup& s = c.setup;
  BOOST_TEST((s.active == std::vector<std::string>{"A_x", "A_y", "B_x", "B_y"}));
  // Issue 21: a redundant but consistent constraint runs (no error).
  std::string msg = error_of([&] { run_case(load_case(f, {{"constraints.B_y_copy", "true"}})); });
  BOOST_TEST(msg.empty(), msg);
  msg = error_of([&] { load_case(f, {{"parameters.omega", "3"}}); });
  BOOST_TEST(has(msg, "'parameters.omega'"), msg);
  BOOST_TEST(has(msg, "slider_crank"), msg);
  msg = error_of([&] { load_case(d.write("bad.toml", "model = \"pendulum\"\n[initial]\ns = 1\n")); });
  BOOST_TEST(has(msg, "'initial.s'"), msg);
  BOOST_TEST(has(msg, "x x_d y y_d"), msg);
  msg = error_of([&] { load_case(f, {{"parameters.l1", "-1"}}); });  // the model's own range check
  BOOST_TEST(has(msg, "'parameters.l1'"), msg);
}

// The output directory is written whole: stale files of an earlier run disappear, a second
// writer is refused while the first holds the lock, and a directory pcsim did not make is never
// replaced.
BOOST_AUTO_TEST_CASE(output_directory_is_replaced_whole_and_locked) {
  TempDir d;
  const Case c = load_case(d.write("pend.toml", kPendulum), {{"solver.t_end", "0.1"}});
  const fs::path out = d.path / "out";
  run_case(c, writing_to(out));
  std::ofstream(out / "stale.png") << "old plot";
  run_case(c, writing_to(out));
  BOOST_TEST(!fs::exists(out / "stale.png"));
  BOOST_TEST(fs::exists(out / "summary.json"));
  {
    OutputDirectory holder(out, "run");  // another pcsim writing there
    const std::string msg = error_of([&] { run_case(c, writing_to(out)); });
    BOOST_TEST(has(msg, "in use by another pcsim run"), msg);
  }
  const fs::path mine = d.path / "mine";
  fs::create_directories(mine);
  std::ofstream(mine / "thesis.tex") << "precious";
  const std::string msg = error_of([&] { run_case(c, writing_to(mine)); });
  BOOST_TEST(has(msg, "not a pcsim output directory"), msg);
  BOOST_TEST(fs::exists(mine / "thesis.tex"));
}

// A case without `model` is a case of the default model an application registered (the sieve's
// in the pcsim executable); the case layer alone has none, and says so, naming the file and
// the key.
BOOST_AUTO_TEST_CASE(a_case_without_model_needs_a_registered_default_model) {
  try {
    pcsim::sim::load_case_text("[solver]\nt_end = 0.1\n", "no_model.toml");
    BOOST_FAIL("a case without model loaded without a default model");
  } catch (const pcsim::InputError& e) {
    const std::string what = e.what();
    BOOST_TEST(what.find("no_model.toml") != std::string::npos, what);
    BOOST_TEST(what.find("key 'model'") != std::string::npos, what);
  }
}
