// The sweep machinery with a deterministic fake runner: grid expansion, the table, failed
// points, threads, resume after interruption, refusal of a foreign sweep.csv.
#define BOOST_TEST_MODULE study_sweep
#include <boost/test/unit_test.hpp>

#include <filesystem>
#include <string>
#include <vector>

#include "study/sweep.hpp"
#include "study/table.hpp"
#include "sim/vary.hpp"
#include "study_fixtures.hpp"

using namespace pcsim::study;
using namespace pcsim::sim;
using study_test::FakeRunner;
using study_test::slurp;

namespace {

// 3 x 4 = 12 points; the 4 with omega = 1100 fail.
Grid test_grid(const pcsim::sim::Case& base) {
  return make_grid({"parameters.omega=260,280,1100", "initial.s0=-0.3:0.3:4"}, base);
}

SweepOptions opts(const std::filesystem::path& dir, unsigned jobs) {
  SweepOptions o;
  o.out_dir = dir;
  o.jobs = jobs;
  return o;
}

/// sweep.csv's lines (header first).
std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> v;
  std::size_t start = 0;
  for (std::size_t end; (end = text.find('\n', start)) != std::string::npos; start = end + 1)
    v.push_back(text.substr(start, end - start));
  return v;
}

}  // namespace

BOOST_AUTO_TEST_CASE(range_has_count_values_with_exact_ends_and_shortest_text) {
  const auto dir = study_test::scratch("sweep_range");
  const auto base = study_test::minimal_case(dir);
  const Axis a = parse_vary("parameters.omega=250:300:6", base);
  BOOST_TEST(a.key == "parameters.omega");
  BOOST_TEST(a.texts == (std::vector<std::string>{"250", "260", "270", "280", "290", "300"}),
             boost::test_tools::per_element());
  // 0.1 steps must print as the decimals a user expects (no 0.30000000000000004), and
  // parse back to the same double.
  const Axis b = parse_vary("parameters.y0=0:1:11", base);
  BOOST_TEST(b.texts[3] == "0.3");
  BOOST_TEST(parse_vary("initial.s0=-0.4:0.4:9", base).texts[1] == "-0.3");
  BOOST_TEST(std::stod(b.texts[7]) == 0.7);
  const Axis c = parse_vary("parameters.omega=300", base);  // a one-element list
  BOOST_TEST(c.texts == std::vector<std::string>{"300"}, boost::test_tools::per_element());
}

BOOST_AUTO_TEST_CASE(grid_is_in_nested_loop_order_last_axis_fastest) {
  const auto dir = study_test::scratch("sweep_order");
  const auto base = study_test::minimal_case(dir);
  const Grid g = test_grid(base);
  BOOST_TEST(g.size() == 12u);
  BOOST_TEST(g.texts(0) == (std::vector<std::string>{"260", "-0.3"}),
             boost::test_tools::per_element());
  BOOST_TEST(g.texts(1) == (std::vector<std::string>{"260", "-0.1"}),
             boost::test_tools::per_element());
  BOOST_TEST(g.texts(4) == (std::vector<std::string>{"280", "-0.3"}),
             boost::test_tools::per_element());
  BOOST_TEST(g.texts(11) == (std::vector<std::string>{"1100", "0.3"}),
             boost::test_tools::per_element());
  const auto c = g.point_case(base, 6);
  BOOST_TEST(study_test::num(c, "parameters.omega") == 280.0);
  BOOST_TEST(study_test::num(c, "initial.s0") == std::stod(g.texts(6)[1]));
}

BOOST_AUTO_TEST_CASE(csv_lines_round_trip_quotes_commas_and_line_breaks) {
  const std::vector<std::string> f = {"a", "", "x,y", "say \"hi\"", "two\nlines"};
  const auto back = parse_csv_line(csv_line(f));
  BOOST_REQUIRE(back);
  BOOST_TEST(*back == (std::vector<std::string>{"a", "", "x,y", "say \"hi\"", "two lines"}),
             boost::test_tools::per_element());
  BOOST_TEST(!parse_csv_line("\"unterminated,1"));
}

