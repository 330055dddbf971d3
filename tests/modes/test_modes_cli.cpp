// `pcsim modes` through the executable (PCSIM_EXE): the files it writes (modes.json, modes.csv,
// the trace and its figure) in a directory it owns; bad input as exit 2 and a linearization that
// does not exist as exit 3, with nothing written; and the Floquet multipliers that `pcsim steady`
// reports for a linear forced system equal exp(lambda T) of the eigenvalues `pcsim modes`
// reports for the same system with its excitation off.
#define BOOST_TEST_MODULE modes_cli
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <complex>

#include <nlohmann/json.hpp>

#include "../support/cli_util.hpp"
#include "modes_test_util.hpp"

using namespace pcsim_test;
using namespace pcsim::modes::testing;

namespace {

pcsim_test::Result run_cli(const std::string& args, const fs::path& cwd) { return sh("'" + exe() + "' " + args, cwd); }

fs::path forced_chain(const fs::path& dir, double rtol) {
  Chain c;
  c.k3 = 30;
  c.c1 = 0.5;
  c.c2 = 0.3;
  c.c3 = 0.1;
  c.F = 10;
  c.omega = 12;
  std::ostringstream extra;
  extra << "\n[solver]\nrtol = " << rtol << "\natol = " << rtol * 1e-2 << "\n";
  write(dir / "chain.toml", chain_case(c) + extra.str());
  return dir / "chain.toml";
}

}  // namespace

BOOST_AUTO_TEST_CASE(writes_modes_json_and_csv_into_its_own_directory) {
  TempDir tmp("modes_cli");
  const fs::path src = fs::current_path();
  const auto r = run_cli("modes '" + (src / "tests/modes/pendulum_far_case.toml").string() + "' --out out", tmp.path);
  BOOST_TEST_MESSAGE(r.out);
  BOOST_REQUIRE(r.status == 0);
  BOOST_TEST(has(r.out, "tangent space: dimension 2 of the 4 states"));
  BOOST_TEST(has(r.out, "excitation none declared"));
  const auto j = nlohmann::json::parse(read(tmp.path / "out" / "modes.json"));
  BOOST_TEST(j["modes"].size() == 1u);
  const std::string csv = read(tmp.path / "out" / "modes.csv");
  BOOST_TEST(csv.rfind("mode,kind,re,im,natural_frequency_rad_s,natural_frequency_hz,damped_frequency_rad_s,"
                       "damping_ratio,dominant,x_abs,x_phase_deg,y_abs,y_phase_deg\n", 0) == 0);
  BOOST_TEST(has(read(tmp.path / "out" / ".pcsim-output"), "modes"));
  // pcsim run will not write into it, and pcsim modes will not write into a run's directory.
  const auto r2 = run_cli("run '" + (src / "tests/modes/pendulum_far_case.toml").string() + "' --out out", tmp.path);
  BOOST_TEST(r2.status == 2);
  // A single linearization has nothing to draw against.
  const auto p = run_cli("plot out", tmp.path);
  BOOST_TEST(p.status == 2);
  BOOST_TEST(has(p.out, "--vary"));
}

BOOST_AUTO_TEST_CASE(bad_input_exits_2_and_writes_nothing) {
  TempDir tmp("modes_cli_bad");
  const fs::path src = fs::current_path();
  const std::string pc = "'" + (src / "tests/modes/pendulum_far_case.toml").string() + "'";
  // Not at rest: the residual and the coordinate.
  auto r = run_cli("modes " + pc + " --set initial.x=1000.1 --set initial.y=-501.49666295470957 --out o1", tmp.path);
  BOOST_TEST(r.status == 2);
  BOOST_TEST(has(r.out, "not a rest state"));
  BOOST_TEST(has(r.out, "accelerating: x"));
  BOOST_TEST(!fs::exists(tmp.path / "o1" / "modes.json"));
  // A bad excitation, a phase without a period, an unknown cyclic name, a bad --vary.
  r = run_cli("modes " + pc + " --excitation sometimes --out o2", tmp.path);
  BOOST_TEST(r.status == 2);
  BOOST_TEST(has(r.out, "modes.excitation"));
  r = run_cli("modes " + pc + " --excitation 1.0 --out o2", tmp.path);
  BOOST_TEST(r.status == 2);
  BOOST_TEST(has(r.out, "declares none"));
  r = run_cli("modes " + pc + " --cyclic psi --out o2", tmp.path);
  BOOST_TEST(r.status == 2);
  r = run_cli("modes " + pc + " --vary parameters.L=1:2 --out o2", tmp.path);
  BOOST_TEST(r.status == 2);
  BOOST_TEST(!fs::exists(tmp.path / "o2"));
  // A [modes] table with an unknown key.
  write(tmp.path / "c.toml", "model = '" + (src / "tests/modes/pendulum_far.toml").string() +
                                 "'\n[initial]\nx = 1000.0\ny = -501.5\n[modes]\nexcitaton = 'off'\n");
  r = run_cli("modes c.toml --out o3", tmp.path);
  BOOST_TEST(r.status == 2);
  BOOST_TEST(has(r.out, "modes.excitaton"));
  BOOST_TEST(!fs::exists(tmp.path / "o3"));
  // The case with [modes] still runs (pcsim run leaves [modes] to pcsim modes).
  write(tmp.path / "d.toml", "model = '" + (src / "tests/modes/pendulum_far.toml").string() +
                                 "'\n[initial]\nx = 1000.0\ny = -501.5\n[modes]\nexcitation = 'off'\n"
                                 "[solver]\nt_end = 0.01\n");
  r = run_cli("run d.toml --out o4", tmp.path);
  BOOST_TEST(r.status == 0);
}

