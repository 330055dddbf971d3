// `pcsim steady` and `pcsim response` through the executable (PCSIM_EXE, set by CTest): the
// files they write (steady.json and one period of timeseries.csv with pcsim run's columns;
// response.csv and response.json, and the plots), Newton's failure as exit 3 with the residual
// reached and nothing written, and bad input as exit 2 before anything is computed.
#define BOOST_TEST_MODULE steady_cli
#include <boost/test/unit_test.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "../support/cli_util.hpp"

namespace fs = std::filesystem;

namespace {

using pcsim_test::Result;
using pcsim_test::run_pcsim;

std::string slurp(const fs::path& p) { return pcsim_test::read(p); }
fs::path scratch(const std::string& name) { return pcsim_test::scratch("steady_cli", name); }

const std::string kSieve = std::string(PCSIM_SOURCE_DIR) + "/cases/sieve_1995.toml";
const std::string kDuffing = std::string(PCSIM_SOURCE_DIR) + "/tests/steady/duffing.toml";

std::string first_line(const std::string& text) { return text.substr(0, text.find('\n')); }

}  // namespace

BOOST_AUTO_TEST_CASE(steady_writes_steady_json_and_one_period_of_the_time_series) {
  const auto dir = scratch("steady");
  const auto r = run_pcsim("steady " + kSieve + " --out '" + (dir / "out").string() + "'", dir);
  BOOST_REQUIRE_MESSAGE(r.status == 0, r.out);
  BOOST_TEST(r.out.find("the orbit is STABLE") != std::string::npos, r.out);
  BOOST_TEST(r.out.find("slow coordinate s: held at its period mean 0.4") != std::string::npos, r.out);
  const auto j = nlohmann::json::parse(slurp(dir / "out" / "steady.json"));
  for (const char* k : {"state", "floquet", "newton", "slow", "summary", "periodicity_check", "shooting"})
    BOOST_TEST(j.contains(k), k);
  BOOST_TEST(j["newton"]["converged"].get<bool>());
  BOOST_TEST(j["summary"]["contact_kept"].get<bool>());
  // The same columns as pcsim run, one period of rows (at least 200).
  const auto run = run_pcsim("run " + kSieve + " --set solver.t_end=0.01 --out '" + (dir / "run").string() + "'", dir);
  BOOST_REQUIRE(run.status == 0);
  const std::string ts = slurp(dir / "out" / "timeseries.csv");
  BOOST_TEST(first_line(ts) == first_line(slurp(dir / "run" / "timeseries.csv")));
  long rows = 0;
  for (char c : ts) rows += c == '\n';
  BOOST_TEST(rows - 1 >= 200);
  // pcsim plot draws the period (steady.json's summary).
  if (std::system("command -v gnuplot > /dev/null 2>&1") == 0) {
    const auto p = run_pcsim("plot '" + (dir / "out").string() + "'", dir);
    BOOST_TEST(p.status == 0, p.out);
    BOOST_TEST(fs::exists(dir / "out" / "R_u.png"));
  }
}