BOOST_AUTO_TEST_CASE(rows_are_in_grid_order_and_equal_single_runs_exactly) {
  const auto dir = study_test::scratch("sweep_rows");
  const auto base = study_test::minimal_case(dir);
  const Grid g = test_grid(base);
  FakeRunner runner;
  const auto report = run_sweep(base, g, runner, opts(dir, 3));
  BOOST_REQUIRE_MESSAGE(report.ok, report.error);
  BOOST_TEST(report.ran == 12u);
  BOOST_TEST(report.failed == 4u);
  const auto table = read_csv(report.csv);
  BOOST_REQUIRE(table);
  BOOST_TEST(table->header == sweep_header(base, g), boost::test_tools::per_element());
  BOOST_REQUIRE(table->rows.size() == 12u);
  const auto cols = summary_columns(base);
  for (std::size_t i = 0; i < g.size(); ++i) {
    const auto& row = table->rows[i];
    BOOST_TEST(std::vector<std::string>(row.begin(), row.begin() + 2) == g.texts(i),
               boost::test_tools::per_element());
    const std::string status = row[2 + cols.size()];
    if (g.texts(i)[0] == "1100") {
      BOOST_TEST(status == "error");
      BOOST_TEST(row.back().find("step size too small") != std::string::npos);
      continue;
    }
    BOOST_TEST(status == "ok");
    // The single run of the same point, compared exactly: every numeric field parses back
    // to the very double of the summary.
    const auto single = pcsim::sim::to_json(runner(g.point_case(base, i)));
    const auto fields = numeric_fields(cols, std::vector<std::string>(row.begin() + 2, row.end()));
    BOOST_TEST(fields.at("amplitude.x") == single["amplitude"]["x"].get<double>());
    BOOST_TEST(fields.at("amplitude.theta") == single["amplitude"]["theta"].get<double>());
    BOOST_TEST(fields.at("R_u_min_over_weight") == single["R_u_min_over_weight"].get<double>());
    BOOST_TEST(fields.at("contact_margin") == single["R_u_min_over_weight"].get<double>());
    BOOST_TEST(fields.at("fstar_max") == single["fstar_max"].get<double>());
    BOOST_TEST(fields.at("rolling_margin") == 1.0 - single["fstar_max"].get<double>() / 0.3);
    BOOST_TEST(fields.at("stats.steps") == single["stats"]["steps"].get<double>());
    BOOST_TEST(fields.at("contact_kept") == 1.0);
    BOOST_TEST(fields.count("first_violation.contact") == 0u);  // null -> empty field
  }
}

BOOST_AUTO_TEST_CASE(one_and_four_threads_write_the_same_file) {
  const auto d1 = study_test::scratch("sweep_j1");
  const auto d4 = study_test::scratch("sweep_j4");
  const auto base = study_test::minimal_case(d1);
  const Grid g = test_grid(base);
  BOOST_REQUIRE(run_sweep(base, g, FakeRunner{}, opts(d1, 1)).ok);
  BOOST_REQUIRE(run_sweep(base, g, FakeRunner{}, opts(d4, 4)).ok);
  BOOST_TEST(slurp(d1 / "sweep.csv") == slurp(d4 / "sweep.csv"));
}

BOOST_AUTO_TEST_CASE(resumed_sweep_equals_uninterrupted_and_runs_only_missing_points) {
  const auto full = study_test::scratch("sweep_full");
  const auto base = study_test::minimal_case(full);
  const Grid g = test_grid(base);
  BOOST_REQUIRE(run_sweep(base, g, FakeRunner{}, opts(full, 2)).ok);
  const std::string reference = slurp(full / "sweep.csv");
  const auto lines = lines_of(reference);
  BOOST_REQUIRE(lines.size() == 13u);

  // An interrupted journal: header, 5 complete rows in completion (not grid) order, and the
  // first half of a sixth row without its newline (the write in flight).
  const auto resumed = study_test::scratch("sweep_resumed");
  std::filesystem::copy_file(full / "sweep.key", resumed / "sweep.key");  // the same sweep
  {
    std::ofstream out(resumed / "sweep.csv", std::ios::binary);
    out << lines[0] << "\n" << lines[7] << "\n" << lines[2] << "\n" << lines[12] << "\n"
        << lines[1] << "\n" << lines[9] << "\n" << lines[4].substr(0, lines[4].size() / 2);
  }
  FakeRunner runner;
  const auto report = run_sweep(base, g, runner, opts(resumed, 2));
  BOOST_REQUIRE_MESSAGE(report.ok, report.error);
  BOOST_TEST(report.skipped == 5u);
  BOOST_TEST(report.ran == 7u);
  BOOST_TEST(report.dropped == 1u);
  BOOST_TEST(*runner.calls == 7);
  BOOST_TEST(slurp(resumed / "sweep.csv") == reference);

  // Running the same command again runs nothing and leaves the file as it is.
  FakeRunner again;
  const auto second = run_sweep(base, g, again, opts(resumed, 2));
  BOOST_TEST(second.ran == 0u);
  BOOST_TEST(*again.calls == 0);
  BOOST_TEST(slurp(resumed / "sweep.csv") == reference);
}

