// Issue 19, runs: no runaway run (a step budget or an output that cannot cover the time span is
// refused before any work, naming the key), tolerances that cannot give the printed digits are
// refused or reported unreliable, a failed run of any kind keeps what it computed (time series
// up to the failure, summary.json with "complete": false, the reason and the time, exit 3),
// messages that count in the right number, no "nan" token in a CSV, dependent constraints named
// with what the user can do, and pcsim response refusing keys that cannot move the orbit.
// PCSIM_EXE (set by pcsim_boost_tests) is the executable. The oracles are closed forms (blow-up
// times, oscillator frequencies), never the code's own output.
#define BOOST_TEST_MODULE sim_runs_trust
#include <boost/test/unit_test.hpp>

#include "../support/cli_util.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace fs = std::filesystem;

namespace {

using pcsim_test::exe;
using pcsim_test::has;
using pcsim_test::read;
using pcsim_test::Result;
using pcsim_test::sh;

struct TempDir : pcsim_test::TempDir {
  TempDir() : pcsim_test::TempDir("runs") {}
};

const std::string kSource = PCSIM_SOURCE_DIR;

void write(const fs::path& f, const std::string& text) { std::ofstream(f) << text; }

// An oscillator x'' + c x' + k x = F cos(omega t) (an inline model; period 2 pi/omega).
std::string oscillator(double k, double c = 0.1, const std::string& extra = "") {
  std::ostringstream os;
  os.precision(17);
  os << "[model]\nname = \"osc\"\ncoordinates = [\"x\"]\nperiod = \"2*pi/omega\"\n"
        "[model.parameters]\n"
     << "k = { value = " << k << " }\n"
     << "c = { value = " << c << ", min = 0.0 }\n"
     << "F = { value = 0.5 }\nomega = { value = 1.0, positive = true }\n"
     << "unused = { value = 2.0 }\n"
        "[model.energy]\nkinetic = \"0.5*x_d^2\"\npotential = \"0.5*k*x^2\"\n"
        "dissipation = \"0.5*c*x_d^2\"\n"
        "[model.forces]\nx = \"F*cos(omega*t)\"\n"
     << extra;
  return os.str();
}

nlohmann::json summary(const fs::path& dir) { return nlohmann::json::parse(read(dir / "summary.json")); }

// The rows of a time series: each line split at commas (fields kept as text).
std::vector<std::vector<std::string>> csv_rows(const fs::path& f) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(read(f));
  std::string line;
  while (std::getline(in, line)) {
    std::vector<std::string> row;
    std::string cell;
    std::istringstream ls(line);
    while (std::getline(ls, cell, ',')) row.push_back(cell);
    if (!line.empty() && line.back() == ',') row.push_back("");
    rows.push_back(row);
  }
  return rows;
}

double last_time(const fs::path& f) {
  const auto rows = csv_rows(f);
  return rows.size() > 1 ? std::stod(rows.back()[0]) : -1.0;
}

bool has_nonfinite_token(const std::string& text) {
  std::istringstream in(text);
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    std::string cell;
    std::istringstream ls(line);
    while (std::getline(ls, cell, ','))
      if (has(cell, "nan") || has(cell, "inf") || has(cell, "NaN") || has(cell, "Inf")) return true;
  }
  return false;
}

// A failed run's directory: exit 3, the time and reason on stderr, summary.json with
// "complete": false and failure.t, and time-series rows up to (not past) the failure time.
void check_kept(const Result& r, const fs::path& dir, const std::string& reason_part) {
  BOOST_TEST(r.status == 3, r.out);
  BOOST_TEST(has(r.out, "failed at t = "), r.out);
  BOOST_TEST(has(r.out, reason_part), r.out);
  BOOST_TEST(has(r.out, "marked \"complete\": false"), r.out);
  BOOST_REQUIRE(fs::exists(dir / "summary.json"));
  BOOST_REQUIRE(fs::exists(dir / "timeseries.csv"));
  const auto s = summary(dir);
  BOOST_TEST(s["complete"].get<bool>() == false);
  BOOST_REQUIRE(s.contains("failure"));
  const double tf = s["failure"]["t"].get<double>();
  BOOST_TEST(has(s["failure"]["reason"].get<std::string>(), reason_part));
  const double last = last_time(dir / "timeseries.csv");
  const double dt = s["output_dt"].get<double>();
  BOOST_TEST(last <= tf * (1 + 1e-12));
  BOOST_TEST(last >= tf - dt - 1e-12, "last row " << last << ", failure at " << tf);
  BOOST_TEST(!has_nonfinite_token(read(dir / "timeseries.csv")));
}

}  // namespace

