// Issue 21 through the executable (PCSIM_EXE): redundant-but-consistent constraints run with no
// user action, the singular positions of IFToMM A02 (N = 1) are crossed at every rtol from 1e-4
// to 1e-12, and the motion is checked against an independent one-degree-of-freedom model
// written here (not pcsim's engine): every crank of a parallelogram chain turns by the same
// angle θ, the couplers translate, so with n_c cranks (rods about their pivots, J = m L²/3) and
// n_k couplers (translating with the crank tips, speed L θ̇):
//   I θ̈ = −m g L c cos θ,  I = m L² (n_c/3 + n_k),  c = n_c/2 + n_k,
// integrated by classical RK4 with h = 1e-4 s (global error ~1e-13 over 10 s: far below the
// tolerances checked). θ(0) = π/2, θ̇(0) = −1/s (B0 at +1 m/s).
#define BOOST_TEST_MODULE redundant_cli
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>


#include <nlohmann/json.hpp>

#include "../support/cli_util.hpp"

namespace fs = std::filesystem;

namespace {

using pcsim_test::Result;
using pcsim_test::run_pcsim;

std::string slurp(const fs::path& p) { return pcsim_test::read(p); }
fs::path scratch(const std::string& name) { return pcsim_test::scratch("redundant_cli", name); }

struct Table {
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;
  int col(const std::string& name) const {
    for (std::size_t i = 0; i < header.size(); ++i)
      if (header[i] == name) return static_cast<int>(i);
    BOOST_FAIL("no column " + name);
    return -1;
  }
};

Table read_csv(const fs::path& p) {
  Table t;
  std::ifstream in(p);
  std::string line;
  std::getline(in, line);
  std::stringstream hs(line);
  for (std::string c; std::getline(hs, c, ',');) t.header.push_back(c);
  while (std::getline(in, line)) {
    std::stringstream ls(line);
    std::vector<double> r;
    for (std::string c; std::getline(ls, c, ',');) r.push_back(std::stod(c));
    t.rows.push_back(r);
  }
  return t;
}

// θ(t) of the one-degree-of-freedom model at the times asked (increasing).
std::vector<double> one_dof_angle(int cranks, int couplers, const std::vector<double>& times) {
  const double m = 1.0, L = 1.0, g = 9.81;
  const double I = m * L * L * (cranks / 3.0 + couplers), c = cranks / 2.0 + couplers;
  auto f = [&](double th, double w, double& dth, double& dw) {
    dth = w;
    dw = -m * g * L * c / I * std::cos(th);
  };
  double th = M_PI / 2, w = -1.0, t = 0.0;
  std::vector<double> out;
  for (double T : times) {
    while (t < T - 1e-13) {
      const double h = std::min(1e-4, T - t);
      double k1t, k1w, k2t, k2w, k3t, k3w, k4t, k4w;
      f(th, w, k1t, k1w);
      f(th + h / 2 * k1t, w + h / 2 * k1w, k2t, k2w);
      f(th + h / 2 * k2t, w + h / 2 * k2w, k3t, k3w);
      f(th + h * k3t, w + h * k3w, k4t, k4w);
      th += h / 6 * (k1t + 2 * k2t + 2 * k3t + k4t);
      w += h / 6 * (k1w + 2 * k2w + 2 * k3w + k4w);
      t += h;
    }
    out.push_back(th);
  }
  return out;
}

struct Errors {
  double angle = 0.0, spread = 0.0, energy = 0.0, theta_end = 0.0;
};

Errors run_and_compare(const std::string& case_name, int cranks, int couplers, const std::string& rtol) {
  const auto dir = scratch(case_name + "_" + rtol);
  const std::string c = std::string(PCSIM_SOURCE_DIR) + "/cases/" + case_name + ".toml";
  const auto r = run_pcsim("run '" + c + "' --set solver.rtol=" + rtol + " --out '" +
                               (dir / "out").string() + "'", dir);
  BOOST_REQUIRE_MESSAGE(r.status == 0, case_name + " at rtol " + rtol + ": " + r.out);
  const Table t = read_csv(dir / "out" / "timeseries.csv");
  std::vector<double> times;
  for (const auto& row : t.rows) times.push_back(row[0]);
  const std::vector<double> th = one_dof_angle(cranks, couplers, times);
  const int e = t.col("energy");
  std::vector<int> tc;
  for (int k = 0; k < cranks - (case_name == "parallelogram_third_crank" ? 1 : 0); ++k)
    tc.push_back(t.col("tc" + std::to_string(k)));
  Errors out;
  for (std::size_t i = 0; i < t.rows.size(); ++i) {
    const auto& row = t.rows[i];
    out.angle = std::max(out.angle, std::abs(row[tc[0]] - th[i]));
    for (int k : tc) out.spread = std::max(out.spread, std::abs(row[k] - row[tc[0]]));
    out.energy = std::max(out.energy, std::abs(row[e] - t.rows[0][e]));
  }
  out.theta_end = t.rows.back()[tc[0]];
  BOOST_TEST_MESSAGE(case_name << " rtol " << rtol << ": |theta - oracle| " << out.angle
                               << ", crank spread " << out.spread << ", energy drift " << out.energy);
  return out;
}

}  // namespace

