// The incline study on the fake runner: pairs of runs (theta free, locked) per design point,
// the margins and their differences, the default design axis.
#define BOOST_TEST_MODULE study_incline
#include <boost/test/unit_test.hpp>

#include <limits>

#include "sieve/incline/incline.hpp"
#include "study/table.hpp"
#include "../study/study_fixtures.hpp"

using namespace pcsim::study;
using namespace pcsim::sim;
using namespace pcsim::sieve;

BOOST_AUTO_TEST_CASE(default_axis_spans_the_deck_minus_the_roller_radius) {
  const auto dir = study_test::scratch("incline_axis");
  const auto base = study_test::minimal_case(dir);  // a = 0.5, r = 0.1
  const Axis a = default_incline_axis(base);
  BOOST_TEST(a.key == "initial.s0");
  BOOST_REQUIRE(a.texts.size() == 9u);
  BOOST_TEST(a.texts.front() == "-0.4");
  BOOST_TEST(a.texts[4] == "0");
  BOOST_TEST(a.texts.back() == "0.4");
}

BOOST_AUTO_TEST_CASE(table_pairs_free_and_locked_runs_and_differences) {
  const auto dir = study_test::scratch("incline_table");
  const auto base = study_test::minimal_case(dir);
  InclineOptions o;
  o.out_dir = dir;
  o.jobs = 2;
  o.plot = false;
  study_test::FakeRunner runner;
  const auto r = run_incline_study(base, {default_incline_axis(base)}, runner, o);
  BOOST_REQUIRE_MESSAGE(r.ok, r.error);
  BOOST_TEST(r.points == 9u);
  BOOST_TEST(*runner.calls == 18);
  const auto t = read_csv(r.table);
  BOOST_REQUIRE(t);
  BOOST_REQUIRE(t->rows.size() == 9u);
  for (const auto& row : t->rows) {
    const double s0 = std::stod(row[0]);
    const double a = 0.01 * 280.0 * 280.0 / 400.0;
    // The fake's closed forms: contact margin 1 - a/g (1 + k s0^2), k = 1 free, 0.5 locked;
    // rolling margin 1 - (0.1 + 0.01 s0 + 0.02 [free]) / 0.3. Tolerances: a few ulps.
    const double cf = 1.0 - a / 9.81 * (1.0 + s0 * s0), cl = 1.0 - a / 9.81 * (1.0 + 0.5 * s0 * s0);
    BOOST_TEST(std::stod(row[1]) == cf, boost::test_tools::tolerance(1e-14));
    BOOST_TEST(std::stod(row[2]) == cl, boost::test_tools::tolerance(1e-14));
    BOOST_TEST(std::abs(std::stod(row[3]) - (cf - cl)) < 1e-14);
    BOOST_TEST(std::abs(std::stod(row[6]) - (-0.02 / 0.3)) < 1e-14);
    BOOST_TEST(std::stod(row[7]) == 1e-4 * s0);
    BOOST_TEST(row[8] == "ok");
  }
  // The underlying sweep has the lock_theta axis last and is resumable like any sweep.
  const auto sweep = read_csv(r.sweep.csv);
  BOOST_REQUIRE(sweep);
  BOOST_TEST(sweep->header[1] == "constraints.lock_theta");
  BOOST_TEST(sweep->rows[0][1] == "false");
  BOOST_TEST(sweep->rows[1][1] == "true");
  study_test::FakeRunner again;
  BOOST_TEST(run_incline_study(base, {default_incline_axis(base)}, again, o).sweep.ran == 0u);
  BOOST_TEST(*again.calls == 0);
}

BOOST_AUTO_TEST_CASE(failed_design_point_is_reported_in_its_row) {
  const auto dir = study_test::scratch("incline_fail");
  const auto base = study_test::minimal_case(dir);
  InclineOptions o;
  o.out_dir = dir;
  o.jobs = 2;
  o.plot = false;
  const auto r = run_incline_study(base, {Axis{"parameters.omega", {"280", "1100"}}},
                                   study_test::FakeRunner{}, o);
  BOOST_TEST(r.failed == 1u);
  const auto t = read_csv(r.table);
  BOOST_REQUIRE(t);
  BOOST_TEST(t->rows[0][t->header.size() - 2] == "ok");
  BOOST_TEST(t->rows[1][t->header.size() - 2] == "error");
  BOOST_TEST(t->rows[1].back().find("theta free") != std::string::npos);
}

// An undefined value is an empty field, never "nan" or "inf" (issue 19): a margin that is
// infinite in both runs has an undefined difference (inf - inf), and a summary value that is not
// finite reaches neither the sweep's table nor the incline table as a token.
BOOST_AUTO_TEST_CASE(undefined_margins_and_differences_are_empty_fields) {
  const auto dir = study_test::scratch("incline_undefined");
  const auto base = study_test::minimal_case(dir);
  InclineOptions o;
  o.out_dir = dir;
  o.jobs = 1;
  o.plot = false;
  const double inf = std::numeric_limits<double>::infinity();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const study_test::FakeRunner fake;
  auto runner = [&](const pcsim::sim::Case& c) {
    pcsim::sim::RunResult r = fake(c);
    nlohmann::json& j = r.additions;
    const bool locked = c.table.at_path("constraints.lock_theta").value_or(false);
    // The sieve's client derives contact_margin = R_u_min_over_weight and
    // rolling_margin = 1 - fstar_max / f.
    j["R_u_min_over_weight"] = inf;             // both runs: the difference is inf - inf
    j["fstar_max"] = locked ? nan : 0.0;        // rolling margin 1 free, undefined locked
    j["amplitude"]["theta"] = locked ? 0.0 : -inf;  // the free run's amplitude column
    return r;
  };
  const auto r = run_incline_study(base, {Axis{"initial.s0", {"0", "0.1"}}}, runner, o);
  BOOST_REQUIRE_MESSAGE(r.ok, r.error);
  for (const auto& file : {r.table, r.sweep.csv}) {
    const std::string text = study_test::slurp(file);
    BOOST_TEST_INFO(file.string() << ":\n" << text);
    BOOST_TEST(text.find("nan") == std::string::npos);
    BOOST_TEST(text.find("inf") == std::string::npos);
  }
  const auto t = read_csv(r.table);
  BOOST_REQUIRE(t);
  BOOST_REQUIRE(t->rows.size() == 2u);
  const auto col = [&](const std::string& name) { return t->column(name).value(); };
  for (const auto& row : t->rows) {
    BOOST_TEST(row[col("contact_margin_free")] == "");
    BOOST_TEST(row[col("contact_margin_locked")] == "");
    BOOST_TEST(row[col("contact_margin_diff")] == "");
    BOOST_TEST(row[col("rolling_margin_free")] == "1");
    BOOST_TEST(row[col("rolling_margin_locked")] == "");
    BOOST_TEST(row[col("rolling_margin_diff")] == "");
    BOOST_TEST(row[col("amplitude_theta_free")] == "");
    BOOST_TEST(row[col("status")] == "ok");
  }
}
