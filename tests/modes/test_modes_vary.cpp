// Traces over a parameter (--vary): eigenvalues are paired across steps by continuity, not by
// sorting: two decoupled oscillators whose frequencies cross keep their identities (sorting by
// |lambda| would swap them); a damping that changes sign is found as a stability crossing; a
// range through a point where the linearization does not exist fails naming the point, and
// nothing is written.
#define BOOST_TEST_MODULE modes_vary
#include <boost/test/unit_test.hpp>

#include <cmath>

#include "../support/cli_util.hpp"
#include "common/error.hpp"
#include "modes/modes_case.hpp"
#include "modes_test_util.hpp"
#include "sim/case.hpp"

using namespace pcsim;
using namespace pcsim::modes;
using namespace pcsim::modes::testing;

BOOST_AUTO_TEST_CASE(pairing_is_the_least_total_distance_assignment) {
  // |1 - 1.05| + |2 - 5| = 3.05 against |1 - 5| + |2 - 1.05| = 4.95: 0 -> 1.05, 1 -> 5.
  std::vector<int> a = pair_by_continuity({{1, 0}, {2, 0}}, {{5, 0}, {1.05, 0}});
  BOOST_TEST(a[0] == 1);
  BOOST_TEST(a[1] == 0);
  // Crossing values: the predictions 2.1 and 0.9 (extrapolated) take the values nearest them,
  // where the previous values (1, 2) would swap them. And a case where the greedy choice of
  // the closest pair first fails: it gives 1.05 to track 1 (0.05) and 5 to track 0 (4): 4.05,
  // while the optimum is 0 -> 1.05 (0.05), 1 -> 5 (3.9): 3.95.
  a = pair_by_continuity({{1.0, 0}, {1.1, 0}}, {{1.05, 0}, {5, 0}});
  BOOST_TEST(a[0] == 0);
  BOOST_TEST(a[1] == 1);
  a = pair_by_continuity({{2.1, 0}, {0.9, 0}, {0, 3}}, {{0, 3.01}, {0.95, 0}, {2.05, 0}});
  BOOST_TEST(a[0] == 2);
  BOOST_TEST(a[1] == 1);
  BOOST_TEST(a[2] == 0);
}

// Two oscillators without coupling (k2 = 0): x1 at sqrt(k1/m1), x2 at sqrt(k3/m2) = 10 rad/s.
// k1 from 50 to 250 crosses 200 (where they would swap under sorting) between two steps.
BOOST_AUTO_TEST_CASE(crossing_frequencies_keep_their_tracks) {
  Chain c;
  c.k2 = 0;
  c.k3 = 200;
  const sim::Case k = sim::load_case_text(chain_case(c), "chain.toml");
  const nlohmann::json j = modes_vary(k, {}, parse_vary("parameters.k1=50:250:11"));
  BOOST_TEST(j["tracks"].size() == 4u);
  int checked = 0;
  for (const auto& t : j["tracks"]) {
    const double first = std::abs(t["im"].front().get<double>()), last = std::abs(t["im"].back().get<double>());
    if (std::abs(first - std::sqrt(50.0)) < 1e-9) {
      BOOST_TEST(std::abs(last - std::sqrt(250.0)) < 1e-9);  // x1's track ends at x1's frequency
      ++checked;
    } else {
      BOOST_TEST(std::abs(first - 10.0) < 1e-9);
      BOOST_TEST(std::abs(last - 10.0) < 1e-9);
      ++checked;
    }
  }
  BOOST_TEST(checked == 4);
  BOOST_TEST(j["stability_crossings"].empty());
  // The undamped frequencies are paired the same way.
  BOOST_REQUIRE(j["undamped_tracks"].size() == 2u);
  for (const auto& t : j["undamped_tracks"]) {
    const double first = t["omega_rad_s"].front().get<double>(), last = t["omega_rad_s"].back().get<double>();
    if (std::abs(first - std::sqrt(50.0)) < 1e-9) BOOST_TEST(std::abs(last - std::sqrt(250.0)) < 1e-9);
    else BOOST_TEST(std::abs(last - 10.0) < 1e-9);
  }
}

// Only c1 damps: the real parts are proportional to c1 to first order and change sign at
// c1 = 0, which the steps straddle (0.5 .. -0.5 in 10 steps: +-0.0556 around 0).
BOOST_AUTO_TEST_CASE(a_damping_that_changes_sign_is_a_stability_crossing) {
  Chain c;
  c.k3 = 30;
  c.c1 = 0.5;
  const sim::Case k = sim::load_case_text(chain_case(c), "chain.toml");
  const nlohmann::json j = modes_vary(k, {}, parse_vary("parameters.c1=0.5:-0.5:10"));
  int unstable = 0;
  for (const auto& x : j["stability_crossings"]) {
    BOOST_TEST(x["direction"].get<std::string>() == "becomes unstable");
    BOOST_TEST(std::abs(x["value"].get<double>()) < 2e-3);  // linear interpolation over +-0.0556
    ++unstable;
  }
  BOOST_TEST(unstable == 4);  // both pairs
}

BOOST_AUTO_TEST_CASE(a_range_through_a_point_without_linearization_fails_and_writes_nothing) {
  Chain c;
  c.k3 = 30;
  const sim::Case k = sim::load_case_text(chain_case(c), "chain.toml");
  pcsim_test::TempDir tmp("modes_vary");
  ModesOptions o;
  o.out_dir = tmp.path / "out";
  // m1 = 0 at the middle step: the mass matrix is singular there.
  try {
    modes_vary(k, o, parse_vary("parameters.m1=1:-1:3"));
    BOOST_FAIL("expected NumericalError");
  } catch (const NumericalError& e) {
    BOOST_TEST_MESSAGE(e.what());
    BOOST_TEST(pcsim_test::has(e.what(), "parameters.m1 = 0"));
    BOOST_TEST(pcsim_test::has(e.what(), "nothing written"));
  }
  BOOST_TEST(!std::filesystem::exists(tmp.path / "out" / "modes_vary.csv"));
  BOOST_TEST(!std::filesystem::exists(tmp.path / "out" / "modes_vary.json"));
  // Bad specifications.
  BOOST_CHECK_THROW(parse_vary("parameters.m1=1:2"), InputError);
  BOOST_CHECK_THROW(parse_vary("parameters.m1=1:2:1"), InputError);
  BOOST_CHECK_THROW(parse_vary("parameters.m1=1:x:3"), InputError);
  BOOST_CHECK_THROW(modes_vary(k, o, parse_vary("solver.method=1:2:3")), InputError);
}