// A02, N = 1: 3 rods, the bars on the x axis twice a revolution (rank 8 -> 7). In 10 s the
// crank turns from pi/2 to about -30.3 rad: ten singular positions crossed (the rank report
// lists them, a02_n1_reports_each_singular_position_...). Bounds: the angle to 100 rtol (at least
// 1e-6 rad: the crossing of a singular position costs up to ~1e-7 rad at the tightest
// tolerances), the cranks equal to 1e-6 rad, the energy (about 20 J) to max(500 rtol, 1e-6) J
// (the filtered crossing of a singular position costs up to ~2e-7 J at tight tolerances).
BOOST_AUTO_TEST_CASE(a02_n1_crosses_singular_positions_and_follows_the_one_dof_model) {
  for (const std::string rtol : {"1e-6", "1e-8", "1e-10"}) {
    const double rt = std::stod(rtol);
    const Errors e = run_and_compare("fourbar_a02_N1", 2, 1, rtol);
    BOOST_TEST(e.angle <= std::max(100 * rt, 1e-6), rtol << ": " << e.angle);
    BOOST_TEST(e.spread <= 1e-6, rtol << ": " << e.spread);
    BOOST_TEST(e.energy <= std::max(500 * rt, 1e-6), rtol << ": " << e.energy);
    BOOST_TEST(e.theta_end < -3 * 2 * M_PI + M_PI / 2);  // at least three revolutions made
  }
}

// The ends of the range finish too, with the motion right to their accuracy.
BOOST_AUTO_TEST_CASE(a02_n1_finishes_at_rtol_1e_4_and_1e_12) {
  const Errors loose = run_and_compare("fourbar_a02_N1", 2, 1, "1e-4");
  BOOST_TEST(loose.angle <= 1e-2);
  const Errors tight = run_and_compare("fourbar_a02_N1", 2, 1, "1e-12");
  BOOST_TEST(tight.angle <= 1e-6);
  BOOST_TEST(tight.energy <= 1e-6);
}

// A parallelogram with a third crank: 12 coordinates, 12 constraints, dependent everywhere
// (before issue 21 refused: "'M_coupler_y' is redundant ... deactivate one of them"). It runs
// with every constraint on and moves as the one-degree-of-freedom model with 3 cranks.
BOOST_AUTO_TEST_CASE(parallelogram_with_a_redundant_third_crank_runs_and_moves_as_one_dof) {
  for (const std::string rtol : {"1e-6", "1e-8", "1e-10"}) {
    const double rt = std::stod(rtol);
    const Errors e = run_and_compare("parallelogram_third_crank", 3, 1, rtol);
    BOOST_TEST(e.angle <= std::max(100 * rt, 1e-6), rtol << ": " << e.angle);
    BOOST_TEST(e.spread <= 1e-6, rtol << ": " << e.spread);
    BOOST_TEST(e.energy <= std::max(500 * rt, 1e-6), rtol << ": " << e.energy);
  }
}