// ---- 1. runaway runs: the step budget and the output rows against the time span -------------

// pcsim steady with omega = 1e-9: an orbit period of 6e9 s that no step budget can cover is
// refused at once (exit 2), naming solver.max_steps and the bound, instead of running on.
// Variants: smaller frequencies down to the example, each refused within seconds.
BOOST_AUTO_TEST_CASE(steady_refuses_an_orbit_period_beyond_the_step_budget) {
  TempDir d;
  write(d.path / "osc.toml", oscillator(1.0));
  for (const char* omega : {"1e-9", "1e-7", "1e-6"}) {
    const Result r = sh("timeout 60 '" + exe() + "' steady osc.toml --set parameters.omega=" +
                            omega + " --out o",
                        d.path);
    BOOST_TEST(r.status == 2, omega << ": " << r.out);
    BOOST_TEST(has(r.out, "solver.max_steps"), r.out);
    BOOST_TEST(has(r.out, "parameters.omega"), r.out);  // the key that sets the period
    BOOST_TEST(!fs::exists(d.path / "o"));
  }
  // The shipped Duffing example (omega = 1) is not refused by the budget.
  const Result ok = sh("timeout 120 '" + exe() + "' steady '" + kSource + "/tests/steady/duffing.toml' --out ok", d.path);
  BOOST_TEST(ok.status == 0, ok.out);
  // pcsim response over a range reaching such a frequency: refused before any point is computed.
  const Result resp = sh("timeout 60 '" + exe() + "' response osc.toml --vary parameters.omega=1e-9,1 --out rr", d.path);
  BOOST_TEST(resp.status == 2, resp.out);
  BOOST_TEST(has(resp.out, "solver.max_steps"), resp.out);
  BOOST_TEST(!fs::exists(d.path / "rr"));
}

// pcsim run: the step budget against solver.t_end, with the oscillator's frequency as the
// oracle (sqrt(k)/(2 pi)): a budget below 2 steps per oscillation period over t_end is refused
// (exit 2, naming solver.max_steps); one above it is never refused by the budget check.
BOOST_AUTO_TEST_CASE(run_refuses_a_step_budget_below_two_steps_per_oscillation) {
  TempDir d;
  std::mt19937 rng(19);
  std::uniform_real_distribution<double> lk(0, 8), lt(-1, 1.5);
  for (int i = 0; i < 12; ++i) {
    const double k = std::pow(10.0, lk(rng)), t_end = std::pow(10.0, lt(rng));
    const double need = 2 * t_end * std::max(std::sqrt(k) / (2 * M_PI), 1 / (2 * M_PI));
    // A budget a factor 4 below or above the bound (never near it: the estimate is numerical).
    const bool below = i % 2 == 0;
    const long budget = std::max(1L, static_cast<long>(below ? need / 4 : need * 4));
    if (!below && budget > 2000000) continue;  // keep the test fast
    write(d.path / "osc.toml", oscillator(k, 0.0));
    std::ostringstream cmd;
    cmd.precision(17);
    cmd << "timeout 120 '" << exe() << "' run osc.toml --set solver.t_end=" << t_end
        << " --set solver.max_steps=" << budget << " --set output.dt=" << t_end / 100 << " --out o" << i;
    const Result r = sh(cmd.str(), d.path);
    BOOST_TEST_CONTEXT("k = " << k << ", t_end = " << t_end << ", budget " << budget << ", bound " << need) {
      if (below && need / 4 >= 1) {
        BOOST_TEST(r.status == 2, r.out);
        BOOST_TEST(has(r.out, "solver.max_steps"), r.out);
        BOOST_TEST(!fs::exists(d.path / ("o" + std::to_string(i))));
      } else if (!below) {
        BOOST_TEST(r.status != 2, r.out);
      }
    }
  }
}

