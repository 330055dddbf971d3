// Cases of any model through the generic layer: the registered models run from a case exactly
// as through the C++ API, constraints are chosen per case, keys are the model's, the summary
// has the generic contract, and the output directory is written whole and locked.
#define BOOST_TEST_MODULE sim_case_any_model
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "common/error.hpp"
#include "common/files.hpp"
#include "mech/models/registry.hpp"
#include "mech/simulation.hpp"
#include "sim/case.hpp"
#include "sim/run.hpp"

#include "../modelfile/chain_model.hpp"

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

// Issue 22: the initial angular velocity of a spatial body, given by the case in body axes
// (initial.b_w1..w3) or in ground axes (initial.b_wx..wz), becomes the rates of its Euler
// parameters ė = ½ Gᵀ ω' (docs/bodies-spatial.md), here written out by hand for the turn by
// χ = 1.1 rad about u = (1, 2, 2)/3, e = (cos χ/2, u sin χ/2); the ground-axis key with ω = A ω'
// (A by Rodrigues' formula, not from e) gives the same rates; the run starts with b_w1..3 = ω'.
BOOST_AUTO_TEST_CASE(initial_angular_velocity_key_gives_the_hand_computed_euler_parameter_rates) {
  const double chi = 1.1, c = std::cos(chi / 2), s = std::sin(chi / 2);
  const double u[3] = {1.0 / 3, 2.0 / 3, 2.0 / 3};
  const double e0 = c, e1 = u[0] * s, e2 = u[1] * s, e3 = u[2] * s;
  const double w[3] = {0.7, -1.3, 2.1};  // body axes
  // ė = ½ Gᵀ ω', G = [−e1 e0 e3 −e2; −e2 −e3 e0 e1; −e3 e2 −e1 e0]
  const double ed[4] = {0.5 * (-e1 * w[0] - e2 * w[1] - e3 * w[2]), 0.5 * (e0 * w[0] - e3 * w[1] + e2 * w[2]),
                        0.5 * (e3 * w[0] + e0 * w[1] - e1 * w[2]), 0.5 * (-e2 * w[0] + e1 * w[1] + e0 * w[2])};
  // ω = A ω', A = cos χ I + sin χ [u]× + (1 − cos χ) u uᵀ
  double wg[3];
  for (int i = 0; i < 3; ++i) {
    const double cross[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
    const double udw = u[0] * w[0] + u[1] * w[1] + u[2] * w[2];
    wg[i] = std::cos(chi) * w[i] + std::sin(chi) * cross[i] + (1 - std::cos(chi)) * u[i] * udw;
  }
  auto text = [&](const std::string& keys) {
    std::ostringstream os;
    os.precision(17);
    os << "[model]\nname = \"spinner\"\n[model.body.b]\nkind = \"spatial\"\nmass = 2.0\n"
          "inertia = [0.1, 0.2, 0.3]\n[model.outputs]\nw1 = \"b_w1\"\nw2 = \"b_w2\"\nw3 = \"b_w3\"\n"
          "[initial]\nb_x = 1000.0\nb_e0 = " << e0 << "\nb_e1 = " << e1 << "\nb_e2 = " << e2 << "\nb_e3 = " << e3
       << "\n" << keys << "[solver]\nt_end = 0.01\n";
    return os.str();
  };
  std::ostringstream body, ground;
  body.precision(17);
  ground.precision(17);
  body << "b_w1 = " << w[0] << "\nb_w2 = " << w[1] << "\nb_w3 = " << w[2] << "\n";
  ground << "b_wx = " << wg[0] << "\nb_wy = " << wg[1] << "\nb_wz = " << wg[2] << "\n";
  for (const std::string& keys : {body.str(), ground.str()}) {
    const Case k = load_case_text(text(keys), "spinner.toml");
    const int i0 = k.model->coordinate_index("b_e0");
    BOOST_REQUIRE(i0 >= 0);
    for (int j = 0; j < 4; ++j) BOOST_TEST(std::abs(k.setup.qd0[i0 + j] - ed[j]) < 1e-15, "e" << j << "_d");
    TempDir dir;
    run_case(k, writing_to(dir.path / "out"));
    std::ifstream csv(dir.path / "out" / "timeseries.csv");
    std::string header, first;
    std::getline(csv, header);
    std::getline(csv, first);
    // the first row's outputs w1..w3
    std::vector<double> v;
    std::vector<std::string> names;
    std::stringstream ss(first), hs(header);
    for (std::string cell; std::getline(ss, cell, ',');) v.push_back(std::stod(cell));
    for (std::string cell; std::getline(hs, cell, ',');) names.push_back(cell);
    const std::size_t iw = static_cast<std::size_t>(std::find(names.begin(), names.end(), "w1") - names.begin());
    BOOST_REQUIRE(iw + 2 < v.size());
    for (std::size_t j = 0; j < 3; ++j) BOOST_TEST(std::abs(v[iw + j] - w[j]) < 1e-14, "w" << j + 1);
  }
}

// The same key with explicit Euler-parameter rates, in both frames at once, or without an
// orientation is refused naming the key (the CLI's exit 2: test_hostile_model_cli).
BOOST_AUTO_TEST_CASE(initial_angular_velocity_conflicts_are_refused_naming_the_key) {
  const std::string model = "[model]\nname = \"spinner\"\n[model.body.b]\nkind = \"spatial\"\nmass = 2.0\n"
                            "inertia = [0.1, 0.2, 0.3]\n";
  auto err = [&](const std::string& initial) {
    return error_of([&] { load_case_text(model + "[initial]\n" + initial, "bad.toml"); });
  };
  const std::string a = err("b_e0 = 1.0\nb_w1 = 1.0\nb_e2_d = 0.5\n");
  BOOST_TEST(has(a, "bad.toml: key 'initial.b_e2_d'"), a);
  BOOST_TEST(has(a, "not both"), a);
  const std::string b = err("b_e0 = 1.0\nb_w1 = 1.0\nb_wz = 0.5\n");
  BOOST_TEST(has(b, "bad.toml: key 'initial.b_wz'"), b);
  BOOST_TEST(has(b, "initial.b_w1 is given too"), b);
  const std::string c = err("b_w3 = 1.0\n");
  BOOST_TEST(has(c, "bad.toml: key 'initial.b_e0'"), c);
  BOOST_TEST(has(c, "not all 0"), c);
  BOOST_TEST(error_of([&] { load_case_text(model + "[initial]\nb_e0 = 1.0\nb_wy = 2.0\n", "good.toml"); }).empty());
}

// Euler parameters all 0 are no orientation (the mass matrix is singular there): refused naming
// the first one's key, for a body's own (without an angular velocity too) and for a spherical
// tree joint's; a rotation vector gives a free body's. A spherical tree joint's parameters take
// no rotation-vector or angular-velocity keys (they are not the body's orientation in ground).
BOOST_AUTO_TEST_CASE(euler_parameters_all_zero_are_refused_naming_the_key) {
  const std::string model = "[model]\nname = \"spinner\"\n[model.body.b]\nkind = \"spatial\"\nmass = 2.0\n"
                            "inertia = [0.1, 0.2, 0.3]\n";
  auto err = [&](const std::string& text) { return error_of([&] { load_case_text(text, "bad.toml"); }); };
  const std::string a = err(model + "[initial]\nb_x = 3.0\n");
  BOOST_TEST(has(a, "bad.toml: key 'initial.b_e0'"), a);
  BOOST_TEST(has(a, "b_e0..b_e3 not all 0"), a);
  BOOST_TEST(has(a, "got all 0"), a);
  BOOST_TEST(err(model + "[initial]\nb_rx = 0.3\n").empty());
  BOOST_TEST(err(model + "[initial]\nb_e2 = -1.0\n").empty());
  const std::string ball = "[model]\nname = \"ball\"\n[model.body.b]\nkind = \"spatial\"\nmass = 2.0\n"
                           "inertia = [0.1, 0.2, 0.3]\nmarkers.m = [0, 0, 0.5]\n[model.joint.j]\ntype = \"spherical\"\n"
                           "body2 = \"b\"\nmarker2 = \"m\"\ncoordinates = [\"p0\", \"p1\", \"p2\", \"p3\"]\n";
  const std::string b = err(ball + "[initial]\np1_d = 1.0\n");
  BOOST_TEST(has(b, "bad.toml: key 'initial.p0'"), b);
  BOOST_TEST(has(b, "on the spherical joint j"), b);
  BOOST_TEST(has(b, "p0 = 1 for marker2's frame aligned with marker1's"), b);
  BOOST_TEST(err(ball + "[initial]\np0 = 1.0\np1_d = 1.0\n").empty());
  for (const char* key : {"b_w1", "b_wx", "b_rx"}) {
    const std::string c = err(ball + "[initial]\np0 = 1.0\n" + key + " = 1.0\n");
    BOOST_TEST(has(c, std::string("key 'initial.") + key + "'"), c);
  }
}

// Issue 22: the initial orientation of a spatial body as a rotation vector (initial.b_rx..rz =
// chi u, ground axes) gives the Euler parameters (cos chi/2, u sin chi/2), written out here for
// chi = 1.1 about u = (1, 2, 2)/3; with the ground angular-velocity keys the rates follow at that
// orientation (the same as with the Euler parameters given); a zero vector is the identity;
// together with an Euler parameter it is refused naming that key.
BOOST_AUTO_TEST_CASE(initial_rotation_vector_key_gives_the_euler_parameters) {
  const double chi = 1.1, c = std::cos(chi / 2), s = std::sin(chi / 2);
  const double u[3] = {1.0 / 3, 2.0 / 3, 2.0 / 3};
  const double e[4] = {c, u[0] * s, u[1] * s, u[2] * s};
  const std::string model = "[model]\nname = \"spinner\"\n[model.body.b]\nkind = \"spatial\"\nmass = 2.0\n"
                            "inertia = [0.1, 0.2, 0.3]\n[solver]\nt_end = 0.01\n";
  auto with = [&](const std::string& initial) {
    std::ostringstream os;
    os.precision(17);
    os << model << "[initial]\nb_x = -500.0\n" << initial;
    return os.str();
  };
  std::ostringstream rv, ev;
  rv.precision(17);
  ev.precision(17);
  rv << "b_rx = " << chi * u[0] << "\nb_ry = " << chi * u[1] << "\nb_rz = " << chi * u[2] << "\nb_wx = 0.4\nb_wz = -1.5\n";
  ev << "b_e0 = " << e[0] << "\nb_e1 = " << e[1] << "\nb_e2 = " << e[2] << "\nb_e3 = " << e[3] << "\nb_wx = 0.4\nb_wz = -1.5\n";
  const Case a = load_case_text(with(rv.str()), "rv.toml");
  const Case b = load_case_text(with(ev.str()), "ev.toml");
  const int i0 = a.model->coordinate_index("b_e0");
  BOOST_REQUIRE(i0 >= 0);
  for (int j = 0; j < 4; ++j) {
    BOOST_TEST(std::abs(a.setup.q0[i0 + j] - e[j]) < 1e-15, "e" << j);
    BOOST_TEST(std::abs(a.setup.qd0[i0 + j] - b.setup.qd0[i0 + j]) < 1e-15, "e" << j << "_d");
  }
  BOOST_TEST(a.setup.q0[a.model->coordinate_index("b_x")] == -500.0);
  const Case z = load_case_text(with("b_ry = 0.0\n"), "zero.toml");
  BOOST_TEST(z.setup.q0[i0] == 1.0);
  BOOST_TEST(z.setup.q0.segment(i0 + 1, 3).cwiseAbs().maxCoeff() == 0.0);
  const std::string err = error_of([&] { load_case_text(with("b_ry = 0.5\nb_e2 = 0.3\n"), "both.toml"); });
  BOOST_TEST(has(err, "both.toml: key 'initial.b_e2'"), err);
  BOOST_TEST(has(err, "rotation vector (initial.b_ry)"), err);
  // no Euler parameters and an angular velocity: the rotation vector is the orientation
  BOOST_TEST(error_of([&] { load_case_text(with("b_rz = 0.2\nb_w1 = 1.0\n"), "ok.toml"); }).empty());
  TempDir dir;
  run_case(a, writing_to(dir.path / "out"));
  BOOST_TEST(std::filesystem::exists(dir.path / "out" / "summary.json"));
}

// Issue 23: the summary monitor of a large model (n >= 60: no exact-refinement allowance, the
// 33-point grid from the dense output, with q̈, R and the multipliers interpolated through 9
// full samples per step and the derived columns from them) against an independent oracle: the
// time-series rows, each a full evaluation of the dynamics at its own time, 1e-4 s apart. Every
// column's window maximum and minimum must reach the rows' (the monitor misses no sampled
// extreme) and exceed them by no more than a peak between rows can (an eighth of the rows'
// largest second difference, with a margin of 1.5 for its estimate, plus rounding): an error
// of the interpolation or of the grid's quartic larger than that fails. The 20-link chain
// (60 coordinates, 181 columns) released at 0.5 rad, 0.05 s at rtol 1e-10.
BOOST_AUTO_TEST_CASE(large_model_extremes_agree_with_rows_of_full_samples) {
  TempDir d;
  const int N = 20;
  d.write("chain.toml", pcsim::modelfile::testing::pendulum_chain_toml(N));
  std::ostringstream cs;
  cs.precision(17);
  cs << "model = \"chain.toml\"\n[initial]\n";
  const double a = 0.5, h = 0.05;
  for (int i = 1; i <= N; ++i)
    cs << "x" << i << " = " << (2 * i - 1) * h * std::sin(a) << "\ny" << i << " = "
       << -(2 * i - 1) * h * std::cos(a) << "\nth" << i << " = " << a << "\n";
  cs << "[solver]\nt_end = 0.05\nrtol = 1.0e-10\natol = 1.0e-12\n[output]\ndt = 1.0e-4\n";
  const Case c = load_case(d.write("case.toml", cs.str()));
  Kept kept;
  RunOptions o;
  o.keep = &kept;
  const RunResult r = run_case(c, o);
  const std::vector<std::string> names = timeseries_columns(c);
  const std::size_t width = names.size();  // t, the columns, the two residuals
  const std::size_t rows = kept.rows.size() / width;
  BOOST_REQUIRE(rows == 501);
  int checked = 0;
  for (std::size_t j = 1; j + 2 < width; ++j) {
    double hi = -INFINITY, lo = INFINITY, d2 = 0, scale = 0;
    for (std::size_t k = 0; k < rows; ++k) {
      const double v = kept.rows[k * width + j];
      hi = std::max(hi, v);
      lo = std::min(lo, v);
      scale = std::max(scale, std::abs(v));
      if (k > 0 && k + 1 < rows)
        d2 = std::max(d2, std::abs(kept.rows[(k + 1) * width + j] - 2 * v + kept.rows[(k - 1) * width + j]));
    }
    const ColumnExtremes& e = r.extreme(names[j]);
    const double slack = 1.5 * d2 / 8 + 1e-12 * scale + 1e-300;
    BOOST_TEST_CONTEXT(names[j]) {
      BOOST_TEST(e.max >= hi - 1e-13 * scale);
      BOOST_TEST(e.max <= hi + slack);
      BOOST_TEST(e.min <= lo + 1e-13 * scale);
      BOOST_TEST(e.min >= lo - slack);
    }
    ++checked;
  }
  BOOST_TEST(checked == 3 * 3 * N + 1);  // q, q', R of 60 coordinates and the energy
}