BOOST_AUTO_TEST_CASE(torn_header_and_malformed_rows_are_dropped_on_resume) {
  const auto full = study_test::scratch("sweep_full2");
  const auto base = study_test::minimal_case(full);
  const Grid g = test_grid(base);
  BOOST_REQUIRE(run_sweep(base, g, FakeRunner{}, opts(full, 2)).ok);
  const std::string reference = slurp(full / "sweep.csv");
  const auto lines = lines_of(reference);

  const auto torn = study_test::scratch("sweep_torn_header");
  std::filesystem::copy_file(full / "sweep.key", torn / "sweep.key");
  std::ofstream(torn / "sweep.csv", std::ios::binary) << lines[0].substr(0, 10);
  BOOST_TEST(run_sweep(base, g, FakeRunner{}, opts(torn, 2)).dropped == 1u);
  BOOST_TEST(slurp(torn / "sweep.csv") == reference);

  const auto bad = study_test::scratch("sweep_malformed");
  std::filesystem::copy_file(full / "sweep.key", bad / "sweep.key");
  std::ofstream(bad / "sweep.csv", std::ios::binary)
      << lines[0] << "\n" << lines[3] << "\n" << "280,0.1,garbage\n" << lines[5] << "\n";
  const auto r = run_sweep(base, g, FakeRunner{}, opts(bad, 2));
  BOOST_TEST(r.dropped == 1u);
  BOOST_TEST(r.skipped == 2u);
  BOOST_TEST(slurp(bad / "sweep.csv") == reference);
}

BOOST_AUTO_TEST_CASE(sweep_csv_of_another_sweep_is_refused_and_left_untouched) {
  const auto dir = study_test::scratch("sweep_foreign");
  const auto base = study_test::minimal_case(dir);
  const std::string other = "parameters.e,status\n0.01,ok\n";
  std::ofstream(dir / "sweep.csv", std::ios::binary) << other;
  FakeRunner runner;
  const auto report = run_sweep(base, test_grid(base), runner, opts(dir, 2));
  BOOST_TEST(!report.ok);
  BOOST_TEST(report.error.find("another sweep") != std::string::npos);
  BOOST_TEST(*runner.calls == 0);
  BOOST_TEST(slurp(dir / "sweep.csv") == other);
}

BOOST_AUTO_TEST_CASE(wall_time_is_not_a_column_so_tables_are_reproducible) {
  const auto dir = study_test::scratch("columns");
  for (const auto& c : summary_columns(study_test::minimal_case(dir))) BOOST_TEST(c != "stats.wall_seconds");
}

// Rows are reused only for the same effective case: after a change of the case (here a
// parameter set on the command line) the old rows are refused, naming the change, and
// restart computes every point again; the unchanged case still resumes.
BOOST_AUTO_TEST_CASE(rows_of_another_case_are_never_reused) {
  const auto dir = study_test::scratch("sweep_stale");
  const auto base = study_test::minimal_case(dir);
  const Grid g = test_grid(base);
  BOOST_REQUIRE(run_sweep(base, g, FakeRunner{}, opts(dir, 2)).ok);
  const std::string first = slurp(dir / "sweep.csv");
  pcsim::sim::Case changed = base;
  pcsim::sim::set_value(changed, {"parameters.e", "0.02"});
  FakeRunner runner;
  const auto refused = run_sweep(changed, g, runner, opts(dir, 2));
  BOOST_TEST(!refused.ok);
  BOOST_TEST(refused.error.find("e = 0.02") != std::string::npos, refused.error);
  BOOST_TEST(refused.error.find("--restart") != std::string::npos, refused.error);
  BOOST_TEST(*runner.calls == 0);
  BOOST_TEST(slurp(dir / "sweep.csv") == first);
  SweepOptions o = opts(dir, 2);
  o.restart = true;
  const auto fresh = run_sweep(changed, g, runner, o);
  BOOST_REQUIRE_MESSAGE(fresh.ok, fresh.error);
  BOOST_TEST(fresh.ran == g.size());
  BOOST_TEST(slurp(dir / "sweep.csv") != first);
  // Varying a key that the base case sets differently changes nothing: varied keys are not
  // part of the key.
  pcsim::sim::Case other_omega = changed;
  pcsim::sim::set_value(other_omega, {"parameters.omega", "275"});
  FakeRunner none;
  const auto resumed = run_sweep(other_omega, g, none, opts(dir, 2));
  BOOST_TEST(resumed.ok, resumed.error);
  BOOST_TEST(*none.calls == 0);
}

BOOST_AUTO_TEST_CASE(duplicate_vary_values_are_refused) {
  const auto dir = study_test::scratch("sweep_dup");
  const auto base = study_test::minimal_case(dir);
  std::string msg;
  try {
    parse_vary("parameters.omega=250,260,250.0", base);
  } catch (const pcsim::InputError& e) {
    msg = e.what();
  }
  BOOST_TEST(msg.find("250 appears twice") != std::string::npos, msg);
  BOOST_CHECK_THROW(parse_vary("parameters.omega=250:250:3", base), pcsim::InputError);
}
