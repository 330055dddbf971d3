// Optimization in small on the fake runner, whose constrained optimum is known in closed form.
#define BOOST_TEST_MODULE study_optimize
#include <boost/test/unit_test.hpp>

#include <cmath>

#include "common/error.hpp"
#include "study/optimize.hpp"
#include "study_fixtures.hpp"

using namespace pcsim::study;
using pcsim::sim::Bounds;
using pcsim::sim::parse_bounds;

namespace {

// The fake runner's contact margin is 1 - a/g (1 + s0^2) with a = e omega^2 / 400 and
// amplitude.x = a * 1e-3: maximizing it alone drives omega to its lower bound and s0 to 0.
// With amplitude.x >= 1.5625e-3 (a >= 1.5625, i.e. omega >= 250 for e = 0.01) the optimum is
// omega = 250, s0 = 0, margin 1 - 1.5625/9.81, on the constraint's boundary.
struct Setup {
  std::filesystem::path dir = study_test::scratch("optimize");
  pcsim::sim::Case base = study_test::minimal_case(dir);
  std::vector<Bounds> bounds = {parse_bounds("parameters.omega=200:300", base),
                                parse_bounds("initial.s0=-0.3:0.3", base)};
  OptimizeOptions options() const {
    OptimizeOptions o;
    o.constraints = {parse_constraint("amplitude.x>=1.5625e-3", base),
                     parse_constraint("rolling_margin>=0.2", base)};
    o.max_evals = 200;
    o.xtol_rel = 1e-7;
    o.seed = 7;
    return o;
  }
};

}  // namespace

BOOST_AUTO_TEST_CASE(finds_the_known_constrained_optimum) {
  Setup s;
  const auto r = optimize(s.base, s.bounds, study_test::FakeRunner{}, s.options());
  BOOST_REQUIRE(r.best);
  const auto& best = r.evaluations[*r.best];
  BOOST_TEST(best.feasible);
  // COBYLA's linear models converge to the vertex to about the final trust radius; 0.1 rad/s
  // on omega (4e-4 relative) and 1e-3 m on s0 are far looser than xtol 1e-7 of the ranges.
  BOOST_TEST(std::abs(best.design[0] - 250.0) < 0.1);
  BOOST_TEST(std::abs(best.design[1]) < 1e-3);
  BOOST_TEST(std::abs(best.objective - (1.0 - 1.5625 / 9.81)) < 1e-4);
  // The ready-to-run case holds the best design.
  BOOST_TEST(study_test::num(r.best_case, "parameters.omega") == best.design[0]);
  BOOST_TEST(study_test::num(r.best_case, "initial.s0") == best.design[1]);
}

BOOST_AUTO_TEST_CASE(every_evaluation_respects_the_bounds) {
  Setup s;
  const auto r = optimize(s.base, s.bounds, study_test::FakeRunner{}, s.options());
  BOOST_REQUIRE(r.evaluations.size() > 5u);
  for (const auto& e : r.evaluations) {
    BOOST_TEST(e.design[0] >= 200.0);
    BOOST_TEST(e.design[0] <= 300.0);
    BOOST_TEST(e.design[1] >= -0.3);
    BOOST_TEST(e.design[1] <= 0.3);
  }
  // It starts from the case's values clamped into the box: omega 280, s0 0.4 -> 0.3.
  BOOST_TEST(r.evaluations[0].design[0] == 280.0);
  BOOST_TEST(r.evaluations[0].design[1] == 0.3);
}

BOOST_AUTO_TEST_CASE(same_seed_gives_the_same_history) {
  Setup s;
  const auto a = optimize(s.base, s.bounds, study_test::FakeRunner{}, s.options());
  const auto b = optimize(s.base, s.bounds, study_test::FakeRunner{}, s.options());
  BOOST_REQUIRE(a.evaluations.size() == b.evaluations.size());
  for (std::size_t i = 0; i < a.evaluations.size(); ++i) {
    BOOST_TEST(a.evaluations[i].design == b.evaluations[i].design,
               boost::test_tools::per_element());
    BOOST_TEST(a.evaluations[i].objective == b.evaluations[i].objective);
  }
  BOOST_TEST(*a.best == *b.best);
}

BOOST_AUTO_TEST_CASE(failed_runs_are_recorded_and_avoided) {
  // omega > 1000 fails in the fake runner. Starting at 950, COBYLA's first step (+10 % of
  // the range) lands in the failing region; it must record the failure, move away and still
  // reach the optimum omega = 250.
  Setup s;
  std::vector<Bounds> bounds = {parse_bounds("parameters.omega=200:1200", s.base),
                                parse_bounds("initial.s0=-0.3:0.3", s.base)};
  auto o = s.options();
  pcsim::sim::set_value(s.base, {"parameters.omega", "950"});
  const auto r = optimize(s.base, bounds, study_test::FakeRunner{}, o);
  BOOST_REQUIRE(r.evaluations.size() > 2u);
  BOOST_TEST(r.evaluations[1].design[0] == 1050.0);
  BOOST_TEST(r.evaluations[1].error.find("step size too small") != std::string::npos);
  BOOST_TEST(!r.evaluations[1].feasible);
  BOOST_REQUIRE(r.best);
  BOOST_TEST(r.evaluations[*r.best].feasible);
  BOOST_TEST(std::abs(r.evaluations[*r.best].design[0] - 250.0) < 1.0);
}

BOOST_AUTO_TEST_CASE(max_evals_is_a_hard_limit) {
  Setup s;
  auto o = s.options();
  o.max_evals = 6;
  int calls = 0;
  const auto r = optimize(s.base, s.bounds, study_test::FakeRunner{}, o,
                          [&](const Evaluation&) { ++calls; });
  BOOST_TEST(r.evaluations.size() <= 6u);
  BOOST_TEST(calls == static_cast<int>(r.evaluations.size()));
}

BOOST_AUTO_TEST_CASE(bad_constraints_and_objectives_are_rejected) {
  const auto dir = study_test::scratch("optimize_names");
  const pcsim::sim::Case base = study_test::minimal_case(dir);
  BOOST_CHECK_THROW(parse_constraint("rolling_margin>0.2", base), pcsim::InputError);
  BOOST_CHECK_THROW(parse_constraint("rolling_marg>=0.2", base), pcsim::InputError);
  BOOST_CHECK_THROW(parse_constraint("rolling_margin>=abc", base), pcsim::InputError);
  BOOST_CHECK_THROW(check_objective_name("contact", base), pcsim::InputError);
  const auto c = parse_constraint(" amplitude.x <= 1e-4 ", base);
  BOOST_TEST(c.name == "amplitude.x");
  BOOST_TEST(!c.at_least);
  BOOST_TEST(c.value == 1e-4);
}