// Contradictory constraints are still refused at the start, naming the rows, exit 2, nothing
// written: a second ground pin of crank 0 at x = 0.1 contradicts A0_x.
BOOST_AUTO_TEST_CASE(contradictory_constraints_are_refused_naming_the_rows) {
  const auto dir = scratch("contradiction");
  const std::string c = std::string(PCSIM_SOURCE_DIR) + "/cases/fourbar_a02_N1.toml";
  const auto r = run_pcsim("run '" + c + "' --constraint 'pin_shifted=xc0 - h*cos(tc0) - 0.1' --out '" +
                               (dir / "out").string() + "'", dir);
  BOOST_TEST(r.status == 2, r.out);
  BOOST_TEST(r.out.find("'pin_shifted'") != std::string::npos, r.out);
  BOOST_TEST(r.out.find("'A0_x'") != std::string::npos, r.out);
  BOOST_TEST(!fs::exists(dir / "out" / "timeseries.csv"));
}

// `pcsim check CASE`: a report without running. The parallelogram with a third crank: rank 11
// of 12, one degree of freedom against a Grübler count of 0, the redundant row named, exit 0.
// A contradictory pin: exit 2 naming both rows. Nothing is written in either case.
BOOST_AUTO_TEST_CASE(check_reports_rank_dof_and_redundant_rows_and_refuses_contradictions) {
  const auto dir = scratch("check");
  const std::string third = std::string(PCSIM_SOURCE_DIR) + "/cases/parallelogram_third_crank.toml";
  const auto r = run_pcsim("check '" + third + "'", dir);
  BOOST_TEST(r.status == 0, r.out);
  for (const char* s : {"coordinates: 12; active constraints: 12",
                        "rank of the active constraints at the initial state: 11 of 12",
                        "degrees of freedom: 1 (n - rank); Gruebler-style count n - m = 0",
                        "redundant rows: 'M_coupler_y'", "mass matrix M: positive definite",
                        "the case can run"})
    BOOST_TEST(r.out.find(s) != std::string::npos, s << "\n" << r.out);
  const std::string a02 = std::string(PCSIM_SOURCE_DIR) + "/cases/fourbar_a02_N1.toml";
  const auto ok = run_pcsim("check '" + a02 + "'", dir);
  BOOST_TEST(ok.status == 0, ok.out);
  BOOST_TEST(ok.out.find("rank of the active constraints at the initial state: 8 of 8") != std::string::npos, ok.out);
  BOOST_TEST(ok.out.find("redundant rows: none") != std::string::npos, ok.out);
  const auto bad = run_pcsim("check '" + a02 + "' --constraint 'pin_shifted=xc0 - h*cos(tc0) - 0.1'", dir);
  BOOST_TEST(bad.status == 2, bad.out);
  BOOST_TEST(bad.out.find("'pin_shifted' contradicts 'A0_x'") != std::string::npos, bad.out);
  BOOST_TEST(bad.out.find("cannot run") != std::string::npos, bad.out);
}

namespace {

// A bead on a horizontal rail (y = 0) tied by a rod of length 1 to a pivot pulled up the y axis
// at 1 m/s: x = sqrt(1 − t²), so at t = 1 the rod stands vertical (rail and rod rows dependent)
// and beyond it no position satisfies both.
const char* kBeyondReach = R"TOML(
[model]
name = "rail_rod"
coordinates = ["x", "y"]
[model.energy]
kinetic = "0.5*(x_d^2 + y_d^2)"
potential = "0"
[[model.constraint]]
name = "rail"
holonomic = "y"
[[model.constraint]]
name = "rod"
holonomic = "x^2 + (y - t)^2 - 1"

[initial]
x = 1.0
y = 0.0

[solver]
t_end = 2.0

[output]
dt = 0.01
)TOML";