BOOST_AUTO_TEST_CASE(a_range_through_a_singular_point_exits_3_and_writes_nothing) {
  TempDir tmp("modes_cli_vary");
  forced_chain(tmp.path, 1e-8);
  const auto r = run_cli("modes chain.toml --vary parameters.m2=1:-1:3 --out o", tmp.path);
  BOOST_TEST_MESSAGE(r.out);
  BOOST_TEST(r.status == 3);
  BOOST_TEST(has(r.out, "parameters.m2 = 0"));
  BOOST_TEST(!fs::exists(tmp.path / "o" / "modes_vary.csv"));
}

BOOST_AUTO_TEST_CASE(vary_writes_the_trace_and_plot_draws_it) {
  TempDir tmp("modes_cli_plot");
  forced_chain(tmp.path, 1e-8);
  auto r = run_cli("modes chain.toml --vary parameters.k2=10:90:5 --out o", tmp.path);
  BOOST_TEST_MESSAGE(r.out);
  BOOST_REQUIRE(r.status == 0);
  const std::string csv = read(tmp.path / "o" / "modes_vary.csv");
  BOOST_TEST(csv.rfind("parameters.k2,excitation_frequency_rad_s,re_1,im_1,re_2,im_2,re_3,im_3,re_4,im_4,undamped_1,undamped_2\n", 0) == 0);
  BOOST_TEST(std::count(csv.begin(), csv.end(), '\n') == 6);
  r = run_cli("plot o", tmp.path);
  BOOST_TEST_MESSAGE(r.out);
  BOOST_TEST(r.status == 0);
  BOOST_TEST(fs::exists(tmp.path / "o" / "modes_vary.png"));
  BOOST_TEST(has(read(tmp.path / "o" / "plots.gp"), "stability boundary Re = 0"));
  BOOST_TEST(has(read(tmp.path / "o" / "plots.gp"), "excitation frequency"));
}

// The same linear damped 2-DOF chain, forced by F cos(omega t): pcsim steady's Floquet
// multipliers mu (rtol 1e-12) against exp(lambda T) of pcsim modes' eigenvalues with the
// excitation off (a forcing additive in Q averages out exactly). 1e-8: the shooting's
// monodromy matrix is integrated to ~1e-11 relative (tests/steady/test_steady_linear.cpp).
BOOST_AUTO_TEST_CASE(floquet_exponents_of_steady_equal_modes_eigenvalues_unforced) {
  TempDir tmp("modes_cli_floquet");
  forced_chain(tmp.path, 1e-12);
  auto r = run_cli("modes chain.toml --out m", tmp.path);
  BOOST_REQUIRE_MESSAGE(r.status == 0, r.out);
  BOOST_TEST(has(r.out, "excitation off"));
  r = run_cli("steady chain.toml --out s", tmp.path);
  BOOST_REQUIRE_MESSAGE(r.status == 0, r.out);
  const auto m = nlohmann::json::parse(read(tmp.path / "m" / "modes.json"));
  const auto s = nlohmann::json::parse(read(tmp.path / "s" / "steady.json"));
  const double T = s["orbit_period"].get<double>();
  BOOST_TEST(std::abs(T - 2 * M_PI / 12) < 1e-15);
  std::vector<std::complex<double>> from_modes, from_steady;
  for (const auto& e : m["eigenvalues"])
    from_modes.push_back(std::exp(std::complex<double>(e["re"].get<double>(), e["im"].get<double>()) * T));
  for (const auto& mu : s["floquet"]["multipliers"])
    from_steady.emplace_back(mu["re"].get<double>(), mu["im"].get<double>());
  BOOST_REQUIRE(from_modes.size() == from_steady.size());
  BOOST_TEST(set_distance(from_steady, from_modes) <= 1e-8);
  // And both against the characteristic polynomial's roots.
  Chain c;
  c.k3 = 30;
  c.c1 = 0.5;
  c.c2 = 0.3;
  c.c3 = 0.1;
  std::vector<std::complex<double>> roots;
  for (const auto& l : chain_roots(c)) roots.push_back(std::exp(l * T));
  BOOST_TEST(set_distance(from_modes, roots) <= 1e-12);
}