// The time-series rows of pcsim steady's period run are bounded before the shooting starts.
BOOST_AUTO_TEST_CASE(steady_refuses_too_many_rows_before_work) {
  TempDir d;
  write(d.path / "osc.toml", oscillator(1.0) + "[output]\ndt = 1e-12\n");
  const Result r = sh("timeout 60 '" + exe() + "' steady osc.toml --out o", d.path);
  BOOST_TEST(r.status == 2, r.out);
  BOOST_TEST(has(r.out, "output.dt"), r.out);
  BOOST_TEST(!fs::exists(d.path / "o"));
}

// ---- 2. tolerances ----------------------------------------------------------------------------

// rtol and atol have upper bounds (exit 2, naming the key); atol within the bound but above a
// hundredth of a coordinate's magnitude (the sieve's 2e-5 m) makes the result unreliable:
// exit 3, the files written with "accuracy": {"reliable": false}, never a confident verdict.
// On the sieve's cases: the sieve's (skipped in a build without it).
BOOST_AUTO_TEST_CASE(tolerances_that_cannot_give_the_digits_are_refused_or_flagged, *boost::unit_test::enable_if<PCSIM_WITH_SIEVE>()) {
  TempDir d;
  const std::string sieve = kSource + "/cases/sieve_1995.toml";
  for (const char* set : {"solver.rtol=0.01", "solver.rtol=1", "solver.atol=1", "solver.atol=0.5"}) {
    const Result r = sh("'" + exe() + "' run '" + sieve + "' --set " + set + " --out o", d.path);
    BOOST_TEST(r.status == 2, set << ": " << r.out);
    BOOST_TEST(has(r.out, std::string(set).substr(0, std::string(set).find('='))), r.out);
    BOOST_TEST(!fs::exists(d.path / "o"));
  }
  const Result r = sh("'" + exe() + "' run '" + sieve + "' --set solver.atol=1e-4 --set solver.t_end=0.5 --out u", d.path);
  BOOST_TEST(r.status == 3, r.out);
  BOOST_TEST(has(r.out, "not reliable"), r.out);
  BOOST_TEST(has(r.out, "solver.atol"), r.out);
  const auto s = summary(d.path / "u");
  BOOST_TEST(s["accuracy"]["reliable"].get<bool>() == false);
  // The report is still printed, with the UNRELIABLE line naming solver.atol and a value that
  // would do, and that value gives a reliable run of the same case.
  BOOST_TEST(has(r.out, "UNRELIABLE: solver.atol = 0.0001"), r.out);
  BOOST_TEST(has(r.out, "wrote "), r.out);
  const std::string marker = "set solver.atol <= ";
  const auto at = r.out.find(marker);
  BOOST_REQUIRE_MESSAGE(at != std::string::npos, r.out);
  const std::string token = r.out.substr(at + marker.size(), r.out.find_first_of(" ;\n", at + marker.size()) - at - marker.size());
  const double would_do = std::stod(token);
  BOOST_TEST(would_do < 1e-4);
  BOOST_TEST(would_do > 0);
  const Result fixed = sh("'" + exe() + "' run '" + sieve + "' --set solver.atol=" + token +
                              " --set solver.t_end=0.5 --out fixed",
                          d.path);
  BOOST_TEST(fixed.status == 0, fixed.out);
  BOOST_TEST(!has(fixed.out, "UNRELIABLE"), fixed.out);
  // The default tolerances are reliable on the same case.
  const Result ok = sh("'" + exe() + "' run '" + sieve + "' --set solver.t_end=0.5 --out ok", d.path);
  BOOST_TEST(ok.status == 0, ok.out);
  BOOST_TEST(summary(d.path / "ok")["accuracy"]["reliable"].get<bool>() == true);
}

// ---- 3. messages, flat responses, CSV tokens --------------------------------------------------

