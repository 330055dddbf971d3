// The sieve with switching contacts (issue 12). On the paper's case (e = 0.01 m) no switch
// happens, and then every result is today's, bit for bit: the verdicts of (3.1)-(3.3) are the
// case "no switching happened". With e = 0.05 m the roller loses contact; the case runs to the
// end, hopping once per excitation period, and the paper's verdicts name the first switches.
#define BOOST_TEST_MODULE switching_sieve
#include <boost/test/unit_test.hpp>

#include <cmath>

#include "../cli/switching_cli.hpp"
#include "sieve/source.hpp"
#include "sim/run.hpp"

using namespace pcsim;
using switching_cli::TempDir;
using switching_cli::read;

namespace {

const std::string kCase = std::string(PCSIM_SOURCE_DIR) + "/cases/sieve_1995.toml";

// Every value of a, compared with b's exactly (keys of a; wall time and the switching object
// and e_n's assumption entry excepted).
bool skipped(const std::string& path) {
  return path == "/stats/wall_seconds" || path == "/switching" || path == "/assumptions/parameters.e_n";
}

void same_json(const nlohmann::json& a, const nlohmann::json& b, const std::string& path, int& diffs) {
  if (skipped(path)) return;
  if (a.is_object()) {
    for (const auto& [k, v] : a.items()) {
      if (skipped(path + "/" + k)) continue;
      if (!b.contains(k)) {
        ++diffs;
        BOOST_TEST_MESSAGE("missing " << path << "/" << k);
        continue;
      }
      same_json(v, b[k], path + "/" + k, diffs);
    }
    return;
  }
  if (a != b) {
    ++diffs;
    BOOST_TEST_MESSAGE(path << ": " << a.dump() << " vs " << b.dump());
  }
}

}  // namespace

BOOST_AUTO_TEST_CASE(no_switch_happens_on_the_papers_case_and_every_result_is_todays) {
  sieve::register_sieve();
  TempDir dir("switching_sieve");
  const sim::Case plain = sim::load_case(kCase, {{"solver.t_end", "2"}});
  const sim::Case sw = sim::load_case(kCase, {{"solver.t_end", "2"}, {"contact.switching", "true"}});
  sim::RunOptions o1, o2;
  o1.out_dir = dir.path / "plain";
  o2.out_dir = dir.path / "switching";
  const auto a = sim::to_json(sim::run_case(plain, o1));
  const auto b = sim::to_json(sim::run_case(sw, o2));
  BOOST_REQUIRE(b.contains("switching"));
  BOOST_TEST(b["switching"]["events"].get<long>() == 0);
  BOOST_TEST(b["switching"]["contacts"]["contact"]["run"]["contact_fraction"].get<double>() == 1.0);
  int diffs = 0;
  same_json(a, b, "", diffs);
  same_json(b, a, "", diffs);
  BOOST_TEST(diffs == 0);
  // The time series: the same bytes in every column, and one more (the mode: stick throughout).
  std::istringstream ta(read(dir.path / "plain" / "timeseries.csv")), tb(read(dir.path / "switching" / "timeseries.csv"));
  std::string la, lb;
  long rows = 0;
  while (std::getline(ta, la) && std::getline(tb, lb)) {
    BOOST_REQUIRE(lb.size() > la.size());
    BOOST_TEST(lb.substr(0, la.size()) == la);
    BOOST_TEST((lb.substr(la.size()) == ",mode_contact" || lb.substr(la.size()) == ",stick"));
    ++rows;
  }
  BOOST_TEST(rows == 2002);
}

BOOST_AUTO_TEST_CASE(with_e_raised_the_roller_hops_once_per_period_to_the_end) {
  sieve::register_sieve();
  const sim::Case c = sim::load_case(std::string(PCSIM_SOURCE_DIR) + "/cases/sieve_1995_hopping.toml",
                                     {{"solver.t_end", "1"}});
  const auto s = sim::to_json(sim::run_case(c));
  BOOST_TEST(s["complete"].get<bool>());
  const auto& w = s["switching"]["contacts"]["contact"]["window"];
  BOOST_TEST(w["lift_offs"].get<long>() == 5);  // 5 periods in the window, one hop each
  BOOST_TEST(w["impacts"].get<long>() == 5);
  const double cf = w["contact_fraction"].get<double>();
  BOOST_TEST((cf > 0.5 && cf < 0.9), "contact fraction " << cf);
  BOOST_TEST(w["max_impact_velocity"].get<double>() > 0.0);
  BOOST_TEST(w["max_flight_height"].get<double>() > 0.0);
  // The paper's verdicts are the first switches: contact lost from the start (the exciter's
  // start-up throws the roller at t = 0: its initial mode is flight), rolling lost at the first
  // slip; R_u is 0 in flight and f* = f in slip.
  BOOST_TEST(s["switching"]["contacts"]["contact"]["initial_mode"].get<std::string>() == "flight");
  BOOST_TEST(!s["contact_kept"].get<bool>());
  BOOST_TEST(s["first_violation"]["contact"].get<double>() == 0.0);
  BOOST_TEST(!s["rolling_kept"].get<bool>());
  BOOST_TEST(std::abs(s["fstar_max"].get<double>() - 0.3) < 1e-9);
  BOOST_TEST(s["R_u_min"].get<double>() < 1e-9);
  BOOST_TEST(s["assumptions"]["parameters.e_n"].get<double>() == 0.0);
}
