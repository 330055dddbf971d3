// The switching simulation from the shell: `pcsim run` with contact.switching writes events.csv
// and a mode column per unilateral constraint and reports the hops in words; a run that needs an
// LCP fails with exit 3 and names the library when the plugin cannot be loaded, while a run that
// needs none does not care; bad combinations are refused with exit 2 before any computation.
#define BOOST_TEST_MODULE switching_cli
#include <boost/test/unit_test.hpp>

#include <set>

#include "cli_util.hpp"

using namespace switching_cli;

BOOST_AUTO_TEST_CASE(run_writes_events_and_mode_columns_and_reports_the_hops) {
  TempDir dir("switching_cli");
  const fs::path out = dir.path / "hop";
  const Result r = pcsim("run cases/sieve_1995_hopping.toml --set solver.t_end=0.5 --out '" + out.string() + "'");
  BOOST_REQUIRE_MESSAGE(r.status == 0, r.out);
  BOOST_TEST(r.out.find("once per period") != std::string::npos, r.out);
  BOOST_TEST(r.out.find("events.csv") != std::string::npos);
  const std::string events = read(out / "events.csv");
  BOOST_TEST(events.rfind("t,kind,constraint,mode_before,mode_after,normal,tangential,vn_before,vn_after,"
                          "vt_before,vt_after,energy_lost\n", 0) == 0);
  BOOST_TEST(events.find(",lift_off,contact,") != std::string::npos);
  BOOST_TEST(events.find(",impact,contact,") != std::string::npos);
  std::istringstream ts(read(out / "timeseries.csv"));
  std::string header, line;
  std::getline(ts, header);
  BOOST_TEST(header.size() > 13u);
  BOOST_TEST(header.substr(header.size() - 13) == ",mode_contact");
  std::set<std::string> modes;
  while (std::getline(ts, line)) modes.insert(line.substr(line.rfind(',') + 1));
  BOOST_TEST(modes.count("flight") == 1u);
  BOOST_TEST(modes.count("stick") == 1u);
  for (const auto& m : modes) BOOST_TEST((m == "flight" || m == "stick" || m == "slip"), m);
  // Without switching the same case has no events.csv and no mode column.
  const fs::path plain = dir.path / "plain";
  const Result p = pcsim("run cases/sieve_1995.toml --set solver.t_end=0.2 --out '" + plain.string() + "'");
  BOOST_REQUIRE_MESSAGE(p.status == 0, p.out);
  BOOST_TEST(!fs::exists(plain / "events.csv"));
  BOOST_TEST(read(plain / "timeseries.csv").find("mode_") == std::string::npos);
}

BOOST_AUTO_TEST_CASE(a_missing_lcp_library_is_named_only_when_an_lcp_is_needed) {
  TempDir dir("switching_cli");
  const std::string env = "PCSIM_LCP_LIBRARY=/nonexistent/pcsim_lcp_siconos.so";
  const Result r = pcsim("run cases/rocking_block.toml --out '" + (dir.path / "rb").string() + "'", env);
  BOOST_TEST(r.status == 3, r.out);
  BOOST_TEST(r.out.find("pcsim_lcp_siconos.so") != std::string::npos, r.out);
  BOOST_TEST(r.out.find("libsiconos-numerics") != std::string::npos, r.out);
  BOOST_TEST(r.out.find("t = 0.19") != std::string::npos, r.out);  // the first impact's time
  // One contact never needs the LCP: the same environment does not matter.
  const Result b = pcsim("run cases/bouncing_ball.toml --out '" + (dir.path / "bb").string() + "'", env);
  BOOST_TEST(b.status == 0, b.out);
}

BOOST_AUTO_TEST_CASE(impossible_combinations_are_refused_before_computing) {
  struct Bad {
    std::string args, key;
  };
  const std::vector<Bad> bad = {
      {"run cases/sieve_1995_hopping.toml --set solver.form=dae", "solver.form"},
      {"run cases/sieve_1995_hopping.toml --set constraints.contact=false", "contact.switching"},
      {"run cases/sieve_1995_hopping.toml --set constraints.rolling_as_printed=true", "constraints.rolling_as_printed"},
      {"run cases/sieve_1995_hopping.toml --set contact.zeno_time=0", "contact.zeno_time"},
      {"run cases/sieve_1995_hopping.toml --set contact.lcp_solver=pgs", "contact.lcp_solver"},
      {"run cases/sieve_1995_hopping.toml --set parameters.e_n=1.5", "parameters.e_n"},
  };
  TempDir dir("switching_cli");
  for (const auto& b : bad) {
    const fs::path out = dir.path / "x";
    const Result r = pcsim(b.args + " --out '" + out.string() + "'");
    BOOST_TEST_CONTEXT(b.args) {
      BOOST_TEST(r.status == 2, r.out);
      BOOST_TEST(r.out.find("key '" + b.key + "'") != std::string::npos, r.out);
      BOOST_TEST(!fs::exists(out / "summary.json"));
    }
  }
  // A model without unilateral constraints.
  const fs::path cf = dir.path / "pendulum.toml";
  std::ofstream(cf) << "model = \"pendulum\"\n[initial]\nx = 1.0\n[contact]\nswitching = true\n";
  const Result r = pcsim("run '" + cf.string() + "' --out '" + (dir.path / "p").string() + "'");
  BOOST_TEST(r.status == 2, r.out);
  BOOST_TEST(r.out.find("key 'contact.switching'") != std::string::npos, r.out);
  BOOST_TEST(r.out.find("declares none") != std::string::npos, r.out);
}