// A step budget of 1 says "1 step", never "1 steps"; the run keeps what it computed.
// The model: x'' = -x' (no oscillation, no excitation: the budget check has no bound).
BOOST_AUTO_TEST_CASE(step_budget_messages_count_in_the_right_number_and_keep_the_run) {
  TempDir d;
  write(d.path / "damp.toml",
        "[model]\nname = \"damp\"\ncoordinates = [\"x\"]\n[model.energy]\nkinetic = \"0.5*x_d^2\"\n"
        "potential = \"0\"\ndissipation = \"0.5*x_d^2\"\n[initial]\nx_d = 1.0\n[solver]\nt_end = 10.0\n"
        "[output]\ndt = 0.01\n");
  for (int budget : {1, 2, 3}) {
    const std::string dir = "b" + std::to_string(budget);
    const Result r = sh("'" + exe() + "' run damp.toml --set solver.max_steps=" + std::to_string(budget) +
                            " --out " + dir,
                        d.path);
    BOOST_TEST_CONTEXT("budget " << budget) {
      BOOST_TEST(!has(r.out, " 1 steps"), r.out);
      BOOST_TEST(has(r.out, "step budget of " + std::to_string(budget) + (budget == 1 ? " step " : " steps ")), r.out);
      check_kept(r, d.path / dir, "step budget");
    }
  }
}

// pcsim response --vary initial.x: an initial value cannot change a periodic orbit (a flat
// curve): refused, as is a parameter that enters nothing; a real parameter is accepted.
// On the sieve's cases: the sieve's (skipped in a build without it).
BOOST_AUTO_TEST_CASE(response_refuses_keys_that_cannot_move_the_orbit, *boost::unit_test::enable_if<PCSIM_WITH_SIEVE>()) {
  TempDir d;
  write(d.path / "osc.toml", oscillator(1.0));
  for (const char* vary : {"initial.x=0,1,2", "initial.x_d=0,1", "parameters.unused=1,2,3"}) {
    const Result r = sh("timeout 60 '" + exe() + "' response osc.toml --vary " + vary + " --out r", d.path);
    BOOST_TEST(r.status == 2, vary << ": " << r.out);
    BOOST_TEST(has(r.out, "flat curve"), r.out);
    BOOST_TEST(!fs::exists(d.path / "r"));
  }
  const Result ok = sh("timeout 120 '" + exe() + "' response osc.toml --vary parameters.omega=0.8,1.2 --out ok", d.path);
  BOOST_TEST(ok.status == 0, ok.out);
  // The sieve's friction coefficient enters only its verdicts (the rolling margin), which the
  // response's columns show: accepted.
  const Result f = sh("timeout 300 '" + exe() + "' response '" + kSource +
                          "/cases/sieve_1995.toml' --vary parameters.f=0.2,0.3 --out f",
                      d.path);
  BOOST_TEST(f.status == 0, f.out);
}

// The shipped hopping case: f* is undefined in flight (0/0); its field is empty, never "-nan".
// Variant: an output that is 0/0 or 1/0 at times writes empty fields, and the summary holds no
// NaN either (JSON null).
// On the sieve's cases: the sieve's (skipped in a build without it).
BOOST_AUTO_TEST_CASE(no_nan_or_inf_token_in_a_time_series, *boost::unit_test::enable_if<PCSIM_WITH_SIEVE>()) {
  TempDir d;
  const Result r = sh("'" + exe() + "' run '" + kSource +
                          "/cases/sieve_1995_hopping.toml' --set solver.t_end=0.3 --out hop",
                      d.path);
  BOOST_TEST((r.status == 0 || r.status == 3), r.out);
  const std::string ts = read(d.path / "hop" / "timeseries.csv");
  BOOST_TEST(!ts.empty());
  BOOST_TEST(!has_nonfinite_token(ts));
  BOOST_TEST(has(ts, ",,"));  // f* in flight: an empty field
  write(d.path / "div.toml",
        oscillator(1.0, 0.1, "[model.outputs]\nratio = \"sin(x)/x\"\ninverse = \"1/x\"\n") +
            "[initial]\nx = 0.0\n[solver]\nt_end = 1.0\n[output]\ndt = 0.1\n");
  const Result r2 = sh("'" + exe() + "' run div.toml --out div", d.path);
  BOOST_TEST(r2.status == 0, r2.out);
  const std::string ts2 = read(d.path / "div" / "timeseries.csv");
  BOOST_TEST(!has_nonfinite_token(ts2), ts2.substr(0, 400));
  const std::string sj = read(d.path / "div" / "summary.json");
  BOOST_TEST(!has(sj, "NaN"));
  BOOST_TEST(!has(sj, "nan"));
  BOOST_TEST(!has(sj, "Infinity"));
}