// Issue 19: the Newton iterations computed are kept, in steady.json marked "complete": false.
BOOST_AUTO_TEST_CASE(newton_failure_exits_3_with_the_residual_reached_and_keeps_the_iterations) {
  const auto dir = scratch("fail");
  const auto r = run_pcsim("steady " + kDuffing + " --set parameters.omega=1.8 --max-iterations 1 --transient-periods 0 --out '" +
                               (dir / "out").string() + "'",
                           dir);
  BOOST_TEST(r.status == 3, r.out);
  BOOST_TEST(r.out.find("did not converge in 1 iteration: residual reached") != std::string::npos, r.out);
  BOOST_TEST(r.out.find("1 iterations") == std::string::npos, r.out);
  BOOST_TEST_REQUIRE(fs::exists(dir / "out" / "steady.json"));
  std::ifstream in(dir / "out" / "steady.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  BOOST_TEST(j["complete"].get<bool>() == false);
  BOOST_TEST(j["failure"]["reason"].get<std::string>().find("did not converge") != std::string::npos);
  BOOST_TEST(j["newton"]["history"].size() >= 1u);
}

BOOST_AUTO_TEST_CASE(what_steady_and_response_cannot_do_is_refused_before_computing) {
  const auto dir = scratch("bad");
  {
    std::ofstream(dir / "pendulum.toml") << "model = \"pendulum\"\n[initial]\nx = 1.0\n";
    const auto r = run_pcsim("steady '" + (dir / "pendulum.toml").string() + "' --out '" + (dir / "o1").string() + "'", dir);
    BOOST_TEST(r.status == 2, r.out);
    BOOST_TEST(r.out.find("declares no excitation period") != std::string::npos, r.out);
  }
  {
    const auto r = run_pcsim("steady " + kSieve + " --periods 0", dir);
    BOOST_TEST(r.status == 2, r.out);
  }
  {
    const auto r = run_pcsim("response " + kSieve + " --vary solver.rtol=1e-6,1e-7 --out '" + (dir / "o2").string() + "'", dir);
    BOOST_TEST(r.status == 2, r.out);
    BOOST_TEST(r.out.find("pcsim response varies a model parameter") != std::string::npos, r.out);
    BOOST_TEST(!fs::exists(dir / "o2"));
  }
  {
    const auto r = run_pcsim("response " + kSieve + " --vary parameters.omgea=1,2", dir);
    BOOST_TEST(r.status == 2, r.out);
  }
  // A switching case: the orbit shooting finds is the smooth one with the contacts held, so
  // a switching steady state is refused rather than reported under its heading (issue 12/13).
  for (const char* cmd : {"steady ", "response "}) {
    const auto out = dir / (std::string("o3") + cmd[0]);
    const auto r = run_pcsim(std::string(cmd) + kSieve + " --set contact.switching=true" +
                                 (cmd[0] == 'r' ? " --vary parameters.omega=280,281" : "") +
                                 " --out '" + out.string() + "'", dir);
    BOOST_TEST(r.status == 2, r.out);
    BOOST_TEST(r.out.find("key 'contact.switching': expected false") != std::string::npos, r.out);
    BOOST_TEST(!fs::exists(out));
  }
}

BOOST_AUTO_TEST_CASE(response_at_listed_values_writes_its_table_and_curves) {
  const auto dir = scratch("response");
  const auto r = run_pcsim("response " + kDuffing + " --vary parameters.omega=0.8,1.2,3.0 --jobs 2 --out '" +
                               (dir / "out").string() + "'",
                           dir);
  BOOST_REQUIRE_MESSAGE(r.status == 0, r.out);
  const std::string csv = slurp(dir / "out" / "response.csv");
  long rows = 0;
  for (char c : csv) rows += c == '\n';
  BOOST_TEST(rows == 4);  // header + 3 points, in the order given
  BOOST_TEST(first_line(csv).find("point,parameters.omega,status,stable,max_multiplier") == 0u);
  const auto j = nlohmann::json::parse(slurp(dir / "out" / "response.json"));
  BOOST_TEST(j["mode"].get<std::string>() == "listed values");
  BOOST_TEST(j["failed_points"].get<int>() == 0);
  if (std::system("command -v gnuplot > /dev/null 2>&1") == 0) {
    const auto p = run_pcsim("plot '" + (dir / "out").string() + "'", dir);
    BOOST_TEST(p.status == 0, p.out);
    BOOST_TEST(fs::exists(dir / "out" / "amplitudes.png"));
  }
  // A second run into the same directory replaces it (a pcsim output directory).
  const auto again = run_pcsim("response " + kDuffing + " --vary parameters.omega=0.8 --out '" + (dir / "out").string() + "'", dir);
  BOOST_TEST(again.status == 0, again.out);
}