// The crossing times of the one-degree-of-freedom model (the same equation as one_dof_angle):
// where θ passes a multiple of π (every bar on the x axis). RK4 with h = 1e-4 s; inside the
// step that crosses, bisection on one RK4 step of the partial length from the step's start.
std::vector<double> oracle_crossings(int cranks, int couplers, double t_end) {
  const double m = 1.0, L = 1.0, g = 9.81;
  const double I = m * L * L * (cranks / 3.0 + couplers), c = cranks / 2.0 + couplers;
  const auto rk4 = [&](double th, double w, double h, double& th1, double& w1) {
    const auto acc = [&](double x) { return -m * g * L * c / I * std::cos(x); };
    const double k1t = w, k1w = acc(th);
    const double k2t = w + h / 2 * k1w, k2w = acc(th + h / 2 * k1t);
    const double k3t = w + h / 2 * k2w, k3w = acc(th + h / 2 * k2t);
    const double k4t = w + h * k3w, k4w = acc(th + h * k3t);
    th1 = th + h / 6 * (k1t + 2 * k2t + 2 * k3t + k4t);
    w1 = w + h / 6 * (k1w + 2 * k2w + 2 * k3w + k4w);
  };
  std::vector<double> out;
  double th = M_PI / 2, w = -1.0;
  const double h = 1e-4;
  for (long i = 0; i * h < t_end; ++i) {
    double th1, w1;
    rk4(th, w, h, th1, w1);
    const double a = std::floor(th / M_PI), b = std::floor(th1 / M_PI);
    if (a != b) {
      const double k = std::max(a, b) * M_PI;
      double lo = 0.0, hi = h;
      for (int it = 0; it < 60; ++it) {
        const double mid = 0.5 * (lo + hi);
        double tm, wm;
        rk4(th, w, mid, tm, wm);
        ((tm - k) * (th - k) > 0 ? lo : hi) = mid;
      }
      out.push_back(i * h + 0.5 * (lo + hi));
    }
    th = th1;
    w = w1;
  }
  return out;
}

}  // namespace

// Issue 21: a run that reaches a configuration where the constraints cannot be satisfied stops
// with exit 3, the time and the constraints named, and keeps what it computed (complete: false).
BOOST_AUTO_TEST_CASE(a_drive_pulling_a_rod_beyond_its_reach_stops_with_exit_3_naming_the_rows) {
  const auto dir = scratch("beyond_reach");
  {
    std::ofstream f(dir / "reach.toml");
    f << kBeyondReach;
  }
  const auto r = run_pcsim("run '" + (dir / "reach.toml").string() + "' --out '" +
                               (dir / "out").string() + "'", dir);
  BOOST_TEST(r.status == 3, r.out);
  BOOST_TEST(r.out.find("'rail'") != std::string::npos, r.out);
  BOOST_TEST(r.out.find("'rod'") != std::string::npos, r.out);
  const auto s = nlohmann::json::parse(slurp(dir / "out" / "summary.json"));
  BOOST_TEST(!s["complete"].get<bool>());
  const double t = s["failure"]["t"].get<double>();
  BOOST_TEST(t > 0.99);
  // The rod lies along the drive's normal at t = 1 (a singular position, x = 0); beyond it no
  // position satisfies the rows. The run crosses the singular instant itself (the vanishing
  // limit, docs/redundant.md) and stops at the first state past it, within a step's
  // tolerance: measured 1 + 8.3e-9 s.
  BOOST_TEST(t <= 1.0 + 1e-7);
  BOOST_TEST(r.out.find("the simulation failed at t = ") != std::string::npos, r.out);
  // The motion up to there is kept, and right: x = sqrt(1 − t²).
  const Table ts = read_csv(dir / "out" / "timeseries.csv");
  BOOST_TEST(ts.rows.size() >= 99u);
  for (const auto& row : ts.rows)
    if (row[0] <= 0.9) BOOST_TEST(std::abs(row[ts.col("x")] - std::sqrt(1 - row[0] * row[0])) < 1e-6);
}

