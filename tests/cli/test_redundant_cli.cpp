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

#include <sys/wait.h>

namespace fs = std::filesystem;

namespace {

struct Result {
  int status;
  std::string output;
};

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

fs::path scratch(const std::string& name) {
  const fs::path d = fs::path(PCSIM_BINARY_DIR) / "test-scratch" / "redundant_cli" / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

Result run_pcsim(const std::string& args, const fs::path& dir) {
  const char* exe = std::getenv("PCSIM_EXE");
  BOOST_REQUIRE_MESSAGE(exe, "PCSIM_EXE is not set (run through ctest)");
  const auto log = dir / "output.txt";
  const int rc = std::system((std::string(exe) + " " + args + " > '" + log.string() + "' 2>&1").c_str());
  return {WIFEXITED(rc) ? WEXITSTATUS(rc) : -1, slurp(log)};
}

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
  BOOST_REQUIRE_MESSAGE(r.status == 0, case_name + " at rtol " + rtol + ": " + r.output);
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

// A02, N = 1: 3 rods, the bars on the x axis twice a revolution (rank 8 -> 7). 10 s is about
// three revolutions: six singular positions crossed. Bounds: the angle to 100 rtol (at least
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
  BOOST_TEST(r.status == 2, r.output);
  BOOST_TEST(r.output.find("'pin_shifted'") != std::string::npos, r.output);
  BOOST_TEST(r.output.find("'A0_x'") != std::string::npos, r.output);
  BOOST_TEST(!fs::exists(dir / "out" / "timeseries.csv"));
}

// `pcsim check CASE`: a report without running. The parallelogram with a third crank: rank 11
// of 12, one degree of freedom against a Grübler count of 0, the redundant row named, exit 0.
// A contradictory pin: exit 2 naming both rows. Nothing is written in either case.
BOOST_AUTO_TEST_CASE(check_reports_rank_dof_and_redundant_rows_and_refuses_contradictions) {
  const auto dir = scratch("check");
  const std::string third = std::string(PCSIM_SOURCE_DIR) + "/cases/parallelogram_third_crank.toml";
  const auto r = run_pcsim("check '" + third + "'", dir);
  BOOST_TEST(r.status == 0, r.output);
  for (const char* s : {"coordinates: 12; active constraints: 12",
                        "rank of the active constraints at the initial state: 11 of 12",
                        "degrees of freedom: 1 (n - rank); Gruebler-style count n - m = 0",
                        "redundant rows: 'M_coupler_y'", "mass matrix M: positive definite",
                        "the case can run"})
    BOOST_TEST(r.output.find(s) != std::string::npos, s << "\n" << r.output);
  const std::string a02 = std::string(PCSIM_SOURCE_DIR) + "/cases/fourbar_a02_N1.toml";
  const auto ok = run_pcsim("check '" + a02 + "'", dir);
  BOOST_TEST(ok.status == 0, ok.output);
  BOOST_TEST(ok.output.find("rank of the active constraints at the initial state: 8 of 8") != std::string::npos, ok.output);
  BOOST_TEST(ok.output.find("redundant rows: none") != std::string::npos, ok.output);
  const auto bad = run_pcsim("check '" + a02 + "' --constraint 'pin_shifted=xc0 - h*cos(tc0) - 0.1'", dir);
  BOOST_TEST(bad.status == 2, bad.output);
  BOOST_TEST(bad.output.find("'pin_shifted' contradicts 'A0_x'") != std::string::npos, bad.output);
  BOOST_TEST(bad.output.find("cannot run") != std::string::npos, bad.output);
}