// ---- 4. dependent constraints -------------------------------------------------------------------

// Two constraints that become dependent at t = 1 (rows [0, 1] and [-min(0, t - 1), 1]). Before
// issue 21 the run stopped there with exit 3; they stay consistent (both say y = 0), so the run
// now goes on through the rank change to t_end, and the motion is the one both allow (rest).
BOOST_AUTO_TEST_CASE(constraints_that_become_dependent_during_a_run_are_crossed) {
  TempDir d;
  write(d.path / "dep.toml",
        "[model]\nname = \"dep\"\ncoordinates = [\"x\", \"y\"]\n[model.energy]\n"
        "kinetic = \"0.5*(x_d^2 + y_d^2)\"\npotential = \"0\"\n"
        "[[model.constraint]]\nname = \"floor\"\nholonomic = \"y\"\n"
        "[[model.constraint]]\nname = \"ramp\"\nholonomic = \"y - x*min(0, t - 1)\"\n"
        "[solver]\nt_end = 3.0\n[output]\ndt = 0.01\n");
  const Result r = sh("'" + exe() + "' run dep.toml --out o", d.path);
  BOOST_TEST(r.status == 0, r.out);
  const std::string sj = read(d.path / "o" / "summary.json");
  BOOST_TEST(has(sj, "\"complete\": true"), sj.substr(0, 400));
  // The remedy works: with one switched off the run completes.
  const Result ok = sh("'" + exe() + "' run dep.toml --set constraints.ramp=false --out ok", d.path);
  BOOST_TEST(ok.status == 0, ok.out);
}

// ---- 5. every failure keeps what it computed ---------------------------------------------------

// x'' = x^2 from x(0) = a at rest blows up at t* = a^(-1/2) sqrt(3/2)/3 B(1/6, 1/2) (energy
// integral). The run fails there (exit 3) and keeps the rows up to the failure; generated
// variants over a.
BOOST_AUTO_TEST_CASE(a_blow_up_in_finite_time_keeps_the_rows_up_to_it) {
  TempDir d;
  const double beta = std::tgamma(1.0 / 6) * std::tgamma(0.5) / std::tgamma(2.0 / 3);
  for (double a : {0.5, 1.0, 2.0, 4.0}) {
    const double t_star = std::sqrt(1.5) / 3 * beta / std::sqrt(a);
    std::ostringstream c;
    c.precision(17);
    c << "[model]\nname = \"blowup\"\ncoordinates = [\"x\"]\n[model.energy]\nkinetic = \"0.5*x_d^2\"\n"
         "potential = \"-x^3/3\"\n[initial]\nx = "
      << a << "\n[solver]\nt_end = " << 2 * t_star << "\n[output]\ndt = " << t_star / 100 << "\n";
    write(d.path / "b.toml", c.str());
    const std::string dir = "b" + std::to_string(static_cast<int>(a * 10));
    const Result r = sh("'" + exe() + "' run b.toml --out " + dir, d.path);
    BOOST_TEST_CONTEXT("a = " << a << ", t* = " << t_star) {
      check_kept(r, d.path / dir, "");
      const double tf = summary(d.path / dir)["failure"]["t"].get<double>();
      BOOST_TEST(std::abs(tf - t_star) <= 1e-2 * t_star, "failed at " << tf);
    }
  }
}

// A constraint that cannot be satisfied after t = 1 (x^2 = 1 - t): exit 3 near t = 1 with the
// rows up to there.
BOOST_AUTO_TEST_CASE(a_constraint_that_cannot_be_satisfied_keeps_the_rows_up_to_it) {
  TempDir d;
  write(d.path / "c.toml",
        "[model]\nname = \"shrink\"\ncoordinates = [\"x\", \"y\"]\n[model.energy]\n"
        "kinetic = \"0.5*(x_d^2 + y_d^2)\"\npotential = \"9.81*y\"\n"
        "[[model.constraint]]\nname = \"shrink\"\nholonomic = \"x^2 + t - 1\"\n"
        "[initial]\nx = 1.0\nx_d = -0.5\n[solver]\nt_end = 2.0\n[output]\ndt = 0.01\n");
  const Result r = sh("'" + exe() + "' run c.toml --out o", d.path);
  check_kept(r, d.path / "o", "");
  const double tf = summary(d.path / "o")["failure"]["t"].get<double>();
  BOOST_TEST(tf > 0.9);
  BOOST_TEST(tf <= 1.0 + 1e-9);
}