// Issue 21: the rank changes are reported. A02 N = 1 at rtol 1e-8: summary.json's "rank" lists
// each singular position with its instant, the rank 7 of 8 and a dependent row; events.csv has
// a rank_lost and a rank_regained row for each; the instants are those where the independent
// one-degree-of-freedom model has every bar on the x axis (θ = k π), to 1e-6 s (the run's angle
// error, about 1e-6 rad, over crank rates of 1.5 to 7 rad/s), and each interval where the
// scaled σ_min is below 1e-6 σ_max lies within 1e-5 s of its instant.
BOOST_AUTO_TEST_CASE(a02_n1_reports_each_singular_position_as_a_rank_change_at_the_oracle_s_instant) {
  const auto dir = scratch("a02_rank");
  const std::string c = std::string(PCSIM_SOURCE_DIR) + "/cases/fourbar_a02_N1.toml";
  const auto r = run_pcsim("run '" + c + "' --out '" + (dir / "out").string() + "'", dir);
  BOOST_REQUIRE_MESSAGE(r.status == 0, r.out);
  BOOST_TEST(r.out.find("rank of the active constraints: 8 of 8 at the start") != std::string::npos, r.out);
  const auto s = nlohmann::json::parse(slurp(dir / "out" / "summary.json"));
  BOOST_REQUIRE(s.contains("rank"));
  const auto& rank = s["rank"];
  BOOST_TEST(rank["rank_start"].get<int>() == 8);
  BOOST_TEST(!rank.contains("indeterminate"));
  const std::vector<double> oracle = oracle_crossings(2, 1, 10.0);
  BOOST_REQUIRE(oracle.size() >= 6u);
  BOOST_TEST(rank["changes"].size() == oracle.size());
  for (std::size_t i = 0; i < std::min(oracle.size(), rank["changes"].size()); ++i) {
    const auto& ch = rank["changes"][i];
    const double t = ch["t"].get<double>();
    BOOST_TEST(std::abs(t - oracle[i]) < 1e-6, "change " << i << " at " << t << ", oracle " << oracle[i]);
    BOOST_TEST(ch["rank"].get<int>() == 7);
    BOOST_TEST(ch["dependent"].size() == 1u);
    BOOST_TEST(ch["t_from"].get<double>() <= t);
    BOOST_TEST(ch["t_to"].get<double>() >= t);
    BOOST_TEST(ch["t_to"].get<double>() - ch["t_from"].get<double>() < 1e-5);
  }
  const std::string ev = slurp(dir / "out" / "events.csv");
  std::size_t lost = 0, regained = 0;
  for (std::size_t p = 0; (p = ev.find(",rank_lost,", p)) != std::string::npos; ++p) ++lost;
  for (std::size_t p = 0; (p = ev.find(",rank_regained,", p)) != std::string::npos; ++p) ++regained;
  BOOST_TEST(lost == oracle.size());
  BOOST_TEST(regained == oracle.size());
  BOOST_TEST(ev.rfind("t,kind,constraint,mode_before,mode_after,", 0) == 0u);
}

// The parallelogram with a third crank: dependent from the start, its split of R indeterminate
// with a null space of dimension 1 (summary "rank.indeterminate"), and the report says so.
BOOST_AUTO_TEST_CASE(a_set_redundant_from_the_start_is_marked_indeterminate_with_its_nullity) {
  const auto dir = scratch("third_rank");
  const std::string c = std::string(PCSIM_SOURCE_DIR) + "/cases/parallelogram_third_crank.toml";
  const auto r = run_pcsim("run '" + c + "' --set solver.t_end=0.5 --out '" + (dir / "out").string() + "'", dir);
  BOOST_REQUIRE_MESSAGE(r.status == 0, r.out);
  const auto s = nlohmann::json::parse(slurp(dir / "out" / "summary.json"));
  BOOST_TEST(s["rank"]["rank_start"].get<int>() == 11);
  BOOST_TEST(s["rank"]["indeterminate"]["nullity"].get<int>() == 1);
  BOOST_TEST(s["rank"]["indeterminate"]["from"].get<double>() == 0.0);
  BOOST_TEST(s["rank"]["indeterminate"]["rows"].size() == 1u);
  BOOST_TEST(r.out.find("indeterminate, null space of dimension 1") != std::string::npos, r.out);
}

// Models whose rows keep full rank write what they wrote before: no "rank" key, no events.csv.
BOOST_AUTO_TEST_CASE(a_full_rank_run_has_no_rank_key_and_no_events_file) {
  const auto dir = scratch("full_rank");
  const std::string c = std::string(PCSIM_SOURCE_DIR) + "/cases/slider_crank.toml";
  const auto r = run_pcsim("run '" + c + "' --out '" + (dir / "out").string() + "'", dir);
  BOOST_REQUIRE_MESSAGE(r.status == 0, r.out);
  const auto s = nlohmann::json::parse(slurp(dir / "out" / "summary.json"));
  BOOST_TEST(!s.contains("rank"));
  BOOST_TEST(!fs::exists(dir / "out" / "events.csv"));
  BOOST_TEST(r.out.find("rank of the active") == std::string::npos, r.out);
}
