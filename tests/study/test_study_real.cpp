// The study machinery with the real integrator (sieve::run_case), on short runs to stay fast
// (solver.t_end = 0.02 s, ~1 excitation period; the summary window is clipped to the run,
// which does not matter for comparing runs with each other).
#define BOOST_TEST_MODULE study_real
#include <boost/test/unit_test.hpp>

#include <filesystem>

#include "sim/run.hpp"
#include "sieve/incline/incline.hpp"
#include "study/optimize.hpp"
#include "study/sweep.hpp"
#include "study/table.hpp"
#include "study_fixtures.hpp"

using namespace pcsim::study;
using namespace pcsim::sim;
using namespace pcsim::sieve;

namespace {
pcsim::sim::Case paper_case() {
  return pcsim::sim::load_case(std::filesystem::path(PCSIM_SOURCE_DIR) / "cases/sieve_1995.toml",
                                 {{"solver.t_end", "0.02"}});
}
}  // namespace

BOOST_AUTO_TEST_CASE(sweep_rows_equal_single_runs_exactly) {
  const auto dir = study_test::scratch("real_rows");
  const auto base = paper_case();
  const Grid g = make_grid({"parameters.omega=260,300", "initial.s0=0.2,0.4"}, base);
  SweepOptions o;
  o.out_dir = dir;
  o.jobs = 2;
  const auto r = run_sweep(base, g, case_runner(), o);
  BOOST_REQUIRE_MESSAGE(r.ok, r.error);
  const auto t = read_csv(r.csv);
  BOOST_REQUIRE(t);
  BOOST_REQUIRE(t->rows.size() == g.size());
  const auto cols = summary_columns(base);
  for (std::size_t i = 0; i < g.size(); ++i) {
    const auto c = g.point_case(base, i);
    const pcsim::sim::RunResult run = pcsim::sim::run_case(c);  // the same point, run on its own
    const auto single = pcsim::sim::to_json(run);
    const std::vector<std::string> row_summary(t->rows[i].begin() + 2,
                                               t->rows[i].begin() + 2 + cols.size());
    // Exactly: the text of every field, hence the double it parses back to.
    BOOST_TEST(row_summary == flatten_summary(run, c, cols),
               boost::test_tools::per_element());
    const auto f = numeric_fields(cols, row_summary);
    BOOST_TEST(f.at("R_u_min_over_weight") == single["R_u_min_over_weight"].get<double>());
    BOOST_TEST(f.at("amplitude.x") == single["amplitude"]["x"].get<double>());
    BOOST_TEST(f.at("fstar_max") == single["fstar_max"].get<double>());
    BOOST_TEST(t->rows[i][2 + cols.size()] == "ok");
    // The derived margins agree with the ones run_case reports (same formulas, computed
    // independently: min R_u/(m2 g) and 1 - max f*/f); 1e-15 allows the last-bit rounding.
    BOOST_TEST(std::abs(f.at("contact_margin") - single["margins"]["contact"].get<double>()) < 1e-15);
    BOOST_TEST(std::abs(f.at("rolling_margin") - single["margins"]["rolling"].get<double>()) < 1e-15);
  }
}

BOOST_AUTO_TEST_CASE(one_and_two_threads_give_the_same_table) {
  const auto d1 = study_test::scratch("real_j1"), d2 = study_test::scratch("real_j2");
  const auto base = paper_case();
  const Grid g = make_grid({"parameters.omega=250,310", "initial.s0=0.3"}, base);
  SweepOptions o;
  o.out_dir = d1;
  o.jobs = 1;
  BOOST_REQUIRE(run_sweep(base, g, case_runner(), o).ok);
  o.out_dir = d2;
  o.jobs = 2;
  BOOST_REQUIRE(run_sweep(base, g, case_runner(), o).ok);
  BOOST_TEST(study_test::slurp(d1 / "sweep.csv") == study_test::slurp(d2 / "sweep.csv"));
}

BOOST_AUTO_TEST_CASE(incline_locked_runs_have_no_theta_motion) {
  const auto dir = study_test::scratch("real_incline");
  const auto base = paper_case();
  InclineOptions o;
  o.out_dir = dir;
  o.jobs = 2;
  o.plot = false;
  const auto r = run_incline_study(base, {Axis{"initial.s0", {"0", "0.4"}}}, case_runner(), o);
  BOOST_REQUIRE_MESSAGE(r.ok, r.error);
  BOOST_TEST(r.failed == 0u);
  const auto sweep = read_csv(r.sweep.csv);
  BOOST_REQUIRE(sweep);
  const auto th = sweep->column("amplitude.theta").value();
  // theta = 0 is a constraint of the locked runs, kept to the projection tolerance; the free
  // desk rocks (theta amplitude > 0). 1e-9 rad is far above the constraint residuals.
  for (std::size_t i = 0; i < sweep->rows.size(); ++i) {
    const double amp = std::stod(sweep->rows[i][th]);
    if (sweep->rows[i][1] == "true") BOOST_TEST(amp < 1e-9);
    else BOOST_TEST(amp > 1e-9);
  }
}

BOOST_AUTO_TEST_CASE(optimizer_is_deterministic_and_within_bounds_on_the_paper_case) {
  const auto dir = study_test::scratch("real_opt");
  const auto base = paper_case();
  const std::vector<Bounds> b = {parse_bounds("parameters.omega=260:300", base),
                                 parse_bounds("initial.s0=0.1:0.4", base)};
  OptimizeOptions o;
  o.max_evals = 3;
  o.seed = 3;
  const auto r1 = optimize(base, b, case_runner(), o);
  const auto r2 = optimize(base, b, case_runner(), o);
  BOOST_REQUIRE(r1.evaluations.size() == r2.evaluations.size());
  for (std::size_t i = 0; i < r1.evaluations.size(); ++i) {
    const auto& e = r1.evaluations[i];
    BOOST_TEST(e.design == r2.evaluations[i].design, boost::test_tools::per_element());
    BOOST_TEST(e.objective == r2.evaluations[i].objective);
    BOOST_TEST(e.design[0] >= 260.0);
    BOOST_TEST(e.design[0] <= 300.0);
    BOOST_TEST(e.design[1] >= 0.1);
    BOOST_TEST(e.design[1] <= 0.4);
  }
  BOOST_REQUIRE(r1.best);
  // The best case file reads back to the best design.
  const auto file = dir / "best.toml";
  std::ofstream(file) << pcsim::sim::to_toml(r1.best_case);
  const auto back = pcsim::sim::load_case(file);
  BOOST_TEST(study_test::num(back, "parameters.omega") == r1.evaluations[*r1.best].design[0]);
  BOOST_TEST(study_test::num(back, "initial.s0") == r1.evaluations[*r1.best].design[1]);
}