// pcsim steady that does not converge keeps its Newton iterations: steady.json with
// "complete": false and the reason, exit 3 (one Newton iteration from far away).
BOOST_AUTO_TEST_CASE(a_steady_state_not_found_keeps_the_newton_iterations) {
  TempDir d;
  write(d.path / "duff.toml", read(fs::path(kSource) / "tests/steady/duffing.toml"));
  const Result f = sh("timeout 120 '" + exe() + "' steady duff.toml --set initial.x=40 "
                      "--max-iterations 1 --transient-periods 0 --out f",
                      d.path);
  BOOST_TEST(f.status == 3, f.out);
  BOOST_TEST(has(f.out, "marked \"complete\": false"), f.out);
  BOOST_REQUIRE(fs::exists(d.path / "f" / "steady.json"));
  const auto j = nlohmann::json::parse(read(d.path / "f" / "steady.json"));
  BOOST_TEST(j["complete"].get<bool>() == false);
  BOOST_TEST(!j["failure"]["reason"].get<std::string>().empty());
  BOOST_TEST(j["newton"]["history"].size() >= 1u);
}

// An infinite force names its coordinate (not "(coordinate )"), with the time, exit 3, and the
// run keeps its (single) row. V = -1/x: Q = -1/x^2 is infinite at x = 0.
BOOST_AUTO_TEST_CASE(an_infinite_force_names_its_coordinate) {
  TempDir d;
  write(d.path / "inf.toml",
        "[model]\nname = \"inf\"\ncoordinates = [\"x\", \"y\"]\n[model.energy]\n"
        "kinetic = \"0.5*(x_d^2 + y_d^2)\"\npotential = \"-1/x + y^2\"\n[initial]\nx = 0.0\ny = 1.0\n"
        "[solver]\nt_end = 1.0\n");
  const Result r = sh("'" + exe() + "' run inf.toml --out o", d.path);
  BOOST_TEST((r.status == 2 || r.status == 3), r.out);
  BOOST_TEST(has(r.out, "'x'"), r.out);
  BOOST_TEST(!has(r.out, "(coordinate )"), r.out);
}

// contact.flight_hmax against the step budget (issue 19: limits checked before work): with
// switching contacts every step in flight is at most flight_hmax long, so t_end / flight_hmax
// steps above solver.max_steps cannot suffice for a body that flies. Refused before work (exit
// 2) naming both keys, nothing written; at the bound the run is accepted.
BOOST_AUTO_TEST_CASE(flight_hmax_against_the_step_budget_is_checked_before_work) {
  TempDir d;
  const std::string ball = kSource + "/cases/bouncing_ball.toml";
  for (const char* sets : {"--set contact.flight_hmax=1e-6",  // 2 s / 1e-6 s = 2e6 > 1e6 (default)
                           "--set contact.flight_hmax=1e-3 --set solver.max_steps=1999"}) {
    const Result r = sh("'" + exe() + "' run '" + ball + "' " + sets + " --out o", d.path);
    BOOST_TEST(r.status == 2, sets << ": " << r.out);
    BOOST_TEST(has(r.out, "contact.flight_hmax"), r.out);
    BOOST_TEST(has(r.out, "solver.max_steps"), r.out);
    BOOST_TEST(!fs::exists(d.path / "o"), sets);
  }
  // 2 s / 1e-3 s = 2000 steps: a budget of 2000 may suffice, so the run is not refused.
  const Result ok = sh("'" + exe() + "' run '" + ball +
                           "' --set contact.flight_hmax=1e-3 --set solver.max_steps=100000 --out ok",
                       d.path);
  BOOST_TEST(ok.status == 0, ok.out);
  const Result edge = sh("'" + exe() + "' run '" + ball +
                             "' --set contact.flight_hmax=1e-3 --set solver.max_steps=2000 --out edge",
                         d.path);
  BOOST_TEST(edge.status != 2, edge.out);
  BOOST_TEST(!has(edge.out, "contact.flight_hmax"), edge.out);
}
